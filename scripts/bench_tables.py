#!/usr/bin/python3
"""Print docs/performance.md's speed tables (markdown) from one machine's full benchmark run.

    scripts/bench_tables.py results/bench/<machine>.csv [--only step|scaling|crowd]
    scripts/bench_tables.py results/bench/<machine>.csv --floors results/gate.json

The CSV is what scripts/bench.sh writes (`testbed gate --csv`): the median seconds per item of
every benchmark. A benchmark that is missing was skipped because its run diverged. --floors
prints every gate's floor (the project's commitments, scripts/gate_thresholds.py) against this
machine's ratio. docs/performance.md holds the output as generated blocks
(scripts/docs_tables.py rewrites them).
"""
import json
import os
import sys

from gate_thresholds import medians  # the same reading of a machine's CSV
from report.catalogue import CONFIGS, PAIRWISE_SOLVER, RULES, RULES_ENGINE, RULE_INFO, SCENARIOS

# the engines beside the rules and the pairwise solver (the speed baseline), in the catalogue's
# order
OTHER_ENGINES = [solver for solver, _ in CONFIGS if solver not in (RULES_ENGINE, PAIRWISE_SOLVER)]


def floors(t, gates_path, machine):
    """Every gate's floor against this machine's ratio: reached, not reached, or no time."""
    print(f"| gate | floor | {machine} | reached |")
    print("|---|---|---|---|")
    for g in json.load(open(gates_path))["gates"]:
        bound = ("≥ " if "min" in g else "≤ ") + f"{g['floor']:g}"
        num, den = t.get(g["numerator"]), t.get(g["denominator"])
        # a run that predates a rule, or a whole benchmark binary (python/...), did not time it
        names = (g["numerator"], g["denominator"])
        if not all(in_run(t, part) for name in names for part in name.split("/")[2:3]) or \
                not all(any(k.startswith(name.split("/")[0] + "/") for k in t) for name in names):
            print(f"| {g['name']} | {bound} | not in this run | - |")
            continue
        if num is None or den is None:
            print(f"| {g['name']} | {bound} | diverged | ✗ |")
            continue
        ratio = (num / g.get("numerator_per", 1)) / (den / g.get("denominator_per", 1))
        reached = ratio >= g["floor"] if "min" in g else ratio <= g["floor"]
        print(f"| {g['name']} | {bound} | {ratio:.2f} | {'✓' if reached else '✗'} |")


def main():
    args = sys.argv[1:]
    usage = ("usage: bench_tables.py MACHINE.csv [--only step|scaling|crowd] "
             "| MACHINE.csv --floors gate.json")
    if len(args) not in (1, 3) or (len(args) == 3 and args[1] not in ("--only", "--floors")) \
            or (len(args) == 3 and args[1] == "--only" and args[2] not in SECTIONS):
        sys.exit(usage)
    t = medians(args[0])
    if len(args) == 3 and args[1] == "--floors":
        floors(t, args[2], os.path.splitext(os.path.basename(args[0]))[0])
        return
    only = args[2] if len(args) == 3 else None
    printers = {"step": step_tables, "scaling": scaling_table, "crowd": crowd_table}
    for i, name in enumerate(n for n in SECTIONS if only in (None, n)):
        if i:
            print()
        printers[name](t)


SECTIONS = ("step", "scaling", "crowd")


def in_run(t, solver):
    """whether this machine's run had the solver at all (a run that diverges in every scenario
    still times its short chain): an older run predates the newer rules"""
    return any(solver in key.split("/") for key in t)


def rules(t):
    return [rule for rule in RULES if in_run(t, rule)]


def others(t):
    """the engines other than the rules and the baseline that this run timed"""
    return [solver for solver in OTHER_ENGINES if any(k.endswith("/" + solver) for k in t)]


def scenarios(t):
    """the scenarios the step benchmark timed, in the catalogue's order"""
    timed = {key.split("/")[1] for key in t if key.startswith("step/")}
    return [scenario for scenario in SCENARIOS if scenario in timed]


