import math
import os
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from .catalogue import CANDIDATES_CSV as C
from .catalogue import FRONTIER_CSV as F
from .catalogue import ROBUSTNESS_CSV as R
from .catalogue import VERDICT_CSV as V
from .catalogue import (CANDIDATE_OK, CONFIGS, DT, FRONTIER_SCENARIO, HZ, MET, PER_SECOND, M,
                        RULES_ENGINE, SCENARIOS, ST, STAGES, TRUTH, stage_metric, style)
from .common import dt_text, fmt, label, ordered
from .readers import read_trace


def grid(n):
    cols = min(4, n)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.4 * rows + 0.9), squeeze=False)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    return fig, list(axes.flat[:n])


def legend_below(fig, configs, extra=()):
    handles = [plt.Line2D([], [], color=style(c)[0],
                          marker=style(c)[1], label=label(c)) for c in configs]
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
            color, _ = style(config)
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
                                                            ST.reseeded_mean, TRUTH))]
            ys = [s.get(scenario, config, dt, metric, ST.reseeded_mean, TRUTH) for dt in xs]
            if not xs:
                continue
            shown += ys
            color, marker = style(config)
            ax.loglog(xs, ys, color=color, marker=marker, ms=4, lw=1.1)
            partial = [(x, y) for x, y in zip(xs, ys)
                       if s.get(scenario, config, x, M.reseeded_diverged, ST.count, TRUTH) > 0]
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
                x = s.get(scenario, config, dt, M.realtime_factor, ST.value)
                y = s.get(scenario, config, dt, M.pose_err_m, ST.reseeded_mean, TRUTH)
                if not math.isnan(x) and not math.isnan(y):
                    points.append((x, y, dt))
            if not points:
                continue
            color, marker = style(config)
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
    rules = [c for c in s.configs if c[0] == RULES_ENGINE]
    if not rules:
        return None
    fig, axes = grid(len(rules))
    colors = ["#1b9e77", "#d95f02", "#7570b3", "#e7298a"]
    top = 0.0
    for ax, config in zip(axes, rules):
        bottom = [0.0] * len(s.scenarios)
        for stage, color in zip(STAGES, colors):
            heights = [s.get(sc, config, dt, stage_metric(stage), ST.median) for sc in s.scenarios]
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
    for ax, quantity in zip(axes, [HZ, DT]):
        chosen = [r for r in rows if r[F.quantity] == quantity]
        if not chosen:
            ax.set_visible(False)
            continue
        values = [float(r[k]) for r in chosen for k in ("largest_ok", "first_diverged") if r[k]]
        base, top = min(values) / 2, max(values) * 12
        show = (lambda v: fmt(v, 3)) if quantity == HZ else dt_text
        ys = list(range(len(chosen)))[::-1]
        for y, r in zip(ys, chosen):
            color = style((r[F.solver], r[F.rule]))[0]
            if r[F.largest_ok]:
                ok = float(r[F.largest_ok])
                ax.barh(y, ok - base, left=base, color=color, edgecolor="black", lw=0.5)
                text = show(ok) if r[F.first_diverged] else f"≥ {show(ok)} (top of range)"
                gap = float(r[F.pin_gap_at_largest_ok_m] or 0)
                if gap > 0.01:
                    text += f", hand pin {fmt(gap)} m off"
                ax.text(ok, y, " " + text, va="center", fontsize=8)
            else:
                ax.text(base, y, f"  diverges already at {show(float(r[F.first_diverged]))} "
                        f"({r[F.reason]})", va="center", fontsize=8, color="#d62728")
        ax.set_yticks(ys)
        ax.set_yticklabels([label((r[F.solver], r[F.rule])) for r in chosen])
        ax.set_xscale("log")
        ax.set_xlim(base, top)
        held = float(chosen[0][F.held])
        if quantity == HZ:
            ax.set_xlabel("largest circle frequency that stays ok (Hz)")
            ax.set_title(f"{FRONTIER_SCENARIO}, 0.3 m circle, dt = {dt_text(held)} s")
        else:
            ax.set_xlabel("largest dt that stays ok (s)")
            ax.set_title(f"{FRONTIER_SCENARIO}, 0.3 m circle at {fmt(held, 3)} Hz")
        ax.grid(True, axis="x", alpha=0.3)
    fig.suptitle("Stability frontier: a free puppet held only by the hand, no air drag "
                 "(bisected to 5 %)")
    fig.tight_layout()
    path = os.path.join(out, "frontier.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def plot_robustness(rows, out):
    if not rows:
        return None
    # the catalogue's order, and any name it does not know after it: nothing is dropped
    scenarios = ordered({r[R.scenario] for r in rows}, SCENARIOS)
    configs = ordered({(r[R.solver], r[R.rule]) for r in rows}, CONFIGS)
    dts = sorted({r[R.dt] for r in rows})
    by_key = {(r[R.scenario], (r[R.solver], r[R.rule]), r[R.dt]): r for r in rows}
    fig, axes = plt.subplots(len(dts), 1, figsize=(11, 3.6 * len(dts)), squeeze=False)
    width = 0.8 / max(len(configs), 1)
    for row, d in enumerate(dts):
        ax = axes[row][0]
        for k, c in enumerate(configs):
            colour, marker = style(c)
            xs, ys, lo, hi = [], [], [], []
            for i, sc in enumerate(scenarios):
                r = by_key.get((sc, c, d))
                if r is None:
                    continue
                xs.append(i - 0.4 + (k + 0.5) * width)
                ys.append(r[R.rate])
                lo.append(max(0.0, r[R.rate] - r[R.ci95_low]))  # 9 digits: -1e-10 is 0
                hi.append(max(0.0, r[R.ci95_high] - r[R.rate]))
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
            mine = [c for c in v.candidates if c[C.scenario] == scenario and c["config"] == config
                    and c[C.status] == CANDIDATE_OK and not math.isnan(c[C.error_m])]
            if not mine:
                continue
            mine.sort(key=lambda c: c[C.error_m])
            # the cheapest within each error: a staircase falling as the budget grows
            xs, ys, cheapest = [], [], math.inf
            for c in mine:
                cheapest = min(cheapest, c[C.cost_us_per_s])
                xs.append(c[C.error_m])
                ys.append(cheapest)
            colour, marker = style(config)
            ax.step(xs, ys, where="post", color=colour, lw=1.1)
            chosen = [v.row(scenario, config, PER_SECOND, b) for b in v.budgets]
            chosen = [r for r in chosen if r and r[V.verdict] == MET]
            ax.plot([r[V.budget_m] for r in chosen], [r[V.cost_us_per_s] for r in chosen],
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
