#!/usr/bin/env bash
# Runs every test of guideway. Usage: bash scripts/test.sh
#  1. set-up (libclang, .venv), idempotent
#  2. cargo test (unit, integration, FMU import with the `fmi` crate)
#  3. export the FMUs of the built-in scenes (+ cross-check files)
#  4. `guideway release` into out/dist (all built-in scenes)
#  5. pytest scripts/tests: fmpy, fmutool, libcosimpy against those FMUs;
#     the release; the scripted examples; the Dask sweep
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh

# One build for everything (tests, the CLI and the cdylib it packages,
# target/release/libguideway.so), so that the features of the dependencies
# are unified once and nothing is compiled twice.
cargo build --release --all-targets
cargo test --release --all-targets
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

.venv/bin/python -m pytest -q scripts/tests
