#!/usr/bin/env bash
# Builds the FMU binary (libguideway.so) against glibc 2.17 (the oldest
# glibc Rust supports: RHEL/CentOS 7 and every distribution since), and
# prints its path. Usage: cdylib=$(bash scripts/build_portable.sh)
#
# A binary linked on this Debian 12 machine needs glibc >= 2.34: since glibc
# 2.34, pthread_key_create, pthread_key_delete and pthread_setspecific (used
# by Rust's std) live in libc with the version GLIBC_2.34, and the linker
# picks the newest version the build machine has. maturin's `--zig` links
# against zig's glibc stubs of the manylinux2014 baseline (2.17) instead
# (scripts/lib/portable.sh); both come from PyPI (maturin, ziglang) through
# scripts/requirements.txt.
# The target triple is the host's, so no Rust target needs installing.
#
# One compile for both portable binaries: maturin builds the wheel's
# `guideway` command (scripts/build_wheel.sh), and cargo builds the package's
# library for it with every crate type Cargo.toml declares, the cdylib
# included, linked by the same zig. A separate `cargo zigbuild --lib` would
# compile every crate once more (its flags differ from maturin's), which
# cost about 220 s of the test command (docs/performance-log.md, "The test
# command's time").
set -euo pipefail
cd "$(dirname "$0")/.."

# shellcheck source=scripts/lib/portable.sh
. scripts/lib/portable.sh
bash scripts/setup.sh >&2
ROOT=$PWD
# This build's wheel is not kept.
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
maturin_build "$ROOT" "$scratch"
deps="$(portable_release_dir)/deps"
built="$deps/libguideway.so"
# Linked after the library's rlib: older means cargo no longer built it here.
if [ ! -f "$built" ] || [ "$built" -ot "$deps/libguideway.rlib" ]; then
    echo "build_portable: maturin's build left no fresh $built" >&2
    exit 1
fi
# Where `guideway export` and `release` look for it (src/fmu/mod.rs,
# portable_cdylib).
out="$(portable_release_dir)/libguideway.so"
cp "$built" "$out.tmp"
mv "$out.tmp" "$out"
echo "$out"
