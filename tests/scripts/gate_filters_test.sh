#!/usr/bin/env bash
# scripts/gate_filters.py: each binary's quick filter selects every benchmark results/gate.json
# reads from it and, besides, only each scaling family's smallest chain; bad input exits 2.
#   gate_filters_test.sh BENCHMARKS_DIR SOURCE_DIR
set -euo pipefail
bin=$1
source_dir=$2
filters="/usr/bin/python3 $source_dir/scripts/gate_filters.py"
gate="$source_dir/results/gate.json"
fail() { echo "gate_filters_test: $*" >&2; exit 1; }
# the gate's benchmark names, a line each
wanted=$(/usr/bin/python3 -c '
import json, sys
for g in json.load(open(sys.argv[1]))["gates"]:
    print(g["numerator"]); print(g["denominator"])' "$gate" | sort -u)
for entry in "step bench_step ^step/" "stages bench_stages ^floor/" \
  "scaling bench_scaling ^(scaling|crowd)/"; do
  read -r kind binary prefix <<<"$entry"
  filter=$($filters "$gate" "$kind") || fail "$kind: status $?"
  # what the binary runs under the filter, without its arguments' suffixes (/real_time, ...)
  listed=$("$bin/$binary" --benchmark_list_tests --benchmark_filter="$filter")
  [ -n "$listed" ] || fail "$kind: the filter selects nothing"
  while read -r name; do
    grep -q "^$name/" <<<"$listed" || fail "$kind: the gate reads $name, which the filter leaves out"
  done < <(grep -E "$prefix" <<<"$wanted")
  while read -r run; do
    name=$(grep -oE "$filter" <<<"$run" | sed 's/\/$//')
    grep -qxF "$name" <<<"$wanted" || [[ $name =~ ^scaling/[^/]+/4$ ]] ||
      fail "$kind: the filter selects $run, which no gate reads"
  done <<<"$listed"
done
set +e
message=$($filters "$gate" nothing 2>&1); status=$?
set -e
[ "$status" -eq 2 ] || fail "an unknown binary: status $status"
message=$($filters /nonexistent/gate.json step 2>&1) && fail "a missing gate.json was read"
[[ "$message" == *"/nonexistent/gate.json"* ]] || fail "a missing gate.json said: $message"
echo "gate_filters_test: ok"
