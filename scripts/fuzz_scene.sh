#!/usr/bin/env bash
# Long run of the scene fuzzer (tests/scene_fuzz.rs): random and mutated
# scene TOML through parse + validate + Simulation::new.
# Usage: bash scripts/fuzz_scene.sh [CASES]   (default 100000)
set -euo pipefail
cd "$(dirname "$0")/.."
GUIDEWAY_SCENE_FUZZ_CASES="${1:-100000}" \
    cargo test --release --test scene_fuzz -- --nocapture --exact \
    fuzzed_scenes_load_or_are_refused_naming_where_and_never_panic_or_hang
