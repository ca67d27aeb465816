#!/usr/bin/env bash
# Builds every target with ThreadSanitizer (the tsan preset: clang 14, warnings as errors, so
# that it is also CI's check that the whole project builds with clang) and runs the multi-job
# sweep ROUNDS times (default 3): every solver and rule on Pinocchio, hang and drag, two dts,
# with the truths, on --jobs 2, so that the jobs share what the engines share (a library's
# global state, the truth cache, the progress line). Any data race TSan reports fails the run,
# and its report is kept in build/tsan/reports/.
#
#   scripts/tsan_sweep.sh [ROUNDS]
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-3}
[[ $rounds =~ ^[0-9]+$ ]] || { echo "tsan_sweep.sh: ROUNDS must be a whole number, got '$rounds'" >&2; exit 2; }
scripts/setup.sh
cmake --preset tsan >/dev/null
cmake --build --preset tsan
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
rm -rf build/tsan/reports
mkdir -p build/tsan/reports
# halt_on_error: the first race ends the run with its report; the libraries' own code is not
# instrumented, so what TSan sees is the project's memory
export TSAN_OPTIONS="halt_on_error=1 exitcode=66 log_path=$PWD/build/tsan/reports/race second_deadlock_stack=1"
for round in $(seq 1 "$rounds"); do
  build/tsan/testbed run --scenario hang,drag --solver all --rule all --dt 1/60,1/120 \
    --duration 0.5 --no-timing --jobs 2 --truth-cache "$work/cache" --out "$work/out" \
    >/dev/null 2>"$work/stderr" || {
    status=$?
    echo "tsan_sweep.sh: round $round exited $status" >&2
    tail -n 5 "$work/stderr" >&2
    ls build/tsan/reports/ >&2
    exit 1
  }
  if compgen -G "build/tsan/reports/race*" >/dev/null; then
    echo "tsan_sweep.sh: round $round: ThreadSanitizer reports in build/tsan/reports/" >&2
    exit 1
  fi
done
echo "tsan_sweep.sh: $rounds multi-job sweeps without a ThreadSanitizer report"
