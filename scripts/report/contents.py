"""REPORT.md as a table of contents: one module per section (sections/), each with an ID that
`plot.py --section ID` and the docs' generated blocks name, and `lines(r)`, its Markdown lines
from the report's inputs `r`."""
import os
from dataclasses import dataclass, field

from .catalogue import CONFIGS, SCENARIOS
from .common import ReportError, label, write_atomically
from .readers import Summary
from .sections import (ablation, accuracy, contact, findings, frontier, humanoid, joint_gaps,
                       open_limits,
                       plot_list, robustness, time_per_step, title, truth_floor, truths_agree,
                       verdict, verdict_search, what_was_run)

SECTIONS = [title, what_was_run, verdict, contact, verdict_search, truth_floor, truths_agree, accuracy,
            open_limits, joint_gaps, time_per_step, frontier, humanoid, robustness, ablation,
            findings, plot_list]


@dataclass
class Inputs:
    """what every section reads: the main run's summary, the frontier's rows, the plots written
    (title, path) and the results folder"""
    s: Summary
    frontier: list
    plots: list
    folder: str
    dt: float = field(init=False)  # the tables' dt
    truths: list = field(init=False)  # the references the run has truths for
    second: bool = field(init=False)  # whether it has the second truth

    def __post_init__(self):
        self.dt = self.s.table_dt()
        self.truths = self.s.truths()
        self.second = self.s.has_second_truth()

    def unknown_names(self):
        """the summary's scenarios and solvers that the testbed's catalogue does not list"""
        return ([sc for sc in self.s.scenarios if sc not in SCENARIOS]
                + [label(c) for c in self.s.configs if c not in CONFIGS])


def report_lines(r):
    return [line for section in SECTIONS for line in section.lines(r)]


def report(s, frontier, plots, folder):
    text = "\n".join(report_lines(Inputs(s, frontier, plots, folder)))
    write_atomically(os.path.join(folder, "REPORT.md"), text)


def section(s, frontier, folder, ident):
    """One section of the report by its ID, without its heading: docs pages hold it as a
    generated block (scripts/docs_tables.py), the same figures as REPORT.md's"""
    chosen = next((m for m in SECTIONS if m.ID == ident), None)
    if chosen is None:
        known = ", ".join(m.ID for m in SECTIONS)
        raise ReportError(f"the report has no section `{ident}` (its sections: {known})")
    lines = chosen.lines(Inputs(s, frontier, [], folder))
    start = next((i + 1 for i, line in enumerate(lines) if line.startswith("## ")), 0)
    return "\n".join(lines[start:]).strip("\n") + "\n"
