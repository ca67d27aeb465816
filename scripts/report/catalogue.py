"""The testbed's catalogues, as `testbed list --json` gives them and the main job commits them
(results/catalogue.json; a test checks it against the build): the scenarios, engines, rules,
stages, truths, metrics, the summary's columns and how a trace's file is named. No name is
spelled here or anywhere in the report: what a new scenario, rule or engine needs is read from
the catalogue, and a name the catalogue does not know gets a default style and is listed after
the known ones, never dropped."""
import json
import os
import re



PATH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "results",
                    "catalogue.json")

with open(PATH) as _file:
    _CATALOGUE = json.load(_file)

SCENARIOS = list(_CATALOGUE["scenarios"])
# the scenario a table quotes when it quotes one: a user dragging the puppet
HEADLINE = _CATALOGUE["headline_scenario"]
# what each scenario asks of a solver (a catalogue written before this key reads as none)
SCENARIO_ASKS = dict(_CATALOGUE.get("scenario_asks", {}))
# the scenario the stability frontier searches (testbed frontier)
FRONTIER_SCENARIO = _CATALOGUE["frontier_scenario"]
RULES = [rule["name"] for rule in _CATALOGUE["rules"]]
# the paper's own readings of its adjust (a catalogue written before this key reads as none)
SEED_RULES = [rule["name"] for rule in _CATALOGUE["rules"] if rule.get("seed")]
# the rule wherever one rule is implied
DEFAULT_RULE = _CATALOGUE["default_rule"]
# the scenes on the ground, judged by the contact judge
CONTACT_SCENARIOS = list(_CATALOGUE.get("contact_scenarios", []))
# each rule's defaults and what its iterations count ("": it makes one pass)
RULE_INFO = {rule["name"]: rule for rule in _CATALOGUE["rules"]}
# the engine a sweep runs once per rule
RULES_ENGINE = next(engine["name"] for engine in _CATALOGUE["engines"] if engine["rules"])
# (solver, rule) in the tables' order: the rules' engine once per rule, then the others
CONFIGS = [config for engine in _CATALOGUE["engines"]
           for config in ([(engine["name"], rule) for rule in RULES] if engine["rules"]
                          else [(engine["name"], "")])]
# what a verdict searches for each configuration besides dt: [(flags, label)], the flags as
# candidates.csv names a setting ("--substeps 8"; "": the defaults), the label as tables show it
SEARCH = {(entry["solver"], entry["rule"]): [(s["flags"], s["label"]) for s in entry["settings"]]
          for entry in _CATALOGUE["verdict_search"]}
STAGES = list(_CATALOGUE["stages"])
# the accuracy rows' references: the truth, the second truth (studies/.../sweep.h), the pairwise
TRUTH, SECOND_TRUTH = (truth["reference"] for truth in _CATALOGUE["truths"])
TRUTHS = (TRUTH, SECOND_TRUTH)
# how the report names each truth's engine ("MuJoCo (RK4)"), by its solver
TRUTH_TEXT = {truth["solver"]: truth["text"] for truth in _CATALOGUE["truths"]}
# how each truth's constraint model is refined with its dt, by its solver
TRUTH_REFINED = {truth["solver"]: truth["refined"] for truth in _CATALOGUE["truths"]}
# how each engine holds joints, limits, pins and contacts, in a sentence
CONSTRAINTS = {engine["name"]: engine["constraints"] for engine in _CATALOGUE["engines"]}
# the engines the procedural solver is compared with
REFERENCE_ENGINES = [engine["name"] for engine in _CATALOGUE["engines"] if not engine["rules"]]
# the engines whose cost is WebAssembly's (jolt): shown in their own rows, labelled, and never
# ranked against native code's
WASM_ENGINES = [engine["name"] for engine in _CATALOGUE["engines"]
                if not engine.get("native", True)]
PAIRWISE = _CATALOGUE["pairwise"]["reference"]
PAIRWISE_SOLVER = _CATALOGUE["pairwise"]["solver"]
PAIRWISE_CONFIG = (PAIRWISE_SOLVER, "")
METRICS = {metric["name"]: metric for metric in _CATALOGUE["metrics"]}
SUMMARY_HEADER = _CATALOGUE["summary_header"].split(",")
# every CSV the testbed writes, by file name ("trace" for traces/<stem>.csv): its columns
TABLES = {name: header.split(",") for name, header in _CATALOGUE["tables"].items()}
TABLES["summary.csv"] = SUMMARY_HEADER

