#!/usr/bin/python3
"""Plots and REPORT.md from the testbed's CSV files, and nothing else.

    scripts/plot.py [RESULTS]            (default: results/)
    scripts/plot.py --section TITLE [RESULTS]   (one section of the report, to stdout)

reads RESULTS/main/summary.csv and RESULTS/main/traces/*.csv (testbed run --out RESULTS/main),
RESULTS/frontier/frontier.csv (testbed frontier, optional) and the optional folders beside them
(truths-open-limits, humanoid, robustness, ablation), and writes RESULTS/plots/*.png and RESULTS/REPORT.md. It runs on the distribution's python3 and
python3-matplotlib (hence /usr/bin/python3, not whatever python3 comes first on PATH).
"""

import csv
import math
import os
import sys
import tempfile
from collections import defaultdict
from datetime import datetime, timezone

import matplotlib

# the testbed's folders under RESULTS (each command replaces its own folder whole)
MAIN = "main"  # testbed run: summary.csv and traces/
FRONTIER = "frontier"  # testbed frontier: frontier.csv

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SCENARIOS = ["hang", "drag", "shake", "spin", "drop", "water", "tremble", "yank"]
RULES = ["literal", "smoothed", "weighted", "subtree", "relaxed", "xpbd", "tree"]
CONFIGS = [("procedural", r) for r in RULES] + [("bullet-multibody", ""), ("bullet-rigid", ""),
                                               ("mujoco", "")]
STYLE = {
    ("procedural", "literal"): ("#9ecae1", "o"),
    ("procedural", "smoothed"): ("#c6dbef", "v"),
    ("procedural", "weighted"): ("#6baed6", "s"),
    ("procedural", "subtree"): ("#3182bd", "D"),
    ("procedural", "relaxed"): ("#08519c", "^"),
    ("procedural", "xpbd"): ("#2ca02c", "P"),
    ("procedural", "tree"): ("#9467bd", "*"),
    ("bullet-multibody", ""): ("#000000", "o"),
    ("bullet-rigid", ""): ("#d62728", "s"),
    ("mujoco", ""): ("#8c564b", "X"),  # brown: orange rings mark diverged seeds
}
TABLE_DT = 1.0 / 240.0
STAGES = ["update", "adjust", "contacts", "velocities"]


class ReportError(Exception):
    pass


def label(config):
    solver, rule = config
    return f"{solver} {rule}" if rule else solver


def dt_text(dt):
    return f"1/{round(1.0 / dt)}"


def fmt(value, digits=2):
    if value is None or (isinstance(value, float) and math.isnan(value)):
        return "–"
    if value == 0:
        return "0"
    if abs(value) >= 1e4 or abs(value) < 1e-2:
        return f"{value:.{digits - 1}e}"
    return f"{value:.{digits}g}" if abs(value) < 1 else f"{value:.{max(digits, 3)}g}"


# the truths (compare/include/puppet/compare/sweep.h): the rows' references; which engine each
# one is and its dt h are read from the CSV's "truth_dt" rows
TRUTH, SECOND_TRUTH = "truth", "second-truth"
TRUTHS = (TRUTH, SECOND_TRUTH)
# a truth's error bar: BAR_MARGIN × 2^p/(2^p − 1) × |x_h − x_{h/2}|, p its order read from its runs
# at 2h, h and h/2, taken as at least MIN_ORDER (docs/design.md, "Metrics")
BAR_MARGIN = 1.5
MIN_ORDER = 0.5


