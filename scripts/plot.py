#!/usr/bin/python3
"""Plots and REPORT.md from the testbed's CSV files, and nothing else (the package report/:
its catalogue of names, readers, plots, and one module per section of the report).

    scripts/plot.py [RESULTS]            (default: results/)
    scripts/plot.py --section ID [RESULTS]      (one section of the report, to stdout, by its
                                                 ID: report/contents.py lists them)

reads RESULTS/main/summary.csv and RESULTS/main/traces/*.csv (testbed run --out RESULTS/main),
RESULTS/frontier/frontier.csv (testbed frontier, optional) and the optional folders beside them
(truths-open-limits, humanoid, robustness, ablation), and writes RESULTS/plots/*.png and RESULTS/REPORT.md. It runs on the distribution's python3 and
python3-matplotlib (hence /usr/bin/python3, not whatever python3 comes first on PATH).
"""

import os
import sys

from report.common import FRONTIER, MAIN, PLOTS, ReportError
from report.contents import report, section
from report.plots import (plot_error_vs_dt, plot_frontier, plot_joint_gap, plot_robustness,
                          plot_speed_accuracy, plot_stage_time, plot_verdict)
from report.readers import Summary, read_frontier, read_robustness, read_verdict


def main(argv):
    ident = None
    if len(argv) >= 3 and argv[1] == "--section":
        ident = argv[2]
        argv = argv[:1] + argv[3:]
    if len(argv) > 2 or (len(argv) == 2 and argv[1].startswith("-")):
        print(__doc__.strip(), file=sys.stderr)
        return 2
    folder = argv[1] if len(argv) == 2 else "results"
    summary_path = os.path.join(folder, MAIN, "summary.csv")
    if not os.path.exists(summary_path):
        print(f"plot.py: {summary_path}: not found (run testbed run first)", file=sys.stderr)
        return 2
    try:
        s = Summary(summary_path)
        frontier = read_frontier(os.path.join(folder, FRONTIER, "frontier.csv"))
        read_robustness(folder)  # checked here; the report reads it again
        read_verdict(folder)
    except (ReportError, ValueError, KeyError) as error:
        print(f"plot.py: {error}", file=sys.stderr)
        return 2
    if ident is not None:
        try:
            sys.stdout.write(section(s, frontier, folder, ident))
        except ReportError as error:
            print(f"plot.py: {error}", file=sys.stderr)
            return 2
        return 0
    out = os.path.join(folder, PLOTS)
    os.makedirs(out, exist_ok=True)
    plots = [
        ("Joint gap over time", plot_joint_gap(s, folder, out)),
        ("Re-seeded pose error against dt",
         plot_error_vs_dt(s, out, "pose_err_m", "m", "error_vs_dt.png")),
        ("Re-seeded joint-angle error against dt",
         plot_error_vs_dt(s, out, "joint_angle_err_deg", "deg", "angle_error_vs_dt.png")),
        ("Speed against accuracy", plot_speed_accuracy(s, out)),
        ("Procedural stages", plot_stage_time(s, out)),
        ("Stability frontier", plot_frontier(frontier, out)),
        ("Robustness over random starts", plot_robustness(read_robustness(folder), out)),
        ("Cost against error budget", plot_verdict(read_verdict(folder), out)),
    ]
    report(s, frontier, plots, folder)
    written = [p for _, p in plots if p]
    print(f"wrote {os.path.join(folder, 'REPORT.md')} and {len(written)} plots under {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
