"""The report's section `verdict-search`: what the verdict searched for each solver besides dt,
from the catalogue's rows (testbed list --json), with the dts and count of the committed run."""
from collections import Counter

from ..catalogue import CANDIDATES_CSV as C
from ..catalogue import CONFIGS, RULES_ENGINE, SEARCH
from ..common import VERDICT, dt_text, label, md_table, or_list, ordered
from ..readers import read_verdict

ID = "verdict-search"


def choices(settings):
    """a configuration's settings in a few words: 1, 2, 4, 8 or 16 substeps (`--substeps`)"""
    flags = [flag for flag, _ in settings if flag]
    if not flags:
        return "nothing: dt is the only choice"
    # the engine's defaults among other settings (flags "", label "")
    settings = [(flag, text or "its defaults") for flag, text in settings]
    if all(flag == text for flag, text in settings):  # not in the catalogue: its flags
        return or_list(f"`{flag}`" for flag in flags)
    words = [text.split(" ", 1) for _, text in settings]
    if all(len(w) == 2 and w[0].isdigit() for w in words):
        text = or_list(w[0] for w in words) + " " + words[-1][1]
    else:
        text = or_list(text for _, text in settings)
    names = sorted({flag.split(" ", 1)[0] for flag in flags})
    return text + " (" + ", ".join(f"`{name}`" for name in names) + ")"


def rows(v):
    """(solvers, choices) with the configurations that search alike merged, in the tables'
    order: those the committed verdict searched (a configuration the catalogue lacks with the
    flags it ran), else every one the catalogue has"""
    searched = {}
    if v:
        for c in v.candidates:
            searched.setdefault(c["config"], {})[c[C.setting]] = None
    configs = ordered(set(searched), CONFIGS) if v else [c for c in CONFIGS if c in SEARCH]
    out = []
    for config in configs:
        settings = SEARCH.get(config) or [(flags, flags) for flags in searched[config]]
        text = choices(settings)
        if out and out[-1][1] == text and (out[-1][0][-1][0] == RULES_ENGINE) == (
                config[0] == RULES_ENGINE):
            out[-1][0].append(config)
        else:
            out.append(([config], text))
    return out


def solvers_text(configs):
    if configs[0][0] == RULES_ENGINE and len(configs) > 1:
        return f"{RULES_ENGINE} " + ", ".join(rule for _, rule in configs)
    return ", ".join(label(c) for c in configs)


def lines(r):
    v = read_verdict(r.folder)
    dts = sorted({c[C.dt] for c in v.candidates}, reverse=True) if v else []
    header = "besides dt" + (f" ({', '.join(dt_text(dt) for dt in dts)} s)" if dts else "")
    out = ["## What the verdict searched", "",
           md_table(["solver", header], [[solvers_text(c), text] for c, text in rows(v)]), ""]
    if v:
        per_scenario = Counter(c[C.scenario] for c in v.candidates)
        counts = sorted(set(per_scenario.values()))
        out += [f"That is {or_list(str(n) for n in counts)} candidates per scenario on {v.model} "
                f"(`{VERDICT}/candidates.csv`). A candidate's `setting` column holds the testbed "
                "flags that rebuild it.", ""]
    return out
