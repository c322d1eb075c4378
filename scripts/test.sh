#!/usr/bin/env bash
# Runs every test of guideway. Usage: bash scripts/test.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo test --release --all-targets
