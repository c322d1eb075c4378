#!/usr/bin/env bash
# Long runs of the scene fuzzers.
# Usage: bash scripts/fuzz_scene.sh [CASES]                 (default 100000)
#   tests/product/scene_fuzz.rs: random and mutated scene TOML through parse +
#   validate + Simulation::new.
# Usage: bash scripts/fuzz_scene.sh --magnitudes [CASES]    (default 2000)
#   tests/product/magnitude_fuzz.rs: extreme values in every numeric field, each
#   scene run by `guideway run` within a CPU-time and memory budget.
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ "${1:-}" == "--magnitudes" ]]; then
    GUIDEWAY_MAGNITUDE_FUZZ_CASES="${2:-2000}" \
        cargo test --release --test product -- --nocapture --exact \
        magnitude_fuzz::scenes_with_extreme_magnitudes_run_within_budget_or_are_refused
else
    GUIDEWAY_SCENE_FUZZ_CASES="${1:-100000}" \
        cargo test --release --test product -- --nocapture --exact \
        scene_fuzz::fuzzed_scenes_load_or_are_refused_naming_where_and_never_panic_or_hang
fi
