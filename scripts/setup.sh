#!/usr/bin/env bash
# Installs what isotrace needs on a fresh Debian/Ubuntu machine:
#  - checks for a Rust toolchain (cargo; install it with rustup), and
#  - when no Vulkan driver is present, Mesa's CPU driver lavapipe
#    (apt-get install mesa-vulkan-drivers libvulkan1; as root, else the exact
#    command is printed), from Mesa 25 of bookworm-backports on Debian 12.
# Sourced by scripts/demo.sh and scripts/test.sh (which also sources
# scripts/setup-browser.sh for the browser tests).
set -euo pipefail

if ! command -v cargo >/dev/null 2>&1; then
    echo "isotrace setup: cargo not found. Install Rust (1.90 or newer) with rustup: https://rustup.rs" >&2
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
        echo "isotrace setup: no Vulkan driver found; installing Mesa's CPU driver (lavapipe)" >&2
        DEBIAN_FRONTEND=noninteractive bash -c "$cmd" >&2
    else
        echo "isotrace setup: no Vulkan driver found. Install Mesa's CPU driver with:" >&2
        echo "    sudo $cmd" >&2
        exit 1
    fi
fi
# Debian 12 ships Mesa 22.3; its bookworm-backports has Mesa 25, whose lavapipe
# draws the same pictures with faster frames (docs/benchmarks.md).
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
        echo "isotrace setup: installing Mesa 25's lavapipe from bookworm-backports (faster frames)" >&2
        DEBIAN_FRONTEND=noninteractive bash -c "$cmd" >&2 ||
            echo "isotrace setup: bookworm-backports unavailable; keeping Mesa $(mesa_version)" >&2
    else
        echo "isotrace setup: Mesa $(mesa_version) works; Mesa 25 renders faster. To install it:" >&2
        echo "    sudo bash -c \"$cmd\"" >&2
    fi
fi
# Mesa's device-select layer warns on every start without this.
export NODEVICE_SELECT=1
