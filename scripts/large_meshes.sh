#!/usr/bin/env bash
# The whole crossing of 65,536 elements with HHT-α at the paper's step
# (15 to 60 s on a 2-core machine; kept out of the suite).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --release --test large_meshes -- --ignored --nocapture
