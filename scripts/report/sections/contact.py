"""The report's section `contact`: the scenes on the ground, as the verdict judges them."""
import math
import os

from ..catalogue import CANDIDATES_CSV as C
from ..catalogue import CONTACT_CSV as K
from ..common import VERDICT, dt_text, fmt, label, md_table
from ..readers import read_table, read_verdict

ID = "contact"

VIOLATIONS = ["penetration", "joint_gap", "limit_overshoot", "energy_gain"]
VIOLATION_TEXT = {"penetration": "penetration", "joint_gap": "joint gap",
                  "limit_overshoot": "limit overshoot", "energy_gain": "energy gained"}


def value(rows, scenario, role, measure, stat):
    for r in rows:
        if (r[K.scenario], r[K.truth_role], r[K.measure], r[K.stat]) == (scenario, role, measure,
                                                                         stat):
            return float(r[K.value]) if r[K.value] else math.nan
    return math.nan


def lines(r):
    path = os.path.join(r.folder, VERDICT, "contact.csv")
    v = read_verdict(r.folder)
    if v is None or not os.path.exists(path):
        return []
    rows = read_table(path, "contact.csv")
    scenes = [sc for sc in v.scenarios if any(x[K.scenario] == sc for x in rows)]
    if not scenes:
        return []
    solvers = {x[K.truth_role]: x[K.solver] for x in rows if x[K.solver]}
    roles = [role for role in ("truth", "second") if role in solvers]
    outcomes = sorted({x[K.measure] for x in rows if x[K.stat] == "ks_critical"},
                      key=lambda m: [x[K.measure] for x in rows].index(m))
    out = ["## The scenes on the ground", "",
           "`" + "`, `".join(scenes) + "` are judged by contact, not by their trajectory "
           "(docs/verdict.md, \"Contact scenes\"): a configuration's error is the largest of its "
           "violations (each a length) and its mean pose error up to 1/30 s past the truth's "
           "first contact, and the configuration chosen must also end its random starts like "
           "the truth, by the two-sample Kolmogorov–Smirnov test of each outcome against a bar, "
           "the larger of the test's critical value and the two truths' own statistic. From "
           f"`{VERDICT}/contact.csv`: what the truths give.", ""]
    header = ["scenario", "first contact (s)", "window ends (s)", "window floor (m)"]
    header += [f"{VIOLATION_TEXT[m]} (m): " + " / ".join(solvers[x] for x in roles)
               for m in VIOLATIONS]
    table = []
    for sc in scenes:
        row = [sc, fmt(value(rows, sc, "truth", "first_contact", "value")),
               fmt(value(rows, sc, "truth", "window_end", "value")),
               fmt(value(rows, sc, "truth", "window_error", "floor"))]
        row += [" / ".join(fmt(value(rows, sc, role, m, "max")) for role in roles)
                for m in VIOLATIONS]
        table.append(row)
    out += [md_table(header, table), ""]
    header = ["scenario", "outcome"] + [f"{solvers[x]}: median [min, max]" for x in roles]
    header += ["KS between the truths", "critical value"]
    table = []
    for sc in scenes:
        for m in outcomes:
            row = [sc, m]
            for role in roles:
                row.append(f"{fmt(value(rows, sc, role, m, 'median'))} "
                           f"[{fmt(value(rows, sc, role, m, 'min'))}, "
                           f"{fmt(value(rows, sc, role, m, 'max'))}]")
            row += [fmt(value(rows, sc, "second", m, "ks_statistic"), 2),
                    fmt(value(rows, sc, "truth", m, "ks_critical"), 2)]
            table.append(row)
    out += [f"The outcomes over the {v.starts} random starts (m; time to rest in s):", "",
            md_table(header, table), ""]
    # each configuration's least error there and what set it
    header = ["solver"] + scenes
    table = []
    for config in v.configs:
        row = [label(config)]
        for sc in scenes:
            mine = [c for c in v.candidates if c["config"] == config and c[C.scenario] == sc
                    and not math.isnan(c[C.error_m])]
            if not mine:
                row.append("diverges")
                continue
            best = min(mine, key=lambda c: c[C.error_m])
            row.append(f"{fmt(best[C.error_m])} ({best[C.measure]}, {dt_text(best[C.dt])} s)")
        table.append(row)
    out += ["Each solver's least error in them (m), what set it and at which dt:", "",
            md_table(header, table), ""]
    return out
