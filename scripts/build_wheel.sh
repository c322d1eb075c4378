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
# shellcheck source=scripts/lib/portable.sh
. scripts/lib/portable.sh
cdylib=$(bash scripts/build_portable.sh)
native_dir=$(dirname "$(portable_target_dir)")
data=$(wheel_data_dir "$PWD")
rm -rf "${data:?}/data" "$native_dir/wheels"
mkdir -p "$data/data/lib/guideway"
cp "$cdylib" "$data/data/lib/guideway/libguideway.so"
# The same compile as build_portable.sh: cargo has nothing to do.
maturin_build "$PWD" "$native_dir/wheels"
ls "$native_dir"/wheels/guideway-*.whl
