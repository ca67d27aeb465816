"""The report's section `findings`: what the tables above say, in sentences."""
import math

from ..catalogue import FRONTIER_CSV as F
from ..catalogue import ROBUSTNESS_CSV as R
from ..catalogue import (CONFIGS, FRONTIER_SCENARIO, HZ, M, PAIRWISE_CONFIG, RULES_ENGINE, ST,
                        TRUTH, WASM_ENGINES)
from ..common import dt_text, fmt, geometric_mean, label, ordered
from ..readers import read_robustness


def findings(s, frontier, dt, robustness=None):
    found = []
    multibody = PAIRWISE_CONFIG
    rules = [c for c in s.configs if c[0] == RULES_ENGINE]
    finished = [sc for sc in s.scenarios
                if all(not math.isnan(s.get(sc, c, dt, M.pose_err_m, ST.reseeded_mean, TRUTH))
                       for c in rules + [multibody] if c in s.configs)]
    if rules and finished:
        score = {c: geometric_mean([s.get(sc, c, dt, M.pose_err_m, ST.reseeded_mean, TRUTH)
                                    for sc in finished]) for c in rules}
        best = min(score, key=score.get)
        ref = geometric_mean([s.get(sc, multibody, dt, M.pose_err_m, ST.reseeded_mean, TRUTH)
                              for sc in finished])
        text = (f"Of the procedural rules, **{best[1]}** tracks the truth best: a re-seeded pose "
                f"error of {fmt(score[best])} m (geometric mean over {', '.join(finished)}) at "
                f"dt = {dt_text(dt)} s")
        if not math.isnan(ref):
            text += (f", against {fmt(ref)} m for {label(multibody)} at the same dt "
                     f"({score[best] / ref:.1f}x)")
        found.append(text + ".")
        fine, coarse = s.dts[0], s.dts[-1]

        def mean_at(config, d):
            return geometric_mean([s.get(sc, config, d, M.pose_err_m, ST.reseeded_mean, TRUTH)
                                   for sc in finished])

        if len(s.dts) > 1 and multibody in s.configs:
            # the error's shrink over the dts, said as the figures say it: a factor, per halving
            halvings = math.log2(coarse / fine)

            def per_halving(config):
                ratio = mean_at(config, coarse) / mean_at(config, fine)
                return ratio ** (1.0 / halvings) if halvings > 0 and ratio > 0 else float("nan")

            found.append(
                f"Across dt: {best[1]} has {fmt(mean_at(best, fine))} m at dt = {dt_text(fine)} s "
                f"and {fmt(mean_at(best, coarse))} m at {dt_text(coarse)} s "
                f"({per_halving(best):.2f}x per halving of dt), {label(multibody)} "
                f"{fmt(mean_at(multibody, fine))} m and {fmt(mean_at(multibody, coarse))} m "
                f"({per_halving(multibody):.2f}x; first order is 2x; \"What made the difference\" "
                "finds where the procedural rules' floors came from).")
    limits = {sc: s.truth_limit(sc) for sc in s.scenarios} if s.truths() else {}
    loose = [sc for sc in limits if limits[sc] > 0.01]
    if loose:
        found.append(
            "The truth cannot judge errors below a centimetre everywhere: its floor (its error "
            "bar or the truths' disagreement, whichever is larger) is "
            + ", ".join(f"{fmt(limits[sc])} m in {sc}" for sc in loose)
            + " (the `≤` cells).")
    found += joint_gap_findings(s, dt)
    for c in s.configs:
        failed = sorted({sc for sc in s.scenarios for d in s.dts if s.diverged(sc, c, d)},
                        key=s.scenarios.index)
        if failed:
            at = {sc: [d for d in s.dts if s.diverged(sc, c, d)] for sc in failed}
            parts = [f"{sc} ({', '.join(dt_text(d) for d in at[sc])})" for sc in failed]
            found.append(f"{label(c)} diverges in {'; '.join(parts)}.")
        elif any((sc, c, d) in s.status for sc in s.scenarios for d in s.dts):
            found.append(f"{label(c)} stays bounded in every scenario at every dt.")
    for r in frontier:
        if r[F.quantity] != HZ:
            continue
        name = label((r[F.solver], r[F.rule]))
        if not r[F.largest_ok]:
            found.append(f"Held by the hand ({FRONTIER_SCENARIO}), {name} diverges even at "
                         f"{fmt(float(r[F.first_diverged]), 3)} Hz ({r[F.reason]}).")
        elif not r[F.first_diverged]:
            found.append(f"Held by the hand ({FRONTIER_SCENARIO}), {name} stays ok up to the top "
                         "of the range, "
                         f"{fmt(float(r[F.largest_ok]), 3)} Hz, with the hand pin up to "
                         f"{fmt(float(r[F.pin_gap_at_largest_ok_m]))} m from its target.")
        else:
            found.append(f"Held by the hand ({FRONTIER_SCENARIO}), {name} stays ok up to "
                         f"{fmt(float(r[F.largest_ok]), 3)} Hz and diverges at "
                         f"{fmt(float(r[F.first_diverged]), 3)} Hz ({r[F.reason]}).")
    speeds = {c: geometric_mean([s.get(sc, c, dt, M.step_us, ST.median) for sc in s.scenarios])
              for c in s.configs}
    if multibody in speeds and not math.isnan(speeds[multibody]):
        parts = [f"{label(c)} {speeds[multibody] / v:.1f}x" for c, v in speeds.items()
                 if c != multibody and c[0] not in WASM_ENGINES and not math.isnan(v)]
        found.append(f"Time per step against {label(multibody)} ({fmt(speeds[multibody], 3)} µs, "
                     f"geometric mean over scenarios): {', '.join(parts)} faster.")
    found += robustness_findings(robustness)
    return found


