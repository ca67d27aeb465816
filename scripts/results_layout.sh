# shellcheck shell=bash disable=SC2034 # sourced: the names are read by the scripts that source it
# The folders under results/, each written whole by one command: the shell scripts read this
# file (`source scripts/results_layout.sh`) and the report parses it (scripts/report/common.py),
# so that a folder is named once; CMake makes them C++ constants (cmake/results_layout.cmake).
# NAME=folder (or file) lines only.
MAIN=main                            # testbed run: summary.csv and traces/
VERDICT=verdict                      # testbed verdict: verdict.csv, candidates.csv
FRONTIER=frontier                    # testbed frontier: frontier.csv
OPEN_LIMITS=truths-open-limits       # testbed run, Pinocchio with every joint free
HUMANOID=humanoid                    # testbed run on MuJoCo's published humanoid.xml
HUMANOID_VERDICT=humanoid-verdict    # testbed verdict on it: hang, drag, drop and collapse within 1 cm
ABLATION=ablation                    # scripts/ablation.sh: configs.csv, a run per configuration
COMPLIANT_FRONTIER=frontier-compliant  # under ABLATION: the frontier with the compliant grab
ROBUSTNESS=robustness                # scripts/robustness.sh: testbed robustness
PLOTS=plots                          # scripts/plot.py: the plots REPORT.md shows
GATE_THRESHOLDS=gate.json           # benchmarks and the gate: its thresholds (a file)
