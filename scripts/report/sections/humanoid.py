"""The report's section `humanoid`: the scenarios on the humanoid model."""
import math
import os

from ..catalogue import M, PER_SECOND, SECOND_TRUTH, ST, TRUTH
from ..common import HUMANOID, HUMANOID_VERDICT, budget_name, dt_text, fmt, label, md_table
from ..readers import Summary, Verdict
from .verdict import refused_text, verdict_table


def humanoid_verdict(folder):
    """its verdict (main.sh: hang, drag, drop and collapse within 1 cm), as the verdict section's
    table"""
    if not os.path.exists(os.path.join(folder, HUMANOID_VERDICT, "verdict.csv")):
        return []
    v = Verdict(folder, HUMANOID_VERDICT)
    out = []
    for budget in v.budgets:
        table, refused = verdict_table(v, PER_SECOND, budget)
        out += [f"Its verdict within {budget_name(budget)} (`{HUMANOID_VERDICT}/verdict.csv`, "
                f"{v.starts} random starts, judged against {v.truth} as Pinocchio's is): CPU µs "
                "per simulated second of the cheapest configuration each solver has; in "
                "brackets, how many times cheaper than the cheapest reference engine.", "",
                table, ""]
        if refused_text(v, refused):
            out += [refused_text(v, refused), ""]
    contact = [sc for sc in v.scenarios if sc in ("drop", "collapse")]
    if contact:
        out += [f"In {' and '.join(contact)} the error is the contact judge's, as Pinocchio's is "
                "(\"The scenes on the ground\"): the largest violation or the first impact's "
                "error, and the random starts must end like the truth's; `unlike truth` when no "
                "configuration's do. What the truth gives there is in "
                f"`{HUMANOID_VERDICT}/contact.csv`.", ""]
    return out


def humanoid_section(folder):
    """the main scenarios on MuJoCo's published humanoid.xml in every solver that runs it
    (main.sh)"""
    path = os.path.join(folder, HUMANOID, "summary.csv")
    if not os.path.exists(path):
        return []
    h = Summary(path)
    dt = h.table_dt()
    second = h.has_second_truth()

    def cell(sc, c):
        if (sc, c, dt) not in h.status:
            return "–"
        if h.diverged(sc, c, dt):
            return f"div@{fmt(h.get(sc, c, dt, M.diverged_at_s, ST.value))}s"
        parts = [fmt(h.get(sc, c, dt, M.pose_err_m, ST.reseeded_mean, TRUTH))]
        if second:
            parts.append(fmt(h.get(sc, c, dt, M.pose_err_m, ST.reseeded_mean, SECOND_TRUTH)))
        return " / ".join(parts) + f", gap {fmt(h.get(sc, c, dt, M.joint_gap_m, ST.max))}"

    out = ["## A published character: MuJoCo's humanoid", "",
           f"`{HUMANOID}/`: the scenarios on `{h.model}`, MuJoCo 2.2.2's `humanoid.xml` read "
           "unchanged (Debian's libmujoco-samples; `testbed validate` reads dm_control's "
           "humanoid the same but for the left hip's third range, 110° here and 120° there): "
           "joint springs, dampers and armature, hips of three hinges, ankles of two hinges 4 cm "
           "apart. It runs in every solver that builds it (" +
           ", ".join(label(c) for c in h.configs) + "); the others refuse its ankles in one line "
           "(docs/mjcf.md). The truth is MuJoCo itself, which builds the joints' armature "
           "exactly; the procedural rules add it to each child's inertia instead, a stand-in "
           "whose error (docs/model-format.md measures it) is part of theirs here. dt = " + dt_text(dt) + " s. Each cell: re-seeded pose "
           "error against the truth" + (" / against the second truth" if second else "") +
           " (m), and the largest joint gap (m); `div@t`: the run diverged at t.", "",
           md_table(["scenario"] + [label(c) for c in h.configs],
                    [[sc] + [cell(sc, c) for c in h.configs] for sc in h.scenarios]), ""]
    out += humanoid_verdict(folder)
    if all(math.isnan(h.truth_bar(sc)) for sc in h.scenarios):
        return out + [f"The humanoid is judged against its first truth alone ({h.truth_text()}), "
                      "at its own dt only (`--first-truth-only`): no error bar, no second truth. "
                      "It shows the scenarios on a second model; the judging with error bars is "
                      "Pinocchio's.", ""]
    rows = [[sc, fmt(h.truth_bar(sc))] +
            ([fmt(h.truth_bar(sc, SECOND_TRUTH)), fmt(h.truths_agreement(sc, ST.reseeded_mean))]
             if second else []) for sc in h.scenarios]
    out += [f"The truths on the humanoid ({h.truth_text()}"
            + (f"; second {h.truth_text(SECOND_TRUTH)}" if second else "") + "): each one's "
            "error bar and their agreement (re-seeded pose error, m):", "",
            md_table(["scenario", "truth's bar"] +
                     (["second truth's bar", "truths' agreement"] if second else []), rows), ""]
    return out


ID = "humanoid"


def lines(r):
    return humanoid_section(r.folder)
