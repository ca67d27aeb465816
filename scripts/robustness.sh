#!/usr/bin/env bash
# The committed robustness results (results/robustness/): every rule, both Bullet solvers and
# MuJoCo when the build has it, at dt = 1/60 and 1/240 s, STARTS random starts per scenario (500
# by default: 80,000 runs, about 30 minutes on 2 cores); then REPORT.md and the docs' generated
# blocks. Extra arguments go to testbed robustness (--shard I/N, ...).
#   STARTS=100 scripts/robustness.sh     the committed sweep (16,000 runs, 6 minutes on 2 cores)
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_layout.sh
scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release
solvers=procedural,bullet-multibody,bullet-rigid
if ./build/release/testbed list | grep -qw mujoco; then solvers+=,mujoco; fi
./build/release/testbed robustness --solver "$solvers" --rule all --dt 1/60,1/240 --starts "${STARTS:-500}" \
  --out "results/$ROBUSTNESS" "$@"
/usr/bin/python3 scripts/plot.py results
/usr/bin/python3 scripts/docs_tables.py
