"""The report's section `ablation`: what made the difference: the ablation of the position-based
rules."""
import os

from ..catalogue import FRONTIER_CSV as F
from ..catalogue import DT, FRONTIER_SCENARIO, HZ, M, RULES_ENGINE, SCENARIOS, ST, TRUTH
from ..common import (ABLATION, COMPLIANT_FRONTIER, FRONTIER, dt_text, fmt, label, md_table,
                      ordered)
from ..readers import read_ablation, read_frontier


def ablation_cell(s, scenario, config):
    """re-seeded pose error (m) / largest joint gap (m), or the divergence"""
    dt = s.table_dt()
    if (scenario, config, dt) not in s.status:
        return "–"
    error = s.get(scenario, config, dt, M.pose_err_m, ST.reseeded_mean, TRUTH)
    gap = s.get(scenario, config, dt, M.joint_gap_m, ST.max)
    cell = f"{fmt(error)} / {fmt(gap)}"
    if s.diverged(scenario, config, dt):
        cell += f" (div@{fmt(s.get(scenario, config, dt, M.diverged_at_s, ST.value))}s)"
    return cell


def kind(c):
    """what a configuration of the ablation is, from its run: a dt series (several dts), a set of
    solvers (several configurations), or one rule changed in one thing (an ingredient)"""
    s = c["summary"]
    if len(s.dts) > 1:
        return "dt series"
    return "solvers" if len(s.configs) > 1 else "ingredient"


def rule_config(s):
    return next(k for k in s.configs if k[0] == RULES_ENGINE)


def comparison(c, other, scenarios):
    """a configuration read against the one it changes one thing of, scenario by scenario"""
    a, b = other["summary"], c["summary"]
    ca, cb = rule_config(a), rule_config(b)

    def error(s, config, sc):
        return s.get(sc, config, s.table_dt(), M.pose_err_m, ST.reseeded_mean, TRUTH)

    def gap(s, config, sc):
        return s.get(sc, config, s.table_dt(), M.joint_gap_m, ST.max)

    def diverged(s, config, sc):
        return " (diverged)" if s.diverged(sc, config, s.table_dt()) else ""

    parts = [f"{sc} {fmt(error(a, ca, sc))}{diverged(a, ca, sc)} → {fmt(error(b, cb, sc))}"
             f"{diverged(b, cb, sc)} m, joint gap {fmt(gap(a, ca, sc))} → {fmt(gap(b, cb, sc))} m"
             for sc in scenarios]
    return f"`{c['name']}` against `{other['name']}`: " + "; ".join(parts) + "."


def series_finding(c):
    """how much a dt series' error shrinks from its coarsest dt to its finest"""
    s = c["summary"]
    fine, coarse = s.dts[0], s.dts[-1]
    parts = []
    for config in [k for k in s.configs if k[0] == RULES_ENGINE]:
        ratios = []
        for sc in s.scenarios:
            a = s.get(sc, config, coarse, M.pose_err_m, ST.reseeded_mean, TRUTH)
            b = s.get(sc, config, fine, M.pose_err_m, ST.reseeded_mean, TRUTH)
            diverged = any(s.diverged(sc, config, d) for d in s.dts)
            ratios.append(f"{a / b:.1f}x in {sc}" + (" (diverged)" if diverged else ""))
        parts.append(f"{config[1]}'s by {', '.join(ratios)}")
    return (f"`{c['name']}` (the table below): from dt = {dt_text(coarse)} to {dt_text(fine)} s "
            f"the error shrinks {'; '.join(parts)} (first order would be {coarse / fine:.0f}x).")


def series_table(c):
    s = c["summary"]
    rows = []
    for config in [k for k in s.configs if k[0] == RULES_ENGINE]:
        for sc in s.scenarios:
            errors = [s.get(sc, config, dt, M.pose_err_m, ST.reseeded_mean, TRUTH)
                      for dt in reversed(s.dts)]
            cells = [fmt(e) + (" †" if s.diverged(sc, config, dt) else "")
                     for e, dt in zip(errors, reversed(s.dts))]
            ratios = [f"{a / b:.2f}" if b > 0 else "–" for a, b in zip(errors, errors[1:])]
            rows.append([label(config), sc] + cells + [", ".join(ratios)])
    return [f"`{c['name']}`, {c['label']} (`{c['flags']}`), against a truth of the same model: "
            "re-seeded pose error (m) per dt, and how much it shrinks per halving of dt. †: the "
            "full run diverged.", "",
            md_table(["solver", "scenario"] + [dt_text(dt) for dt in reversed(s.dts)] +
                     ["ratio per halving"], rows), ""]


