"""The report's section `robustness`: divergence rates over random starts."""

from ..catalogue import ROBUSTNESS_CSV as R
from ..catalogue import CONFIGS, SCENARIOS
from ..common import ROBUSTNESS, dt_text, label, md_table, ordered
from ..readers import read_robustness


def robustness_section(rows):
    if not rows:
        return []
    # the catalogue's order, and any name it does not know after it: nothing is dropped
    scenarios = ordered({r[R.scenario] for r in rows}, SCENARIOS)
    configs = ordered({(r[R.solver], r[R.rule]) for r in rows}, CONFIGS)
    dts = sorted({r[R.dt] for r in rows})
    by_key = {(r[R.scenario], (r[R.solver], r[R.rule]), r[R.dt]): r for r in rows}
    runs = sorted({r[R.runs] for r in rows})
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
            return f"{r[R.rate]:.2f} [{r[R.ci95_low]:.2f}, {r[R.ci95_high]:.2f}]"
        out += [f"dt = {dt_text(d)} s:", "",
                md_table(["solver"] + scenarios,
                         [[label(c)] + [cell(sc, c) for sc in scenarios] for c in configs]), ""]
    return out


ID = "robustness"


def lines(r):
    return robustness_section(read_robustness(r.folder))
