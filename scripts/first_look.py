#!/usr/bin/env python3
"""The first look (scripts/first_look.sh): what to run, and the table of what ran.

  scripts/first_look.py --choices VERDICT_FOLDER SCENARIO SOLVER[:RULE]...
      one line per solver: the testbed flags of the configuration the committed verdict chose
      for it within 1 cm in that scenario (its dt and its own setting), or dt 1/240 where it chose
      none
  scripts/first_look.py SUMMARY_CSV...
      the table: per run (one scenario at one dt each), its error against the truth, how far its
      joints opened, and its CPU time per simulated second, each column saying what it is
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from report.catalogue import M, MET, PER_SECOND, ST, TRUTH  # noqa: E402
from report.catalogue import VERDICT_CSV as V  # noqa: E402
from report.common import HEADLINE_BUDGET, ReportError, dt_text, label  # noqa: E402
from report.readers import Summary, Verdict  # noqa: E402


def choices(folder, scenario, configs):
    v = Verdict(folder)
    for text in configs:
        solver, _, rule = text.partition(":")
        r = v.row(scenario, (solver, rule), PER_SECOND, HEADLINE_BUDGET)
        flags = [f"--solver {solver}"] + ([f"--rule {rule}"] if rule else [])
        if r and r[V.verdict] == MET:
            flags += [f"--dt {dt_text(r[V.dt])}"] + ([r[V.setting]] if r[V.setting] else [])
        else:
            flags += ["--dt 1/240"]
        print(" ".join(flags))
    return 0


def table(paths):
    rows = []
    scenario = truth = model = None
    for path in paths:
        s = Summary(path)
        if len(s.scenarios) != 1 or len(s.dts) != 1:
            raise ReportError(f"{path}: one scenario at one dt expected")
        if scenario not in (None, s.scenarios[0]):
            raise ReportError(f"{path}: scenario {s.scenarios[0]}, not {scenario}")
        scenario, dt, truth, model = s.scenarios[0], s.dts[0], s.truth_text(), s.model
        for config in s.configs:
            error = s.get(scenario, config, dt, M.pose_err_m, ST.reseeded_mean, TRUTH)
            gap = s.get(scenario, config, dt, M.joint_gap_m, ST.max)
            step = s.get(scenario, config, dt, M.step_us, ST.median)
            rows.append((label(config), dt, error, gap, step / dt if step > 0 else math.nan,
                         s.diverged(scenario, config, dt)))
    cheapest = min((r[4] for r in rows if not math.isnan(r[4])), default=math.nan)
    print(f"{scenario} on {model}, each solver at the step the verdict chose for it within 1 cm, "
          f"against the truth ({truth}):")
    print()
    print(f"  {'solver':<18} {'dt':>7} {'error vs truth':>15} {'joints opened by':>17} "
          f"{'CPU per simulated second':>26}")
    for name, dt, error, gap, cost, diverged in rows:
        if diverged:
            print(f"  {name:<18} {dt_text(dt):>7} {'diverged':>15}")
            continue
        times = f" ({cost / cheapest:.2f}x the cheapest)" if cost > cheapest else ""
        print(f"  {name:<18} {dt_text(dt):>7} {100 * error:>12.2f} cm {1000 * gap:>14.4f} mm "
              f"{cost / 1000:>12.2f} ms{times}")
    print()
    print("The error is the mean distance of the segments from the truth's over half-second runs "
          "restarted from its states (docs/glossary.md). The main job (scripts/main.sh) runs "
          "every scenario and engine this way and finds each one's cheapest setting within 1 cm "
          "over 32 random starts (results/REPORT.md).")
    return 0


def main(argv):
    try:
        if argv and argv[0] == "--choices" and len(argv) >= 4:
            return choices(argv[1], argv[2], argv[3:])
        if argv and not any(a.startswith("-") for a in argv):
            return table(argv)
    except (OSError, ReportError) as error:
        print(f"first_look.py: {error}", file=sys.stderr)
        return 2
    print(__doc__.strip(), file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