class Summary:
    """summary.csv, indexed by (scenario, solver, rule, dt, metric, stat, reference)."""

    HEADER = ("scenario,solver,rule,dt,substeps,metric,stat,value,unit,model,reference,status,"
              "git_sha,machine").split(",")

    def __init__(self, path):
        self.values = {}
        self.status = {}
        self.dts = set()
        self.scenarios, self.configs = [], []
        with open(path, newline="") as f:
            reader = csv.reader(f)
            header = next(reader, None)
            if header != self.HEADER:
                raise ReportError(f"{path}: unexpected header {header}")
            for n, row in enumerate(reader, start=2):
                if len(row) != len(self.HEADER):
                    raise ReportError(f"{path}:{n}: {len(row)} fields, expected {len(self.HEADER)}")
                r = dict(zip(self.HEADER, row))
                dt = float(r["dt"])
                exact = 1 / round(1 / dt)  # every dt is 1/n; the CSV keeps 9 digits
                if abs(dt - exact) <= 1e-6 * exact:
                    dt = exact
                config = (r["solver"], r["rule"])
                value = float(r["value"]) if r["value"] else math.nan
                self.values[(r["scenario"], config, dt, r["metric"], r["stat"], r["reference"])] = value
                if r["reference"] == "" and r["metric"] == "joint_gap_m":
                    self.status[(r["scenario"], config, dt)] = r["status"]
                    self.dts.add(dt)
                    if r["scenario"] not in self.scenarios:
                        self.scenarios.append(r["scenario"])
                    if config not in self.configs:
                        self.configs.append(config)
                self.model, self.git_sha, self.machine = r["model"], r["git_sha"], r["machine"]
        if not self.values:
            raise ReportError(f"{path}: no rows")
        self.dts = sorted(self.dts)
        self.scenarios.sort(key=lambda s: SCENARIOS.index(s) if s in SCENARIOS else len(SCENARIOS))
        self.configs.sort(key=lambda c: CONFIGS.index(c) if c in CONFIGS else len(CONFIGS))

    def get(self, scenario, config, dt, metric, stat, reference=""):
        return self.values.get((scenario, config, dt, metric, stat, reference), math.nan)

    def diverged(self, scenario, config, dt):
        return self.status.get((scenario, config, dt)) == "diverged"

    def table_dt(self):
        return min(self.dts, key=lambda dt: abs(math.log(dt / TABLE_DT)))

    def truth_engine(self, reference=TRUTH):
        """(solver, h) of a truth, from its truth_dt rows; None when the run had no such truth"""
        for k, v in self.values.items():
            if k[3] == "truth_dt" and k[5] == reference:
                h = 1 / round(1 / v)
                return k[1][0], h
        return None

    def truths(self):
        return [r for r in TRUTHS if self.truth_engine(r)]

    def truth_text(self, reference=TRUTH):
        """"MuJoCo (RK4) at 1/7680 s": which engine a truth is"""
        if not self.truth_engine(reference):
            return "none"
        solver, h = self.truth_engine(reference)
        return f"{'MuJoCo (RK4)' if solver == 'mujoco' else solver} at {dt_text(h)} s"

    def truth_own(self, scenario, reference=TRUTH, scale=0.5, stat="reseeded_mean",
                  metric="pose_err_m"):
        """a truth's run at scale·h against its run at h"""
        engine = self.truth_engine(reference)
        if not engine:
            return math.nan
        solver, h = engine
        return self.get(scenario, (solver, ""), 1 / round(1 / (scale * h)), metric, stat, reference)

    def truth_check(self, scenario, reference=TRUTH, stat="reseeded_mean", metric="pose_err_m"):
        """a truth's own difference: its run at h/2 against it"""
        return self.truth_own(scenario, reference, 0.5, stat, metric)

    def truth_order(self, scenario, reference=TRUTH, stat="reseeded_mean", metric="pose_err_m"):
        """the order p of convergence: log2 of the 2h difference over the h/2 difference"""
        fine = self.truth_check(scenario, reference, stat, metric)
        coarse = self.truth_own(scenario, reference, 2.0, stat, metric)
        if not (fine > 0 and coarse > 0):
            return math.nan
        return math.log2(coarse / fine)

    def truth_bar(self, scenario, reference=TRUTH, stat="reseeded_mean", metric="pose_err_m"):
        """a bound on a truth's own error: BAR_MARGIN × 2^p/(2^p − 1) × its h/2 difference"""
        fine = self.truth_check(scenario, reference, stat, metric)
        p = self.truth_order(scenario, reference, stat, metric)
        p = MIN_ORDER if math.isnan(p) else max(p, MIN_ORDER)
        return BAR_MARGIN * 2 ** p / (2 ** p - 1) * fine

    def truths_agreement(self, scenario, stat, against=TRUTH, metric="pose_err_m"):
        """the other truth's run at its h against this one"""
        other = SECOND_TRUTH if against == TRUTH else TRUTH
        engine = self.truth_engine(other)
        if not engine or not self.truth_engine(against):
            return math.nan
        solver, h = engine
        return self.get(scenario, (solver, ""), h, metric, stat, against)

    def truth_limit(self, scenario, reference=TRUTH, stat="reseeded_mean", metric="pose_err_m"):
        """the smallest error a truth can judge (its floor): its error bar, and never below the
        other truth's error against it, judged as every solver is (re-seeded from its states)"""
        agreement = self.truths_agreement(scenario, stat, reference, metric)
        bar = self.truth_bar(scenario, reference, stat, metric)
        return bar if math.isnan(agreement) else max(bar, agreement)

    def has_second_truth(self):
        return self.truth_engine(SECOND_TRUTH) is not None


def read_frontier(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_trace(folder, model, scenario, config, dt):
    solver, rule = config
    name = f"{model}__{scenario}__{solver}__{rule or '-'}__{dt:.9g}.csv"
    path = os.path.join(folder, MAIN, "traces", name)
    if not os.path.exists(path):
        return None
    t, gap = [], []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            t.append(float(row["t"]))
            gap.append(float(row["joint_gap_max_m"]))
    return t, gap


def grid(n):
    cols = min(4, n)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows + 0.9), squeeze=False)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    return fig, list(axes.flat[:n])


def legend_below(fig, configs, extra=()):
    handles = [plt.Line2D([], [], color=STYLE.get(c, ("grey", "o"))[0],
                          marker=STYLE.get(c, ("grey", "o"))[1], label=label(c)) for c in configs]
    handles += list(extra)
    fig.legend(handles=handles, loc="lower center", ncol=min(len(handles), 4), frameon=False,
               fontsize=9)


def save(fig, folder, name, bottom=0.1):
    fig.tight_layout(rect=(0, bottom, 1, 1))
    path = os.path.join(folder, name)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_joint_gap(s, folder, out):
    dt = s.table_dt()
    fig, axes = grid(len(s.scenarios))
    for ax, scenario in zip(axes, s.scenarios):
        for config in s.configs:
            trace = read_trace(folder, s.model, scenario, config, dt)
            if trace is None:
                continue
            t, gap = trace
            color, _ = STYLE.get(config, ("grey", "o"))
            ax.semilogy(t, [max(g, 1e-17) for g in gap], color=color, lw=1.1)
            if s.diverged(scenario, config, dt) and t:
                ax.plot(t[-1], max(gap[-1], 1e-17), "x", color=color, ms=8, mew=2)
        ax.set_title(scenario)
        ax.set_xlabel("t (s)")
        ax.set_ylabel("max joint gap (m)")
        ax.set_ylim(1e-17, 1)
        ax.grid(True, which="major", alpha=0.3)
    fig.suptitle(f"Joint gap over time, dt = {dt_text(dt)} s (x: the run diverged there; "
                 "1e-17 stands for 0)")
    legend_below(fig, s.configs)
    return save(fig, out, "joint_gap.png")


def plot_error_vs_dt(s, out, metric, unit, name):
    fig, axes = grid(len(s.scenarios))
    for ax, scenario in zip(axes, s.scenarios):
        shown = []
        for config in s.configs:
            xs = [dt for dt in s.dts if not math.isnan(s.get(scenario, config, dt, metric,
                                                            "reseeded_mean", "truth"))]
            ys = [s.get(scenario, config, dt, metric, "reseeded_mean", "truth") for dt in xs]
            if not xs:
                continue
            shown += ys
            color, marker = STYLE.get(config, ("grey", "o"))
            ax.loglog(xs, ys, color=color, marker=marker, ms=4, lw=1.1)
            partial = [(x, y) for x, y in zip(xs, ys)
                       if s.get(scenario, config, x, "reseeded_diverged", "count", "truth") > 0]
            if partial:
                ax.plot(*zip(*partial), "o", mfc="none", mec="#ff7f0e", ms=10, mew=1.5)
        limit = s.truth_limit(scenario, metric=metric)
        positive = [v for v in shown + [limit] if v > 0 and not math.isnan(v)]
        if positive:
            low, high = min(positive) / 3, max(positive) * 3
            ax.set_ylim(low, high)
            if not math.isnan(limit):
                ax.axhspan(low, limit, color="0.88", zorder=0)
                ax.axhline(limit, color="0.5", ls="--", lw=1)
        ax.set_title(scenario)
        ax.set_xlabel("dt (s)")
        ax.set_ylabel(f"re-seeded error ({unit})")
        ax.grid(True, which="major", alpha=0.3)
    fig.suptitle(f"Re-seeded {metric} against the truth (mean of 8 seeds, 0.5 s each); grey: "
                 "within the truth's error bar")
    extra = [plt.Line2D([], [], ls="none", marker="o", mfc="none", mec="#ff7f0e", ms=9,
                        label="some seeds diverged")]
    legend_below(fig, s.configs, extra)
    return save(fig, out, name)


