#!/usr/bin/env bash
# Builds the `pip install guideway` wheel and prints its path: the
# `guideway` command and the FMU binary it packages, both against glibc
# 2.17 (manylinux2014), so that `guideway export` in any venv writes
# portable FMUs. Usage: wheel=$(bash scripts/build_wheel.sh)
#
# maturin (pyproject.toml: a bin wheel, through zig) builds the command;
# the FMU binary comes from scripts/build_portable.sh and goes in as the
# wheel's data, installed as <prefix>/lib/guideway/libguideway.so, where
# the command looks for it (src/fmu/mod.rs, portable_cdylib).
set -euo pipefail
cd "$(dirname "$0")/.."
native_dir=${CARGO_TARGET_DIR:-target}
case "$native_dir" in /*) ;; *) native_dir="$PWD/$native_dir" ;; esac
cdylib=$(bash scripts/build_portable.sh)
data="$native_dir/wheel-data"
rm -rf "$data" "$native_dir/wheels"
mkdir -p "$data/data/lib/guideway"
cp "$cdylib" "$data/data/lib/guideway/libguideway.so"
# pyproject.toml names target/wheel-data; a CARGO_TARGET_DIR elsewhere is
# linked there.
if [ "$data" != "$PWD/target/wheel-data" ]; then
    mkdir -p target
    rm -rf target/wheel-data
    ln -s "$data" target/wheel-data
fi
# Its own target directory (maturin's flags differ from build_portable's),
# run from inside it for the reason build_portable.sh gives (bindgen and
# zig's relative lib directory).
ROOT=$PWD
mkdir -p "$native_dir/wheel-build"
cd "$native_dir/wheel-build"
PATH="$ROOT/.venv/bin:$PATH" CARGO_TARGET_DIR="$native_dir/wheel-build" \
    "$ROOT/.venv/bin/maturin" build --release --zig --quiet -m "$ROOT/Cargo.toml" \
    -o "$native_dir/wheels" >&2
ls "$native_dir"/wheels/guideway-*.whl
