#!/usr/bin/env bash
# Builds isotrace and runs the whole test suite (unit, integration, snapshot,
# property and on-device conformance tests) in the release profile, then a
# simulated 4-task Slurm array of the batch examples (docs/batch.md), then the
# browser tests of `isotrace view` (headless Chromium, WebGPU on SwiftShader).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
source scripts/setup-browser.sh
cargo build --release --locked
cargo test --release --locked "$@"
bash scripts/simulate-array.sh
bash scripts/browser-test.sh
