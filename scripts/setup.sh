#!/usr/bin/env bash
# Set-up for building and testing guideway; idempotent, quick on re-run.
#  - libclang (Debian libclang-dev): fmi-sys runs bindgen at build time.
#  - chromium (Debian): tests/product/bridge_check.rs renders the check report
#    headless and reads its PASS/FAIL table.
#  - libtbb12 (Debian): the Ecos co-simulation engine (PyPI ecospy) links
#    libtbb.so.12 and does not ship it.
#  - qemu-user (Debian): the test command runs the guards on an emulated
#    CPU without AVX and FMA (the same bits on every CPU).
#  - .venv in the repository root with scripts/requirements.txt (fmpy,
#    libcosimpy, ecospy, fmu-manipulation-toolbox, pytest, numpy), installed
#    by uv.
set -euo pipefail
cd "$(dirname "$0")/.."

apt_install() {
    if [ "$(id -u)" != 0 ]; then
        echo "setup: need root to apt-get install $*" >&2
        exit 1
    fi
    if [ -z "${APT_UPDATED:-}" ]; then
        apt-get -o DPkg::Lock::Timeout=300 update -qq
        APT_UPDATED=1
    fi
    # Wait for another apt/dpkg run (a second checkout's set-up) instead of failing.
    DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=300 install -y -qq "$@" >/dev/null
}

# shellcheck source=scripts/lib/libclang.sh
. scripts/lib/libclang.sh
if ! has_bindgen_libclang /; then
    echo "setup: installing libclang-dev (for fmi-sys/bindgen)"
    apt_install libclang-dev
fi

# shellcheck source=scripts/lib/packages.sh
. scripts/lib/packages.sh
if ! has_libtbb12; then
    echo "setup: installing libtbb12 (for ecospy)"
    apt_install libtbb12
fi

if ! has_chromium; then
    echo "setup: installing chromium (renders the bridge check report in tests)"
    apt_install chromium
fi

if ! has_qemu_user; then
    echo "setup: installing qemu-user (runs the guards on an older CPU in tests)"
    apt_install --no-install-recommends qemu-user
fi

if ! python3 -c "import venv, ensurepip" 2>/dev/null; then
    echo "setup: installing python3-venv"
    apt_install python3-venv
fi

want=$(sha256sum scripts/requirements.txt | cut -d' ' -f1)
stamp=.venv/.requirements.sha256
if [ ! -x .venv/bin/python ] || [ "$(cat "$stamp" 2>/dev/null)" != "$want" ]; then
    echo "setup: creating .venv from scripts/requirements.txt"
    python3 -m venv .venv
    # uv installs the requirements in 15 s where pip took 58 s (2026-11-29,
    # docs/performance-log.md, "The test command's time"); it comes from
    # PyPI itself, pinned.
    .venv/bin/pip install -q --disable-pip-version-check uv==0.13.9
    .venv/bin/uv pip install -q --python .venv/bin/python -r scripts/requirements.txt
    echo "$want" >"$stamp"
fi
