#!/usr/bin/python3
"""Print docs/performance.md's speed tables (markdown) from one machine's full benchmark run.

    scripts/bench_tables.py results/bench/<machine>.csv

The CSV is what scripts/bench.sh writes (`testbed gate --csv`): the median seconds per item of
every benchmark. A benchmark that is missing was skipped because its run diverged.
"""
import sys

from gate_thresholds import medians  # the same reading of a machine's CSV

RULES = ["literal", "smoothed", "weighted", "subtree", "relaxed", "xpbd", "tree"]
SCENARIOS = ["hang", "drag", "drop"]


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: bench_tables.py MACHINE.csv")
    t = medians(sys.argv[1])

    others = ["bullet-rigid"] + (["mujoco"] if any(k.endswith("/mujoco") for k in t) else [])
    print("| scenario | " + " | ".join(RULES) + " | bullet-multibody | " + " | ".join(others)
          + " | floor |")
    print("|---" * (len(RULES) + 3 + len(others)) + "|")
    for scenario in SCENARIOS:
        multibody = t.get(f"step/{scenario}/bullet-multibody")
        cells = []
        for solver in RULES + others:
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

    floor = t["floor/hang"]
    parts = []
    for rule in RULES:
        time = t.get(f"step/hang/{rule}")
        parts.append(f"{rule} " + ("diverged" if time is None else f"{time / floor:.2f}"))
    print("Procedural step ÷ floor in hang: " + ", ".join(parts) + ".")
    print()

    sizes = [4, 16, 64, 256, 1024]
    print("| solver | " + " | ".join(f"N={n}" for n in sizes) + " | 1024 ÷ 16 |")
    print("|---" * (len(sizes) + 2) + "|")
    for solver in RULES + ["bullet-multibody"] + others:
        per_segment = {n: t[f"scaling/{solver}/{n}"] / n for n in sizes
                       if f"scaling/{solver}/{n}" in t}
        # bench_scaling.cpp stops MuJoCo's chains at 64 (its XML parser nests 100 elements deep)
        not_run = "not MJCF" if solver == "mujoco" else "diverged"
        cells = [f"{per_segment[n] * 1e9:.0f}" if n in per_segment
                 else (not_run if n > 64 else "diverged") for n in sizes]
        growth = (f"{per_segment[1024] / per_segment[16]:.2f}"
                  if 16 in per_segment and 1024 in per_segment else "-")
        print(f"| {solver} | " + " | ".join(cells) + f" | {growth} |")
    print()

    print("| rule | K=1000, 1 thread | K=1000, 2 threads | K=20000, 1 thread | K=20000, 2 threads "
          "| 2 ÷ 1 thread at 1000 / 20000 |")
    print("|---" * 6 + "|")
    for rule in RULES:
        rate = {}
        for k in (1000, 20000):
            for threads in (1, 2):
                time = t.get(f"crowd/{rule}/puppets:{k}/threads:{threads}")
                if time is not None:
                    rate[k, threads] = 1.0 / time
        # the substepped rules' crowds stop at 1,000 puppets (bench_scaling.cpp)
        cells = [f"{rate[key] / 1e3:.0f}k" if key in rate
                 else ("not run" if rule in ("xpbd", "tree") and key[0] == 20000 else "diverged")
                 for key in [(1000, 1), (1000, 2), (20000, 1), (20000, 2)]]
        scaling = [f"{rate[k, 2] / rate[k, 1]:.2f}×" for k in (1000, 20000)
                   if (k, 1) in rate and (k, 2) in rate]
        print(f"| {rule} | " + " | ".join(cells) + " | " + (" / ".join(scaling) or "-") + " |")


if __name__ == "__main__":
    main()
