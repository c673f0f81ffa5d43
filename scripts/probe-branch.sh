#!/usr/bin/env bash
# Which shader code does the driver skip when no invocation of a SIMD bundle
# needs it? The answer decides where per-tile pruning (fidget's tape
# simplification: a tile drops the min/max operands that cannot matter in
# it) can save time on this device: every lane of a bundle belongs to one
# 8x8 tile, so all of them agree on what is pruned.
#
# Renders of a sphere by interval bisection, the same picture each time
# (the extra term is 0 where it runs, or not run at all):
#   plain             the sphere alone;
#   loop-uniform      + heavy(x): a loop of 64 sines under a condition read
#                     from the frame uniforms, never true;
#   loop-divergent    the same under a condition on the interval itself (per
#                     lane as far as the compiler knows), never true;
#   straight-uniform  the 64 sines written out (no loop) under the uniform
#                     condition, never true;
#   straight-divergent  the same under the per-lane condition;
#   always            the 64 sines written out under a condition that holds.
#
# Usage: scripts/probe-branch.sh [ISOTRACE] [SIZE]   (defaults:
# target/release/isotrace, 512). Prints the median GPU ms of 5 runs each.
#
# What it shows (figures in docs/notes/2026-12-07-fixed-costs.md): with
# Mesa 22.3 the body of an `if` runs under a lane mask whether or not a lane
# enters it, so pruning paid only where it shortened a loop (an
# interpreter's tape); with Mesa 25 a body no lane of the bundle enters is
# skipped, so code behind a branch the bundle's lanes agree on costs only
# where it runs.
set -euo pipefail
bin=${1:-target/release/isotrace}
size=${2:-512}
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
export NODEVICE_SELECT=${NODEVICE_SELECT:-1}

uniform_false="F.size.x == 12345u"
lane_false="v.x > 1e30"
always="F.size.x != 12345u"
loop_body="for (var i = 0; i < 64; i = i + 1) { acc = sin(acc * 1.1 + 0.3); }"
straight_body=$(for _ in $(seq 64); do printf 'acc = sin(acc * 1.1 + 0.3); '; done)

# heavy(x): `$2` under the condition `$1`, into file `$3`.
write_heavy() {
    cat > "$3" <<EOF
fn s_heavy(v: f32) -> f32 { return 0.0; }
fn ia_heavy(v: vec2<f32>) -> vec2<f32> {
    var acc = 0.0;
    if ($1) {
        acc = v.x;
        $2
        acc = acc * 1e-30;
    }
    return vec2<f32>(acc - 1e-30, acc + 1e-30);
}
fn ra_heavy(v: vec3<f32>) -> vec3<f32> { return ra_from_ia(ia_heavy(ra_range(v))); }
EOF
}
write_heavy "$uniform_false" "$loop_body" "$dir/loop-uniform.wgsl"
write_heavy "$lane_false" "$loop_body" "$dir/loop-divergent.wgsl"
write_heavy "$uniform_false" "$straight_body" "$dir/straight-uniform.wgsl"
write_heavy "$lane_false" "$straight_body" "$dir/straight-divergent.wgsl"
write_heavy "$always" "$straight_body" "$dir/always.wgsl"
variants="loop-uniform loop-divergent straight-uniform straight-divergent always"

sphere="x^2 + y^2 + z^2 - 1"
gpu_ms() { "$bin" render "$@" --algebra ia --size "$size" --stats -o "$dir/out.png" 2>&1 | sed -n 's/^gpu \([0-9.]*\) ms.*/\1/p'; }
median() { sort -n | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }

# One warm-up each (builds the pipeline; a cold shader cache compiles).
gpu_ms "$sphere" > /dev/null
for v in $variants; do gpu_ms "$sphere + heavy(x)" --inline "$dir/$v.wgsl" > /dev/null; done
declare -A runs
for _ in 1 2 3 4 5; do
    runs[plain]+="$(gpu_ms "$sphere") "
    for v in $variants; do runs[$v]+="$(gpu_ms "$sphere + heavy(x)" --inline "$dir/$v.wgsl") "; done
done
for v in plain $variants; do
    printf '%-19s %s ms\n' "$v" "$(tr ' ' '\n' <<< "${runs[$v]}" | grep . | median)"
done
