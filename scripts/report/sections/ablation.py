"""The report's section `ablation`: what made the difference: the ablation of the position-based
rules."""
import math
import os

from ..catalogue import M, RULES_ENGINE, TRUTH
from ..common import FRONTIER, dt_text, fmt, label, md_table
from ..readers import read_ablation, read_frontier


ABLATION_SCENARIOS = ["hang", "drag", "yank"]


def ablation_cell(s, scenario, config):
    """re-seeded pose error (m) / largest joint gap (m), or the divergence"""
    dt = s.table_dt()
    if (scenario, config, dt) not in s.status:
        return "–"
    error = s.get(scenario, config, dt, M.pose_err_m, "reseeded_mean", TRUTH)
    gap = s.get(scenario, config, dt, M.joint_gap_m, "max")
    cell = f"{fmt(error)} / {fmt(gap)}"
    if s.diverged(scenario, config, dt):
        cell += f" (div@{fmt(s.get(scenario, config, dt, M.diverged_at_s, 'value'))}s)"
    return cell


def ablation_findings(by_name):
    """sentences read from the ablation's numbers"""
    def value(name, scenario, metric, stat, reference=""):
        if name not in by_name:
            return math.nan
        s = by_name[name]["summary"]
        config = next(k for k in s.configs if k[0] == RULES_ENGINE)
        return s.get(scenario, config, s.table_dt(), metric, stat, reference)

    def error(name, scenario):
        return value(name, scenario, M.pose_err_m, "reseeded_mean", TRUTH)

    def gap(name, scenario):
        return value(name, scenario, M.joint_gap_m, "max")

    found = []
    if {"relaxed", "relaxed-64"} <= by_name.keys():
        found.append(
            f"Converging relaxed's sweeps (64 instead of 4) takes its hang error from "
            f"{fmt(error('relaxed', 'hang'))} to {fmt(error('relaxed-64', 'hang'))} m: what 4 "
            "sweeps leave unconverged, the one-sided closure turns into motion. The closure "
            "itself keeps the joints at rounding, but moving a child as if its parent were "
            "infinitely heavy is not stable: with 64 sweeps drag still diverges.")
    if {"xpbd", "tree"} <= by_name.keys():
        found.append(
            f"Gauss–Seidel against the exact projection at equal substeps (8 × 1): xpbd leaves "
            f"joint gaps up to {fmt(gap('xpbd', 'drag'))} m in drag and {fmt(gap('xpbd', 'yank'))} "
            f"m in yank, tree {fmt(gap('tree', 'drag'))} and {fmt(gap('tree', 'yank'))} m; their "
            f"errors against the truth are alike (hang {fmt(error('xpbd', 'hang'))} and "
            f"{fmt(error('tree', 'hang'))} m): at this dt the error is the substep's, not the "
            "projection's.")
    if {"xpbd", "xpbd-iterations", "tree", "tree-iterations"} <= by_name.keys():
        found.append(
            f"Substeps against iterations, for the same eight projections per step: hang's error "
            f"is {fmt(error('xpbd', 'hang'))} m with 8 substeps and "
            f"{fmt(error('xpbd-iterations', 'hang'))} m with 8 sweeps of one step (xpbd), "
            f"{fmt(error('tree', 'hang'))} and {fmt(error('tree-iterations', 'hang'))} m (tree, "
            "whose 8 Newton iterations close the joints to rounding): iterations close the "
            "joints, substeps make the motion accurate.")
    if "open-limits" in by_name:
        s = by_name["open-limits"]["summary"]
        fine, coarse = s.dts[0], s.dts[-1]
        parts = []
        for config in [c for c in s.configs if c[0] == RULES_ENGINE]:
            ratios = []
            for sc in s.scenarios:
                a = s.get(sc, config, coarse, M.pose_err_m, "reseeded_mean", TRUTH)
                b = s.get(sc, config, fine, M.pose_err_m, "reseeded_mean", TRUTH)
                diverged = any(s.diverged(sc, config, d) for d in s.dts)
                ratios.append(f"{a / b:.1f}x in {sc}" + (" (diverged)" if diverged else ""))
            parts.append(f"{config[1]}'s by {', '.join(ratios)}")
        found.append(
            f"With every joint free (the table below), from dt = {dt_text(coarse)} to "
            f"{dt_text(fine)} s the error shrinks: {'; '.join(parts)} (first order would be "
            f"{coarse / fine:.0f}x). So with the model's limits, the floor that tree's error sits on "
            "comes from the limits, which the procedural rules project hard and bullet-multibody "
            "holds with its own limit constraints, not from the integration. Where xpbd's error "
            "does not shrink without limits either, what one sweep per substep leaves unclosed is "
            "an error of its own.")
    return [f"- {f}" for f in found] + ([""] if found else [])


