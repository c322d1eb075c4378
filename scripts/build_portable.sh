#!/usr/bin/env bash
# Builds the FMU binary (libguideway.so) against glibc 2.17 (the oldest
# glibc Rust supports: RHEL/CentOS 7 and every distribution since), and
# prints its path. Usage: cdylib=$(bash scripts/build_portable.sh)
#
# A binary linked on this Debian 12 machine needs glibc >= 2.34: since glibc
# 2.34, pthread_key_create, pthread_key_delete and pthread_setspecific (used
# by Rust's std) live in libc with the version GLIBC_2.34, and the linker
# picks the newest version the build machine has. cargo-zigbuild links
# against zig's glibc stubs of a chosen version instead; both come from PyPI
# (cargo-zigbuild, ziglang) through scripts/requirements.txt. The target
# triple is the host's, so no Rust target needs installing.
set -euo pipefail
cd "$(dirname "$0")/.."

GLIBC=2.17
# Beside the native build, in $CARGO_TARGET_DIR when it is set.
native_dir=${CARGO_TARGET_DIR:-target}
case "$native_dir" in /*) ;; *) native_dir="$PWD/$native_dir" ;; esac
TARGET_DIR="$native_dir/portable"
bash scripts/setup.sh >&2
ROOT=$PWD
# Its own target directory: the native build keeps its build scripts.
mkdir -p "$TARGET_DIR"
# cargo-zigbuild finds zig as `python3 -m ziglang` in the .venv. Run from
# the target directory: zig names its lib directory relative to the working
# directory when it lies below it, and cargo-zigbuild hands that to bindgen
# (in fmi-sys's build script), which runs elsewhere and then misses stddef.h.
cd "$TARGET_DIR"
PATH="$ROOT/.venv/bin:$PATH" cargo zigbuild --manifest-path "$ROOT/Cargo.toml" --release --lib \
    --target "x86_64-unknown-linux-gnu.$GLIBC" --target-dir "$TARGET_DIR" >&2
echo "$TARGET_DIR/x86_64-unknown-linux-gnu/release/libguideway.so"
