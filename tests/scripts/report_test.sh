#!/usr/bin/env bash
# The main job's pipeline on a small run (a four-link chain, to stay quick under the
# sanitizers) in a temporary folder: testbed run, testbed verdict, testbed frontier,
# then scripts/plot.py, which must write every plot and a REPORT.md with its sections; and
# plot.py's own bad input exits 2.
#   report_test.sh TESTBED SOURCE_DIR
set -euo pipefail
testbed=$1
plot="/usr/bin/python3 $2/scripts/plot.py"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
fail() { echo "report_test: $*" >&2; exit 1; }

"$testbed" run --model chain:4 --scenario drop --solver all --rule literal,relaxed --dt 1/60,1/120 \
  --duration 1 --sample-hz 30 --out "$out/main" >"$out/run.log" 2>&1 || fail "testbed run: $(tail -3 "$out/run.log")"
"$testbed" frontier --model chain:4 --solver procedural --rule literal --out "$out/frontier" >"$out/frontier.log" 2>&1 ||
  fail "testbed frontier: $(tail -3 "$out/frontier.log")"
"$testbed" verdict --model chain:4 --scenario drop --solver procedural,bullet-rigid --rule literal \
  --dt 1/60,1/120 --budget 5cm,50cm --starts 2 --out "$out/verdict" >"$out/verdict.log" 2>&1 ||
  fail "testbed verdict: $(tail -3 "$out/verdict.log")"
$plot "$out" || fail "plot.py failed"

for png in joint_gap error_vs_dt angle_error_vs_dt speed_accuracy stage_time frontier verdict; do
  file="$out/plots/$png.png"
  [ -s "$file" ] || fail "$file missing"
  [ "$(head -c 4 "$file" | tail -c 3)" = "PNG" ] || fail "$file is not a PNG"
  grep -q "(plots/$png.png)" "$out/REPORT.md" || fail "REPORT.md does not show $png.png"
done
for section in "## What was run" "## The verdict" "### Within 50 cm, any dt" "### Within 50 cm at 60 Hz" \
  "## How far the truths can be trusted" "## Accuracy" \
  "## Joint gaps and divergence" "## Time per step" "## Stability frontier" "## Findings"; do
  grep -qF "$section" "$out/REPORT.md" || fail "REPORT.md has no \"$section\""
done
# with MuJoCo in the build, the second truth: its section, and every solver judged against it
if grep -q ',second-truth,' "$out/main/summary.csv"; then
  grep -qF "## Where the truths agree" "$out/REPORT.md" || fail "REPORT.md has no truths' agreement"
  grep -qF "Against the second truth" "$out/REPORT.md" || fail "REPORT.md judges nothing against the second truth"
fi
grep -q "| drop | " "$out/REPORT.md" || fail "REPORT.md has no row for drop"
grep -q "tracks the truth best" "$out/REPORT.md" || fail "REPORT.md names no best rule"

# one section alone (what docs/ holds as a generated block) is the report's own text
$plot --section findings "$out" >"$out/findings.md" || fail "plot.py --section findings failed"
[ -s "$out/findings.md" ] || fail "plot.py --section findings printed nothing"
if grep -vxFf "$out/REPORT.md" "$out/findings.md"; then
  fail "plot.py --section findings printed lines REPORT.md does not have"
fi
set +e
message=$($plot --section "No such section" "$out" 2>&1); status=$?
set -e
[ "$status" -eq 2 ] && [[ "$message" == *"no section"* ]] || fail "an unknown section: status $status, $message"

# a name the testbed's catalogue does not list (an engine or scenario added without regenerating
# results/catalogue.json) is reported and drawn in grey, never dropped
odd="$out/odd"
mkdir -p "$odd"
cp -r "$out/main" "$odd/main"
sed -i 's/^drop,bullet-rigid,/dropped,bullet-rigid-2,/' "$odd/main/summary.csv"
$plot "$odd" >/dev/null || fail "plot.py failed on a name outside the catalogue"
grep -q "Not in the testbed's catalogue.*dropped.*bullet-rigid-2" "$odd/REPORT.md" ||
  fail "REPORT.md does not list the names outside the catalogue"
grep -q "| dropped | " "$odd/REPORT.md" || fail "REPORT.md dropped the scenario outside the catalogue"

# bad input: one message, status 2, nothing written
# refused FOLDER WHAT PATTERN [REPORT]: plot.py on FOLDER exits 2 with a message matching the glob
# PATTERN; with REPORT, it wrote no REPORT.md either
refused() {
  local message status
  set +e
  message=$($plot "$1" 2>&1); status=$?
  set -e
  [ "$status" -eq 2 ] || fail "plot.py on $2: status $status"
  # shellcheck disable=SC2053 # the pattern is a glob
  [[ "$message" == $3 ]] || fail "plot.py on $2 said: $message"
  [ -z "${4:-}" ] || [ ! -e "$1/REPORT.md" ] || fail "plot.py wrote a report from $2"
}
empty=$(mktemp -d "$out/empty.XXXX")
refused "$empty" "an empty folder" "*summary.csv: not found*"
mkdir "$empty/main"
echo "scenario,solver" >"$empty/main/summary.csv"
refused "$empty" "a malformed summary" "*unexpected header*" report
# a CSV whose columns are not the catalogue's for its file (a column renamed in the testbed
# without regenerating results/catalogue.json) is refused by name, and no report is written
renamed="$out/renamed"
mkdir -p "$renamed"
cp -r "$out/main" "$out/frontier" "$renamed/"
sed -i '1s/largest_ok/largest_stable/' "$renamed/frontier/frontier.csv"
refused "$renamed" "a renamed column" "*frontier.csv: its columns are not frontier.csv's*" report
# a value the catalogue does not list for its column (a verdict renamed in the testbed) is
# refused by name too
revalued="$out/revalued"
mkdir -p "$revalued"
cp -r "$out/main" "$out/verdict" "$revalued/"
sed -i '2,$s/,met,/,chosen,/' "$revalued/verdict/verdict.csv"
refused "$revalued" "a verdict outside the catalogue" "*verdict.csv:*verdict 'chosen' is not one of*"
echo "report_test: ok"
