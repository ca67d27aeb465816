"""The report's section `verdict`: the verdict: cost at equal accuracy and robustness."""

from ..catalogue import CANDIDATES_CSV as C
from ..catalogue import VERDICT_CSV as V
from ..catalogue import (CONTACT_SCENARIOS, DEFAULT_RULE, ERROR_FLOOR, HEADLINE, MET, PER_FRAME,
                         PER_SECOND, RULES_ENGINE, SEED_RULES, setting_label)
from ..common import (HEADLINE_BUDGET, VERDICT, budget_name, dt_text, fmt, label, md_table,
                      wilson_upper)
from ..readers import Verdict, read_verdict


def setting_text(row):
    """a chosen configuration in a few words: 1/120 s, 8 substeps"""
    text = dt_text(row[V.dt]) + " s"
    setting = setting_label(row["config"], row[V.setting])
    return f"{text}, {setting}" if setting else text


def searched_summary(v):
    """what the verdict searched, in a phrase: dt from 1/30 to 1/960 s and each solver's own
    settings"""
    dts = [c[C.dt] for c in v.candidates]
    return (f"dt from {dt_text(max(dts))} to {dt_text(min(dts))} s, and each solver's own "
            "settings")


def frame_puppets(v, budget, scenario=HEADLINE):
    """(configuration, puppets one core keeps at the frame rate) of those met in the scenario"""
    out = []
    for c in v.configs:
        r = v.row(scenario, c, PER_FRAME, budget)
        if r and r[V.verdict] == MET:
            out.append((c, r[V.puppets_per_core]))
    return out


def verdict_cell(v, scenario, config, view, budget, show_setting=False):
    r = v.row(scenario, config, view, budget)
    if r is None:
        return "–"
    if r[V.verdict] != MET:
        text = r[V.verdict].replace("-", " ")  # error-floor: error floor
        if r[V.verdict] == ERROR_FLOOR:
            text += f" ({fmt(r[V.best_error_m])} m)"
        return text
    cost = r[V.us_per_frame] if view == PER_FRAME else r[V.cost_us_per_s]
    text = f"{cost:,.0f}" if cost >= 100 else fmt(cost, 2)
    reference = v.cheapest_reference(scenario, view, budget)
    if reference and config[0] == RULES_ENGINE:
        ratio = reference[V.cost_us_per_s] / r[V.cost_us_per_s]
        text += f" ({ratio:.1f}×)" if ratio < 9.5 else f" ({ratio:.0f}×)"
    elif reference and r is reference:
        text += " (ref)"
    if show_setting:
        text += f"<br>{setting_text(r)}"
    return text


def verdict_table(v, view, budget, show_setting=False):
    scenarios = [sc for sc in v.scenarios if v.judged(sc, budget)]
    rows = [[label(c)] + [verdict_cell(v, sc, c, view, budget, show_setting) for sc in scenarios]
            for c in v.configs]
    return md_table(["solver"] + scenarios, rows), [sc for sc in v.scenarios if sc not in scenarios]


def refused_text(v, refused):
    if not refused:
        return ""
    return ("Not judged at this budget, because it is finer than the truth's floor there: "
            + ", ".join(f"{sc} (floor {fmt(v.floor[sc])} m)" for sc in refused) + ".")


def two_figures(x):
    """a measured ratio or length as a reader takes it in: two significant figures"""
    return f"{x:.2g}"


def cm_range(values):
    """'4.7 to 50 cm' (or '5 cm' when they round alike)"""
    low, high = (two_figures(100.0 * x) for x in (min(values), max(values)))
    return f"{low} cm" if low == high else f"{low} to {high} cm"


