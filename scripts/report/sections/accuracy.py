"""The report's section `accuracy`: every solver's re-seeded error against the truths, pairwise,
and against dt."""
import math

from ..catalogue import (M, PAIRWISE, PAIRWISE_CONFIG, PAIRWISE_SOLVER, SECOND_TRUTH, ST, TRUTH,
                         TRUTHS)
from ..common import dt_text, fmt, geometric_mean, label, md_table


ID = "accuracy"


def lines(r):
    s = r.s
    dt = r.dt
    second = r.second
    out = []

    def accuracy_cell(sc, config, d, metric=M.pose_err_m, reference=TRUTH):
        v = s.get(sc, config, d, metric, ST.reseeded_mean, reference)
        if math.isnan(v):
            return "div" if s.diverged(sc, config, d) else "–"
        cell = fmt(v)
        if reference in TRUTHS and metric == M.pose_err_m:
            limit = s.truth_limit(sc, reference)
            if v < limit:
                cell = f"≤ {fmt(limit)}"
        seeds = s.get(sc, config, d, M.reseeded_diverged, ST.count, reference)
        if seeds > 0:
            cell += f" ({int(seeds)}/8 div)"
        if s.diverged(sc, config, d):
            cell += " †"
        return cell

    out += ["## Accuracy", "",
            f"Re-seeded pose error against the truth (m), dt = {dt_text(dt)} s. `(k/8 div)`: k "
            "of the 8 re-seeded runs diverged and the mean is over the others; †: the full run "
            "diverged.", "",
            md_table(["scenario"] + [label(c) for c in s.configs],
                     [[sc] + [accuracy_cell(sc, c, dt) for c in s.configs] for sc in s.scenarios]),
            "", "The same, as joint-angle error (deg):", "",
            md_table(["scenario"] + [label(c) for c in s.configs],
                     [[sc] + [accuracy_cell(sc, c, dt, M.joint_angle_err_deg) for c in s.configs]
                      for sc in s.scenarios]), ""]
    if second:
        out += [f"Against the second truth ({s.truth_text(SECOND_TRUTH)}): re-seeded pose error (m), "
                f"dt = {dt_text(dt)} s:", "",
                md_table(["scenario"] + [label(c) for c in s.configs],
                         [[sc] + [accuracy_cell(sc, c, dt, reference=SECOND_TRUTH)
                                  for c in s.configs] for sc in s.scenarios]), ""]
    pair_configs = [c for c in s.configs if c != PAIRWISE_CONFIG]
    if any(not math.isnan(s.get(sc, c, dt, M.pose_err_m, ST.reseeded_mean, PAIRWISE))
           for sc in s.scenarios for c in pair_configs):
        out += [f"Pairwise: re-seeded pose error against {PAIRWISE_SOLVER} at the same dt (m):",
                "",
                md_table(["scenario"] + [label(c) for c in pair_configs],
                         [[sc] + [accuracy_cell(sc, c, dt, reference=PAIRWISE)
                                  for c in pair_configs] for sc in s.scenarios]), ""]
    out += ["Against dt (re-seeded pose error, m, geometric mean over the scenarios each solver "
            "finished at every dt):", ""]
    rows = []
    for c in s.configs:
        row = [label(c)]
        for d in s.dts:
            row.append(fmt(geometric_mean([s.get(sc, c, d, M.pose_err_m, ST.reseeded_mean,
                                                 TRUTH) for sc in s.scenarios])))
        rows.append(row)
    out += [md_table(["solver"] + [dt_text(d) for d in s.dts], rows), ""]
    return out
