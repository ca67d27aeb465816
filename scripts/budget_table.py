#!/usr/bin/python3
"""The engine budget's estimates against the measured costs, from a bench_budget run.

    scripts/budget_table.py results/bench/budget.json [--fit]

Prints a Markdown table: per engine (a row) and figure (a column), the estimate of one simulated
second at 1/240 s (the engine's catalogue row, Engine::second_cost) over the CPU it took, as
bench_budget measured it on the figure folded onto the ground (benchmarks/bench_budget.cpp); the
last columns give the range and the measured cost of the dearest figure. With --fit, prints
instead each engine's cost model fitted to the run (non-negative coefficients, least squares on
the logarithm of the ratio; needs python3-scipy), the numbers behind the rows' second_cost.
"""
import json
import sys

# each engine's terms, as its second_cost combines them (harness/src/engines/*.cpp): the names
# are bench_budget's counters; R is the rows an exact solver carries
FORMS = {
    "xpbd": ("segments", "contact_points", "limit_rows"),
    "tree": ("segments", "contact_points", "limit_rows"),
    "bullet-multibody": ("segments", "dofs*R^2", "contact_points", "limit_rows"),
    "bullet-rigid": ("segments+joint_rows", "limit_rows", "contact_points"),
    "mujoco": ("dofs*max(dofs,Rm)^2", "contact_points", "segments", "limit_rows"),
    "ode": ("segments+joint_rows", "contact_points", "limit_rows"),
    "ode-step": ("segments", "R^3", "box_limits*R^2"),
    "jolt": ("segments+joint_rows", "contact_points", "limit_rows"),
}


def term(name, c):
    rows = c["joint_rows"] + c["limit_rows"] + 3 * c["contact_points"]
    if name == "segments+joint_rows":
        return c["segments"] + c["joint_rows"]
    if name == "dofs*R^2":
        return c["dofs"] * (c["limit_rows"] + 3 * c["contact_points"]) ** 2
    if name == "dofs*max(dofs,Rm)^2":
        contacts = min(c["contact_points"], 4 * c["segments"] + 8)  # MuJoCo's nconmax here
        return c["dofs"] * max(c["dofs"], c["limit_rows"] + 3 * contacts) ** 2
    if name == "R^3":
        return rows ** 3
    if name == "box_limits*R^2":
        return c["box_limits"] * rows ** 2
    return c[name]


def load(path):
    with open(path) as f:
        run = json.load(f)
    rows = {}
    for b in run["benchmarks"]:
        if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
            continue
        if "error_occurred" in b or "measured_s" not in b:
            continue
        _, engine, figure = b["name"].split("/")[:3]
        rows.setdefault(engine, {})[figure] = b
    return run, rows


def table(run, rows):
    figures = []
    for per in rows.values():
        figures += [f for f in per if f not in figures]
    context = run.get("context", {})
    print(f"Estimate over measured CPU per simulated second at 1/240 s, each figure folded onto "
          f"the ground (`bench_budget`, {context.get('num_cpus', '?')} CPUs, "
          f"{context.get('date', '?')[:10]}); from 1/3 to 3 is the promise.\n")
    print("| engine | " + " | ".join(figures) + " | range | dearest (s per s) |")
    print("|---|" + "---|" * (len(figures) + 2))
    for engine, per in rows.items():
        ratios = [per[f]["estimate_over_measured"] for f in figures if f in per]
        cells = [f"{per[f]['estimate_over_measured']:.2f}" if f in per else "-" for f in figures]
        dearest = max(per.values(), key=lambda b: b["measured_s"])
        print(f"| {engine} | " + " | ".join(cells) +
              f" | {min(ratios):.2f}–{max(ratios):.2f} | {dearest['measured_s']:.3g} |")


def fit(rows):
    import numpy as np
    from scipy.optimize import least_squares
    for engine, per in rows.items():
        names = FORMS[engine]
        x = np.array([[term(n, b) for n in names] for b in per.values()], float)
        y = np.array([b["measured_s"] for b in per.values()])
        scale = x.max(0)
        scale[scale == 0] = 1
        solved = least_squares(lambda c: np.log(np.maximum((x / scale) @ c, 1e-30)) - np.log(y),
                               np.full(len(names), y.mean() / len(names)), bounds=(0, np.inf))
        coefficients = solved.x / scale
        ratio = x @ coefficients / y
        per_step = ", ".join(f"{n}: {c / 240 * 1e9:.4g} ns" for n, c in zip(names, coefficients))
        print(f"{engine}: {per_step} per step; fitted ratio {ratio.min():.2f}–{ratio.max():.2f}")


def main(argv):
    if len(argv) not in (2, 3) or (len(argv) == 3 and argv[2] != "--fit"):
        print(__doc__.strip().splitlines()[2].strip(), file=sys.stderr)
        return 2
    run, rows = load(argv[1])
    if not rows:
        print(f"{argv[1]}: no budget/ benchmark with its counters", file=sys.stderr)
        return 2
    fit(rows) if len(argv) == 3 else table(run, rows)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
