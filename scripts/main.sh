#!/usr/bin/env bash
# The main job: set up, build (release), and run every scenario with the procedural solver on
# the built-in Pinocchio; results in results/, a summary table on stdout.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release
./build/release/testbed run --model pinocchio --out results --sample-hz 60 "$@"