def plot_speed_accuracy(s, out):
    fig, axes = grid(len(s.scenarios))
    for ax, scenario in zip(axes, s.scenarios):
        for config in s.configs:
            points = []
            for dt in s.dts:
                x = s.get(scenario, config, dt, "realtime_factor", "value")
                y = s.get(scenario, config, dt, "pose_err_m", "reseeded_mean", "truth")
                if not math.isnan(x) and not math.isnan(y):
                    points.append((x, y, dt))
            if not points:
                continue
            color, marker = STYLE.get(config, ("grey", "o"))
            ax.loglog([p[0] for p in points], [p[1] for p in points], color=color, marker=marker,
                      ms=4, lw=1.1)
            ax.annotate(dt_text(points[0][2]), (points[0][0], points[0][1]), fontsize=6,
                        color=color, xytext=(3, 2), textcoords="offset points")
        limit = s.truth_limit(scenario)
        if not math.isnan(limit):
            ax.axhline(limit, color="0.5", ls="--", lw=1)
        ax.set_title(scenario)
        ax.set_xlabel("real-time factor (simulated s / wall s)")
        ax.set_ylabel("re-seeded pose error (m)")
        ax.grid(True, which="major", alpha=0.3)
    fig.suptitle("Speed against accuracy, one point per dt (labelled: the smallest); up-left is "
                 "worse, down-right better; dashed: the truth's error bar")
    legend_below(fig, s.configs)
    return save(fig, out, "speed_accuracy.png")


def plot_stage_time(s, out):
    dt = s.table_dt()
    rules = [c for c in s.configs if c[0] == "procedural"]
    if not rules:
        return None
    fig, axes = grid(len(rules))
    colors = ["#1b9e77", "#d95f02", "#7570b3", "#e7298a"]
    top = 0.0
    for ax, config in zip(axes, rules):
        bottom = [0.0] * len(s.scenarios)
        for stage, color in zip(STAGES, colors):
            heights = [s.get(sc, config, dt, f"{stage}_us", "median") for sc in s.scenarios]
            heights = [0.0 if math.isnan(h) else h for h in heights]
            ax.bar(s.scenarios, heights, bottom=bottom, color=color, label=stage)
            bottom = [b + h for b, h in zip(bottom, heights)]
        top = max(top, max(bottom))
        ax.set_title(label(config))
        ax.set_ylabel("median time per step (µs)")
        ax.tick_params(axis="x", rotation=60)
    for ax in axes:
        ax.set_ylim(0, top * 1.08)
    fig.suptitle(f"Procedural solver, time per stage, dt = {dt_text(dt)} s (stage clocks on)")
    handles = [plt.Rectangle((0, 0), 1, 1, color=c, label=st) for st, c in zip(STAGES, colors)]
    fig.legend(handles=handles, loc="lower center", ncol=4, frameon=False)
    return save(fig, out, "stage_time.png", bottom=0.08)


