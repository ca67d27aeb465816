#!/usr/bin/python3
"""Prints the --benchmark_filter of one benchmark binary for the quick gate run: the benchmarks
results/gate.json reads, so that scripts/bench.sh --quick times exactly what the gate compares
and no name is listed twice.

    scripts/gate_filters.py results/gate.json step|stages|scaling

step: bench_step's step/<scenario>/<solver> benchmarks; stages: bench_stages' floor/<scenario>;
scaling: bench_scaling's scaling/<rule>/<N> and crowd/... benchmarks, with each scaling family's
smallest chain (4) as well: Google Benchmark's complexity fit crashes on a family with no run
left, and the smoothed and weighted chains diverge from N = 16 on (skipped, known failures).
"""
import json
import re
import sys

PREFIXES = {"step": ("step/",), "stages": ("floor/",), "scaling": ("scaling/", "crowd/")}
SMALLEST_CHAIN = 4  # bench_scaling's first size


def names(gates, prefixes):
    out = set()
    for g in gates:
        for key in ("numerator", "denominator"):
            if g[key].startswith(prefixes):
                out.add(g[key])
    for name in list(out):
        family = re.fullmatch(r"(scaling/[^/]+)/\d+", name)
        if family:
            out.add(f"{family.group(1)}/{SMALLEST_CHAIN}")
    return sorted(out)


def main(argv):
    if len(argv) != 2 or argv[1] not in PREFIXES:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    try:
        with open(argv[0]) as f:
            gates = json.load(f)["gates"]
    except (OSError, ValueError, KeyError) as e:
        print(f"gate_filters.py: {argv[0]}: {e}", file=sys.stderr)
        return 2
    chosen = names(gates, PREFIXES[argv[1]])
    if not chosen:
        print(f"gate_filters.py: {argv[0]}: no gate reads a {argv[1]} benchmark", file=sys.stderr)
        return 2
    # the names are plain (letters, digits, / : _ -): nothing a regular expression reads specially
    odd = [n for n in chosen if not re.fullmatch(r"[A-Za-z0-9/:_-]+", n)]
    if odd:
        print(f"gate_filters.py: {argv[0]}: a benchmark name is not plain: {odd[0]!r}",
              file=sys.stderr)
        return 2
    print("^(" + "|".join(chosen) + ")/")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
