#!/usr/bin/env bash
# The whole crossings of 65,536 and 100,000 elements with HHT-α at the
# paper's step, against 1,024 elements (58 s of CPU for 65,536 on a 2-core
# machine; kept out of the suite).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --release --test physics large_meshes:: -- --ignored --nocapture