def step_tables(t):
    RULES = rules(t)
    OTHERS = others(t)
    print("| scenario | " + " | ".join(RULES) + f" | {PAIRWISE_SOLVER} | " + " | ".join(OTHERS)
          + " | floor |")
    print("|---" * (len(RULES) + 3 + len(OTHERS)) + "|")
    for scenario in scenarios(t):
        multibody = t.get(f"step/{scenario}/{PAIRWISE_SOLVER}")
        cells = []
        for solver in RULES + OTHERS:
            time = t.get(f"step/{scenario}/{solver}")
            if time is None:
                cells.append("diverged")
            else:
                cells.append(f"{time * 1e6:.2f} ({multibody / time:.1f}×)")
        cells.insert(len(RULES), f"{multibody * 1e6:.1f}")
        floor = t.get(f"floor/{scenario}")
        cells.append(f"{floor * 1e6:.2f}")
        print(f"| {scenario} | " + " | ".join(cells) + " |")
    print()

    first = scenarios(t)[0]
    floor = t[f"floor/{first}"]
    parts = []
    for rule in RULES:
        time = t.get(f"step/{first}/{rule}")
        parts.append(f"{rule} " + ("diverged" if time is None else f"{time / floor:.2f}"))
    print(f"Procedural step ÷ floor in {first}: " + ", ".join(parts) + ".")


def scaling_table(t):
    RULES = rules(t)
    sizes = [4, 16, 64, 256, 1024]
    print("| solver | " + " | ".join(f"N={n}" for n in sizes) + " | 1024 ÷ 16 |")
    print("|---" * (len(sizes) + 2) + "|")
    for solver in RULES + [PAIRWISE_SOLVER] + others(t):
        per_segment = {n: t[f"scaling/{solver}/{n}"] / n for n in sizes
                       if f"scaling/{solver}/{n}" in t}
        # bench_scaling.cpp leaves out the chains a reference engine refuses (MuJoCo's beyond
        # 64: its XML parser nests 100 elements deep); the rules take every model, so a rule's
        # missing size diverged
        longest = max((n for n in sizes if n in per_segment), default=0)
        refused = solver not in RULES and all(n in per_segment for n in sizes if n <= longest)
        cells = [f"{per_segment[n] * 1e9:.0f}" if n in per_segment
                 else ("model refused" if refused and n > longest else "diverged")
                 for n in sizes]
        growth = (f"{per_segment[1024] / per_segment[16]:.2f}"
                  if 16 in per_segment and 1024 in per_segment else "-")
        print(f"| {solver} | " + " | ".join(cells) + f" | {growth} |")


def crowd_time(t, rule, k, threads, lanes=1):
    """seconds per puppet-step; runs from before the lanes argument name no lanes (one by one)"""
    time = t.get(f"crowd/{rule}/puppets:{k}/threads:{threads}/lanes:{lanes}")
    if time is None and lanes == 1:
        time = t.get(f"crowd/{rule}/puppets:{k}/threads:{threads}")
    return time


def crowd_table(t):
    RULES = rules(t)
    print("| rule | K=1000, 1 thread | K=1000, 2 threads | K=20000, 1 thread | K=20000, 2 threads "
          "| 2 ÷ 1 thread at 1000 / 20000 |")
    print("|---" * 6 + "|")
    for rule in RULES:
        rate = {}
        for k in (1000, 20000):
            for threads in (1, 2):
                time = crowd_time(t, rule, k, threads)
                if time is not None:
                    rate[k, threads] = 1.0 / time
        # the substepped rules' crowds stop at 1,000 puppets (bench_scaling.cpp)
        substepped = RULE_INFO[rule]["substeps"] > 1
        cells = [f"{rate[key] / 1e3:.0f}k" if key in rate
                 else ("not run" if substepped and key[0] == 20000 else "diverged")
                 for key in [(1000, 1), (1000, 2), (20000, 1), (20000, 2)]]
        scaling = [f"{rate[k, 2] / rate[k, 1]:.2f}×" for k in (1000, 20000)
                   if (k, 1) in rate and (k, 2) in rate]
        print(f"| {rule} | " + " | ".join(cells) + " | " + (" / ".join(scaling) or "-") + " |")
    # a crowd in SIMD lanes (CrowdLanes), for the rules whose runs measured them
    for rule in RULES:
        if crowd_time(t, rule, 1000, 2, 4) is not None:
            lanes_table(t, rule)


def lanes_table(t, rule):
    print()
    print(f"| {rule}, K=1000, puppets per batch | 1 thread | 2 threads | 2 ÷ 1 thread "
          "| over one by one (2 threads) |")
    print("|---" * 5 + "|")
    alone = crowd_time(t, rule, 1000, 2)
    for lanes, name in ((1, "1 (one by one)"), (2, "2 (SSE2)"), (4, "4 (AVX2)"),
                        (8, "8 (AVX-512)")):
        one, two = crowd_time(t, rule, 1000, 1, lanes), crowd_time(t, rule, 1000, 2, lanes)
        if one is None or two is None:
            print(f"| {name} | this processor has none | | | |")
            continue
        print(f"| {name} | {1 / one / 1e3:.0f}k | {1 / two / 1e3:.0f}k | {one / two:.2f}× "
              f"| {alone / two:.2f}× |")


if __name__ == "__main__":
    main()
