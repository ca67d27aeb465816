#!/usr/bin/env bash
# What each ingredient of the position-based rules costs or buys, at dt = 1/240 on Pinocchio:
# the one-sided closure (relaxed), Gauss–Seidel sweeps against the exact projection (xpbd,
# tree), substeps against iterations, and a hard grab against a compliant one (every solver).
# Each configuration is one `testbed run` into FOLDER/<name>; FOLDER/configs.csv names them, and
# scripts/plot.py turns them into REPORT.md's ablation tables. Further arguments go to every
# `testbed run` (main.sh passes its --truth-cache: the configurations on Pinocchio's default
# scenarios then read the main run's truth instead of computing it again).
#
#   scripts/ablation.sh FOLDER [TESTBED RUN FLAGS...]
set -euo pipefail
cd "$(dirname "$0")/.."
folder=${1:?usage: scripts/ablation.sh FOLDER [TESTBED RUN FLAGS...]}
shift
testbed=./build/release/testbed
mkdir -p "$folder"
# name, what it isolates, flags. The compliant grab is C = 1e-4 m/N (10 kN/m): Pinocchio
# (69.6 kg) hanging from it alone, as in yank, stretches it by 7 cm; Ten Minute Physics' 0.01 m/N
# is for light bodies and would let this one hang 7 m below the hand
configs=(
  "relaxed|relaxed: 4 sweeps, then the one-sided closure|--solver procedural --rule relaxed"
  "relaxed-64|relaxed: 64 sweeps, then the one-sided closure|--solver procedural --rule relaxed --iterations 64"
  "xpbd|xpbd: 8 substeps x 1 sweep|--solver procedural --rule xpbd"
  "xpbd-iterations|xpbd: 1 substep x 8 sweeps|--solver procedural --rule xpbd --substeps 1 --iterations 8"
  "tree|tree: 8 substeps x 1 exact solve|--solver procedural --rule tree"
  "tree-iterations|tree: 1 substep x 8 Newton iterations|--solver procedural --rule tree --substeps 1 --iterations 8"
  "tree-2x2|tree: 2 substeps x 2 Newton iterations|--solver procedural --rule tree --substeps 2 --iterations 2"
  "hard|hard grab (C = 0)|--solver procedural,bullet-multibody,bullet-rigid --rule relaxed,xpbd,tree --scenario drag,yank"
  "open-limits|every joint free (models/pinocchio-open-limits.json), dt 1/60 to 1/480|--model models/pinocchio-open-limits.json --solver procedural --rule xpbd,tree --scenario hang,drag,spin --dt 1/60,1/120,1/240,1/480"
  "compliant|compliant grab (C = 1e-4 m/N)|--solver procedural,bullet-multibody,bullet-rigid --rule relaxed,xpbd,tree --scenario drag,yank --grab-compliance 1e-4"
)
manifest="name,label,flags"
for config in "${configs[@]}"; do
  IFS='|' read -r name label flags <<<"$config"
  # the ablation's defaults unless the configuration names its own
  defaults=""
  [[ $flags == *--scenario* ]] || defaults+=" --scenario hang,drag,yank"
  [[ $flags == *--model* ]] || defaults+=" --model pinocchio"
  [[ $flags == *--dt* ]] || defaults+=" --dt 1/240"
  # shellcheck disable=SC2086 # flags are words
  # the first truth alone: the ablation compares configurations (REPORT.md's truth sections
  # give its error bars, from the main run)
  "$testbed" run --no-timing --first-truth-only --sample-hz 1 $defaults $flags "$@" \
    --out "$folder/$name" >/dev/null
  manifest+=$'\n'"\"$name\",\"$label\",\"$flags\""
  echo "ablation: $name"
done
# the yank frontier with the compliant grab, beside the hard one in results/frontier/frontier.csv
"$testbed" frontier --model pinocchio --solver procedural,bullet-multibody,bullet-rigid \
  --rule relaxed,xpbd,tree --grab-compliance 1e-4 --out "$folder/frontier-compliant" >/dev/null
echo "ablation: frontier-compliant"
tmp=$(mktemp "$folder/configs.csv.XXXXXX")
printf '%s\n' "$manifest" >"$tmp"
mv "$tmp" "$folder/configs.csv"
