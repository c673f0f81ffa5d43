#!/usr/bin/env bash
# Cold first-frame and warm frame times of the compiled and the tape field
# source (README, "Compiled or tape"): one process per measurement, Mesa's
# shader cache off. Usage: scripts/field-crossover.sh [SIZE] [TIMEOUT_S]
# Needs `cargo build --release --benches` first. Generated formulas go to
# $OUT (default /tmp/field-crossover).
set -u
SIZE=${1:-512}
LIMIT=${2:-200}
OUT=${OUT:-/tmp/field-crossover}
mkdir -p "$OUT"
B=$(ls target/release/deps/field_sources-* | grep -v '\.d$' | head -1)
python3 - "$OUT" <<'PY'
import sys
out = sys.argv[1]
open(f"{out}/p400.txt", "w").write(" + ".join(f"(x - {i})*(y + {i})" for i in range(1, 401)))
def gen(n):
    terms = "+".join(f"({0.5+i*0.001:.3f}*x-y)*(z+{i*0.002+0.001:.3f})" for i in range(n))
    return "x^2+y^2+z^2-1+1e-4*(" + terms + ")"
for n, name in [(178, "f1253"), (356, "f2503"), (1785, "f12503")]:
    open(f"{out}/{name}.txt", "w").write(gen(n))
PY
run() { # field method algebra formula-label formula
    local r
    local rc=0
    r=$(MESA_SHADER_CACHE_DISABLE=true timeout "$LIMIT" "$B" "$1" "$2" "$3" "$SIZE" "$5" 2>/dev/null) || rc=$?
    if [ "$rc" = 124 ]; then
        r="$1 $2 $3 $SIZE timeout >${LIMIT}s"
    elif [ "$rc" != 0 ]; then
        r="$1 $2 $3 $SIZE failed (exit $rc)"
    fi
    echo "$4 $r"
}
for f in p400 f1253 f2503 f12503; do
    for field in tape compiled; do run $field bisect ia "$f" "$(cat "$OUT/$f.txt")"; done
done
for field in tape compiled; do
    run $field bisect raa @creature @creature
    run $field bisect raa @city @city
    run $field bisect ia @tangle @tangle
    run $field bisect raa @tangle @tangle
    run $field sphere ia @creature-sphere @creature
done
