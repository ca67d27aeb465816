"""The report's section `truth-floor`: each truth's order of convergence, error bar and floor."""
import math

from ..catalogue import SECOND_TRUTH, TRUTH, TRUTH_REFINED
from ..common import BAR_MARGIN, MIN_ORDER, fmt, md_table


ID = "truth-floor"


def lines(r):
    s = r.s
    truths = r.truths
    out = []
    # the truths' error bars and their agreement
    second = r.second
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
                + ". Each is run at h/2 and at 2h too, its constraint model refined with dt ("
                + ", ".join(TRUTH_REFINED.get(s.truth_engine(ref)[0], s.truth_engine(ref)[0])
                            for ref in truths)
                + "), and "
                "compared with itself at h (re-seeded pose error, m). The two differences give "
                "its order of convergence p = log2(2h difference / h/2 difference) and so a bound "
                f"on its own error: the error bar {BAR_MARGIN:g} × 2^p/(2^p − 1) × the h/2 "
                f"difference (Richardson's estimate with a margin of {BAR_MARGIN:g}; p taken as at "
                f"least {MIN_ORDER:g}). The floor is what the truth can judge: its error bar, and "
                "never less than the second truth's error against it, judged as every solver is "
                "(re-seeded from the truth's states; \"re-seeded\" below). Errors under it are "
                "shown as `≤ floor`.", "",
                md_table(header, rows), ""]
    return out
