#!/usr/bin/env bash
# Browser tests of `isotrace view` (tests/browser/view.test.js): Debian's
# Chromium with WebGPU on SwiftShader, driven by playwright-core (pinned in
# tests/browser/package-lock.json; no browser download), both installed by
# scripts/setup-browser.sh (sourced by scripts/test.sh). Screenshots and figures: target/browser-artifacts/.
set -euo pipefail
cd "$(dirname "$0")/.."
export NODEVICE_SELECT=1
node tests/browser/view.test.js
