// What the commands print when they are done: a table on standard output of what they wrote
// (the files hold every figure; a table shows the ones a reader looks at first).
#pragma once

#include <vector>

#include "puppet/compare/frontier.h"
#include "puppet/compare/robustness.h"
#include "puppet/compare/run.h"
#include "puppet/compare/verdict.h"

namespace puppet::testbed {

// the dt of a sweep that run's table shows: the one nearest 1/240 s
double table_dt(const std::vector<double>& dts);
// run: one row per scenario and solver at dt
void print_run_table(const std::vector<compare::RunResult>& results, double dt);
// frontier: the largest frequency and dt that stay ok, per solver
void print_frontier_table(const compare::FrontierSpec& spec,
                          const std::vector<compare::FrontierRow>& rows);
// verdict: per scenario and solver, the cheapest cost within each budget
void print_verdict_table(const compare::VerdictSpec& spec, const compare::VerdictResult& result);
// robustness and merge: divergence rates with their intervals, from the rows as written
void print_rates(const std::vector<compare::RobustnessRow>& rows);

}  // namespace puppet::testbed
