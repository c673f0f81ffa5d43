#!/usr/bin/env bash
# Simulates a 4-task Slurm job array on this machine, with the variables
# Slurm sets (SLURM_ARRAY_TASK_ID, _COUNT, _MIN, _MAX, _STEP), for the two
# example batch scripts:
#   1. examples/batch/slurm.sh (render --frames --shard auto --skip-existing):
#      all four tasks, `isotrace manifest merge`; then two frames are deleted
#      and the array is re-queued: exactly those two are rendered again;
#   2. examples/batch/slurm-bench.sh (bench --shard auto): all four tasks,
#      `isotrace bench --merge`, and the merged report compared with one
#      unsharded run, key by key except timings;
#   3. the GNU parallel (or xargs) one-liner of docs/batch.md.
# Fails on any missing frame or mismatch. Tiny sizes: a few seconds.
# Run by scripts/test.sh (CI) after the test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${ISOTRACE:-$PWD/target/release/isotrace}
[ -x "$BIN" ] || { echo "simulate-array: build first: cargo build --release ($BIN missing)" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export NODEVICE_SELECT=1
# This machine may itself run inside a scheduler: only the simulated
# variables may be seen.
unset SLURM_ARRAY_TASK_ID SLURM_ARRAY_TASK_COUNT SLURM_ARRAY_TASK_MIN SLURM_ARRAY_TASK_MAX SLURM_ARRAY_TASK_STEP \
    JOB_COMPLETION_INDEX ISOTRACE_SHARD_COUNT
fail() { echo "simulate-array: FAILED: $*" >&2; exit 1; }

# Runs script $1 as task $2 of a 4-task array (--array=0-3), in the background.
task() {
    SLURM_ARRAY_JOB_ID=4242 SLURM_ARRAY_TASK_ID=$2 SLURM_ARRAY_TASK_COUNT=4 SLURM_ARRAY_TASK_MIN=0 \
        SLURM_ARRAY_TASK_MAX=3 SLURM_ARRAY_TASK_STEP=1 ISOTRACE=$BIN bash "$1" >"$work/log-$(basename "$1")-$2" 2>&1 &
}
# Waits for every task; prints the log of one that failed.
wait_all() {
    local failed=0 pid
    for pid in $(jobs -p); do wait "$pid" || failed=1; done
    if [ $failed = 1 ]; then tail -n 20 "$work"/log-* >&2; fail "a task failed"; fi
}

echo "== frames: 4 tasks of examples/batch/slurm.sh, 10 frames"
mkdir -p "$work/frames"
export SIZE=16 FRAMES=10 OUT=$work/frames
for i in 0 1 2 3; do task examples/batch/slurm.sh "$i"; done
wait_all
"$BIN" manifest merge "$work/frames/*.manifest.json" || fail "frames are missing after the array"
[ "$(find "$work/frames" -name 'f_*.png' | wc -l)" = 10 ] || fail "expected 10 frame files"
for i in 0 1 2 3; do grep -q '"finished": "' "$work/frames/f_.shard-$i-of-4.manifest.json" || fail "shard $i/4 did not finish"; done

echo "== frames: delete 2 frames, re-queue the whole array"
rm "$work/frames/f_0003.png" "$work/frames/f_0006.png"
if "$BIN" manifest merge "$work/frames/*.manifest.json" >/dev/null 2>"$work/missing.txt"; then fail "the merge did not see the deleted frames"; fi
grep -q "2 of 10 frames are missing: 3 (f_0003.png), 6 (f_0006.png)" "$work/missing.txt" || { cat "$work/missing.txt" >&2; fail "wrong missing list"; }
for i in 0 1 2 3; do task examples/batch/slurm.sh "$i"; done
wait_all
"$BIN" manifest merge "$work/frames/*.manifest.json" || fail "frames are missing after the re-queue"
rendered=$(cat "$work"/frames/*.manifest.json | grep -c '"status":"rendered"' || true)
skipped=$(cat "$work"/frames/*.manifest.json | grep -c '"status":"skipped"' || true)
[ "$rendered" = 2 ] && [ "$skipped" = 8 ] || fail "the re-queue rendered $rendered and skipped $skipped frames (expected 2 and 8)"

echo "== bench: 4 tasks of examples/batch/slurm-bench.sh, 3 surfaces x 3 algebras"
mkdir -p "$work/bench"
export SURFACES="sphere steiner tangle" SIZE=16 REPEAT=1 OUT=$work/bench
for i in 0 1 2 3; do task examples/batch/slurm-bench.sh "$i"; done
wait_all
"$BIN" bench --merge "$work/bench/part-*.json" --json "$work/all.json" --markdown "$work/all.md" >/dev/null \
    || fail "bench --merge"
"$BIN" bench sphere steiner tangle --algebra ia,raa,auto --size 16 --repeat 1 --json "$work/single.json" >/dev/null 2>&1 \
    || fail "the unsharded bench run"
# The reports are indented JSON, one key a line: compare the settings but
# the shard, and the results but the timings (commas at line ends aside).
strip() {
    sed -n -e '/^  "isotrace_version"/p' -e '/^  "settings": {/,/^  },/p' -e '/^  "results": \[/,/^  \]/p' "$1" \
        | grep -Ev '"(gpu_ms|tile_ms|fps|wall_ms|setup_ms|shard)":' | sed 's/,$//'
}
diff <(strip "$work/single.json") <(strip "$work/all.json") >"$work/diff.txt" \
    || { cat "$work/diff.txt" >&2; fail "the merged report differs from a single run"; }
strip "$work/all.json" >"$work/all.stripped"
[ "$(grep -c '"index":' "$work/all.stripped")" = 9 ] || fail "expected 9 jobs in the merged report"
grep -q '"eps_relative":' "$work/all.stripped" || fail "no settings in the merged report"

echo "== GNU parallel one-liner (docs/batch.md), 4 shards of 6 frames"
mkdir -p "$work/par"
cd "$work"
if command -v parallel >/dev/null 2>&1; then
    parallel -j 2 "$BIN" render @water --size 16 --frames 6 -o par/f_%04d.png --shard {}/4 --skip-existing ::: 0 1 2 3
else
    echo "(GNU parallel is not installed: the xargs form of the same line)"
    printf '%s\n' 0 1 2 3 | xargs -P 2 -I{} "$BIN" render @water --size 16 --frames 6 -o par/f_%04d.png --shard {}/4 --skip-existing
fi
"$BIN" manifest merge 'par/*.manifest.json' || fail "frames are missing after the parallel run"
echo "simulate-array: OK"
