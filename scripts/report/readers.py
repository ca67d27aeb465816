import csv
import math
import os

from .catalogue import (CONFIGS, M, RULES_ENGINE, SCENARIOS, SECOND_TRUTH, SUMMARY_HEADER, TRUTH,
                        TRUTH_TEXT, TRUTHS, trace_stem)
from .common import (ABLATION, BAR_MARGIN, MAIN, MIN_ORDER, ROBUSTNESS, ReportError, TABLE_DT, VERDICT,
                     dt_text, ordered)


class Summary:
    """summary.csv, indexed by (scenario, solver, rule, dt, metric, stat, reference)."""

    HEADER = SUMMARY_HEADER  # the testbed's (catalogue)

    def __init__(self, path):
        self.values = {}
        self.status = {}
        self.dts = set()
        self.scenarios, self.configs = [], []
        with open(path, newline="") as f:
            reader = csv.reader(f)
            header = next(reader, None)
            if header != self.HEADER:
                raise ReportError(f"{path}: unexpected header {header}")
            for n, row in enumerate(reader, start=2):
                if len(row) != len(self.HEADER):
                    raise ReportError(f"{path}:{n}: {len(row)} fields, expected {len(self.HEADER)}")
                r = dict(zip(self.HEADER, row))
                dt = float(r["dt"])
                exact = 1 / round(1 / dt)  # every dt is 1/n; the CSV keeps 9 digits
                if abs(dt - exact) <= 1e-6 * exact:
                    dt = exact
                config = (r["solver"], r["rule"])
                value = float(r["value"]) if r["value"] else math.nan
                self.values[(r["scenario"], config, dt, r["metric"], r["stat"], r["reference"])] = value
                if r["reference"] == "" and r["metric"] == M.joint_gap_m:
                    self.status[(r["scenario"], config, dt)] = r["status"]
                    self.dts.add(dt)
                    if r["scenario"] not in self.scenarios:
                        self.scenarios.append(r["scenario"])
                    if config not in self.configs:
                        self.configs.append(config)
                self.model, self.git_sha, self.machine = r["model"], r["git_sha"], r["machine"]
        if not self.values:
            raise ReportError(f"{path}: no rows")
        self.dts = sorted(self.dts)
        self.scenarios.sort(key=lambda s: SCENARIOS.index(s) if s in SCENARIOS else len(SCENARIOS))
        self.configs.sort(key=lambda c: CONFIGS.index(c) if c in CONFIGS else len(CONFIGS))

    def get(self, scenario, config, dt, metric, stat, reference=""):
        return self.values.get((scenario, config, dt, metric, stat, reference), math.nan)

    def diverged(self, scenario, config, dt):
        return self.status.get((scenario, config, dt)) == "diverged"

    def table_dt(self):
        return min(self.dts, key=lambda dt: abs(math.log(dt / TABLE_DT)))

    def truth_engine(self, reference=TRUTH):
        """(solver, h) of a truth, from its truth_dt rows; None when the run had no such truth"""
        for k, v in self.values.items():
            if k[3] == M.truth_dt and k[5] == reference:
                h = 1 / round(1 / v)
                return k[1][0], h
        return None

    def truths(self):
        return [r for r in TRUTHS if self.truth_engine(r)]

    def truth_text(self, reference=TRUTH):
        """"MuJoCo (RK4) at 1/7680 s": which engine a truth is"""
        if not self.truth_engine(reference):
            return "none"
        solver, h = self.truth_engine(reference)
        return f"{TRUTH_TEXT.get(solver, solver)} at {dt_text(h)} s"

    def truth_own(self, scenario, reference=TRUTH, scale=0.5, stat="reseeded_mean",
                  metric=M.pose_err_m):
        """a truth's run at scale·h against its run at h"""
        engine = self.truth_engine(reference)
        if not engine:
            return math.nan
        solver, h = engine
        return self.get(scenario, (solver, ""), 1 / round(1 / (scale * h)), metric, stat, reference)

    def truth_check(self, scenario, reference=TRUTH, stat="reseeded_mean", metric=M.pose_err_m):
        """a truth's own difference: its run at h/2 against it"""
        return self.truth_own(scenario, reference, 0.5, stat, metric)

    def truth_order(self, scenario, reference=TRUTH, stat="reseeded_mean", metric=M.pose_err_m):
        """the order p of convergence: log2 of the 2h difference over the h/2 difference"""
        fine = self.truth_check(scenario, reference, stat, metric)
        coarse = self.truth_own(scenario, reference, 2.0, stat, metric)
        if not (fine > 0 and coarse > 0):
            return math.nan
        return math.log2(coarse / fine)

    def truth_bar(self, scenario, reference=TRUTH, stat="reseeded_mean", metric=M.pose_err_m):
        """a bound on a truth's own error: BAR_MARGIN × 2^p/(2^p − 1) × its h/2 difference"""
        fine = self.truth_check(scenario, reference, stat, metric)
        p = self.truth_order(scenario, reference, stat, metric)
        p = MIN_ORDER if math.isnan(p) else max(p, MIN_ORDER)
        return BAR_MARGIN * 2 ** p / (2 ** p - 1) * fine

    def truths_agreement(self, scenario, stat, against=TRUTH, metric=M.pose_err_m):
        """the other truth's run at its h against this one"""
        other = SECOND_TRUTH if against == TRUTH else TRUTH
        engine = self.truth_engine(other)
        if not engine or not self.truth_engine(against):
            return math.nan
        solver, h = engine
        return self.get(scenario, (solver, ""), h, metric, stat, against)

    def truth_limit(self, scenario, reference=TRUTH, stat="reseeded_mean", metric=M.pose_err_m):
        """the smallest error a truth can judge (its floor): its error bar, and never below the
        other truth's error against it, judged as every solver is (re-seeded from its states)"""
        agreement = self.truths_agreement(scenario, stat, reference, metric)
        bar = self.truth_bar(scenario, reference, stat, metric)
        return bar if math.isnan(agreement) else max(bar, agreement)

    def has_second_truth(self):
        return self.truth_engine(SECOND_TRUTH) is not None


