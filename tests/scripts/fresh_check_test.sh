#!/usr/bin/env bash
# The bare-machine check reads the README's quick start: exactly two commands, each an executable
# script of the project, and the second one the test command CI runs verbatim (as a timed stage).
set -euo pipefail
source_dir=$1
mapfile -t commands < <("$source_dir/scripts/fresh_check.sh" --print-readme)
[ ${#commands[@]} -eq 2 ] || { echo "expected 2 quick-start commands, got ${#commands[@]}"; exit 1; }
for cmd in "${commands[@]}"; do
  program=${cmd%% *}
  [ -x "$source_dir/$program" ] || { echo "quick-start command not an executable: $cmd"; exit 1; }
done
# a line of .ci/run, verbatim or timed as a stage ("stage scripts/test.sh")
grep -qxE "(stage )?${commands[1]}" "$source_dir/.ci/run" ||
  { echo ".ci/run does not run the README's test command: ${commands[1]}"; exit 1; }
grep -qxE '(stage )?scripts/fresh_check.sh --readme' "$source_dir/.ci/run" ||
  { echo ".ci/run does not run the bare-machine check"; exit 1; }
# a README whose quick start lost a command is refused
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
mkdir -p "$scratch/scripts"
cp "$source_dir/scripts/fresh_check.sh" "$scratch/scripts/"
sed '/^scripts\/test.sh/d' "$source_dir/README.md" >"$scratch/README.md"
if SRC=$scratch "$scratch/scripts/fresh_check.sh" --print-readme >"$scratch/out" 2>&1; then
  echo "a quick start with one command was accepted"; exit 1
fi
grep -q "has 1 commands, expected 2" "$scratch/out" || { cat "$scratch/out"; exit 1; }
echo "quick start: ${commands[*]}"
