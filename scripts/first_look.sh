#!/usr/bin/env bash
# A first look, in seconds once the packages are in (scripts/setup.sh, which this runs
# first) and the testbed is built (this builds it if needed): the headline scenario, drag, for two
# simulated seconds in rule xpbd and in ODE, each at the configuration the committed verdict
# chose for it within 1 cm (results/verdict/verdict.csv), against the truth, and one small table
# (scripts/first_look.py). Nothing is written in the tree.
#   scripts/first_look.sh
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -eq 0 ] || { echo "first_look.sh: takes no arguments" >&2; exit 2; }
scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release --target testbed >/dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
k=0
while read -r -a flags; do
  k=$((k + 1))
  ./build/release/testbed run --scenario drag "${flags[@]}" --duration 2 --first-truth-only \
    --out "$out/$k" >/dev/null 2>"$out/$k.log" || { cat "$out/$k.log" >&2; exit 1; }
done < <(/usr/bin/python3 scripts/first_look.py --choices results drag procedural:xpbd ode)
/usr/bin/python3 scripts/first_look.py "$out"/*/summary.csv
