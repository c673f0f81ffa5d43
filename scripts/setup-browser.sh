#!/usr/bin/env bash
# Installs what the browser tests of `isotrace view` need (tests/browser/):
# Debian's Chromium (WebGPU on its bundled SwiftShader), Node.js and npm, and
# the pinned playwright-core (tests/browser/package-lock.json, npm ci; no
# browser download). As root it installs them; otherwise it prints the
# commands. Sourced by scripts/test.sh after scripts/setup.sh.
set -euo pipefail

as_root() {
    # $1: what, $2: the apt-get packages
    if [ "$(id -u)" = "0" ]; then
        echo "isotrace setup: installing $1 for the browser tests" >&2
        DEBIAN_FRONTEND=noninteractive bash -c "apt-get update -qq && apt-get install -y -qq $2" >&2
    else
        echo "isotrace setup: the browser tests need $1: sudo apt-get install -y $2" >&2
    fi
}

if [ ! -x /usr/lib/chromium/chromium ]; then
    as_root "Chromium" chromium
fi
if ! command -v npm >/dev/null 2>&1; then
    as_root "Node.js and npm" "nodejs npm"
fi
if command -v npm >/dev/null 2>&1; then
    (cd "$(dirname "${BASH_SOURCE[0]}")/../tests/browser" && npm ci --no-audit --no-fund --silent >&2) ||
        echo "isotrace setup: npm ci in tests/browser failed; the browser tests cannot run" >&2
fi
