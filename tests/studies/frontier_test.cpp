// frontier.cpp: the bisection brackets the boundary, and a direct run on each side agrees.
#include "puppet/compare/frontier.h"

#include <gtest/gtest.h>

#include "support/source_dir.h"

namespace puppet::compare {
namespace {

const std::string kPinocchio = std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";

bool yank_stays_ok(const Model& model, const SolverConfig& config, double hz, double dt) {
  ScenarioOptions options;
  options.hz = hz;
  const Scenario yank = make_scenario("yank", model, options);
  RunOptions run;
  run.dt = dt;
  run.timing = false;
  auto simulator = make_simulator(config.solver, config.options);
  return !run_scenario(*simulator, model, yank, run).diverged;
}

TEST(Frontier, BisectionBracketsTheBoundaryToItsResolution) {
  const Model model = load_model(kPinocchio);
  FrontierSpec spec;
  spec.model = &model;
  SolverOptions literal;
  literal.procedural.rule = procedural::Rule::kLiteral;
  spec.configs = {{"procedural", literal}};
  spec.hz_low = 2.0;
  spec.hz_high = 16.0;
  spec.jobs = 2;
  const auto rows = find_frontier(spec);
  ASSERT_EQ(rows.size(), 2u);
  const FrontierRow& hz = rows[0];
  EXPECT_EQ(hz.quantity, "hz");
  EXPECT_EQ(hz.rule, "literal");
  ASSERT_TRUE(hz.largest_ok && hz.first_diverged);
  std::printf("[ frontier ] procedural literal, yank: ok at %.3f Hz, diverged at %.3f Hz (%s)\n",
              *hz.largest_ok, *hz.first_diverged, hz.reason.c_str());
  EXPECT_LT(*hz.largest_ok, *hz.first_diverged);
  EXPECT_LE(*hz.first_diverged / *hz.largest_ok, spec.resolution);
  EXPECT_FALSE(hz.reason.empty());
  EXPECT_TRUE(yank_stays_ok(model, spec.configs[0], *hz.largest_ok, spec.hz_dt));
  EXPECT_FALSE(yank_stays_ok(model, spec.configs[0], *hz.first_diverged, spec.hz_dt));
  // literal is ok at both ends of the dt range: nothing diverged, the top is reported
  const FrontierRow& dt = rows[1];
  EXPECT_EQ(dt.quantity, "dt");
  ASSERT_TRUE(dt.largest_ok);
  EXPECT_FALSE(dt.first_diverged);
  EXPECT_EQ(*dt.largest_ok, spec.dt_high);
  EXPECT_EQ(dt.runs, 2);

  const std::string csv = frontier_csv(rows, {"pinocchio", "abc", "machine"});
  EXPECT_EQ(csv.substr(0, csv.find('\n')), kFrontierHeader);
}

}  // namespace
}  // namespace puppet::compare
