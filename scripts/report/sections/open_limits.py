"""The report's section `open-limits`: both truths with every joint free."""
import math
import os

from ..catalogue import M, SECOND_TRUTH, ST, TRUTH, TRUTHS
from ..common import OPEN_LIMITS, dt_text, fmt, label, md_table
from ..readers import Summary


def open_limits_agreement(folder, scenario):
    """the truths' re-seeded agreement for Pinocchio with its limits opened (main.sh)"""
    path = os.path.join(folder, OPEN_LIMITS, "summary.csv")
    if not os.path.exists(path):
        return "–"
    return fmt(Summary(path).truths_agreement(scenario, ST.reseeded_mean))


def open_limits_section(folder):
    """every solver against both truths for Pinocchio with its limits opened (main.sh)"""
    path = os.path.join(folder, OPEN_LIMITS, "summary.csv")
    if not os.path.exists(path):
        return []
    o = Summary(path)
    if not o.has_second_truth():
        return []
    dt = o.table_dt()

    def cell(sc, c):
        a = o.get(sc, c, dt, M.pose_err_m, ST.reseeded_mean, TRUTH)
        b = o.get(sc, c, dt, M.pose_err_m, ST.reseeded_mean, SECOND_TRUTH)
        if math.isnan(a) and math.isnan(b):
            return "div" if o.diverged(sc, c, dt) else "–"
        return f"{fmt(a)} / {fmt(b)}" + (" †" if o.diverged(sc, c, dt) else "")

    pins = any(k[3] == M.pin_gap_m and k[5] in TRUTHS for k in o.values)
    rows = [[sc] + [fmt(o.truth_bar(sc)), fmt(o.truth_bar(sc, SECOND_TRUTH)),
                    fmt(o.truths_agreement(sc, ST.reseeded_mean))] +
            ([fmt(o.truths_agreement(sc, stat, against, M.pin_gap_m))
              for against in (SECOND_TRUTH, TRUTH) for stat in (ST.max, ST.rms)]
             if pins else []) for sc in o.scenarios]
    return ["## Both truths, limits opened", "",
            f"`{OPEN_LIMITS}/`: `{o.model}` (every joint free), where the two engines "
            "model the same bodies and joints and differ only in their pins, contacts and "
            "solvers: the truth is "
            f"{o.truth_text()}, the second truth {o.truth_text(SECOND_TRUTH)}. Each truth's error "
            "bar and their agreement (re-seeded pose error, m)"
            + ("; and how far each truth lets its pinned points from their targets (max and RMS "
               "over the samples, m): where the agreement is far above both truths' error bars, "
               "the truth whose pins give is the one to doubt" if pins else "") + ":", "",
            md_table(["scenario", "truth's bar", "second truth's bar", "truths' agreement"] +
                     (["truth pin gap max", "rms", "second truth pin gap max", "rms"]
                      if pins else []), rows),
            "", f"Every solver against both truths: re-seeded pose error (m), truth / "
            f"second truth, dt = {dt_text(dt)} s (†: the full run diverged):", "",
            md_table(["scenario"] + [label(c) for c in o.configs],
                     [[sc] + [cell(sc, c) for c in o.configs] for sc in o.scenarios]), ""]


ID = "open-limits"


def lines(r):
    return open_limits_section(r.folder)
