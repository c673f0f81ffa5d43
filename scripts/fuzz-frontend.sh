#!/usr/bin/env bash
# Long fuzz run of the formula front end (issue 15's evidence): the
# panic-freedom properties of src/tests/frontend_fuzz.rs with CASES random
# inputs each (default 400000: 1.2 million inputs over the three garbage
# generators), then WELL_FORMED random well-formed programs whose shaders
# are validated with naga in every domain (default 20000). Not part of CI's
# time budget; prints the inputs tried and the time taken.
#   scripts/fuzz-frontend.sh [CASES] [WELL_FORMED]
set -euo pipefail
cd "$(dirname "$0")/.."
cases=${1:-400000}
well_formed=${2:-20000}
cargo test --release --locked --lib --no-run >/dev/null 2>&1
start=$(date +%s)
PROPTEST_CASES=$cases cargo test --release --locked --lib -- --exact \
    tests::frontend_fuzz::arbitrary_bytes_never_panic tests::frontend_fuzz::arbitrary_text_never_panics \
    tests::frontend_fuzz::token_soup_never_panics
mid=$(date +%s)
PROPTEST_CASES=$well_formed cargo test --release --locked --lib -- --exact \
    tests::frontend_fuzz::well_formed_formulas_compile_and_validate
end=$(date +%s)
echo "fuzz-frontend: $((3 * cases)) garbage inputs in $((mid - start)) s," \
     "$well_formed well-formed programs in $((end - mid)) s, no panic"
