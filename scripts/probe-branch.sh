#!/usr/bin/env bash
# Does the driver skip a block of shader code that no invocation of a SIMD
# bundle enters? The answer decides whether per-tile pruning (fidget's tape
# simplification, done in generated code: the tile pass marks which min/max
# operands a tile can drop, the per-pixel kernel branches around their code)
# can save time: every lane of a bundle belongs to one tile, so all of them
# agree on the branch.
#
# Four renders of a sphere by interval bisection, the same picture each time
# (the extra term is 0 where it runs, or not run at all):
#   plain      the sphere alone;
#   uniform    + heavy(x): 64 sines under a condition read from the frame
#              uniforms, never true;
#   divergent  the same under a condition on the interval itself (per lane
#              as far as the compiler knows), never true;
#   always     the same under a condition that always holds.
# If `uniform` and `divergent` cost about what `plain` does and `always`
# much more, the driver skips code no lane enters.
#
# Usage: scripts/probe-branch.sh [ISOTRACE] [SIZE]   (defaults:
# target/release/isotrace, 512). Prints the median GPU ms of 5 runs each.
#
# Measured on lavapipe (Mesa 22.3.6, LLVM 15.0.6, AMD EPYC, 2 cores) at
# 512², 2026-12-03, medians of 5: plain 7.3, uniform 11.3, divergent 11.6,
# always 48.0 ms (single runs earlier: 10-11, 11.5, 17-19, 52-55). A block
# no lane enters is skipped, with or without a uniform condition: the
# extra term's call and test cost 4 ms, its 64 sines 37 ms.
set -euo pipefail
bin=${1:-target/release/isotrace}
size=${2:-512}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export NODEVICE_SELECT=${NODEVICE_SELECT:-1}

for v in uniform divergent always; do
    case $v in
        uniform) cond="F.size.x == 12345u" ;;
        divergent) cond="v.x > 1e30" ;;
        always) cond="F.size.x != 12345u" ;;
    esac
    cat > "$dir/$v.wgsl" <<EOF
fn s_heavy(v: f32) -> f32 { return 0.0; }
fn ia_heavy(v: vec2<f32>) -> vec2<f32> {
    var acc = 0.0;
    if ($cond) {
        acc = v.x;
        for (var i = 0; i < 64; i = i + 1) { acc = sin(acc * 1.1 + 0.3); }
        acc = acc * 1e-30;
    }
    return vec2<f32>(acc - 1e-30, acc + 1e-30);
}
fn ra_heavy(v: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_heavy(ra_range(v))); }
EOF
done

sphere="x^2 + y^2 + z^2 - 1"
gpu_ms() { "$bin" render "$@" --algebra ia --size "$size" --stats -o "$dir/out.png" 2>&1 | sed -n 's/^gpu \([0-9.]*\) ms.*/\1/p'; }
median() { sort -n | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }

# One warm-up each (builds the pipeline; a cold shader cache compiles).
gpu_ms "$sphere" > /dev/null
for v in uniform divergent always; do gpu_ms "$sphere + heavy(x)" --inline "$dir/$v.wgsl" > /dev/null; done
declare -A runs
for _ in 1 2 3 4 5; do
    runs[plain]+="$(gpu_ms "$sphere") "
    for v in uniform divergent always; do runs[$v]+="$(gpu_ms "$sphere + heavy(x)" --inline "$dir/$v.wgsl") "; done
done
for v in plain uniform divergent always; do
    printf '%-10s %s ms\n' "$v" "$(tr ' ' '\n' <<< "${runs[$v]}" | grep . | median)"
done
