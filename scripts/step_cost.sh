#!/usr/bin/env bash
# Instructions per step (callgrind; independent of the machine's load) of
# the paper's scene started mid-beam, for meshes of 2 to 100,000 elements:
# each case runs at two step counts and the difference is divided by the
# difference of the counts, so start-up is excluded.
#   bash scripts/step_cost.sh [rk4|hht] [elements ...]
#   bash scripts/step_cost.sh contacts [rk4|hht] [contacts ...]
# The second form: N paper wheels spread over a 3 × 25 m continuous beam
# (75 elements, 150 km/h, Δt = 1 ms; examples/step_cost.rs), steps 20 and 40.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v valgrind >/dev/null || { echo "needs valgrind (apt-get install -y valgrind)" >&2; exit 1; }
mode=elements
if [ "${1:-}" = contacts ]; then mode=contacts; shift; fi
integrator=${1:-hht}
shift || true
sizes=("$@")
if [ ${#sizes[@]} -eq 0 ]; then
  if [ $mode = contacts ]; then sizes=(1 4 16 64); else sizes=(2 16 128 1024 8192 65536 100000); fi
fi
cargo build --release --quiet --example step_cost
exe=target/release/examples/step_cost
tmp=$(mktemp -d)
if [ $mode = contacts ]; then
  printf "| contacts | instructions per step | integrations per step | instructions per contact |\n|---:|---:|---:|---:|\n"
  for n in "${sizes[@]}"; do
    counts=()
    for steps in 20 40; do
      out=$(timeout 3600 valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" "$exe" 75 "$integrator" "$steps" "$n" 2>"$tmp/err")
      refs=$(grep -o "refs: *[0-9,]*" "$tmp/err" | tr -dc 0-9)
      integrations=$(echo "$out" | sed -E 's/.* ([0-9]+) integrations/\1/')
      counts+=("$refs" "$integrations")
    done
    python3 -c "
n, (r1, i1, r2, i2) = $n, [int(x) for x in '${counts[*]}'.split()]
per_step = (r2 - r1) / 20
per_int = (i2 - i1) / 20
print(f'| {n} | {per_step:,.0f} | {per_int:.2f} | {per_step / n:,.0f} |')"
  done
  rm -rf "$tmp"
  exit 0
fi
printf "| elements | instructions per step | integrations per step | instructions per element-integration |\n|---:|---:|---:|---:|\n"
for n in "${sizes[@]}"; do
  counts=()
  for steps in 2 4; do
    out=$(timeout 1800 valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" "$exe" "$n" "$integrator" "$steps" 2>"$tmp/err")
    refs=$(grep -o "refs: *[0-9,]*" "$tmp/err" | tr -dc 0-9)
    integrations=$(echo "$out" | sed -E 's/.* ([0-9]+) integrations/\1/')
    counts+=("$refs" "$integrations")
  done
  python3 -c "
n, (r1, i1, r2, i2) = $n, [int(x) for x in '${counts[*]}'.split()]
per_step = (r2 - r1) / 2
per_int = (i2 - i1) / 2
print(f'| {n} | {per_step:,.0f} | {per_int:.2f} | {per_step / per_int / n:,.1f} |')"
done
rm -rf "$tmp"
