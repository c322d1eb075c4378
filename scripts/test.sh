#!/usr/bin/env bash
# Runs every test of guideway. Usage: bash scripts/test.sh
#  1. set-up (libclang, .venv), idempotent
#  2. cargo test (unit, integration, FMU import with the `fmi` crate)
#  3. the shipped FMU binary, built against glibc 2.17
#     (scripts/build_portable.sh)
#     and the `pip install guideway` wheel (scripts/build_wheel.sh)
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

# One build for everything (tests, the CLI and the cdylib it packages,
# target/release/libguideway.so), so that the features of the dependencies
# are unified once and nothing is compiled twice; the shipped binaries are
# built once more, against glibc 2.17, in their own target directory.
cargo build --release --all-targets
phase_done "cargo build"
cargo test --release --all-targets
phase_done "cargo test"
GUIDEWAY_CDYLIB=$(bash scripts/build_portable.sh)
export GUIDEWAY_CDYLIB
# The `pip install guideway` wheel (maturin), for scripts/tests/test_wheel.py:
# packed from the compile above.
GUIDEWAY_WHEEL=$(bash scripts/build_wheel.sh)
export GUIDEWAY_WHEEL
phase_done "the glibc 2.17 build and the wheel"
# cargo builds into $CARGO_TARGET_DIR when it is set.
bin="${CARGO_TARGET_DIR:-target}/release/guideway"
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
