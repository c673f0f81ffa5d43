#!/usr/bin/env bash
# Installs what isotrace needs on a fresh Debian/Ubuntu machine:
#  - a Rust toolchain (cargo) new enough for edition 2024 (checked, not installed:
#    use rustup), and
#  - a Vulkan driver: when no Vulkan ICD is present, Mesa's CPU driver lavapipe
#    (apt-get install mesa-vulkan-drivers libvulkan1; as root, else the exact
#    command is printed), from Mesa 25 of bookworm-backports on Debian 12.
#  - for the browser tests of `isotrace view`: Debian's chromium, Node.js and
#    the pinned playwright-core (tests/browser/package-lock.json, npm ci).
# Sourced by scripts/demo.sh and scripts/test.sh.
set -euo pipefail

if ! command -v cargo >/dev/null 2>&1; then
    echo "isotrace setup: cargo not found. Install Rust (1.85 or newer) with rustup: https://rustup.rs" >&2
    exit 1
fi

have_vulkan() {
    # An installed ICD manifest means a Vulkan driver is present.
    # (Either folder may hold the manifest; grep reads all of ldconfig's
    # output, so pipefail never sees a SIGPIPE.)
    compgen -G '/usr/share/vulkan/icd.d/*.json' >/dev/null || compgen -G '/etc/vulkan/icd.d/*.json' >/dev/null || return 1
    ldconfig -p | grep -c 'libvulkan.so.1' >/dev/null
}

if ! have_vulkan; then
    cmd="apt-get update -qq && apt-get install -y -qq mesa-vulkan-drivers libvulkan1"
    if [ "$(id -u)" = "0" ]; then
        echo "isotrace setup: no Vulkan driver found; installing Mesa lavapipe (CPU Vulkan)" >&2
        DEBIAN_FRONTEND=noninteractive bash -c "$cmd" >&2
    else
        echo "isotrace setup: no Vulkan driver found. Install Mesa's CPU driver with:" >&2
        echo "    sudo $cmd" >&2
        exit 1
    fi
fi
# lavapipe from Mesa 25 rather than Debian 12's Mesa 22.3: the same pictures,
# Knoll frames 1.2-1.9x faster and big RAA kernels compiled in about half the
# time, most other kernels compiled 30-60 % longer (README, "The Vulkan
# driver"). On bookworm, Mesa 25 comes from Debian's own bookworm-backports.
# ISOTRACE_SYSTEM_MESA=1 keeps the distribution's Mesa.
mesa_version() { dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true; }
wants_newer_mesa() {
    [ "${ISOTRACE_SYSTEM_MESA:-0}" = "1" ] && return 1
    command -v dpkg-query >/dev/null 2>&1 || return 1
    [ "$( (. /etc/os-release 2>/dev/null; echo "${VERSION_CODENAME:-}") )" = "bookworm" ] || return 1
    local v
    v="$(mesa_version)"
    [ -n "$v" ] && dpkg --compare-versions "$v" lt 25
}
if wants_newer_mesa; then
    list=/etc/apt/sources.list.d/isotrace-bookworm-backports.list
    cmd="echo 'deb http://deb.debian.org/debian bookworm-backports main' > $list && apt-get update -qq && apt-get install -y -qq -t bookworm-backports mesa-vulkan-drivers"
    if grep -rqs 'bookworm-backports' /etc/apt/sources.list /etc/apt/sources.list.d/; then
        cmd="apt-get update -qq && apt-get install -y -qq -t bookworm-backports mesa-vulkan-drivers"
    fi
    if [ "$(id -u)" = "0" ]; then
        echo "isotrace setup: upgrading lavapipe from Mesa $(mesa_version) to bookworm-backports' Mesa 25" >&2
        DEBIAN_FRONTEND=noninteractive bash -c "$cmd" >&2 ||
            echo "isotrace setup: bookworm-backports unavailable; keeping Mesa $(mesa_version)" >&2
    else
        echo "isotrace setup: Mesa $(mesa_version) works; Mesa 25 draws frames faster (README, \"The Vulkan driver\"). As root:" >&2
        echo "    $cmd" >&2
    fi
fi
# Mesa's device-select layer warns on every start without this.
export NODEVICE_SELECT=1

# The browser tests' Chromium (WebGPU on its bundled SwiftShader) and driver.
if [ ! -x /usr/lib/chromium/chromium ]; then
    if [ "$(id -u)" = "0" ]; then
        echo "isotrace browser tests: installing Debian's chromium" >&2
        DEBIAN_FRONTEND=noninteractive bash -c "apt-get update -qq && apt-get install -y -qq chromium" >&2
    else
        echo "isotrace setup: the browser tests need Chromium: sudo apt-get install -y chromium" >&2
    fi
fi
if ! command -v npm >/dev/null 2>&1; then
    if [ "$(id -u)" = "0" ]; then
        DEBIAN_FRONTEND=noninteractive bash -c "apt-get update -qq && apt-get install -y -qq nodejs npm" >&2
    else
        echo "isotrace setup: the browser tests need Node.js and npm: sudo apt-get install -y nodejs npm" >&2
    fi
fi
if command -v npm >/dev/null 2>&1; then
    (cd "$(dirname "${BASH_SOURCE[0]}")/../tests/browser" && npm ci --no-audit --no-fund --silent >&2) ||
        echo "isotrace setup: npm ci in tests/browser failed; the browser tests cannot run" >&2
fi
