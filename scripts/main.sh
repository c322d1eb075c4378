#!/usr/bin/env bash
# The main job: build the FMU of the default scene and simulate it with fmpy,
# printing the run's summary and writing a plot.
#   out/lee1994_wheel_10.fmu, out/lee1994_wheel_10.png
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
cargo build --release --lib --bins --examples

scene=lee1994-wheel-10
id=${scene//-/_}
mkdir -p out
# `guideway export` once the CLI has it, else the example calling the same
# guideway::fmu::export
if target/release/guideway export --help >/dev/null 2>&1; then
    target/release/guideway export "$scene" -o "out/$id.fmu"
else
    target/release/examples/export_fmu "$scene" -o "out/$id.fmu"
fi
.venv/bin/python scripts/simulate_fmu.py "out/$id.fmu" --plot "out/$id.png"
