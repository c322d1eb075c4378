#!/usr/bin/env bash
# Whole-process time of `guideway run` (exec to exit), two binaries paired:
# hyperfine (-N, no shell) runs OLD and NEW in turn, for ROUNDS rounds
# (OLD, NEW, OLD, NEW, ...), on
#   - the paper's setting: lee1994-wheel-10 (2 elements, RK4, 2.5 ms) with
#     --summary, as scripts/bench_peers.py runs it;
#   - the start-up at 1,000 elements under `auto`: the same scene with
#     elements = 1000, integrator = "auto" and end_time = one step, -q.
# Then the instructions of each run of NEW (callgrind, independent of the
# machine's load) when valgrind is there.
#   bash scripts/process_time.sh OLD_BINARY [NEW_BINARY] [ROUNDS]
# NEW defaults to target/release/guideway, ROUNDS to 2.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v hyperfine >/dev/null || { echo "needs hyperfine (apt-get install -y hyperfine)" >&2; exit 1; }
old=$(realpath "${1:?usage: bash scripts/process_time.sh OLD_BINARY [NEW_BINARY] [ROUNDS]}")
new=$(realpath "${2:-target/release/guideway}")
rounds=${3:-2}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

"$new" scenes --show lee1994-wheel-10 >"$tmp/paper.toml"
sed -e 's/^elements = 2 /elements = 1000 /' -e 's/^integrator = "rk4"/integrator = "auto"/' \
    -e 's/^\[solver\]/[solver]\nend_time = 0.0025/' "$tmp/paper.toml" >"$tmp/e1000.toml"
grep -q '^elements = 1000 ' "$tmp/e1000.toml" && grep -q '^end_time' "$tmp/e1000.toml" \
  || { echo "the built-in scene changed its layout: update this script" >&2; exit 1; }

echo "# $(date -u '+%Y-%m-%d %H:%M UTC'), load average $(cut -d' ' -f1-3 /proc/loadavg)"
for case in paper e1000; do
  if [ $case = paper ]; then args=(run "$tmp/paper.toml" -q --summary "$tmp/s.json"); else args=(run "$tmp/e1000.toml" -q); fi
  for round in $(seq "$rounds"); do
    hyperfine -N -w 5 -r 40 --style basic -n "old $case" "$old ${args[*]}" -n "new $case" "$new ${args[*]}" \
      | grep -E '^Benchmark|Time \(mean|Range'
  done
  if command -v valgrind >/dev/null; then
    for which in old new; do
      bin=$old; [ $which = new ] && bin=$new
      valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" "$bin" "${args[@]}" 2>"$tmp/err" >/dev/null
      echo "$which $case: $(grep -o 'refs: *[0-9,]*' "$tmp/err") instructions"
    done
  fi
done
echo "# load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
