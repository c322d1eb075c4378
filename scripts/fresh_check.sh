#!/usr/bin/env bash
# Proves the README's two commands from a clean state, as far as a machine
# allows: a fresh clone of the committed HEAD in a temporary directory, a
# fresh .venv, a fresh CARGO_TARGET_DIR, and (as root, with --purge) the
# Debian packages that scripts/setup.sh installs removed first.
#
# Usage: bash scripts/fresh_check.sh [--purge] [--fresh-cargo-home] [--keep]
#   --purge             apt-get purge libclang-dev, libtbb12, chromium, qemu-user
#                       and what they brought
#                       (root only), leaving what a fresh machine of our kind has
#                       (libclang-cpp14)
#   --fresh-cargo-home  an empty CARGO_HOME: every crate is downloaded again
#   --keep              keep the temporary directory (its path is printed)
# Uncommitted changes are not checked: the clone is of HEAD.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)

purge=0 fresh_cargo_home=0 keep=0
for arg in "$@"; do
    case "$arg" in
        --purge) purge=1 ;;
        --fresh-cargo-home) fresh_cargo_home=1 ;;
        --keep) keep=1 ;;
        *) echo "fresh_check: unknown option '$arg' (allowed: --purge, --fresh-cargo-home, --keep)" >&2; exit 2 ;;
    esac
done

# Packages scripts/setup.sh may install, beyond a fresh machine's set.
setup_packages=(libclang-dev libclang-14-dev libclang1-14 libclang-common-14-dev libclang-rt-14-dev
    libtbb12 libtbbbind-2-5 libtbbmalloc2 chromium chromium-common qemu-user libcapstone4)
if [ "$purge" = 1 ]; then
    if [ "$(id -u)" != 0 ]; then
        echo "fresh_check: --purge needs root" >&2
        exit 2
    fi
    echo "fresh_check: purging ${setup_packages[*]}"
    DEBIAN_FRONTEND=noninteractive apt-get purge -y -qq "${setup_packages[@]}" >/dev/null 2>&1 || true
    # shellcheck source=scripts/lib/libclang.sh
    . "$repo/scripts/lib/libclang.sh"
    if has_bindgen_libclang /; then
        echo "fresh_check: a libclang that bindgen loads is still present after the purge" >&2
        exit 1
    fi
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/guideway-fresh.XXXXXX")
if [ "$keep" = 0 ]; then
    trap 'rm -rf "$work"' EXIT
fi
git clone -q "$repo" "$work/guideway"
# CI clones with shared/ beside the checkout.
if [ -d "$repo/../shared" ]; then
    ln -s "$(cd "$repo/../shared" && pwd)" "$work/shared"
fi
export CARGO_TARGET_DIR="$work/target"
if [ "$fresh_cargo_home" = 1 ]; then
    export CARGO_HOME="$work/cargo-home"
fi
echo "fresh_check: clone of $(git -C "$repo" rev-parse --short HEAD) in $work/guideway"

run() {
    local name=$1
    shift
    local start end
    start=$(date +%s)
    if (cd "$work/guideway" && "$@") >"$work/$name.log" 2>&1; then
        end=$(date +%s)
        echo "fresh_check: $name passed in $((end - start)) s"
    else
        end=$(date +%s)
        echo "fresh_check: $name FAILED after $((end - start)) s; last lines of $work/$name.log:" >&2
        tail -n 30 "$work/$name.log" >&2
        trap - EXIT
        exit 1
    fi
}

run main bash scripts/main.sh
run test bash scripts/test.sh
tail -n 3 "$work/test.log" | sed 's/^/fresh_check: test: /'
echo "fresh_check: both README commands passed from a fresh clone"
