from datetime import datetime, timezone
import math
import os

from .catalogue import PAIRWISE_CONFIG, SECOND_TRUTH, TRUTH, TRUTHS
from .common import (BAR_MARGIN, FRONTIER, MAIN, MIN_ORDER, ReportError, dt_text, fmt, geometric_mean, label, md_table, write_atomically)
from .readers import read_robustness, read_verdict
from .sections.ablation import ablation_section
from .sections.findings import findings
from .sections.humanoid import humanoid_section
from .sections.open_limits import open_limits_agreement, open_limits_section
from .sections.robustness import robustness_section
from .sections.verdict import verdict_section


def report(s, frontier, plots, folder):
    text = "\n".join(report_lines(s, frontier, plots, folder))
    write_atomically(os.path.join(folder, "REPORT.md"), text)


def section(s, frontier, folder, title):
    """One `## title` section of the report, without its heading: docs pages hold it as a
    generated block (scripts/docs_tables.py), the same figures as REPORT.md's"""
    lines = report_lines(s, frontier, [], folder)
    if "## " + title not in lines:
        raise ReportError(f"the report has no section `{title}`")
    body = lines[lines.index("## " + title) + 1:]
    end = next((i for i, line in enumerate(body) if line.startswith("## ")), len(body))
    return "\n".join(body[:end]).strip("\n") + "\n"


