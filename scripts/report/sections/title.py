"""The report's section `title`: the title, and what the report was generated from."""
from datetime import datetime, timezone

from ..catalogue import REFERENCE_ENGINES
from ..common import FRONTIER, MAIN, and_list


ID = "title"


def lines(r):
    s = r.s
    frontier = r.frontier
    out = []
    now = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    out = [f"# Report: the procedural solver against {and_list(REFERENCE_ENGINES)}", ""]
    out += [f"Generated {now} by `scripts/plot.py` from `{MAIN}/summary.csv`"
            f"{f' and `{FRONTIER}/frontier.csv`' if frontier else ''} (commit `{s.git_sha}`, "
            f"model `{s.model}`, machine: {s.machine}). Every number below is read from those "
            "files; `testbed run` and `testbed frontier` regenerate them.", ""]
    return out