# Plot styles by the catalogue's order: the rules from light to dark blue, then green and purple
# for the two substepped ones; the other engines black, red, brown, cyan and pink (orange rings mark diverged
# seeds). Anything past the palettes is grey.
_RULE_STYLES = [("#9ecae1", "o"), ("#c6dbef", "v"), ("#6baed6", "s"), ("#3182bd", "D"),
                ("#08519c", "^"), ("#2ca02c", "P"), ("#9467bd", "*")]
_ENGINE_STYLES = [("#000000", "o"), ("#d62728", "s"), ("#8c564b", "X"), ("#17becf", "d"),
                  ("#e377c2", "p")]
DEFAULT_STYLE = ("grey", "o")
STYLE = dict(zip([c for c in CONFIGS if c[0] == RULES_ENGINE], _RULE_STYLES))
STYLE.update(zip([c for c in CONFIGS if c[0] != RULES_ENGINE], _ENGINE_STYLES))


def style(config):
    """(colour, marker) of a (solver, rule)"""
    return STYLE.get(config, DEFAULT_STYLE)


class Names:
    """names the catalogue lists, as attributes (M.pose_err_m) or called with one that is not an
    identifier (ST("at_1s")), each checked when read: a misspelt or retired name fails here, not
    as a silently empty table"""

    def __init__(self, what, known):
        self._what, self._known = what, known

    def __getattr__(self, name):
        if name.startswith("_"):  # not a name of the catalogue's (copy, pickle)
            raise AttributeError(name)
        return self(name)

    def __call__(self, name):
        if name not in self._known:
            raise KeyError(f"{name!r} is not one of {self._what} in the testbed's catalogue "
                           f"({PATH})")
        return name


M = Names("the summary's metrics", METRICS)  # the summary's metrics: M.pose_err_m
ST = Names("the summary's stats", {s["name"] for s in _CATALOGUE["stats"]})  # ST.reseeded_mean


def setting_label(config, flags):
    """a verdict's setting in a few words ("8 substeps"), as the catalogue labels it; flags the
    catalogue does not search for that configuration are shown as they are"""
    return dict(SEARCH.get(config, [])).get(flags, flags)


# the values a column may hold, by file and column (VALUES["verdict.csv"]["view"])
VALUES = _CATALOGUE["values"]


def value(table, column, name):
    """a column's value, checked against the catalogue's vocabulary for it"""
    if name not in VALUES.get(table, {}).get(column, []):
        raise KeyError(f"{name!r} is not a value of {table}'s {column} in the testbed's "
                       f"catalogue ({PATH})")
    return name


DIVERGED = value("summary.csv", "status", "diverged")
CANDIDATE_OK = value("candidates.csv", "status", "ok")
MET = value("verdict.csv", "verdict", "met")
ERROR_FLOOR = value("verdict.csv", "verdict", "error-floor")
PER_SECOND = value("verdict.csv", "view", "second")
PER_FRAME = value("verdict.csv", "view", "frame")
HZ = value("frontier.csv", "quantity", "hz")
DT = value("frontier.csv", "quantity", "dt")

# a CSV's columns by file: FRONTIER_CSV.largest_ok
SUMMARY_CSV = Names("summary.csv's columns", TABLES["summary.csv"])
FRONTIER_CSV = Names("frontier.csv's columns", TABLES["frontier.csv"])
CANDIDATES_CSV = Names("candidates.csv's columns", TABLES["candidates.csv"])
VERDICT_CSV = Names("verdict.csv's columns", TABLES["verdict.csv"])
CONTACT_CSV = Names("contact.csv's columns", TABLES["contact.csv"])
ROBUSTNESS_CSV = Names("robustness_summary.csv's columns", TABLES["robustness_summary.csv"])
TRACE_CSV = Names("a trace's columns", TABLES["trace"])


def stage_metric(stage):
    """the summary's metric of a stage's time"""
    return M("{stage}_us").replace("{stage}", stage)


_TRACE = _CATALOGUE["trace"]


def trace_stem(model, scenario, config, dt_text):
    """a run's trace file name without .csv, as the testbed names it (dt as summary.csv has it)"""
    def safe(text):
        return re.sub(f"[^{_TRACE['safe_characters']}]", _TRACE["replacement"], text)
    solver, rule = config
    return (_TRACE["stem"].replace("{model}", safe(model)).replace("{scenario}", safe(scenario))
            .replace("{solver}", safe(solver)).replace("{rule}", safe(rule) if rule
                                                       else _TRACE["no_rule"])
            .replace("{dt}", dt_text))
