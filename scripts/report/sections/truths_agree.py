"""The report's section `truths-agree`: the two truths against each other."""

from ..catalogue import CONSTRAINTS, M, SECOND_TRUTH, ST, TRUTHS
from ..common import OPEN_LIMITS, fmt, md_table
from .open_limits import open_limits_agreement


ID = "truths-agree"


def lines(r):
    s = r.s
    folder = r.folder
    second = r.second
    out = []
    if second:
        pin_rows = any(k[3] == M.pin_gap_m and k[5] in TRUTHS and k[2] not in s.dts
                       for k in s.values)
        rows = []
        for sc in s.scenarios:
            rows.append([sc] + [fmt(s.truths_agreement(sc, stat)) for stat in
                                (ST("at_0.267s"), ST("at_1s"), ST("mean_1s"),
                                 ST.reseeded_mean)] +
                        [fmt(s.truths_agreement(sc, ST.reseeded_mean, SECOND_TRUTH)),
                         fmt(s.truths_agreement(sc, ST.reseeded_mean,
                                                metric=M.joint_angle_err_deg)),
                         fmt(s.truths_agreement(sc, ST.max, SECOND_TRUTH,
                                                M.limit_violation_deg), 2),
                         fmt(s.truths_agreement(sc, ST.max, metric=M.limit_violation_deg), 2)] +
                        ([fmt(s.truths_agreement(sc, ST.max, SECOND_TRUTH, M.pin_gap_m)),
                          fmt(s.truths_agreement(sc, ST.max, metric=M.pin_gap_m))]
                         if pin_rows else []) +
                        [open_limits_agreement(folder, sc)])
        out += ["## Where the truths agree", "",
                f"The second truth ({s.truth_text(SECOND_TRUTH)}) against the truth "
                f"({s.truth_text()}), pose error (m): along the whole run, and re-seeded both "
                "ways (the second from the truth's states against it, the truth from the "
                "second's against it). The last column is the same re-seeded figure for "
                f"Pinocchio with every joint free (`{OPEN_LIMITS}/`), where the engines "
                "differ only in their pins, contacts and solvers.", "",
                md_table(["scenario", "at 0.267 s", "at 1 s", "mean 1 s", "re-seeded",
                          "re-seeded (other way)", "re-seeded angle deg",
                          "truth out of limits, deg", "second truth out of limits, deg"] +
                         (["truth pin gap m", "second truth pin gap m"] if pin_rows else []) +
                         ["re-seeded, limits opened"], rows), "",
                "Pin gap: the largest distance of a pinned point from its target along each "
                "truth." if pin_rows else "",
                "Out of limits: the largest violation of the model's limits (as the metrics "
                "measure them) along each truth.", "",
                "What differs between the engines (docs/mujoco.md): both hang the tree from a "
                "still pin, which then holds exactly. "
                + " ".join(f"In {solver}, {CONSTRAINTS.get(solver, 'not in the catalogue')}."
                           for solver in (s.truth_engine(ref)[0] for ref in TRUTHS)), ""]
    return out
