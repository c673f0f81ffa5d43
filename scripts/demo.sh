#!/usr/bin/env bash
# Builds isotrace and renders the demo images into out/.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
cargo build --release --locked
mkdir -p out
bin=target/release/isotrace
$bin render "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8" --box=-3,3 --size 768 -o out/tangle.png --stats
for name in sphere barth-sextic mitchell klein-bottle decocube sq.csg; do
    if $bin list >/dev/null 2>&1; then
        $bin render "@$name" --size 512 -o "out/$name.png"
    fi
done
echo "demo images are in out/"
