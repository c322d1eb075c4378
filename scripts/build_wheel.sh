#!/usr/bin/env bash
# Builds the `pip install guideway` wheel and prints its path: the
# `guideway` command and the FMU binary it packages, both against glibc
# 2.17 (manylinux2014), so that `guideway export` in any venv writes
# portable FMUs. Usage: wheel=$(bash scripts/build_wheel.sh)
#
# maturin (pyproject.toml: a bin wheel, through zig) builds the command;
# the FMU binary comes from the same compile (scripts/build_portable.sh) and
# goes in as the wheel's data, installed as
# <prefix>/lib/guideway/libguideway.so, where the command looks for it
# (src/fmu/mod.rs, portable_cdylib). So maturin runs twice: once in
# build_portable.sh to compile, once here to pack the wheel with the FMU
# binary, when cargo finds everything built.
set -euo pipefail
cd "$(dirname "$0")/.."
native_dir=${CARGO_TARGET_DIR:-target}
case "$native_dir" in /*) ;; *) native_dir="$PWD/$native_dir" ;; esac
cdylib=$(bash scripts/build_portable.sh)
# build_portable.sh made it (linked as target/wheel-data, which
# pyproject.toml names, when CARGO_TARGET_DIR is elsewhere).
data="$native_dir/wheel-data"
rm -rf "${data:?}/data" "$native_dir/wheels"
mkdir -p "$data/data/lib/guideway"
cp "$cdylib" "$data/data/lib/guideway/libguideway.so"
# The same target directory, working directory and flags as
# build_portable.sh, so that cargo has nothing to compile.
ROOT=$PWD
cd "$native_dir/portable"
PATH="$ROOT/.venv/bin:$PATH" CARGO_TARGET_DIR="$native_dir/portable" \
    "$ROOT/.venv/bin/maturin" build --release --zig --quiet -m "$ROOT/Cargo.toml" \
    -o "$native_dir/wheels" >&2
ls "$native_dir"/wheels/guideway-*.whl
