#!/usr/bin/env bash
# Builds isotrace and renders the demo images into out/.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
cargo build --release --locked
mkdir -p out
bin=target/release/isotrace
$bin render "x^4 - 5*x^2 + y^4 - 5*y^2 + z^4 - 5*z^2 + 11.8" --box=-3,3 --size 768 -o out/tangle.png --stats
for name in sphere barth-sextic mitchell klein-bottle decocube sq.csg onion; do
    $bin render "@$name" --size 512 -o "out/$name.png"
done
# Knoll et al.'s modalities and CSG by level-set conditions.
$bin render "min(x^2 + y^2 + (z - 0.3)^2 - 0.25, z + 0.6)" --box=-1.5,1.5,-1.5,1.5,-1,1 --shadows --light 1,-1,3 --size 512 -o out/shadows.png
$bin render @steiner --reflect 2 --env checker --size 512 -o out/reflections.png
$bin render "x^2 + y^2 + z^2 - 1 where z > 0; z where x^2 + y^2 + z^2 - 1 < 0" --box=-1.5,1.5 --eye 3,2,-1.5 --size 512 -o out/csg.png
# A sphere-traced distance field.
$bin render @creature --method sphere --size 512 -o out/creature.png
echo "demo images are in out/"