def read_frontier(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def read_trace(folder, model, scenario, config, dt):
    solver, rule = config
    name = trace_stem(model, scenario, (solver, rule), f"{dt:.9g}") + ".csv"
    path = os.path.join(folder, MAIN, "traces", name)
    if not os.path.exists(path):
        return None
    t, gap = [], []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            t.append(float(row["t"]))
            gap.append(float(row["joint_gap_max_m"]))
    return t, gap


def read_robustness(folder):
    """RESULTS/robustness/robustness_summary.csv (testbed robustness), or None"""
    path = os.path.join(folder, ROBUSTNESS, "robustness_summary.csv")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        rows = list(csv.DictReader(f))
    expected = ["scenario", "solver", "rule", "dt", "runs", "diverged", "rate", "ci95_low",
                "ci95_high"]
    if not rows or list(rows[0].keys()) != expected:
        raise ReportError(f"{path}: unexpected header (expected {','.join(expected)})")
    for r in rows:
        for key in ("dt", "rate", "ci95_low", "ci95_high"):
            r[key] = float(r[key])
        for key in ("runs", "diverged"):
            r[key] = int(r[key])
    return rows


class Verdict:
    """RESULTS/verdict/verdict.csv and candidates.csv (testbed verdict)"""

    def __init__(self, folder):
        path = os.path.join(folder, VERDICT, "verdict.csv")
        with open(path, newline="") as f:
            self.rows = list(csv.DictReader(f))
        with open(os.path.join(folder, VERDICT, "candidates.csv"), newline="") as f:
            self.candidates = list(csv.DictReader(f))
        if not self.rows:
            raise ReportError(f"{path}: no rows")
        for r in self.rows:
            for key in ("budget_m", "dt", "cost_us_per_s", "us_per_frame", "puppets_per_core",
                        "error_m", "divergence_upper", "best_error_m", "truth_floor_m",
                        "frame_hz"):
                r[key] = float(r[key]) if r[key] else math.nan
            r["config"] = (r["solver"], r["rule"])
        for c in self.candidates:
            for key in ("dt", "cost_us_per_s", "error_m", "truth_floor_m"):
                c[key] = float(c[key]) if c[key] else math.nan
            c["config"] = (c["solver"], c["rule"])
            c["starts"], c["diverged_starts"] = int(c["starts"]), int(c["diverged_starts"])
        first = self.rows[0]
        self.model, self.git_sha, self.machine = first["model"], first["git_sha"], first["machine"]
        self.truth, self.frame_hz = first[TRUTH], first["frame_hz"]
        self.budgets = sorted({r["budget_m"] for r in self.rows})
        self.scenarios = ordered({r["scenario"] for r in self.rows}, SCENARIOS)
        self.configs = ordered({r["config"] for r in self.rows}, CONFIGS)
        self.by_key = {(r["scenario"], r["config"], r["view"], r["budget_m"]): r
                       for r in self.rows}
        self.starts = max((int(r["starts"]) for r in self.rows if r["starts"]), default=0)
        self.floor = {r["scenario"]: r["truth_floor_m"] for r in self.rows}

    def row(self, scenario, config, view, budget):
        return self.by_key.get((scenario, config, view, budget))

    def judged(self, scenario, budget):
        """a budget the truth can judge in this scenario (at or above its floor)"""
        return budget >= self.floor[scenario]

    def cheapest(self, scenario, view, budget, procedural):
        """the met row of the cheapest procedural rule, or of the cheapest reference engine (any
        other solver), or None"""
        met = [self.row(scenario, c, view, budget) for c in self.configs
               if (c[0] == RULES_ENGINE) == procedural]
        met = [r for r in met if r and r["verdict"] == "met"]
        return min(met, key=lambda r: r["cost_us_per_s"]) if met else None

    def cheapest_reference(self, scenario, view, budget):
        return self.cheapest(scenario, view, budget, procedural=False)

    def cheapest_procedural(self, scenario, view, budget):
        return self.cheapest(scenario, view, budget, procedural=True)


def read_verdict(folder):
    if not os.path.exists(os.path.join(folder, VERDICT, "verdict.csv")):
        return None
    return Verdict(folder)


def read_ablation(folder):
    """results/ablation: configs.csv and one summary.csv per configuration (scripts/ablation.sh)"""
    path = os.path.join(folder, ABLATION, "configs.csv")
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        configs = list(csv.DictReader(f))
    for c in configs:
        c["summary"] = Summary(os.path.join(folder, ABLATION, c["name"], "summary.csv"))
    return configs
