#!/usr/bin/env bash
# Builds isotrace and runs the whole test suite (unit, integration, snapshot,
# property and on-device conformance tests) in the release profile.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
cargo build --release --locked
cargo test --release --locked "$@"
