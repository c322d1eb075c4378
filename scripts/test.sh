#!/usr/bin/env bash
# Runs every test of guideway. Usage: bash scripts/test.sh
#  1. set-up (libclang, .venv), idempotent
#  2. cargo test (unit, integration, FMU import with the `fmi` crate), of
#     the build against glibc 2.17 that ships; the guards again on an
#     emulated CPU without AVX and FMA (qemu-user)
#  3. the shipped FMU binary from it (scripts/build_portable.sh) and the
#     `pip install guideway` wheel (scripts/build_wheel.sh)
#  4. export the FMUs of the built-in scenes (+ cross-check files) with it
#  5. `guideway release` into out/dist (all built-in scenes)
#  6. pytest scripts/tests: fmpy, fmutool, libcosimpy, Ecos against those
#     FMUs; the binary; the release; the scripted examples; the Dask sweep
# Each phase's time goes to stderr as it ends, and the whole at the end
# (CI's budget is 15 minutes; docs/performance.md, "The two commands from
# a fresh clone").
set -euo pipefail
cd "$(dirname "$0")/.."

phase_start=$SECONDS
phase_done() {
    echo "test.sh: $1 in $((SECONDS - phase_start)) s" >&2
    phase_start=$SECONDS
}

bash scripts/setup.sh
phase_done "set-up"

# One build for everything (the tests, the `guideway` command and the FMU
# binary libguideway.so), against glibc 2.17 as shipped: the tests run
# what ships. It is maturin's compile (scripts/lib/portable.sh,
# portable_cargo), so the wheel's build below finds every crate built, and
# the features of the dependencies are unified once (Cargo.toml, resolver).
# shellcheck source=scripts/lib/portable.sh
. scripts/lib/portable.sh
release_dir=$(portable_release_dir)
library="$release_dir/deps/libguideway.rlib"
portable_cargo "$PWD" build --release --all-targets
phase_done "cargo build"
portable_cargo "$PWD" test --release --all-targets
phase_done "cargo test"
# The guards' recorded bits (tests/guards/layout_guards.rs) again, on an
# emulated CPU without AVX and FMA: glibc and matrixmultiply choose their
# code by the CPU at run time, so a result that depends on the CPU fails
# here (docs/robustness.md, "The same bits on every CPU").
CARGO_TARGET_X86_64_UNKNOWN_LINUX_GNU_RUNNER="qemu-x86_64 -cpu Nehalem" \
    portable_cargo "$PWD" test --release --test guards layout_guards::
phase_done "the guards on a CPU without AVX"
built_at=$(stat -c %Y "$library")
# The `pip install guideway` wheel (maturin), for scripts/tests/test_wheel.py:
# packed from the compile above, with the FMU binary scripts/build_portable.sh
# takes from it (build_wheel.sh runs it) into the release directory.
GUIDEWAY_WHEEL=$(bash scripts/build_wheel.sh)
export GUIDEWAY_WHEEL
export GUIDEWAY_CDYLIB="$release_dir/libguideway.so"
if [ "$(stat -c %Y "$library")" != "$built_at" ]; then
    echo "test.sh: warning: maturin compiled the library again (the test build's" \
        "flags or features differ from the wheel's build; scripts/lib/portable.sh)" >&2
fi
phase_done "the wheel"
bin="$release_dir/guideway"
# The command the Python tests run (scripts/tests/conftest.py).
export GUIDEWAY_BIN="$bin"
export GUIDEWAY_FMU_DIR="$PWD/out/fmu"
rm -rf "$GUIDEWAY_FMU_DIR"
mkdir -p "$GUIDEWAY_FMU_DIR"
for scene in lee1994-wheel-10 lee1994-glider-30; do
    id=${scene//-/_}
    "$bin" export "$scene" -o "$GUIDEWAY_FMU_DIR/$id.fmu" \
        --cross-check "$GUIDEWAY_FMU_DIR/cross-check"
done

# The release of this version (every built-in scene), for the release tests.
export GUIDEWAY_RELEASE_DIR="$PWD/out/dist"
"$bin" release --out "$GUIDEWAY_RELEASE_DIR" --replace
phase_done "the FMUs and the release"

# On every core: the tests are independent processes and temporary
# directories (84 s on one core, 53 s on two, 2026-11-29).
.venv/bin/python -m pytest -q -n auto scripts/tests
phase_done "pytest"
echo "test.sh: every test passed in $SECONDS s" >&2
