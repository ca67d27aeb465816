"""The report's section `what-was-run`: the scenarios, solvers, dts and truths of the run, and how
errors are measured."""

from ..catalogue import SCENARIO_ASKS, SECOND_TRUTH
from ..common import dt_text, label


ID = "what-was-run"


def lines(r):
    s = r.s
    dt = r.dt
    truths = r.truths
    out = []
    out += ["## What was run", "",
            f"- Scenarios: {', '.join(s.scenarios)}.",
            f"- Solvers: {', '.join(label(c) for c in s.configs)}.",
            f"- dt: {', '.join(dt_text(d) for d in s.dts)} s. Tables use dt = {dt_text(dt)} s "
            "unless they say otherwise.",
            ("- Truth: " + s.truth_text()
             + (f"; the second truth {s.truth_text(SECOND_TRUTH)}" if r.second else "")
             + ", each run at h/2 and 2h too, sampled every 1/30 s. " if truths else
             "- No truth: this model runs in neither truth engine. ") +
            "Errors: "
            "`pose_err_m` (RMS over segments of the COM distance) and `joint_angle_err_deg` (RMS "
            "over joints of the angle between relative rotations). Re-seeded: from 8 truth "
            "states, each solver runs 0.5 s and is compared with the truth; the mean is the "
            "headline figure. The 0.25 s figure is the sample at 8/30 s = 0.267 s, the first "
            "multiple of 1/30 s after it.",
            "- Timing: medians of a separate pass that runs one job at a time."]
    asked = [sc for sc in s.scenarios if SCENARIO_ASKS.get(sc)]
    if asked:
        out += ["", "What each scenario asks, and why (`testbed list --json`):", "",
                "| scenario | what it asks |", "|---|---|"]
        out += [f"| {sc} | {SCENARIO_ASKS[sc]} |" for sc in asked]
    unknown = r.unknown_names()
    if unknown:
        out += [f"- Not in the testbed's catalogue (drawn in grey, listed last): "
                f"{', '.join(unknown)}."]
    out += [""]
    return out
