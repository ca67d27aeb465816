#!/usr/bin/env python3
"""Prints the README's headline table and nothing else.

  scripts/readme_headline.py [results]                   the verdict: CPU µs per simulated
                                                         second within 1 cm, from
                                                         results/verdict/verdict.csv
  scripts/readme_headline.py --per-step results/main/summary.csv
                                                         µs per step at one dt (docs/performance.md)

The README and docs/performance.md hold them as generated blocks that scripts/docs_tables.py
rewrites (and checks).
"""
import math
import os
import sys

from report.catalogue import HEADLINE, M, PAIRWISE_CONFIG, PAIRWISE_SOLVER, SCENARIOS, ST, TRUTH
from report.common import MAIN, VERDICT, fmt, label
from report.readers import Summary
from report.sections.verdict import verdict_headline

def headline(summary_path):
    s = Summary(summary_path)
    dt = s.table_dt()
    scenarios = [x for x in SCENARIOS if x in s.scenarios]

    def step_us(config):
        times = [s.get(x, config, dt, M.step_us, ST.median) for x in scenarios]
        times = [t for t in times if not math.isnan(t) and t > 0]
        return math.exp(sum(math.log(t) for t in times) / len(times)) if times else math.nan

    base = step_us(PAIRWISE_CONFIG)
    limit = s.truth_limit(HEADLINE)
    lines = [
        f"| solver | µs per step (geometric mean of the {len(scenarios)} scenarios) "
        f"| × {PAIRWISE_SOLVER}'s speed | scenarios diverged (of {len(scenarios)}) "
        f"| re-seeded pose error in `{HEADLINE}`, m |",
        "|---|---|---|---|---|",
    ]
    for config in s.configs:
        t = step_us(config)
        diverged = sum(1 for x in scenarios if s.diverged(x, config, dt))
        err = s.get(HEADLINE, config, dt, M.pose_err_m, ST.reseeded_mean, TRUTH)
        err_text = f"≤ {fmt(limit)}" if err < limit else fmt(err)
        lines.append(f"| {label(config)} | {fmt(t)} | {fmt(base / t)} | {diverged} | {err_text} |")
    return (f"At dt = 1/{round(1 / dt)} s on {s.model}, from `results/{MAIN}/summary.csv` (commit "
            f"`{s.git_sha}`, {s.machine}), printed by `scripts/readme_headline.py`. The error is "
            f"against the fine-step truth ({s.truth_text()}), the mean over the "
            "re-seeded half-second runs; errors within the truth's floor (its error bar, or "
            f"the two truths' disagreement) read `≤ {fmt(limit)}`. The full tables are in "
            "results/REPORT.md.\n\n"
            + "\n".join(lines) + "\n")


def main(argv):
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    if argv and argv[0] == "--per-step" and len(argv) <= 2:
        summary = argv[1] if len(argv) == 2 else os.path.join(root, "results", MAIN,
                                                              "summary.csv")
        sys.stdout.write(headline(summary))
        return 0
    if len(argv) > 1 or (argv and argv[0].startswith("-")):
        print(__doc__.strip(), file=sys.stderr)
        return 2
    folder = argv[0] if argv else os.path.join(root, "results")
    path = os.path.join(folder, VERDICT, "verdict.csv")
    if not os.path.isfile(path):
        print(f"readme_headline.py: {path}: not found (testbed verdict writes it)", file=sys.stderr)
        return 2
    sys.stdout.write(verdict_headline(folder))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
