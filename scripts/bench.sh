#!/usr/bin/env bash
# Build and run the benchmarks, then the performance gate (testbed gate, results/gate.json).
#
#   scripts/bench.sh           every benchmark, 9 repetitions of ≥ 0.2 s in random interleaving
#                              (~15 min), and bench_budget once (~8 min); writes the JSON to
#                              results/bench/ and
#                              results/bench/<machine>.csv (medians)
#   scripts/bench.sh --quick   only what the gate reads, with shorter runs (CI, ~2 min);
#                              writes to build/release/bench/
#
# Exit status: the gate's (0 pass, 1 a ratio below its threshold, 2 bad input).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_layout.sh
thresholds=results/$GATE_THRESHOLDS
mode=full
if [ "${1:-}" = "--quick" ]; then mode=quick; fi
scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release

bin=build/release/benchmarks
common=(--benchmark_repetitions=9 --benchmark_enable_random_interleaving=true
  --benchmark_report_aggregates_only=true --benchmark_out_format=json)
machine=$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | tr -cs 'A-Za-z0-9' '-' |
  tr 'A-Z' 'a-z' | sed 's/^-//; s/-$//')-$(nproc)cpu

if [ "$mode" = quick ]; then
  out=build/release/bench
  mkdir -p "$out"
  quick=(--benchmark_min_time=0.05)
  # what results/gate.json reads, and nothing else (scripts/gate_filters.py; an assignment, so
  # that a failure stops here instead of timing everything)
  step=$(/usr/bin/python3 scripts/gate_filters.py "$thresholds" step)
  stages=$(/usr/bin/python3 scripts/gate_filters.py "$thresholds" stages)
  scaling=$(/usr/bin/python3 scripts/gate_filters.py "$thresholds" scaling)
  "$bin/bench_step" "${common[@]}" "${quick[@]}" --benchmark_out="$out/bench_step.json" \
    --benchmark_filter="$step"
  "$bin/bench_stages" "${common[@]}" "${quick[@]}" --benchmark_out="$out/bench_stages.json" \
    --benchmark_filter="$stages"
  "$bin/bench_scaling" "${common[@]}" "${quick[@]}" --benchmark_out="$out/bench_scaling.json" \
    --benchmark_filter="$scaling"
  # the verdict's choices (results/verdict/verdict.csv): the cheapest procedural rule against
  # the cheapest reference per scenario and budget
  "$bin/bench_verdict" "${common[@]}" "${quick[@]}" --benchmark_out="$out/bench_verdict.json"
  # step() from Python against C++ (the Python package's cost)
  "$bin/bench_python" "${common[@]}" "${quick[@]}" --benchmark_out="$out/bench_python.json"
  ./build/release/testbed gate "$out"/bench_step.json "$out"/bench_stages.json \
    "$out"/bench_scaling.json "$out"/bench_verdict.json "$out"/bench_python.json \
    --thresholds "$thresholds"
else
  out=results/bench
  mkdir -p "$out"
  for b in bench_step bench_stages bench_scaling bench_verdict bench_python; do
    "$bin/$b" "${common[@]}" --benchmark_min_time=0.2 --benchmark_out="$out/$b.json"
  done
  # the engine budget's estimates against piles on the ground (docs/reliability.md): once, its
  # exact solvers' piles take minutes (the rods of 32 boxes in dWorldStep: 4.6 s a step)
  "$bin/bench_budget" --benchmark_min_time=0.05 --benchmark_out_format=json \
    --benchmark_out="$out/budget.json"
  status=0
  ./build/release/testbed gate "$out"/bench_step.json "$out"/bench_stages.json \
    "$out"/bench_scaling.json "$out"/bench_verdict.json "$out"/bench_python.json \
    --thresholds "$thresholds" --csv "$out/$machine.csv" || status=$?
  # docs/performance.md's tables are generated blocks that name a machine's CSV
  /usr/bin/python3 scripts/docs_tables.py
  grep -q "results/bench/$machine.csv" docs/performance.md ||
    echo "bench.sh: docs/performance.md has no block for results/bench/$machine.csv yet:" \
      "add one naming it (see the blocks there; scripts/bench_tables.py prints them)"
  exit "$status"
fi