def plain_result(v, budget=HEADLINE_BUDGET, view=PER_SECOND):
    """the verdict in three plain sentences: the paper's own rules, the default rule against the
    cheapest reference engine, and where it wins most and where the family loses"""
    within = budget_name(budget)
    model = v.model[:1].upper() + v.model[1:]
    judged = [sc for sc in v.scenarios if v.judged(sc, budget)]
    off_ground = [sc for sc in judged if sc not in CONTACT_SCENARIOS]
    out = []
    seed_rows = [v.row(sc, (RULES_ENGINE, rule), view, budget) for rule in SEED_RULES
                 for sc in off_ground]
    seed_rows = [r for r in seed_rows if r]
    if seed_rows:
        met = sorted({r[V.scenario] for r in seed_rows if r[V.verdict] == MET})
        floors = [r[V.best_error_m] for r in seed_rows if r[V.verdict] == ERROR_FLOOR]
        sentence = (f"In the scenes off the ground, the paper's own rules "
                    f"({', '.join(SEED_RULES)}) "
                    + (f"keep {model} within {within} of the truth only in {', '.join(met)}"
                       if met else f"never keep {model} within {within} of the truth"))
        if floors:
            sentence += (f"; {'elsewhere ' if met else ''}the least error they reach is "
                         f"{cm_range(floors)}")
        out.append(sentence + ".")
    rule = DEFAULT_RULE
    ratios, references, lost = {}, {}, []
    met_count = 0
    for sc in judged:
        r = v.row(sc, (RULES_ENGINE, rule), view, budget)
        ref = v.cheapest_reference(sc, view, budget)
        if r and r[V.verdict] == MET:
            met_count += 1
            if ref:
                ratios[sc] = ref[V.cost_us_per_s] / r[V.cost_us_per_s]
                references[sc] = label(ref["config"])
        elif not v.cheapest_procedural(sc, view, budget) and ref:
            lost.append((sc, label(ref["config"])))
    if ratios:
        ordered_ratios = sorted(ratios.values())
        median = ordered_ratios[len(ordered_ratios) // 2]
        out.append(
            f"{rule}, the best of the family and the default rule, keeps it within {within} in "
            f"{met_count} of the {len(judged)} scenes the truth can judge there, for "
            f"{two_figures(min(ratios.values()))}× to {two_figures(max(ratios.values()))}× less "
            "CPU per simulated second than the cheapest reference engine in each (median "
            f"{two_figures(median)}×).")
        best, least = max(ratios, key=ratios.get), min(ratios, key=ratios.get)
        sentence = (f"It gains most in {best} ({two_figures(ratios[best])}× "
                    f"{references[best]}'s speed) and least in {least} "
                    f"({two_figures(ratios[least])}× {references[least]}'s)")
        if lost:
            sentence += ("; no procedural rule meets the budget in "
                         + ", ".join(f"{sc}, where {engine} does" for sc, engine in lost))
        out.append(sentence + ".")
    return " ".join(out)


def verdict_headline(folder, budget=HEADLINE_BUDGET):
    """the README's headline: µs per simulated second at one budget, per solver and scenario"""
    v = Verdict(folder)
    table, refused = verdict_table(v, PER_SECOND, budget)
    return (plain_result(v, budget) + "\n\n" + f"CPU µs per simulated second to keep Pinocchio within {budget_name(budget)} of "
            f"the truth ({v.truth}) and never diverge in {v.starts} random starts, with the "
            f"cheapest configuration each solver has ({searched_summary(v)}); in brackets, how "
            "many times cheaper than the cheapest reference engine "
            f"(`(ref)`: that engine). From `results/{VERDICT}/verdict.csv` (commit "
            f"`{v.git_sha}`, {v.machine}), printed by `scripts/readme_headline.py`. "
            + refused_text(v, refused) + "\n\n" + table + "\n\n"
            + "\n".join(f"- {line}" for line in family_findings(v, budgets=[budget])) + "\n")


def family_findings(v, view=PER_SECOND, budgets=None):
    """where the procedural family wins and loses, per budget"""
    out = []
    for budget in budgets or v.budgets:
        wins, losses, none = [], [], []
        for sc in v.scenarios:
            if not v.judged(sc, budget):
                continue
            p = v.cheapest_procedural(sc, view, budget)
            r = v.cheapest_reference(sc, view, budget)
            if p and r:
                ratio = r[V.cost_us_per_s] / p[V.cost_us_per_s]
                (wins if ratio >= 1 else losses).append(
                    f"{sc} ({p[V.rule]}, {ratio:.2g}× as fast as {label(r['config'])})")
            elif p:
                wins.append(f"{sc} ({p[V.rule]}; no reference meets it)")
            elif r:
                losses.append(f"{sc} (no procedural rule meets it; {label(r['config'])} does)")
            else:
                none.append(sc)
        parts = []
        if wins:
            parts.append("the procedural family is cheaper in " + ", ".join(wins))
        if losses:
            parts.append("dearer in " + ", ".join(losses))
        if none:
            parts.append("no solver meets it in " + ", ".join(none))
        if parts:
            out.append(f"Within {budget_name(budget)}: " + "; ".join(parts) + ".")
    return out


def verdict_section(v):
    if v is None:
        return []
    budgets = ", ".join(budget_name(b) for b in v.budgets)
    out = ["## The verdict: cost at equal accuracy and robustness", "",
           f"`{VERDICT}/`: `testbed verdict`. For every solver and scenario, every configuration "
           f"was measured ({searched_summary(v)}; \"What the verdict searched\" lists them, "
           "`candidates.csv` has each). Each was timed "
           "through the whole scenario in one thread, the configurations of a scenario in turn "
           "a quarter of a simulated second at a time, as CPU µs per simulated second; and "
           f"judged by its re-seeded pose error against the truth ({v.truth}); a configuration "
           "whose scenario run or any re-seeded run diverged is out. For each budget "
           f"({budgets}), the configurations within it were put, cheapest first, through "
           f"{v.starts} random starts (docs/robustness.md) until one survived them all: no "
           f"divergence in {v.starts} starts, a divergence rate below "
           f"{fmt(wilson_upper(0, v.starts), 2)} at 95 % (Wilson). A budget below the truth's "
           "floor in a scenario is refused there. Cells: CPU µs per simulated second of the "
           "chosen configuration, and for the procedural rules how many times cheaper than the "
           "cheapest native reference engine (`(ref)`); a WebAssembly engine's cost (jolt: "
           "Jolt's own WebAssembly build, timed per step inside Node.js) stands in its own "
           "row, so marked, and is never the `(ref)` or a ratio's; otherwise why none: "
           "`diverges` (every "
           "configuration), `error floor` (its least error, m), `not robust` (within the "
           "budget only where a random start diverged). The budget is on the pose error: a "
           "solver may meet it with its joints opened (the joint gaps are in \"Joint gaps and "
           "divergence\"). In the scenes on the ground the error is the contact judge's "
           "instead: the largest violation or the first impact's error, and the outcomes over "
           "the starts must be like the truth's (`unlike truth` when none are; \"The scenes on "
           "the ground\"). Why the exact solvers read `not robust` in the two-pin scenarios: "
           "docs/tried.md, \"The verdict's search and its random starts\".", ""]
    out += ["Where the procedural family wins and where it loses (its cheapest rule against the "
            "cheapest reference, per simulated second):", ""]
    out += [f"- {line}" for line in family_findings(v)] + [""]
    for budget in v.budgets:
        table, refused = verdict_table(v, PER_SECOND, budget, show_setting=True)
        out += [f"### Within {budget_name(budget)}, any dt", "", table, "",
                refused_text(v, refused), ""]
    for budget in v.budgets:
        table, refused = verdict_table(v, PER_FRAME, budget, show_setting=True)
        hz = f"{v.frame_hz:g}"
        puppets = frame_puppets(v, budget)
        out += [f"### Within {budget_name(budget)} at {hz} Hz", "",
                f"µs per {hz} Hz frame, the frame taken in whole steps (dt = 1/{hz} s or a "
                f"divisor of it). A core keeps 10⁶/({hz} × µs per frame) puppets at {hz} Hz"
                + (f": in {HEADLINE} " + ", ".join(f"{label(c)} {n:,.0f}" for c, n in puppets)
                   if puppets else "") + ".", "", table, "", refused_text(v, refused), ""]
    return out


ID = "verdict"


def lines(r):
    return verdict_section(read_verdict(r.folder))