def plot_frontier(rows, out):
    if not rows:
        return None
    fig, axes = plt.subplots(1, 2, figsize=(13, 0.5 * len(rows) / 2 + 2.0))
    for ax, quantity in zip(axes, ["hz", "dt"]):
        chosen = [r for r in rows if r["quantity"] == quantity]
        if not chosen:
            ax.set_visible(False)
            continue
        values = [float(r[k]) for r in chosen for k in ("largest_ok", "first_diverged") if r[k]]
        base, top = min(values) / 2, max(values) * 12
        show = (lambda v: fmt(v, 3)) if quantity == "hz" else dt_text
        ys = list(range(len(chosen)))[::-1]
        for y, r in zip(ys, chosen):
            color = STYLE.get((r["solver"], r["rule"]), ("grey", "o"))[0]
            if r["largest_ok"]:
                ok = float(r["largest_ok"])
                ax.barh(y, ok - base, left=base, color=color, edgecolor="black", lw=0.5)
                text = show(ok) if r["first_diverged"] else f"≥ {show(ok)} (top of range)"
                gap = float(r["pin_gap_at_largest_ok_m"] or 0)
                if gap > 0.01:
                    text += f", hand pin {fmt(gap)} m off"
                ax.text(ok, y, " " + text, va="center", fontsize=8)
            else:
                ax.text(base, y, f"  diverges already at {show(float(r['first_diverged']))} "
                        f"({r['reason']})", va="center", fontsize=8, color="#d62728")
        ax.set_yticks(ys)
        ax.set_yticklabels([label((r["solver"], r["rule"])) for r in chosen])
        ax.set_xscale("log")
        ax.set_xlim(base, top)
        held = float(chosen[0]["held"])
        if quantity == "hz":
            ax.set_xlabel("largest circle frequency that stays ok (Hz)")
            ax.set_title(f"yank, 0.3 m circle, dt = {dt_text(held)} s")
        else:
            ax.set_xlabel("largest dt that stays ok (s)")
            ax.set_title(f"yank, 0.3 m circle at {fmt(held, 3)} Hz")
        ax.grid(True, axis="x", alpha=0.3)
    fig.suptitle("Stability frontier: a free puppet held only by the hand, no air drag "
                 "(bisected to 5 %)")
    fig.tight_layout()
    path = os.path.join(out, "frontier.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


# ---- the report ---------------------------------------------------------------------------


def md_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def geometric_mean(values):
    values = [v for v in values if v > 0 and not math.isnan(v)]
    return math.exp(sum(math.log(v) for v in values) / len(values)) if values else math.nan


def open_limits_agreement(folder, scenario):
    """the truths' re-seeded agreement for Pinocchio with its limits opened (main.sh)"""
    path = os.path.join(folder, "truths-open-limits", "summary.csv")
    if not os.path.exists(path):
        return "–"
    return fmt(Summary(path).truths_agreement(scenario, "reseeded_mean"))


def open_limits_section(folder):
    """every solver against both truths for Pinocchio with its limits opened (main.sh)"""
    path = os.path.join(folder, "truths-open-limits", "summary.csv")
    if not os.path.exists(path):
        return []
    o = Summary(path)
    if not o.has_second_truth():
        return []
    dt = o.table_dt()

    def cell(sc, c):
        a = o.get(sc, c, dt, "pose_err_m", "reseeded_mean", "truth")
        b = o.get(sc, c, dt, "pose_err_m", "reseeded_mean", SECOND_TRUTH)
        if math.isnan(a) and math.isnan(b):
            return "div" if o.diverged(sc, c, dt) else "–"
        return f"{fmt(a)} / {fmt(b)}" + (" †" if o.diverged(sc, c, dt) else "")

    pins = any(k[3] == "pin_gap_m" and k[5] in TRUTHS for k in o.values)
    rows = [[sc] + [fmt(o.truth_bar(sc)), fmt(o.truth_bar(sc, SECOND_TRUTH)),
                    fmt(o.truths_agreement(sc, "reseeded_mean"))] +
            ([fmt(o.truths_agreement(sc, stat, against, "pin_gap_m"))
              for against in (SECOND_TRUTH, TRUTH) for stat in ("max", "rms")]
             if pins else []) for sc in o.scenarios]
    return ["## Both truths, limits opened", "",
            f"`truths-open-limits/`: `{o.model}` (every joint free), where the two engines "
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


def humanoid_section(folder):
    """the main scenarios on models/humanoid.xml in every solver (main.sh)"""
    path = os.path.join(folder, "humanoid", "summary.csv")
    if not os.path.exists(path):
        return []
    h = Summary(path)
    dt = h.table_dt()
    second = h.has_second_truth()

    def cell(sc, c):
        if (sc, c, dt) not in h.status:
            return "–"
        if h.diverged(sc, c, dt):
            return f"div@{fmt(h.get(sc, c, dt, 'diverged_at_s', 'value'))}s"
        parts = [fmt(h.get(sc, c, dt, "pose_err_m", "reseeded_mean", "truth"))]
        if second:
            parts.append(fmt(h.get(sc, c, dt, "pose_err_m", "reseeded_mean", SECOND_TRUTH)))
        return " / ".join(parts) + f", gap {fmt(h.get(sc, c, dt, 'joint_gap_m', 'max'))}"

    out = ["## The humanoid (`models/humanoid.xml`)", "",
           f"`humanoid/`: the scenarios on `{h.model}` (MJCF after MuJoCo's classic humanoid, "
           "docs/mjcf.md), every solver, dt = " + dt_text(dt) + " s. Each cell: re-seeded pose "
           "error against the truth" + (" / against the second truth" if second else "") +
           " (m), and the largest joint gap (m); `div@t`: the run diverged at t.", "",
           md_table(["scenario"] + [label(c) for c in h.configs],
                    [[sc] + [cell(sc, c) for c in h.configs] for sc in h.scenarios]), ""]
    if all(math.isnan(h.truth_bar(sc)) for sc in h.scenarios):
        return out + [f"The humanoid is judged against its first truth alone ({h.truth_text()}), "
                      "at its own dt only (`--first-truth-only`): no error bar, no second truth. "
                      "It shows the scenarios on a second model; the judging with error bars is "
                      "Pinocchio's.", ""]
    rows = [[sc, fmt(h.truth_bar(sc))] +
            ([fmt(h.truth_bar(sc, SECOND_TRUTH)), fmt(h.truths_agreement(sc, "reseeded_mean"))]
             if second else []) for sc in h.scenarios]
    out += [f"The truths on the humanoid ({h.truth_text()}"
            + (f"; second {h.truth_text(SECOND_TRUTH)}" if second else "") + "): each one's "
            "error bar and their agreement (re-seeded pose error, m):", "",
            md_table(["scenario", "truth's bar"] +
                     (["second truth's bar", "truths' agreement"] if second else []), rows), ""]
    return out


ROBUSTNESS = "robustness"  # testbed robustness: robustness_summary.csv, worst.csv


def read_robustness(folder):
    """RESULTS/robustness/robustness_summary.csv (testbed robustness), or None"""
    path = os.path.join(folder, ROBUSTNESS, "robustness_summary.csv")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        rows = list(csv.DictReader(f))
    expected = ["scenario", "solver", "rule", "dt", "runs", "diverged", "rate", "ci95_low",
                "ci95_high"]
    if not rows or list(rows[0].keys()) != expected:
        raise ReportError(f"{path}: unexpected header (expected {','.join(expected)})")
    for r in rows:
        for key in ("dt", "rate", "ci95_low", "ci95_high"):
            r[key] = float(r[key])
        for key in ("runs", "diverged"):
            r[key] = int(r[key])
    return rows


def robustness_section(rows):
    if not rows:
        return []
    scenarios = [sc for sc in SCENARIOS if any(r["scenario"] == sc for r in rows)]
    configs = [c for c in CONFIGS if any((r["solver"], r["rule"]) == c for r in rows)]
    dts = sorted({r["dt"] for r in rows})
    by_key = {(r["scenario"], (r["solver"], r["rule"]), r["dt"]): r for r in rows}
    runs = sorted({r["runs"] for r in rows})
    out = ["## Robustness over random starts", "",
           f"`{ROBUSTNESS}/`: `testbed robustness`, each scenario from "
           f"{' or '.join(str(n) for n in runs)} random starts (a pose and joint velocities "
           "inside the limits, the tilt, the grab's point, frequency and phase; "
           "docs/robustness.md). Each cell: the share of runs that diverged (the testbed's "
           "criteria) and its 95 % Wilson interval. `worst.csv` has the worst starts of each "
           "configuration as `testbed run` and viewer command lines.", ""]
    for d in dts:
        def cell(sc, c):
            r = by_key.get((sc, c, d))
            if r is None:
                return "–"
            return f"{r['rate']:.2f} [{r['ci95_low']:.2f}, {r['ci95_high']:.2f}]"
        out += [f"dt = {dt_text(d)} s:", "",
                md_table(["solver"] + scenarios,
                         [[label(c)] + [cell(sc, c) for sc in scenarios] for c in configs]), ""]
    return out


def plot_robustness(rows, out):
    if not rows:
        return None
    scenarios = [sc for sc in SCENARIOS if any(r["scenario"] == sc for r in rows)]
    configs = [c for c in CONFIGS if any((r["solver"], r["rule"]) == c for r in rows)]
    dts = sorted({r["dt"] for r in rows})
    by_key = {(r["scenario"], (r["solver"], r["rule"]), r["dt"]): r for r in rows}
    fig, axes = plt.subplots(len(dts), 1, figsize=(11, 3.6 * len(dts)), squeeze=False)
    width = 0.8 / max(len(configs), 1)
    for row, d in enumerate(dts):
        ax = axes[row][0]
        for k, c in enumerate(configs):
            colour, marker = STYLE[c]
            xs, ys, lo, hi = [], [], [], []
            for i, sc in enumerate(scenarios):
                r = by_key.get((sc, c, d))
                if r is None:
                    continue
                xs.append(i - 0.4 + (k + 0.5) * width)
                ys.append(r["rate"])
                lo.append(max(0.0, r["rate"] - r["ci95_low"]))  # 9 digits: -1e-10 is 0
                hi.append(max(0.0, r["ci95_high"] - r["rate"]))
            ax.errorbar(xs, ys, yerr=[lo, hi], fmt=marker, color=colour, ecolor=colour,
                        markersize=5, capsize=2, linewidth=1, label=label(c))
        ax.set_xticks(range(len(scenarios)))
        ax.set_xticklabels(scenarios)
        ax.set_ylim(-0.03, 1.03)
        ax.set_ylabel("share diverged")
        ax.set_title(f"Random starts, dt = {dt_text(d)} s (bars: 95 % Wilson interval)")
        ax.grid(axis="y", alpha=0.3)
    legend_below(fig, configs)
    return save(fig, out, "robustness.png", bottom=0.12)


# the verdict (testbed verdict): per solver, scenario and budget, the cheapest configuration
VERDICT = "verdict"  # testbed verdict: verdict.csv, candidates.csv
# the budget of the README's headline
HEADLINE_BUDGET = 0.01


class Verdict:
    """RESULTS/verdict/verdict.csv and candidates.csv (testbed verdict)"""

    def __init__(self, folder):
        path = os.path.join(folder, VERDICT, "verdict.csv")
        with open(path, newline="") as f:
            self.rows = list(csv.DictReader(f))
        with open(os.path.join(folder, VERDICT, "candidates.csv"), newline="") as f:
            self.candidates = list(csv.DictReader(f))
        if not self.rows:
            raise ReportError(f"{path}: no rows")
        for r in self.rows:
            for key in ("budget_m", "dt", "cost_us_per_s", "us_per_frame", "puppets_per_core",
                        "error_m", "divergence_upper", "best_error_m", "truth_floor_m",
                        "frame_hz"):
                r[key] = float(r[key]) if r[key] else math.nan
            r["config"] = (r["solver"], r["rule"])
        for c in self.candidates:
            for key in ("dt", "cost_us_per_s", "error_m", "truth_floor_m"):
                c[key] = float(c[key]) if c[key] else math.nan
            c["config"] = (c["solver"], c["rule"])
            c["starts"], c["diverged_starts"] = int(c["starts"]), int(c["diverged_starts"])
        first = self.rows[0]
        self.model, self.git_sha, self.machine = first["model"], first["git_sha"], first["machine"]
        self.truth, self.frame_hz = first["truth"], first["frame_hz"]
        self.budgets = sorted({r["budget_m"] for r in self.rows})
        self.scenarios = ordered({r["scenario"] for r in self.rows}, SCENARIOS)
        self.configs = ordered({r["config"] for r in self.rows}, CONFIGS)
        self.by_key = {(r["scenario"], r["config"], r["view"], r["budget_m"]): r
                       for r in self.rows}
        self.starts = max((int(r["starts"]) for r in self.rows if r["starts"]), default=0)
        self.floor = {r["scenario"]: r["truth_floor_m"] for r in self.rows}

    def row(self, scenario, config, view, budget):
        return self.by_key.get((scenario, config, view, budget))

    def judged(self, scenario, budget):
        """a budget the truth can judge in this scenario (at or above its floor)"""
        return budget >= self.floor[scenario]

    def cheapest(self, scenario, view, budget, procedural):
        """the met row of the cheapest procedural rule, or of the cheapest reference engine (any
        other solver), or None"""
        met = [self.row(scenario, c, view, budget) for c in self.configs
               if (c[0] == "procedural") == procedural]
        met = [r for r in met if r and r["verdict"] == "met"]
        return min(met, key=lambda r: r["cost_us_per_s"]) if met else None

    def cheapest_reference(self, scenario, view, budget):
        return self.cheapest(scenario, view, budget, procedural=False)

    def cheapest_procedural(self, scenario, view, budget):
        return self.cheapest(scenario, view, budget, procedural=True)


def ordered(names, known):
    """the names in the order of `known`, any others after them, sorted"""
    return [n for n in known if n in names] + sorted(n for n in names if n not in known)


def read_verdict(folder):
    if not os.path.exists(os.path.join(folder, VERDICT, "verdict.csv")):
        return None
    return Verdict(folder)


WHY = {"diverges": "diverges", "error-floor": "error floor", "not-robust": "not robust",
       "not-measured": "not measured", "refused": "refused"}


def budget_name(budget):
    """1 mm, 1 cm, 5 cm"""
    return f"{budget * 100:g} cm" if budget >= 0.01 - 1e-12 else f"{budget * 1000:g} mm"


def setting_text(row):
    """a chosen configuration in a few words: 1/120 s, 8 substeps"""
    text = dt_text(row["dt"]) + " s"
    flags = row["setting"].split()
    for flag, value in zip(flags[::2], flags[1::2]):
        if flag == "--mujoco-integrator":
            text += ", " + {"rk4": "RK4", "euler": "Euler"}.get(value, value)
            continue
        noun = {"--substeps": "substep", "--iterations": "sweep",
                "--bullet-iterations": "sweep"}.get(flag, flag)
        text += f", {value} {noun}{'' if value == '1' else 's'}"
    return text


def verdict_cell(v, scenario, config, view, budget, show_setting=False):
    r = v.row(scenario, config, view, budget)
    if r is None:
        return "–"
    if r["verdict"] != "met":
        text = WHY.get(r["verdict"], r["verdict"])
        if r["verdict"] == "error-floor":
            text += f" ({fmt(r['best_error_m'])} m)"
        return text
    cost = r["us_per_frame"] if view == "frame" else r["cost_us_per_s"]
    text = f"{cost:,.0f}" if cost >= 100 else fmt(cost, 2)
    reference = v.cheapest_reference(scenario, view, budget)
    if reference and config[0] == "procedural":
        ratio = reference["cost_us_per_s"] / r["cost_us_per_s"]
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


def verdict_headline(folder, budget=HEADLINE_BUDGET):
    """the README's headline: µs per simulated second at one budget, per solver and scenario"""
    v = Verdict(folder)
    table, refused = verdict_table(v, "second", budget)
    return (f"CPU µs per simulated second to keep Pinocchio within {budget_name(budget)} of "
            f"the truth ({v.truth}) and never diverge in {v.starts} random starts, with the "
            "cheapest configuration each solver has (dt from 1/30 to 1/960 s, its substeps or "
            "sweeps); in brackets, how many times cheaper than the cheapest reference engine "
            "(`(ref)`: that engine). From `results/verdict/verdict.csv` (commit "
            f"`{v.git_sha}`, {v.machine}), printed by `scripts/readme_headline.py`. "
            + refused_text(v, refused) + "\n\n" + table + "\n\n"
            + "\n".join(f"- {line}" for line in family_findings(v, budgets=[budget])) + "\n")


def family_findings(v, view="second", budgets=None):
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
                ratio = r["cost_us_per_s"] / p["cost_us_per_s"]
                (wins if ratio >= 1 else losses).append(
                    f"{sc} ({p['rule']}, {ratio:.2g}× as fast as {label(r['config'])})")
            elif p:
                wins.append(f"{sc} ({p['rule']}; no reference meets it)")
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
           "was measured: dt from 1/30 to 1/960 s, and xpbd's and tree's substeps, relaxed's "
           "sweeps, Bullet's sweeps and MuJoCo's integrator (`candidates.csv`). Each was timed "
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
           "cheapest reference engine (`(ref)`); otherwise why none: `diverges` (every "
           "configuration), `error floor` (its least error, m), `not robust` (within the "
           "budget only where a random start diverged). The budget is on the pose error: a "
           "solver may meet it with its joints opened (the joint gaps are in \"Joint gaps and "
           "divergence\"). Why the exact solvers read `not robust` in the two-pin scenarios: "
           "docs/tried.md, \"The verdict's search and its random starts\".", ""]
    out += ["Where the procedural family wins and where it loses (its cheapest rule against the "
            "cheapest reference, per simulated second):", ""]
    out += [f"- {line}" for line in family_findings(v)] + [""]
    for budget in v.budgets:
        table, refused = verdict_table(v, "second", budget, show_setting=True)
        out += [f"### Within {budget_name(budget)}, any dt", "", table, "",
                refused_text(v, refused), ""]
    for budget in v.budgets:
        table, refused = verdict_table(v, "frame", budget, show_setting=True)
        hz = f"{v.frame_hz:g}"
        puppets = frame_puppets(v, budget)
        out += [f"### Within {budget_name(budget)} at {hz} Hz", "",
                f"µs per {hz} Hz frame, the frame taken in whole steps (dt = 1/{hz} s or a "
                f"divisor of it). A core keeps 10⁶/({hz} × µs per frame) puppets at {hz} Hz"
                + (": in drag " + ", ".join(f"{label(c)} {n:,.0f}" for c, n in puppets)
                   if puppets else "") + ".", "", table, "", refused_text(v, refused), ""]
    return out


def frame_puppets(v, budget, scenario="drag"):
    out = []
    for c in v.configs:
        r = v.row(scenario, c, "frame", budget)
        if r and r["verdict"] == "met":
            out.append((c, r["puppets_per_core"]))
    return out


def wilson_upper(k, n, z=1.959963984540054):
    """the upper end of the 95 % Wilson score interval of k in n"""
    p = k / n
    centre = p + z * z / (2 * n)
    spread = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return (centre + spread) / (1 + z * z / n)


def plot_verdict(v, out):
    """cost against error budget per solver and scenario: the cheapest candidate within each
    error (its scenario run and re-seeded runs finished; random starts not required), and the
    verdict's choices (which survived them) as filled markers"""
    if v is None:
        return None
    fig, axes = grid(len(v.scenarios))
    for ax, scenario in zip(axes, v.scenarios):
        floor = v.floor[scenario]
        for config in v.configs:
            mine = [c for c in v.candidates if c["scenario"] == scenario and c["config"] == config
                    and c["status"] == "ok" and not math.isnan(c["error_m"])]
            if not mine:
                continue
            mine.sort(key=lambda c: c["error_m"])
            # the cheapest within each error: a staircase falling as the budget grows
            xs, ys, cheapest = [], [], math.inf
            for c in mine:
                cheapest = min(cheapest, c["cost_us_per_s"])
                xs.append(c["error_m"])
                ys.append(cheapest)
            colour, marker = STYLE.get(config, ("grey", "o"))
            ax.step(xs, ys, where="post", color=colour, lw=1.1)
            chosen = [v.row(scenario, config, "second", b) for b in v.budgets]
            chosen = [r for r in chosen if r and r["verdict"] == "met"]
            ax.plot([r["budget_m"] for r in chosen], [r["cost_us_per_s"] for r in chosen],
                    ls="none", marker=marker, color=colour, ms=6)
        ax.axvspan(1e-6, floor, color="0.85", zorder=0)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlim(1e-4, 1.0)
        ax.set_title(scenario)
        ax.set_xlabel("error budget (m)")
        ax.set_ylabel("CPU µs per simulated second")
        ax.grid(True, which="major", alpha=0.3)
    fig.suptitle("Cost against error budget: lines, the cheapest configuration within each error; "
                 f"markers, the verdict's choice at each budget (survived {v.starts} random "
                 "starts); grey: below the truth's floor")
    legend_below(fig, v.configs)
    return save(fig, out, "verdict.png")

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
    pair_configs = [c for c in s.configs if c != ("bullet-multibody", "")]
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
    multibody = ("bullet-multibody", "")
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


ABLATION_SCENARIOS = ["hang", "drag", "yank"]


def read_ablation(folder):
    """results/ablation: configs.csv and one summary.csv per configuration (scripts/ablation.sh)"""
    path = os.path.join(folder, "ablation", "configs.csv")
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        configs = list(csv.DictReader(f))
    for c in configs:
        c["summary"] = Summary(os.path.join(folder, "ablation", c["name"], "summary.csv"))
    return configs


def ablation_cell(s, scenario, config):
    """re-seeded pose error (m) / largest joint gap (m), or the divergence"""
    dt = s.table_dt()
    if (scenario, config, dt) not in s.status:
        return "–"
    error = s.get(scenario, config, dt, "pose_err_m", "reseeded_mean", "truth")
    gap = s.get(scenario, config, dt, "joint_gap_m", "max")
    cell = f"{fmt(error)} / {fmt(gap)}"
    if s.diverged(scenario, config, dt):
        cell += f" (div@{fmt(s.get(scenario, config, dt, 'diverged_at_s', 'value'))}s)"
    return cell


def ablation_findings(by_name):
    """sentences read from the ablation's numbers"""
    def value(name, scenario, metric, stat, reference=""):
        if name not in by_name:
            return math.nan
        s = by_name[name]["summary"]
        config = next(k for k in s.configs if k[0] == "procedural")
        return s.get(scenario, config, s.table_dt(), metric, stat, reference)

    def error(name, scenario):
        return value(name, scenario, "pose_err_m", "reseeded_mean", "truth")

    def gap(name, scenario):
        return value(name, scenario, "joint_gap_m", "max")

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
        for config in [c for c in s.configs if c[0] == "procedural"]:
            ratios = []
            for sc in s.scenarios:
                a = s.get(sc, config, coarse, "pose_err_m", "reseeded_mean", "truth")
                b = s.get(sc, config, fine, "pose_err_m", "reseeded_mean", "truth")
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
        config = next(k for k in s.configs if k[0] == "procedural")
        rows.append([c["label"], f"`{c['flags'].replace('--solver procedural ', '')}`"] +
                    [ablation_cell(s, sc, config) for sc in ABLATION_SCENARIOS])
    out += [md_table(["configuration", "flags"] + ABLATION_SCENARIOS, rows), ""]
    out += ablation_findings(by_name)
    if "open-limits" in by_name:
        s = by_name["open-limits"]["summary"]
        rows = []
        for config in [c for c in s.configs if c[0] == "procedural"]:
            for sc in s.scenarios:
                errors = [s.get(sc, config, dt, "pose_err_m", "reseeded_mean", "truth")
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
                    pin = s.get(sc, config, s.table_dt(), "pin_gap_m", "rms")
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


def findings(s, frontier, dt, robustness=None):
    found = []
    multibody = ("bullet-multibody", "")
    rules = [c for c in s.configs if c[0] == "procedural"]
    finished = [sc for sc in s.scenarios
                if all(not math.isnan(s.get(sc, c, dt, "pose_err_m", "reseeded_mean", "truth"))
                       for c in rules + [multibody] if c in s.configs)]
    if rules and finished:
        score = {c: geometric_mean([s.get(sc, c, dt, "pose_err_m", "reseeded_mean", "truth")
                                    for sc in finished]) for c in rules}
        best = min(score, key=score.get)
        ref = geometric_mean([s.get(sc, multibody, dt, "pose_err_m", "reseeded_mean", "truth")
                              for sc in finished])
        text = (f"Of the procedural rules, **{best[1]}** tracks the truth best: a re-seeded pose "
                f"error of {fmt(score[best])} m (geometric mean over {', '.join(finished)}) at "
                f"dt = {dt_text(dt)} s")
        if not math.isnan(ref):
            text += (f", against {fmt(ref)} m for bullet-multibody at the same dt "
                     f"({score[best] / ref:.1f}x)")
        found.append(text + ".")
        fine, coarse = s.dts[0], s.dts[-1]

        def mean_at(config, d):
            return geometric_mean([s.get(sc, config, d, "pose_err_m", "reseeded_mean", "truth")
                                   for sc in finished])

        if len(s.dts) > 1 and multibody in s.configs:
            found.append(
                f"Across dt the best procedural rule's error hardly moves: {best[1]} has "
                f"{fmt(mean_at(best, fine))} m at dt = {dt_text(fine)} s and "
                f"{fmt(mean_at(best, coarse))} m at {dt_text(coarse)} s, while bullet-multibody "
                f"goes from {fmt(mean_at(multibody, fine))} m to {fmt(mean_at(multibody, coarse))} "
                "m (\"What made the difference\" finds where the floor comes from).")
    limits = {sc: s.truth_limit(sc) for sc in s.scenarios} if s.truths() else {}
    loose = [sc for sc in limits if limits[sc] > 0.01]
    if loose:
        found.append(
            "The truth cannot judge errors below a centimetre everywhere: its floor (its error "
            "bar or the truths' disagreement, whichever is larger) is "
            + ", ".join(f"{fmt(limits[sc])} m in {sc}" for sc in loose)
            + " (the `≤` cells).")
    rigid = ("bullet-rigid", "")
    if rigid in s.configs:
        gaps = {sc: s.get(sc, rigid, dt, "joint_gap_m", "max") for sc in s.scenarios}
        worst = max(gaps, key=lambda k: -1 if math.isnan(gaps[k]) else gaps[k])
        coarse_worst = max((s.get(sc, rigid, s.dts[-1], "joint_gap_m", "max"), sc)
                           for sc in s.scenarios)
        found.append(
            f"The Bullet ragdoll (bullet-rigid) opens its joints: up to {fmt(gaps[worst])} m in "
            f"{worst} at dt = {dt_text(dt)} s and {fmt(coarse_worst[0])} m in {coarse_worst[1]} at "
            f"{dt_text(s.dts[-1])} s"
            f"{' (before it diverged)' if s.diverged(coarse_worst[1], rigid, s.dts[-1]) else ''}.")
    closed, opened = [], []
    for c in s.configs:
        if c == rigid:
            continue
        worst = max(((s.get(sc, c, dt, "joint_gap_m", "max"), sc) for sc in s.scenarios),
                    key=lambda p: -1 if math.isnan(p[0]) else p[0])
        (closed if worst[0] < 1e-9 else opened).append((c, worst))
    if closed:
        verb = "keeps" if len(closed) == 1 else "keep"
        text = (f"At dt = {dt_text(dt)} s, {', '.join(label(c) for c, _ in closed)} {verb} every "
                "joint closed to rounding (< 1e-9 m) in every scenario, up to any divergence")
        if opened:
            text += "; " + ", ".join(f"{label(c)} opens {fmt(w[0])} m in {w[1]}"
                                     for c, w in opened)
        found.append(text + ".")
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
        if r["quantity"] != "hz":
            continue
        name = label((r["solver"], r["rule"]))
        if not r["largest_ok"]:
            found.append(f"Held by the hand (yank), {name} diverges even at "
                         f"{fmt(float(r['first_diverged']), 3)} Hz ({r['reason']}).")
        elif not r["first_diverged"]:
            found.append(f"Held by the hand (yank), {name} stays ok up to the top of the range, "
                         f"{fmt(float(r['largest_ok']), 3)} Hz, with the hand pin up to "
                         f"{fmt(float(r['pin_gap_at_largest_ok_m']))} m from its target.")
        else:
            found.append(f"Held by the hand (yank), {name} stays ok up to "
                         f"{fmt(float(r['largest_ok']), 3)} Hz and diverges at "
                         f"{fmt(float(r['first_diverged']), 3)} Hz ({r['reason']}).")
    speeds = {c: geometric_mean([s.get(sc, c, dt, "step_us", "median") for sc in s.scenarios])
              for c in s.configs}
    if multibody in speeds and not math.isnan(speeds[multibody]):
        parts = [f"{label(c)} {speeds[multibody] / v:.1f}x" for c, v in speeds.items()
                 if c != multibody and not math.isnan(v)]
        found.append(f"Time per step against bullet-multibody ({fmt(speeds[multibody], 3)} µs, "
                     f"geometric mean over scenarios): {', '.join(parts)} faster.")
    found += robustness_findings(robustness)
    return found


def robustness_findings(rows):
    """per dt of the robustness sweep: who never diverged, and each configuration's worst scenario"""
    if not rows:
        return []
    found = []
    for d in sorted({r["dt"] for r in rows}, reverse=True):
        at = [r for r in rows if r["dt"] == d]
        configs = [c for c in CONFIGS if any((r["solver"], r["rule"]) == c for r in at)]
        never = [label(c) for c in configs
                 if all(r["diverged"] == 0 for r in at if (r["solver"], r["rule"]) == c)]
        worst = []
        for c in configs:
            mine = [r for r in at if (r["solver"], r["rule"]) == c and r["diverged"] > 0]
            if mine:
                r = max(mine, key=lambda r: r["rate"])
                worst.append(f"{label(c)} {r['diverged']}/{r['runs']} in {r['scenario']}")
        runs = sorted({r["runs"] for r in at})
        found.append(f"From {' or '.join(str(n) for n in runs)} random starts per scenario at "
                     f"dt = {dt_text(d)} s: "
                     + (f"{', '.join(never)} never diverged, and the others' worst scenario "
                        if never else "every solver diverged somewhere; each one's worst ")
                     + "(runs diverged of runs): " + ", ".join(worst) + ".")
    return found


def write_atomically(path, text):
    folder = os.path.dirname(path) or "."
    fd, temporary = tempfile.mkstemp(dir=folder, suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.replace(temporary, path)


def main(argv):
    title = None
    if len(argv) >= 3 and argv[1] == "--section":
        title = argv[2]
        argv = argv[:1] + argv[3:]
    if len(argv) > 2 or (len(argv) == 2 and argv[1].startswith("-")):
        print(__doc__.strip(), file=sys.stderr)
        return 2
    folder = argv[1] if len(argv) == 2 else "results"
    summary_path = os.path.join(folder, MAIN, "summary.csv")
    if not os.path.exists(summary_path):
        print(f"plot.py: {summary_path}: not found (run testbed run first)", file=sys.stderr)
        return 2
    try:
        s = Summary(summary_path)
        frontier = read_frontier(os.path.join(folder, FRONTIER, "frontier.csv"))
        read_robustness(folder)  # checked here; the report reads it again
        read_verdict(folder)
    except (ReportError, ValueError, KeyError) as error:
        print(f"plot.py: {error}", file=sys.stderr)
        return 2
    if title is not None:
        try:
            sys.stdout.write(section(s, frontier, folder, title))
        except ReportError as error:
            print(f"plot.py: {error}", file=sys.stderr)
            return 2
        return 0
    out = os.path.join(folder, "plots")
    os.makedirs(out, exist_ok=True)
    plots = [
        ("Joint gap over time", plot_joint_gap(s, folder, out)),
        ("Re-seeded pose error against dt",
         plot_error_vs_dt(s, out, "pose_err_m", "m", "error_vs_dt.png")),
        ("Re-seeded joint-angle error against dt",
         plot_error_vs_dt(s, out, "joint_angle_err_deg", "deg", "angle_error_vs_dt.png")),
        ("Speed against accuracy", plot_speed_accuracy(s, out)),
        ("Procedural stages", plot_stage_time(s, out)),
        ("Stability frontier", plot_frontier(frontier, out)),
        ("Robustness over random starts", plot_robustness(read_robustness(folder), out)),
        ("Cost against error budget", plot_verdict(read_verdict(folder), out)),
    ]
    report(s, frontier, plots, folder)
    written = [p for _, p in plots if p]
    print(f"wrote {os.path.join(folder, 'REPORT.md')} and {len(written)} plots under {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
