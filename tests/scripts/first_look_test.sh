#!/usr/bin/env bash
# The first look (scripts/first_look.py): the configurations it runs, read from the committed
# verdict (xpbd and ode in drag: each one's dt as a fraction, the truth's step dividing it, and
# its own setting), and its table on two short runs of drag: one row per solver with its dt, its
# error in cm, its joint gap in mm and its CPU time per simulated second; a run of two dts is
# refused (exit 2, one line), as is a missing file.
#   first_look_test.sh TESTBED SOURCE_DIR
set -euo pipefail
testbed=$1
look="/usr/bin/python3 $2/scripts/first_look.py"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "first_look_test: $*" >&2; exit 1; }

$look --choices "$2/results" drag procedural:xpbd ode >"$out/choices.txt" || fail "--choices failed"
[ "$(wc -l <"$out/choices.txt")" -eq 2 ] || fail "--choices: $(cat "$out/choices.txt")"
grep -Eq "^--solver procedural --rule xpbd --dt 1/[0-9]+" "$out/choices.txt" ||
  fail "--choices: no xpbd line: $(cat "$out/choices.txt")"
grep -Eq "^--solver ode --dt 1/[0-9]+" "$out/choices.txt" || fail "--choices: no ode line"

"$testbed" run --model chain:4 --scenario drag --solver procedural --rule xpbd \
  --dt 1/120 --duration 0.5 --first-truth-only --out "$out/one" >"$out/run.log" 2>&1 ||
  fail "testbed run: $(tail -3 "$out/run.log")"
"$testbed" run --model chain:4 --scenario drag --solver bullet-rigid \
  --dt 1/240 --duration 0.5 --first-truth-only --out "$out/other" >"$out/run.log" 2>&1 ||
  fail "testbed run: $(tail -3 "$out/run.log")"
$look "$out/one/summary.csv" "$out/other/summary.csv" >"$out/table.txt" || fail "first_look.py failed"
grep -q "^drag on chain" "$out/table.txt" || fail "no title: $(head -1 "$out/table.txt")"
grep -q "against the truth (MuJoCo" "$out/table.txt" || fail "no truth: $(head -1 "$out/table.txt")"
for row in "procedural xpbd +1/120" "bullet-rigid +1/240"; do
  grep -Eq "^  $row +[0-9.]+ cm +[0-9.]+ mm +[0-9.]+ ms" "$out/table.txt" ||
    fail "no row $row: $(cat "$out/table.txt")"
done

"$testbed" run --model chain:4 --scenario drag --solver procedural --rule xpbd --dt 1/120,1/60 \
  --duration 0.25 --first-truth-only --no-timing --out "$out/two" >"$out/run2.log" 2>&1 ||
  fail "testbed run (two dts): $(tail -3 "$out/run2.log")"
set +e
$look "$out/two/summary.csv" >/dev/null 2>"$out/err.txt"
status=$?
$look "$out/missing.csv" >/dev/null 2>"$out/err2.txt"
status2=$?
set -e
[ "$status" -eq 2 ] || fail "two dts: exit $status, not 2"
[ "$(wc -l <"$out/err.txt")" -eq 1 ] || fail "two dts: not one line: $(cat "$out/err.txt")"
grep -q "one scenario at one dt expected" "$out/err.txt" || fail "two dts: $(cat "$out/err.txt")"
[ "$status2" -eq 2 ] || fail "a missing file: exit $status2, not 2"
[ "$(wc -l <"$out/err2.txt")" -eq 1 ] || fail "a missing file: not one line: $(cat "$out/err2.txt")"
echo "first_look_test: the table and its refusals"
