"""The report's section `frontier`: the stability frontier of its scenario (yank)."""

from ..catalogue import FRONTIER_CSV as F
from ..catalogue import DT, FRONTIER_SCENARIO, HZ
from ..common import dt_text, fmt, label, md_table


ID = "frontier"


def lines(r):
    frontier = r.frontier
    out = []
    if frontier:
        rows = []
        for r in frontier:
            quantity = r[F.quantity]
            show = (lambda v: fmt(float(v), 3)) if quantity == HZ else (
                lambda v: dt_text(float(v)))
            ok = show(r[F.largest_ok]) if r[F.largest_ok] else "none"
            bad = show(r[F.first_diverged]) if r[F.first_diverged] else "none in range"
            gap = r[F.pin_gap_at_largest_ok_m]
            gap = fmt(float(gap)) if gap else "–"
            rows.append([label((r[F.solver], r[F.rule])), quantity, ok, bad,
                         r[F.reason] or "–", gap])
        held = {r[F.quantity]: float(r[F.held]) for r in frontier}
        out += [f"## Stability frontier ({FRONTIER_SCENARIO}, no air drag)", "",
                "The largest circle frequency (0.3 m circle, at dt = "
                f"{dt_text(held.get(HZ, 1 / 240))} s) and the largest dt (at "
                f"{fmt(held.get(DT, 0.5), 3)} Hz) at which a puppet held only by its hand stays "
                "`ok`, bisected to 5 %. The pin gap says whether the hand was really followed.",
                "",
                md_table(["solver", "search", "largest ok", "first diverged", "why",
                          "pin gap at largest ok (m)"], rows), ""]
    return out
