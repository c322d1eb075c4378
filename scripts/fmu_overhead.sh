#!/usr/bin/env bash
# Instructions per communication step (callgrind; independent of the
# machine's load) of the paper's scene stepped at 2.5 ms with every real
# output read after each step: natively, through the model layer and
# through the exported FMU loaded by the `fmi` crate (benches/fmu.rs).
# callgrind counts the stepping loop of 2 crossings of 900 steps of each
# kind alone (--toggle-collect): set-up (build, export, load, instantiate)
# is left out.
#   bash scripts/fmu_overhead.sh
set -euo pipefail
cd "$(dirname "$0")/.."
command -v valgrind >/dev/null || { echo "needs valgrind (apt-get install -y valgrind)" >&2; exit 1; }
exe=$(cargo bench --bench fmu --no-run --message-format=json 2>/dev/null \
  | python3 -c "import json, sys
for line in sys.stdin:
    m = json.loads(line)
    if m.get('reason') == 'compiler-artifact' and m['target']['name'] == 'fmu' and m.get('executable'):
        print(m['executable'])")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
declare -A per_step
for kind in native model fmu; do
  FMU_BENCH_CROSSINGS=$kind:2 valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" \
    --toggle-collect="fmu::${kind}_steps" "$exe" 2>"$tmp/err" >/dev/null
  refs=$(grep -o 'refs: *[0-9,]*' "$tmp/err" | tr -dc 0-9)
  per_step[$kind]=$(( refs / 1800 ))
done
echo "| kind | instructions per step | / native |"
echo "|---|---:|---:|"
for kind in native model fmu; do
  python3 -c "print(f'| $kind | {${per_step[$kind]}:,} | {${per_step[$kind]} / ${per_step[native]}:.3f} |')"
done
