// No heap allocation inside a step: the global operator new is replaced to count calls.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "model_tables.h"
#include "puppet/compare/scenario.h"
#include "puppet/procedural/crowd.h"
#include "puppet/procedural/solver.h"
#include "support/source_dir.h"

namespace {
std::atomic<long> g_allocations{0};
}

// the replacements below are new and delete themselves, on malloc and free: at -O1 and up g++
// inlines them into their callers and reads each pair as mismatched (-Wmismatched-new-delete)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return operator new(size); }
// the nothrow forms too (std::stable_sort's buffer uses them), so every new pairs with free
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  ++g_allocations;
  return std::malloc(size ? size : 1);
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept {
  return operator new(size, tag);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace puppet::procedural {
namespace {

const std::string kPinocchio = std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json";

// heap allocations made while `step(targets)` runs, over `steps` steps of 1/60 s along the
// scenario's pin targets (computing the targets is not counted)
template <typename Step>
long allocations_while_stepping(const compare::Scenario& scenario, int steps, Step step) {
  std::vector<Vector3d> targets;
  targets.reserve(8);
  long during = 0;
  for (int k = 0; k < steps; ++k) {
    scenario.targets_at((k + 1) / 60.0, targets);
    const long before = g_allocations.load();
    step(targets);
    during += g_allocations.load() - before;
  }
  return during;
}

// heap allocations over 40 steps of 1/60 s of the scenario in a solver with these settings
long allocations_in_scenario(const Model& model, const compare::Scenario& scenario,
                             const Settings& settings) {
  Solver solver(model, settings, scenario.environment);
  solver.reset(scenario.initial);
  solver.set_pins(scenario.initial_pins());
  return allocations_while_stepping(scenario, 40, [&](const std::vector<Vector3d>& targets) {
    solver.set_pin_targets(targets);
    solver.step(1.0 / 60.0);
  });
}

TEST(Allocation, NoneInsideAStep) {
  const Model model = load_model(kPinocchio);
  for (const std::string& name : compare::scenario_names()) {
    const compare::Scenario scenario = compare::make_scenario(name, model);
    for (Rule rule : kAllRules) {
      Settings settings;
      settings.rule = rule;
      settings.substeps = 2;
      settings.time_stages = true;
      // 0.67 s at 1/60 in two substeps: long enough for drop to reach the ground
      const long during = allocations_in_scenario(model, scenario, settings);
      EXPECT_EQ(during, 0) << name << " " << rule_name(rule);
    }
  }
  EXPECT_GT(g_allocations.load(), 0);  // the counter counts
}

// a model too large to keep every anchor's order (kKeptOrderSegments): its solver fills orders
// into its workspace as the contacts and the pin move the anchor, without allocating either
TEST(Allocation, NoneInsideAStepOfALargeModel) {
  const Model model = make_chain(kKeptOrderSegments + 40);
  const compare::Scenario scenario = compare::make_scenario("drop", model);
  for (Rule rule : kAllRules) {
    Settings settings;
    settings.rule = rule;
    const long during = allocations_in_scenario(model, scenario, settings);
    EXPECT_EQ(during, 0) << rule_name(rule);
  }
}

TEST(Allocation, NoneInsideACrowdStep) {
  const Model model = load_model(kPinocchio);
  const compare::Scenario scenario = compare::make_scenario("drag", model);
  // relaxed one by one, xpbd in lanes (a partial batch included: 6 puppets)
  for (Rule rule : {Rule::kRelaxed, Rule::kXpbd}) {
    Settings settings;
    settings.rule = rule;
    Crowd crowd(model, settings, scenario.environment, 6, 2);
    EXPECT_EQ(crowd.lanes() > 1, rule == Rule::kXpbd) << rule_name(rule);
    for (int k = 0; k < crowd.size(); ++k) {
      crowd.puppet(k).reset(scenario.initial);
      crowd.puppet(k).set_pins(scenario.initial_pins());
    }
    const long during =
        allocations_while_stepping(scenario, 20, [&](const std::vector<Vector3d>& targets) {
          for (int k = 0; k < crowd.size(); ++k) crowd.puppet(k).set_pin_targets(targets);
          crowd.step(1.0 / 60.0);
        });
    EXPECT_EQ(during, 0) << rule_name(rule);
    // with a control, built once outside the steps as the crowd's interface asks
    const std::vector<Vector3d>* current = nullptr;
    const Crowd::Control control = [&current](int, Solver& puppet) {
      puppet.set_pin_targets(*current);
    };
    const long with_control =
        allocations_while_stepping(scenario, 20, [&](const std::vector<Vector3d>& targets) {
          current = &targets;
          crowd.step(1.0 / 60.0, control);
        });
    EXPECT_EQ(with_control, 0) << rule_name(rule);
  }
}

}  // namespace
}  // namespace puppet::procedural