def ablation_section(folder, frontier):
    configs = read_ablation(folder)
    if not configs:
        return []
    by_name = {c["name"]: c for c in configs}
    out = ["## What made the difference", "",
           "From `ablation/` (scripts/ablation.sh): Pinocchio at dt = 1/240 s, each configuration "
           "one `testbed run`. Each cell: re-seeded pose error against the truth (m) / largest "
           "joint gap over the run (m).", ""]
    rows = []
    for c in configs:
        if c["name"] in ("hard", "compliant", "open-limits"):
            continue
        s = c["summary"]
        config = next(k for k in s.configs if k[0] == RULES_ENGINE)
        rows.append([c["label"], f"`{c['flags'].replace('--solver procedural ', '')}`"] +
                    [ablation_cell(s, sc, config) for sc in ABLATION_SCENARIOS])
    out += [md_table(["configuration", "flags"] + ABLATION_SCENARIOS, rows), ""]
    out += ablation_findings(by_name)
    if "open-limits" in by_name:
        s = by_name["open-limits"]["summary"]
        rows = []
        for config in [c for c in s.configs if c[0] == RULES_ENGINE]:
            for sc in s.scenarios:
                errors = [s.get(sc, config, dt, M.pose_err_m, "reseeded_mean", TRUTH)
                          for dt in reversed(s.dts)]
                cells = [fmt(e) + (" †" if s.diverged(sc, config, dt) else "")
                         for e, dt in zip(errors, reversed(s.dts))]
                ratios = [f"{a / b:.2f}" if b > 0 else "–" for a, b in zip(errors, errors[1:])]
                rows.append([label(config), sc] + cells + [", ".join(ratios)])
        out += [f"The same rules with every joint free (`{by_name['open-limits']['flags']}`"
                "), against a truth of the same model: re-seeded pose error (m) per dt, and how "
                "much it shrinks per halving of dt. †: the full run diverged.", "",
                md_table(["solver", "scenario"] + [dt_text(dt) for dt in reversed(s.dts)] +
                         ["ratio per halving"], rows), ""]
    if "hard" in by_name and "compliant" in by_name:
        hard, soft = by_name["hard"]["summary"], by_name["compliant"]["summary"]
        rows = []
        for config in hard.configs:
            row = [label(config)]
            for sc in ("drag", "yank"):
                for s in (hard, soft):
                    cell = ablation_cell(s, sc, config)
                    pin = s.get(sc, config, s.table_dt(), M.pin_gap_m, "rms")
                    row.append(f"{cell}, pin {fmt(pin)}")
            rows.append(row)
        out += [f"Hard grab against the {by_name['compliant']['label']}; the truth is "
                f"{hard.truth_text() if hard.truths() else 'none'} with the same grab (the "
                "references hold a compliant grab as a spring force). Each cell adds the grab's RMS distance to its "
                "target (m).", "",
                md_table(["solver", "drag hard", "drag compliant", "yank hard", "yank compliant"],
                         rows), ""]
    soft_frontier = read_frontier(os.path.join(folder, "ablation", "frontier-compliant",
                                               "frontier.csv"))
    if frontier and soft_frontier:
        def largest(rows, solver, rule, quantity):
            for r in rows:
                if (r["solver"], r["rule"], r["quantity"]) == (solver, rule, quantity):
                    if not r["largest_ok"]:
                        return "none"
                    value = float(r["largest_ok"])
                    return fmt(value, 3) if quantity == "hz" else dt_text(value)
            return "–"
        rows = []
        for r in soft_frontier:
            if r["quantity"] != "hz":
                continue
            key = (r["solver"], r["rule"])
            rows.append([label(key)] + [largest(f, *key, q) for q in ("hz", "dt")
                                        for f in (frontier, soft_frontier)])
        out += [f"The yank frontier with the hard grab (`{FRONTIER}/frontier.csv`) and the compliant one "
                "(`ablation/frontier-compliant/frontier.csv`).", "",
                md_table(["solver", "largest Hz, hard", "largest Hz, compliant", "largest dt, hard",
                          "largest dt, compliant"], rows), ""]
    return out


ID = "ablation"


def lines(r):
    return ablation_section(r.folder, r.frontier)
