"""The report's section `joint-gaps`: the largest joint gaps, and every diverged run."""

from ..catalogue import M, ST
from ..common import dt_text, fmt, label, md_table


ID = "joint-gaps"


def lines(r):
    s = r.s
    dt = r.dt
    out = []
    # constraints and divergence
    def gap_cell(sc, c, d):
        v = s.get(sc, c, d, M.joint_gap_m, ST.max)
        return fmt(v) + (" †" if s.diverged(sc, c, d) else "")

    out += ["## Joint gaps and divergence", "",
            f"Max joint gap (m), dt = {dt_text(dt)} s (†: diverged, the max is up to then):", "",
            md_table(["scenario"] + [label(c) for c in s.configs],
                     [[sc] + [gap_cell(sc, c, dt) for c in s.configs] for sc in s.scenarios]), ""]
    rows = []
    for c in s.configs:
        cells = []
        for sc in s.scenarios:
            failed = [d for d in s.dts if s.diverged(sc, c, d)]
            if failed:
                times = ", ".join(f"{dt_text(d)}@{fmt(s.get(sc, c, d, M.diverged_at_s, ST.value))}s"
                                  for d in failed)
                cells.append(f"{sc}: {times}")
        rows.append([label(c), "; ".join(cells) if cells else "none"])
    out += ["Diverged runs over the whole sweep (dt@time):", "",
            md_table(["solver", "diverged"], rows), ""]
    return out
