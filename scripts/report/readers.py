import csv
import math
import os

from .catalogue import CANDIDATES_CSV as C
from .catalogue import (CONFIGS, DIVERGED, M, MET, RULES_ENGINE, SCENARIOS, SECOND_TRUTH, ST,
                        SUMMARY_HEADER, TABLES, TRUTH, TRUTHS, TRUTH_TEXT, VALUES, WASM_ENGINES,
                        trace_stem)
from .catalogue import ROBUSTNESS_CSV as R
from .catalogue import SUMMARY_CSV as S
from .catalogue import TRACE_CSV as T
from .catalogue import VERDICT_CSV as V
from .common import (ABLATION, BAR_MARGIN, MAIN, MIN_ORDER, ROBUSTNESS, ReportError, TABLE_DT,
                     VERDICT, dt_text, ordered)


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
                dt = float(r[S.dt])
                exact = 1 / round(1 / dt)  # every dt is 1/n; the CSV keeps 9 digits
                if abs(dt - exact) <= 1e-6 * exact:
                    dt = exact
                config = (r[S.solver], r[S.rule])
                value = float(r[S.value]) if r[S.value] else math.nan
                key = (r[S.scenario], config, dt, r[S.metric], r[S.stat], r[S.reference])
                self.values[key] = value
                if r[S.reference] == "" and r[S.metric] == M.joint_gap_m:
                    if r[S.status] not in VALUES["summary.csv"]["status"]:
                        raise ReportError(f"{path}:{n}: status {r[S.status]!r} is not one of the "
                                          "testbed's catalogue")
                    self.status[(r[S.scenario], config, dt)] = r[S.status]
                    self.dts.add(dt)
                    if r[S.scenario] not in self.scenarios:
                        self.scenarios.append(r[S.scenario])
                    if config not in self.configs:
                        self.configs.append(config)
                self.model, self.git_sha, self.machine = r[S.model], r[S.git_sha], r[S.machine]
        if not self.values:
            raise ReportError(f"{path}: no rows")
        self.dts = sorted(self.dts)
        self.scenarios.sort(key=lambda s: SCENARIOS.index(s) if s in SCENARIOS else len(SCENARIOS))
        self.configs.sort(key=lambda c: CONFIGS.index(c) if c in CONFIGS else len(CONFIGS))

    def get(self, scenario, config, dt, metric, stat, reference=""):
        return self.values.get((scenario, config, dt, metric, stat, reference), math.nan)

    def diverged(self, scenario, config, dt):
        return self.status.get((scenario, config, dt)) == DIVERGED

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

    def truth_own(self, scenario, reference=TRUTH, scale=0.5, stat=ST.reseeded_mean,
                  metric=M.pose_err_m):
        """a truth's run at scale·h against its run at h"""
        engine = self.truth_engine(reference)
        if not engine:
            return math.nan
        solver, h = engine
        return self.get(scenario, (solver, ""), 1 / round(1 / (scale * h)), metric, stat, reference)

    def truth_check(self, scenario, reference=TRUTH, stat=ST.reseeded_mean, metric=M.pose_err_m):
        """a truth's own difference: its run at h/2 against it"""
        return self.truth_own(scenario, reference, 0.5, stat, metric)

    def truth_order(self, scenario, reference=TRUTH, stat=ST.reseeded_mean, metric=M.pose_err_m):
        """the order p of convergence: log2 of the 2h difference over the h/2 difference"""
        fine = self.truth_check(scenario, reference, stat, metric)
        coarse = self.truth_own(scenario, reference, 2.0, stat, metric)
        if not (fine > 0 and coarse > 0):
            return math.nan
        return math.log2(coarse / fine)

    def truth_bar(self, scenario, reference=TRUTH, stat=ST.reseeded_mean, metric=M.pose_err_m):
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

    def truth_limit(self, scenario, reference=TRUTH, stat=ST.reseeded_mean, metric=M.pose_err_m):
        """the smallest error a truth can judge (its floor): its error bar, and never below the
        other truth's error against it, judged as every solver is (re-seeded from its states)"""
        agreement = self.truths_agreement(scenario, stat, reference, metric)
        bar = self.truth_bar(scenario, reference, stat, metric)
        return bar if math.isnan(agreement) else max(bar, agreement)

    def has_second_truth(self):
        return self.truth_engine(SECOND_TRUTH) is not None


