// The engine catalogue (harness/src/engines/): every row makes what it names, the lists every
// client reads come from it, and each engine's flags read back what its replay flags write.
#include "puppet/compare/engines.h"

#include <gtest/gtest.h>

#include <CLI/CLI.hpp>
#include <algorithm>

#include "puppet/compare/scenario.h"
#include "puppet/model/model.h"

namespace puppet::compare {
namespace {

TEST(Engines, EveryBuiltRowMakesTheEngineItNames) {
  const Model model = load_named_model("pinocchio");
  const Scenario hang = make_scenario("hang", model);
  int built = 0;
  for (const Engine& engine : engines()) {
    ASSERT_TRUE(engine.model_problem && engine.make) << engine.name;
    EXPECT_FALSE(engine.summary.empty()) << engine.name;
    if (!engine.built) {
      EXPECT_EQ(find_engine(engine.name), nullptr) << engine.name;
      continue;
    }
    ++built;
    EXPECT_EQ(find_engine(engine.name), &engine);
    EXPECT_EQ(engine.model_problem(model), "") << engine.name;
    const auto simulator = engine.make(SolverOptions{});
    EXPECT_EQ(simulator->name(), engine.name);
    simulator->reset(model, hang);
    simulator->step(1.0 / 240);
    EXPECT_FALSE(simulator->diverged()) << engine.name;
  }
  EXPECT_GE(built, 3);  // procedural and Bullet's two are always built
}

TEST(Engines, TheNamesAreTheBuiltRowsInOrder) {
  std::vector<std::string> built;
  for (const Engine& engine : engines()) {
    if (engine.built) built.emplace_back(engine.name);
  }
  EXPECT_EQ(solver_names(), built);
  std::vector<std::string> sorted = built;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end()) << "a name twice";
}

TEST(Engines, AnUnknownNameIsRefused) {
  EXPECT_EQ(find_engine("physx"), nullptr);
  EXPECT_THROW(make_simulator("physx", {}), ScenarioError);
  const Model model = load_named_model("pinocchio");
  EXPECT_NE(engine_model_problem("physx", model).find("unknown solver"), std::string::npos);
}

// options that differ from the defaults in every field a flag sets
SolverOptions changed_options() {
  SolverOptions o;
  o.procedural.iterations = 3;
  o.procedural.substeps = 5;
  o.procedural.derive_velocities = false;
  o.bullet.iterations = 7;
  o.bullet.euler_ball_limits = true;
  o.mujoco.integrator = reference::MujocoIntegrator::kRk4;
  return o;
}

TEST(Engines, ReplayFlagsReadBackAsTheOptionsTheyCameFrom) {
  const SolverOptions cases[] = {SolverOptions{}, changed_options()};
  for (const SolverOptions& options : cases) {
    std::string replay;
    CLI::App app;
    SolverOptions read;
    for (const Engine& engine : engines()) {
      if (engine.replay_flags) engine.replay_flags(options, replay);
      if (engine.add_flags) engine.add_flags(app, read);
    }
    if (&options == &cases[0]) {
      EXPECT_EQ(replay, "") << "the defaults replay as nothing";
    }
    app.parse(replay, false);
    EXPECT_EQ(read.procedural.iterations, options.procedural.iterations) << replay;
    EXPECT_EQ(read.procedural.substeps, options.procedural.substeps) << replay;
    EXPECT_EQ(read.procedural.derive_velocities, options.procedural.derive_velocities) << replay;
    EXPECT_EQ(read.bullet.iterations, options.bullet.iterations) << replay;
    EXPECT_EQ(read.bullet.euler_ball_limits, options.bullet.euler_ball_limits) << replay;
    EXPECT_EQ(read.mujoco.integrator, options.mujoco.integrator) << replay;
  }
}

TEST(Engines, AFlagIsDefinedByOneRowOnly) {
  CLI::App app;
  SolverOptions options;
  // CLI11 throws OptionAlreadyAdded when two rows define the same flag
  EXPECT_NO_THROW({
    for (const Engine& engine : engines()) {
      if (engine.add_flags) engine.add_flags(app, options);
    }
  });
}

}  // namespace
}  // namespace puppet::compare
