#!/usr/bin/env bash
# Builds the libFuzzer targets (the fuzz preset: clang 14 with ASan and UBSan) and runs each for
# SECONDS (default 60) on its seed corpus: fuzz/corpus/, models/, tests/data/ and its MJCF corpora
# (the malformed files too). New inputs go to a temporary folder; a finding is written to
# build/fuzz/findings/ and fails the run. An <include> in a fuzzed input reads from the working
# directory, within it only, and a bounded regular file at most (mjcf_reader.cpp).
#
#   scripts/fuzz.sh [SECONDS]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
[[ $seconds =~ ^[0-9]+$ ]] || { echo "fuzz.sh: SECONDS must be a whole number, got '$seconds'" >&2; exit 2; }
scripts/setup.sh
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p build/fuzz/findings
# each target and its seeds: a writable copy first, then the read-only folders
build/fuzz/fuzz/fuzz_model_loader -max_total_time="$seconds" -max_len=65536 -timeout=10 \
  -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix=build/fuzz/findings/ \
  "$work" fuzz/corpus models tests/data tests/data/bad tests/data/mjcf tests/data/mjcf_classes 2>&1 | grep -E "^(#[0-9]+ +DONE|Done|stat::number_of_executed_units|==[0-9]+== ERROR|SUMMARY)" || true
if compgen -G "build/fuzz/findings/*" >/dev/null; then
  echo "fuzz.sh: findings in build/fuzz/findings/" >&2
  exit 1
fi
echo "fuzz.sh: fuzz_model_loader ran ${seconds} s without a finding"
