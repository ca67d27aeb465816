"""The report's section `time-per-step`: µs per step, and the speed over the pairwise solver."""

from ..catalogue import M, PAIRWISE_CONFIG, ST, WASM_ENGINES
from ..common import dt_text, fmt, label, md_table


ID = "time-per-step"


def lines(r):
    s = r.s
    dt = r.dt
    out = []
    # timing
    multibody = PAIRWISE_CONFIG
    rows = []
    for c in s.configs:
        row = [label(c)]
        for sc in s.scenarios:
            us = s.get(sc, c, dt, M.step_us, ST.median)
            ref = s.get(sc, multibody, dt, M.step_us, ST.median)
            ratio = ""
            # a WebAssembly engine's time is shown, never put against native code's
            if c != multibody and c[0] not in WASM_ENGINES and us > 0 and ref > 0:
                # whole times from 10x, one decimal below (a solver slower than the reference
                # reads 0.5x, not 0x)
                ratio = f" ({ref / us:.0f}x)" if ref >= 9.5 * us else f" ({ref / us:.1f}x)"
            row.append(fmt(us, 3) + ratio)
        rows.append(row)
    out += ["## Time per step", "",
            f"Median µs per step at dt = {dt_text(dt)} s; in brackets, how many times faster than "
            f"{label(multibody)} in the same run (not for a WebAssembly engine, whose time is "
            "Jolt's own step inside Node.js). These come from one timing pass on a shared "
            "machine; the benchmarks measure speed properly.", "",
            md_table(["solver"] + s.scenarios, rows), ""]
    return out
