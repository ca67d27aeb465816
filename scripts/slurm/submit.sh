#!/bin/bash
# Submits a testbed robustness sweep to Slurm as N array tasks and a merge that runs when all of
# them succeeded; prints the two job ids. The merged results land in OUT/merged.
#
#   scripts/slurm/submit.sh OUT N [testbed robustness flags...]
set -euo pipefail
cd "$(dirname "$0")/../.."
if [ $# -lt 2 ] || ! [[ $2 =~ ^[1-9][0-9]*$ ]]; then
  echo "usage: scripts/slurm/submit.sh OUT N [testbed robustness flags...]" >&2
  exit 2
fi
out=$1
count=$2
shift 2
mkdir -p "$out"
array=$(sbatch --parsable --array=0-$((count - 1)) --output="$out/slurm-%A_%a.out" \
  scripts/slurm/robustness.sbatch "$out" "$@")
array=${array%%;*}  # sbatch --parsable prints id[;cluster]
merge=$(sbatch --parsable --dependency=afterok:"$array" --output="$out/slurm-%j.out" \
  scripts/slurm/merge.sbatch "$out" "$count")
echo "array job $array ($count shards), merge job ${merge%%;*}: results in $out/merged"