def solvers_table(c, other):
    """every solver of two solver sets side by side (the grab: hard against compliant)"""
    a, b = other["summary"], c["summary"]
    scenarios = [sc for sc in a.scenarios if sc in b.scenarios]
    rows = []
    for config in a.configs:
        row = [label(config)]
        for sc in scenarios:
            for s in (a, b):
                cell = ablation_cell(s, sc, config)
                pin = s.get(sc, config, s.table_dt(), M.pin_gap_m, ST.rms)
                row.append(f"{cell}, pin {fmt(pin)}")
        rows.append(row)
    return [f"`{c['name']}`, the {c['label']}, against `{other['name']}`, the "
            f"{other['label']}; the "
            f"truth is {a.truth_text() if a.truths() else 'none'} with the same setting (the "
            "references hold a compliant grab as a spring force). Each cell adds the grab's RMS "
            "distance to its target (m).", "",
            md_table(["solver"] + [f"{sc} {x['name']}" for sc in scenarios for x in (other, c)],
                     rows), ""]


def frontier_table(frontier, soft_frontier, names):
    def largest(rows, solver, rule, quantity):
        for r in rows:
            if (r[F.solver], r[F.rule], r[F.quantity]) == (solver, rule, quantity):
                if not r[F.largest_ok]:
                    return "none"
                value = float(r[F.largest_ok])
                return fmt(value, 3) if quantity == HZ else dt_text(value)
        return "–"
    rows = []
    for r in soft_frontier:
        if r[F.quantity] != HZ:
            continue
        key = (r[F.solver], r[F.rule])
        rows.append([label(key)] + [largest(f, *key, q) for q in (HZ, DT)
                                    for f in (frontier, soft_frontier)])
    hard, soft = names
    return [f"The {FRONTIER_SCENARIO} frontier with the {hard} grab (`{FRONTIER}/frontier.csv`) "
            f"and the {soft} one (`{ABLATION}/{COMPLIANT_FRONTIER}/frontier.csv`).", "",
            md_table(["solver", f"largest Hz, {hard}", f"largest Hz, {soft}",
                      f"largest dt, {hard}", f"largest dt, {soft}"], rows), ""]


def ablation_section(folder, frontier):
    configs = read_ablation(folder)
    if not configs:
        return []
    by_name = {c["name"]: c for c in configs}
    ingredients = [c for c in configs if kind(c) == "ingredient"]
    scenarios = ordered({sc for c in ingredients for sc in c["summary"].scenarios}, SCENARIOS)
    dts = sorted({dt_text(c["summary"].table_dt()) for c in ingredients})
    out = ["## What made the difference", "",
           f"From `{ABLATION}/` (scripts/ablation.sh): dt = {' or '.join(dts)} s, each "
           "configuration one `testbed run`. Each cell: re-seeded pose error against the truth "
           "(m) / largest joint gap over the run (m). Each configuration is read against the one "
           "it changes one thing of (`against`); docs/solver.md, \"What made the difference\", "
           "says what the differences mean.", ""]
    rows = []
    for c in ingredients:
        s = c["summary"]
        flags = " ".join(w for w in c["flags"].split() if w not in (RULES_ENGINE, "--solver"))
        rows.append([f"`{c['name']}`", c["label"], f"`{c['against']}`" if c["against"] else "",
                     f"`{flags}`"] + [ablation_cell(s, sc, rule_config(s)) for sc in scenarios])
    out += [md_table(["configuration", "what it is", "against", "flags"] + scenarios, rows), ""]
    found = [comparison(c, by_name[c["against"]], scenarios) for c in ingredients
             if c["against"] in by_name and kind(by_name[c["against"]]) == "ingredient"]
    found += [series_finding(c) for c in configs if kind(c) == "dt series"]
    out += [f"- {f}" for f in found] + ([""] if found else [])
    for c in configs:
        if kind(c) == "dt series":
            out += series_table(c)
    grabs = [(c, by_name[c["against"]]) for c in configs if kind(c) == "solvers"
             and c["against"] in by_name and kind(by_name[c["against"]]) == "solvers"]
    for c, other in grabs:
        out += solvers_table(c, other)
    soft_frontier = read_frontier(os.path.join(folder, ABLATION, COMPLIANT_FRONTIER,
                                               "frontier.csv"))
    if frontier and soft_frontier and grabs:
        out += frontier_table(frontier, soft_frontier, (grabs[0][1]["name"], grabs[0][0]["name"]))
    return out


ID = "ablation"


def lines(r):
    return ablation_section(r.folder, r.frontier)