def read_table(path, table):
    """the rows of a CSV the testbed wrote, as dicts by column; its header must be the one the
    catalogue gives for its file (TABLES[table]), else the report stops naming both"""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader, None)
        if header != TABLES[table]:
            raise ReportError(f"{path}: its columns are not {table}'s in the testbed's catalogue "
                              f"(expected {','.join(TABLES[table])})")
        rows = []
        allowed = VALUES.get(table, {})
        for n, row in enumerate(reader, start=2):
            if len(row) != len(header):
                raise ReportError(f"{path}:{n}: {len(row)} fields, expected {len(header)}")
            r = dict(zip(header, row))
            for column, names in allowed.items():
                if r[column] not in names:
                    raise ReportError(f"{path}:{n}: {column} {r[column]!r} is not one of the "
                                      f"testbed's catalogue ({', '.join(names)})")
            rows.append(r)
        return rows


def read_frontier(path):
    if not os.path.exists(path):
        return []
    return read_table(path, "frontier.csv")


def read_trace(folder, model, scenario, config, dt):
    solver, rule = config
    name = trace_stem(model, scenario, (solver, rule), f"{dt:.9g}") + ".csv"
    path = os.path.join(folder, MAIN, "traces", name)
    if not os.path.exists(path):
        return None
    t, gap = [], []
    for row in read_table(path, "trace"):
        t.append(float(row[T.t]))
        gap.append(float(row[T.joint_gap_max_m]))
    return t, gap


def read_robustness(folder):
    """RESULTS/robustness/robustness_summary.csv (testbed robustness), or None"""
    path = os.path.join(folder, ROBUSTNESS, "robustness_summary.csv")
    if not os.path.exists(path):
        return None
    rows = read_table(path, "robustness_summary.csv")
    if not rows:
        raise ReportError(f"{path}: no rows")
    for r in rows:
        for key in (R.dt, R.rate, R.ci95_low, R.ci95_high):
            r[key] = float(r[key])
        for key in (R.runs, R.diverged):
            r[key] = int(r[key])
    return rows


class Verdict:
    """RESULTS/verdict/verdict.csv and candidates.csv (testbed verdict), or another verdict's
    folder under RESULTS"""

    def __init__(self, folder, sub=VERDICT):
        path = os.path.join(folder, sub, "verdict.csv")
        self.rows = read_table(path, "verdict.csv")
        self.candidates = read_table(os.path.join(folder, sub, "candidates.csv"),
                                     "candidates.csv")
        if not self.rows:
            raise ReportError(f"{path}: no rows")
        for r in self.rows:
            for key in (V.budget_m, V.dt, V.cost_us_per_s, V.us_per_frame, V.puppets_per_core,
                        V.error_m, V.divergence_upper, V.best_error_m, V.truth_floor_m,
                        V.frame_hz):
                r[key] = float(r[key]) if r[key] else math.nan
            r["config"] = (r[V.solver], r[V.rule])
        for c in self.candidates:
            for key in (C.dt, C.cost_us_per_s, C.error_m, C.truth_floor_m):
                c[key] = float(c[key]) if c[key] else math.nan
            c["config"] = (c[C.solver], c[C.rule])
            c[C.starts], c[C.diverged_starts] = int(c[C.starts]), int(c[C.diverged_starts])
        first = self.rows[0]
        self.model, self.git_sha, self.machine = first[V.model], first[V.git_sha], first[V.machine]
        self.truth, self.frame_hz = first[V.truth], first[V.frame_hz]
        self.budgets = sorted({r[V.budget_m] for r in self.rows})
        self.scenarios = ordered({r[V.scenario] for r in self.rows}, SCENARIOS)
        self.configs = ordered({r["config"] for r in self.rows}, CONFIGS)
        self.by_key = {(r[V.scenario], r["config"], r[V.view], r[V.budget_m]): r
                       for r in self.rows}
        self.starts = max((int(r[V.starts]) for r in self.rows if r[V.starts]), default=0)
        self.floor = {r[V.scenario]: r[V.truth_floor_m] for r in self.rows}

    def row(self, scenario, config, view, budget):
        return self.by_key.get((scenario, config, view, budget))

    def judged(self, scenario, budget):
        """a budget the truth can judge in this scenario (at or above its floor)"""
        return budget >= self.floor[scenario]

    def cheapest(self, scenario, view, budget, procedural):
        """the met row of the cheapest procedural rule, or of the cheapest native reference engine
        (any other solver but a WebAssembly one), or None"""
        met = [self.row(scenario, c, view, budget) for c in self.configs
               if (c[0] == RULES_ENGINE) == procedural and c[0] not in WASM_ENGINES]
        met = [r for r in met if r and r[V.verdict] == MET]
        return min(met, key=lambda r: r[V.cost_us_per_s]) if met else None

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
