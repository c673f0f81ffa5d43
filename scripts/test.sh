#!/usr/bin/env bash
# Builds isotrace and runs the whole test suite (unit, integration, snapshot,
# property and on-device conformance tests) in the release profile, then a
# simulated 4-task Slurm array of the batch examples (docs/batch.md), then the
# library examples, then the browser tests of `isotrace view` (headless Chromium, WebGPU on SwiftShader).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
source scripts/setup-browser.sh
cargo build --release --locked
cargo test --release --locked "$@"
# The library examples of docs/library.md, run as a user runs them.
cargo run --release --locked --quiet --example render_formula
cargo run --release --locked --quiet --example edit_scene
bash scripts/simulate-array.sh
bash scripts/browser-test.sh
