#!/usr/bin/env bash
# The main job: build the FMU of the default scene and simulate it with fmpy,
# printing the run's summary and writing a plot.
#   out/lee1994_wheel_10.fmu, out/lee1994_wheel_10.png
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
cargo build --release --lib --bins
# cargo builds into $CARGO_TARGET_DIR when it is set.
bin="${CARGO_TARGET_DIR:-target}/release/guideway"

scene=lee1994-wheel-10
id=${scene//-/_}
mkdir -p out
"$bin" export "$scene" -o "out/$id.fmu"
.venv/bin/python scripts/simulate_fmu.py "out/$id.fmu" --plot "out/$id.png"