def widest_gap(s, config, dt):
    """(the widest joint gap of any scenario at dt, that scenario); NaN gaps count as none"""
    return max(((s.get(sc, config, dt, M.joint_gap_m, ST.max), sc) for sc in s.scenarios),
               key=lambda p: -1 if math.isnan(p[0]) else p[0])


def joint_gap_findings(s, dt):
    """who keeps every joint closed at the tables' dt and who opens them, and how wide the
    joints open at the coarsest dt"""
    found = []
    closed, opened = [], []
    for c in s.configs:
        worst = widest_gap(s, c, dt)
        (closed if worst[0] < 1e-9 else opened).append((c, worst))
    if closed:
        verb = "keeps" if len(closed) == 1 else "keep"
        text = (f"At dt = {dt_text(dt)} s, {', '.join(label(c) for c, _ in closed)} {verb} every "
                "joint closed to rounding (< 1e-9 m) in every scenario, up to any divergence")
        if opened:
            text += "; " + ", ".join(f"{label(c)} opens {fmt(w[0])} m in {w[1]}"
                                     for c, w in opened)
        found.append(text + ".")
    coarse = s.dts[-1]
    if opened and coarse != dt:
        parts = []
        for c, _ in opened:
            gap, sc = widest_gap(s, c, coarse)
            if not math.isnan(gap):
                after = " (before it diverged)" if s.diverged(sc, c, coarse) else ""
                parts.append(f"{label(c)} {fmt(gap)} m in {sc}{after}")
        if parts:
            found.append(f"At dt = {dt_text(coarse)} s they open up to: " + ", ".join(parts)
                         + ".")
    return found


def robustness_findings(rows):
    """per dt of the robustness sweep: who never diverged, and each configuration's worst scenario"""
    if not rows:
        return []
    found = []
    for d in sorted({r[R.dt] for r in rows}, reverse=True):
        at = [r for r in rows if r[R.dt] == d]
        configs = ordered({(r[R.solver], r[R.rule]) for r in at}, CONFIGS)
        never = [label(c) for c in configs
                 if all(r[R.diverged] == 0 for r in at if (r[R.solver], r[R.rule]) == c)]
        worst = []
        for c in configs:
            mine = [r for r in at if (r[R.solver], r[R.rule]) == c and r[R.diverged] > 0]
            if mine:
                r = max(mine, key=lambda r: r[R.rate])
                worst.append(f"{label(c)} {r[R.diverged]}/{r[R.runs]} in {r[R.scenario]}")
        runs = sorted({r[R.runs] for r in at})
        found.append(f"From {' or '.join(str(n) for n in runs)} random starts per scenario at "
                     f"dt = {dt_text(d)} s: "
                     + (f"{', '.join(never)} never diverged, and the others' worst scenario "
                        if never else "every solver diverged somewhere; each one's worst ")
                     + "(runs diverged of runs): " + ", ".join(worst) + ".")
    return found


ID = "findings"


def lines(r):
    return (["## Findings", ""] + [f"- {f}" for f in findings(r.s, r.frontier, r.dt,
                                                                read_robustness(r.folder))]
            + [""])
