import math
import os
import re
import tempfile


def _layout():
    """the folders under RESULTS, as scripts/results_layout.sh names them for the shell scripts"""
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "results_layout.sh")
    out = {}
    with open(path) as f:
        for line in f:
            match = re.match(r"([A-Z_]+)=(\S+)", line)
            if match:
                out[match.group(1)] = match.group(2)
    return out


_LAYOUT = _layout()
MAIN, VERDICT, FRONTIER = _LAYOUT["MAIN"], _LAYOUT["VERDICT"], _LAYOUT["FRONTIER"]
OPEN_LIMITS, HUMANOID = _LAYOUT["OPEN_LIMITS"], _LAYOUT["HUMANOID"]
HUMANOID_VERDICT = _LAYOUT["HUMANOID_VERDICT"]
ROBUSTNESS, PLOTS = _LAYOUT["ROBUSTNESS"], _LAYOUT["PLOTS"]
ABLATION, COMPLIANT_FRONTIER = _LAYOUT["ABLATION"], _LAYOUT["COMPLIANT_FRONTIER"]


TABLE_DT = 1.0 / 240.0


class ReportError(Exception):
    pass


def label(config):
    """a (solver, rule) as tables name it; an engine whose cost is WebAssembly's says so"""
    from .catalogue import WASM_ENGINES  # the catalogue reads nothing from here
    solver, rule = config
    if solver in WASM_ENGINES:
        return f"{solver} (WebAssembly)"
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


# a truth's error bar: BAR_MARGIN × 2^p/(2^p − 1) × |x_h − x_{h/2}|, p its order read from its runs
# at 2h, h and h/2, taken as at least MIN_ORDER (docs/design.md, "Metrics")
BAR_MARGIN = 1.5


MIN_ORDER = 0.5


def or_list(items, word="or"):
    """a, b or c"""
    items = list(items)
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + f" {word} " + items[-1]


def and_list(items):
    """a, b and c"""
    return or_list(items, "and")


def md_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines)


def geometric_mean(values):
    values = [v for v in values if v > 0 and not math.isnan(v)]
    return math.exp(sum(math.log(v) for v in values) / len(values)) if values else math.nan


# the budget of the README's headline
HEADLINE_BUDGET = 0.01


def ordered(names, known):
    """the names in the order of `known`, any others after them, sorted"""
    return [n for n in known if n in names] + sorted(n for n in names if n not in known)




def budget_name(budget):
    """1 mm, 1 cm, 5 cm"""
    return f"{budget * 100:g} cm" if budget >= 0.01 - 1e-12 else f"{budget * 1000:g} mm"


def wilson_upper(k, n, z=1.959963984540054):
    """the upper end of the 95 % Wilson score interval of k in n"""
    p = k / n
    centre = p + z * z / (2 * n)
    spread = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return (centre + spread) / (1 + z * z / n)


def write_atomically(path, text):
    folder = os.path.dirname(path) or "."
    fd, temporary = tempfile.mkstemp(dir=folder, suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.replace(temporary, path)
