#!/usr/bin/env bash
# What each ingredient of the position-based rules costs or buys, at dt = 1/240 on Pinocchio:
# the one-sided closure (relaxed), Gauss–Seidel sweeps against the exact projection (xpbd,
# tree), substeps against iterations, the lever arms of the substep's start against the corrected
# pose's (xpbd), the limits as functions against the clamp and their place in the sweep (xpbd),
# the limits' velocity pass (xpbd, tree), and a hard grab against a compliant one (every
# solver).
# Each configuration is one `testbed run` into FOLDER/<name>; FOLDER/configs.csv names them, and
# scripts/plot.py turns them into REPORT.md's ablation tables. Further arguments go to every
# `testbed run` (main.sh passes its --truth-cache: the configurations on Pinocchio's default
# scenarios then read the main run's truth instead of computing it again).
#
#   scripts/ablation.sh FOLDER [TESTBED RUN FLAGS...]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_layout.sh
folder=${1:?usage: scripts/ablation.sh FOLDER [TESTBED RUN FLAGS...]}
shift
testbed=./build/release/testbed
mkdir -p "$folder"
# name, what it isolates, the configuration it is read against (the one it changes one thing
# of), flags. The compliant grab is C = 1e-4 m/N (10 kN/m): Pinocchio (69.6 kg) hanging from it
# alone, as in yank, stretches it by 7 cm; Ten Minute Physics' 0.01 m/N is for light bodies and
# would let this one hang 7 m below the hand
configs=(
  "relaxed|4 sweeps, then the one-sided closure||--solver procedural --rule relaxed"
  "relaxed-64|64 sweeps, then the one-sided closure|relaxed|--solver procedural --rule relaxed --iterations 64"
  "xpbd|8 substeps x 1 sweep||--solver procedural --rule xpbd"
  "xpbd-iterations|1 substep x 8 sweeps|xpbd|--solver procedural --rule xpbd --substeps 1 --iterations 8"
  "xpbd-current-arms|lever arms of the pose being corrected (PBD's own)|xpbd|--solver procedural --rule xpbd --current-lever-arms"
  "xpbd-no-limit-pass|no limits' velocity pass|xpbd|--solver procedural --rule xpbd --no-limit-pass"
  "xpbd-limit-clamp|ball limits by the clamp, not their functions|xpbd|--solver procedural --rule xpbd --limit-clamp"
  "xpbd-joints-first|joints before limits in a sweep|xpbd|--solver procedural --rule xpbd --joints-before-limits"
  "tree|8 substeps x 1 exact solve|xpbd|--solver procedural --rule tree"
  "tree-iterations|1 substep x 8 Newton iterations|tree|--solver procedural --rule tree --substeps 1 --iterations 8"
  "tree-2x2|2 substeps x 2 Newton iterations|tree|--solver procedural --rule tree --substeps 2 --iterations 2"
  "tree-no-limit-pass|no limits' velocity pass|tree|--solver procedural --rule tree --no-limit-pass"
  "hard|hard grab (C = 0)||--solver procedural,bullet-multibody,bullet-rigid --rule relaxed,xpbd,tree --scenario marionette,yank"
  "open-limits|every joint free (models/pinocchio-open-limits.json), dt 1/60 to 1/480||--model models/pinocchio-open-limits.json --solver procedural --rule xpbd,tree --scenario hang,drag,spin --dt 1/60,1/120,1/240,1/480"
  "compliant|compliant grab (C = 1e-4 m/N)|hard|--solver procedural,bullet-multibody,bullet-rigid --rule relaxed,xpbd,tree --scenario marionette,yank --grab-compliance 1e-4"
)
manifest="name,label,against,flags"
for config in "${configs[@]}"; do
  IFS='|' read -r name label against flags <<<"$config"
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
  manifest+=$'\n'"\"$name\",\"$label\",\"$against\",\"$flags\""
  echo "ablation: $name"
done
# the yank frontier with the compliant grab, beside the hard one in results/$FRONTIER/frontier.csv
"$testbed" frontier --model pinocchio --solver procedural,bullet-multibody,bullet-rigid \
  --rule relaxed,xpbd,tree --grab-compliance 1e-4 --out "$folder/$COMPLIANT_FRONTIER" >/dev/null
echo "ablation: $COMPLIANT_FRONTIER"
tmp=$(mktemp "$folder/configs.csv.XXXXXX")
printf '%s\n' "$manifest" >"$tmp"
mv "$tmp" "$folder/configs.csv"