def report_lines(s, frontier, plots, folder):
    dt = s.table_dt()
    truths = s.truths()
    now = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    out = ["# Report: the procedural solver against Bullet and MuJoCo", ""]
    out += [f"Generated {now} by `scripts/plot.py` from `{MAIN}/summary.csv`"
            f"{f' and `{FRONTIER}/frontier.csv`' if frontier else ''} (commit `{s.git_sha}`, "
            f"model `{s.model}`, machine: {s.machine}). Every number below is read from those "
            "files; `testbed run` and `testbed frontier` regenerate them.", ""]
    out += ["## What was run", "",
            f"- Scenarios: {', '.join(s.scenarios)}.",
            f"- Solvers: {', '.join(label(c) for c in s.configs)}.",
            f"- dt: {', '.join(dt_text(d) for d in s.dts)} s. Tables use dt = {dt_text(dt)} s "
            "unless they say otherwise.",
            ("- Truth: " + s.truth_text()
             + (f"; the second truth {s.truth_text(SECOND_TRUTH)}" if s.has_second_truth() else "")
             + ", each run at h/2 and 2h too, sampled every 1/30 s. " if truths else
             "- No truth: this model runs in neither truth engine. ") +
            "Errors: "
            "`pose_err_m` (RMS over segments of the COM distance) and `joint_angle_err_deg` (RMS "
            "over joints of the angle between relative rotations). Re-seeded: from 8 truth "
            "states, each solver runs 0.5 s and is compared with the truth; the mean is the "
            "headline figure. The 0.25 s figure is the sample at 8/30 s = 0.267 s, the first "
            "multiple of 1/30 s after it.",
            "- Timing: medians of a separate pass that runs one job at a time.", ""]
    out += verdict_section(read_verdict(folder))

    # the truths' error bars and their agreement
    second = s.has_second_truth()
    if truths:
        rows = []
        for sc in s.scenarios:
            row = [sc]
            for ref in truths:
                p = s.truth_order(sc, ref)
                row += [fmt(s.truth_own(sc, ref, 2.0)), fmt(s.truth_check(sc, ref)),
                        "–" if math.isnan(p) else f"{p:.1f}", fmt(s.truth_bar(sc, ref))]
            row += [fmt(s.truth_limit(sc))]
            rows.append(row)
        header = ["scenario"]
        for ref in truths:
            name = "truth" if ref == TRUTH else "second truth"
            header += [f"{name}: 2h vs h", "h/2 vs h", "order p", "error bar"]
        header += ["floor"]
        out += ["## How far the truths can be trusted", "",
                f"The truth is {s.truth_text()}"
                + (f", the second truth {s.truth_text(SECOND_TRUTH)}" if second else
                   "; the second engine cannot run this model")
                + ". Each is run at h/2 and at 2h too, its constraint model refined with dt "
                "(MuJoCo's time constant 2·dt, Bullet's Baumgarte fraction per step), and "
                "compared with itself at h (re-seeded pose error, m). The two differences give "
                "its order of convergence p = log2(2h difference / h/2 difference) and so a bound "
                f"on its own error: the error bar {BAR_MARGIN:g} × 2^p/(2^p − 1) × the h/2 "
                f"difference (Richardson's estimate with a margin of {BAR_MARGIN:g}; p taken as at "
                f"least {MIN_ORDER:g}). The floor is what the truth can judge: its error bar, and "
                "never less than the second truth's error against it, judged as every solver is "
                "(re-seeded from the truth's states; \"re-seeded\" below). Errors under it are "
                "shown as `≤ floor`.", "",
                md_table(header, rows), ""]
    if second:
        pin_rows = any(k[3] == "pin_gap_m" and k[5] in TRUTHS and k[2] not in s.dts
                       for k in s.values)
        rows = []
        for sc in s.scenarios:
            rows.append([sc] + [fmt(s.truths_agreement(sc, stat)) for stat in
                                ("at_0.267s", "at_1s", "mean_1s", "reseeded_mean")] +
                        [fmt(s.truths_agreement(sc, "reseeded_mean", SECOND_TRUTH)),
                         fmt(s.truths_agreement(sc, "reseeded_mean",
                                                metric="joint_angle_err_deg")),
                         fmt(s.truths_agreement(sc, "max", SECOND_TRUTH,
                                                "limit_violation_deg"), 2),
                         fmt(s.truths_agreement(sc, "max", metric="limit_violation_deg"), 2)] +
                        ([fmt(s.truths_agreement(sc, "max", SECOND_TRUTH, "pin_gap_m")),
                          fmt(s.truths_agreement(sc, "max", metric="pin_gap_m"))]
                         if pin_rows else []) +
                        [open_limits_agreement(folder, sc)])
        out += ["## Where the truths agree", "",
                f"The second truth ({s.truth_text(SECOND_TRUTH)}) against the truth "
                f"({s.truth_text()}), pose error (m): along the whole run, and re-seeded both "
                "ways (the second from the truth's states against it, the truth from the "
                "second's against it). The last column is the same re-seeded figure for "
                "Pinocchio with every joint free (`truths-open-limits/`), where the engines "
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
                "What differs between the engines (docs/mujoco.md): a box limit is the same "
                "joint in both (MuJoCo's three hinges, bullet-multibody's rows per angle); a "
                "swing–twist limit is MuJoCo's cone on the whole rotation angle; both hang "
                "the tree from a still pin, which then holds exactly; MuJoCo's limits, contacts "
                "and moving pins are soft (time constant 2·dt, a limit damped at ratio 2 giving "
                "back about 1% of an impact's speed), Bullet's are speculative or Baumgarte "
                "impulses iterated ten sweeps (a limit giving back about 2%, a moving pin aimed "
                "at its target's velocity); a contact's friction cone is elliptic in MuJoCo and "
                "Bullet's impulses are clamped per direction.", ""]

    def accuracy_cell(sc, config, d, metric="pose_err_m", reference="truth"):
        v = s.get(sc, config, d, metric, "reseeded_mean", reference)
        if math.isnan(v):
            return "div" if s.diverged(sc, config, d) else "–"
        cell = fmt(v)
        if reference in TRUTHS and metric == "pose_err_m":
            limit = s.truth_limit(sc, reference)
            if v < limit:
                cell = f"≤ {fmt(limit)}"
        seeds = s.get(sc, config, d, "reseeded_diverged", "count", reference)
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
                     [[sc] + [accuracy_cell(sc, c, dt, "joint_angle_err_deg") for c in s.configs]
                      for sc in s.scenarios]), ""]
    if second:
        out += [f"Against the second truth ({s.truth_text(SECOND_TRUTH)}): re-seeded pose error (m), "
                f"dt = {dt_text(dt)} s:", "",
                md_table(["scenario"] + [label(c) for c in s.configs],
                         [[sc] + [accuracy_cell(sc, c, dt, reference=SECOND_TRUTH)
                                  for c in s.configs] for sc in s.scenarios]), ""]
    out += open_limits_section(folder)
    pair_configs = [c for c in s.configs if c != PAIRWISE_CONFIG]
    if any(not math.isnan(s.get(sc, c, dt, "pose_err_m", "reseeded_mean", "pairwise"))
           for sc in s.scenarios for c in pair_configs):
        out += ["Pairwise: re-seeded pose error against bullet-multibody at the same dt (m):", "",
                md_table(["scenario"] + [label(c) for c in pair_configs],
                         [[sc] + [accuracy_cell(sc, c, dt, reference="pairwise")
                                  for c in pair_configs] for sc in s.scenarios]), ""]
    out += ["Against dt (re-seeded pose error, m, geometric mean over the scenarios each solver "
            "finished at every dt):", ""]
    rows = []
    for c in s.configs:
        row = [label(c)]
        for d in s.dts:
            row.append(fmt(geometric_mean([s.get(sc, c, d, "pose_err_m", "reseeded_mean",
                                                 "truth") for sc in s.scenarios])))
        rows.append(row)
    out += [md_table(["solver"] + [dt_text(d) for d in s.dts], rows), ""]

    # constraints and divergence
    def gap_cell(sc, c, d):
        v = s.get(sc, c, d, "joint_gap_m", "max")
        return fmt(v) + (" †" if s.diverged(sc, c, d) else "")

    out += ["## Joint gaps and divergence", "",
            f"Max joint gap (m), dt = {dt_text(dt)} s (†: diverged, the max is up to then):", "",
            md_table(["scenario"] + [label(c) for c in s.configs],
                     [[sc] + [gap_cell(sc, c, dt) for c in s.configs] for sc in s.scenarios]), ""]
    rows = []
    for c in s.configs:
        cells = []
        for sc in s.scenarios:
            failed = [d for d in s.dts if s.diverged(sc, c, d)]
            if failed:
                times = ", ".join(f"{dt_text(d)}@{fmt(s.get(sc, c, d, 'diverged_at_s', 'value'))}s"
                                  for d in failed)
                cells.append(f"{sc}: {times}")
        rows.append([label(c), "; ".join(cells) if cells else "none"])
    out += ["Diverged runs over the whole sweep (dt@time):", "",
            md_table(["solver", "diverged"], rows), ""]

    # timing
    multibody = PAIRWISE_CONFIG
    rows = []
    for c in s.configs:
        row = [label(c)]
        for sc in s.scenarios:
            us = s.get(sc, c, dt, "step_us", "median")
            ref = s.get(sc, multibody, dt, "step_us", "median")
            ratio = ""
            if c != multibody and us > 0 and ref > 0:
                # whole times from 10x, one decimal below (a solver slower than the reference
                # reads 0.5x, not 0x)
                ratio = f" ({ref / us:.0f}x)" if ref >= 9.5 * us else f" ({ref / us:.1f}x)"
            row.append(fmt(us, 3) + ratio)
        rows.append(row)
    out += ["## Time per step", "",
            f"Median µs per step at dt = {dt_text(dt)} s; in brackets, how many times faster than "
            "bullet-multibody in the same run. These come from one timing pass on a shared "
            "machine; the benchmarks measure speed properly.", "",
            md_table(["solver"] + s.scenarios, rows), ""]

    if frontier:
        rows = []
        for r in frontier:
            quantity = r["quantity"]
            show = (lambda v: fmt(float(v), 3)) if quantity == "hz" else (
                lambda v: dt_text(float(v)))
            ok = show(r["largest_ok"]) if r["largest_ok"] else "none"
            bad = show(r["first_diverged"]) if r["first_diverged"] else "none in range"
            gap = fmt(float(r["pin_gap_at_largest_ok_m"])) if r["pin_gap_at_largest_ok_m"] else "–"
            rows.append([label((r["solver"], r["rule"])), quantity, ok, bad,
                         r["reason"] or "–", gap])
        out += ["## Stability frontier (yank, no air drag)", "",
                "The largest circle frequency (0.3 m circle, at dt = 1/240 s) and the largest dt "
                "(at 0.5 Hz) at which a puppet held only by its hand stays `ok`, bisected to 5 %. "
                "The pin gap says whether the hand was really followed.", "",
                md_table(["solver", "search", "largest ok", "first diverged", "why",
                          "pin gap at largest ok (m)"], rows), ""]

    out += humanoid_section(folder)
    out += robustness_section(read_robustness(folder))
    out += ablation_section(folder, frontier)
    out += ["## Findings", ""] + [f"- {f}" for f in findings(s, frontier, dt,
                                                             read_robustness(folder))] + [""]
    out += ["## Plots", ""]
    for title, path in plots:
        if path:
            out += [f"### {title}", "", f"![{title}](plots/{os.path.basename(path)})", ""]
    return out
