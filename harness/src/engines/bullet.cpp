// The engines `bullet-multibody` (btMultiBody, reduced coordinates) and `bullet-rigid` (a
// btRigidBody ragdoll): one library, two worlds (reference/bullet.h), and one set of flags
// (--bullet-iterations, --bullet-euler-limits) that both read.
#include <CLI/CLI.hpp>
#include <algorithm>

#include "puppet/compare/engines.h"
#include "puppet/reference/bullet.h"
#include "reference_adapter.h"

namespace puppet::compare {
namespace {

template <reference::Kind kKind>
std::unique_ptr<Simulator> make(const SolverOptions& options) {
  const reference::Settings settings = options.bullet;
  const std::string problem = reference::validate(settings);
  if (!problem.empty()) throw ScenarioError(problem, "bullet_iterations");
  return make_reference_simulator(
      kKind == reference::Kind::kMultibody ? "bullet-multibody" : "bullet-rigid",
      [settings](const Model& model, const Environment& environment) {
        return reference::make_solver(kKind, model, environment, settings);
      });
}

void add_flags(CLI::App& command, SolverOptions& options) {
  command
      .add_option("--bullet-iterations", options.bullet.iterations,
                  "Bullet: sequential-impulse sweeps per step")
      ->check(whole_number_check())
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  command.add_flag("--bullet-euler-limits", options.bullet.euler_ball_limits,
                   "bullet-multibody: Bullet's own ball limits (a box of Euler angles)");
}

void replay_flags(const SolverOptions& options, std::string& out) {
  const SolverOptions defaults;
  if (options.bullet.iterations != defaults.bullet.iterations) {
    out += " --bullet-iterations " + std::to_string(options.bullet.iterations);
  }
  if (options.bullet.euler_ball_limits) out += " --bullet-euler-limits";
}

// Bullet's default sweeps, and enough for its limits to converge
void search(const SolverOptions& base, std::vector<Setting>& out) {
  for (const int n : {10, 50}) {
    Setting s{"--bullet-iterations " + std::to_string(n), std::to_string(n) + " sweeps", base};
    s.options.bullet.iterations = n;
    out.push_back(std::move(s));
  }
}

// Measured on the reference machine (docs/reliability.md, "Engines bounded by what they can
// step"): chains of limited ball joints at dt 1/240 s, 20 steps, Release. A btMultiBody
// constraint row spans every degree of freedom of the tree, so with every limit acting a step
// grows with dofs × rows² (100, 200 and 400 links: 0.08, 0.66 and 5.9 s a step, 3.5 ns each);
// with none acting, each limit's rows are still built, dofs × rows (6 ns each).
// Figures folded onto the ground (bench_budget: chains of capsules, boxes and box-limited boxes,
// four rods of many boxes, Pinocchio and humanoid.xml, each let go curled and timed 1.5 s later;
// scripts/budget_table.py results/bench/budget.json --fit gives the terms, docs/reliability.md
// the ratios): about 2 µs a link and 1.9 µs a contact point
// (within 0.7–3.0× of all eleven). The estimate takes every limit acting and every shape on the
// ground, the worst a scenario can ask.
double multibody_cost(const Model& model, const SolverOptions&) {
  const ModelSize n = model_size(model);
  const double dofs = n.dofs, rows = n.limit_rows;
  const double step = 2e-6 * n.segments + 1.9e-6 * n.contact_points + 6e-9 * dofs * rows +
                      3.5e-9 * dofs * rows * rows;
  return step / kBudgetDt;
}

// A btRigidBody ragdoll is linear in its bodies and rows, per sweep. Figures folded onto the ground
// (bench_budget: chains of capsules, boxes and box-limited boxes, four rods of many boxes,
// Pinocchio and humanoid.xml, each let go curled and timed 1.5 s later; scripts/budget_table.py
// results/bench/budget.json --fit gives the terms, docs/reliability.md the ratios): at ten sweeps,
// 0.5 µs a body or joint row, 0.08 µs a limit row and 0.25 µs a contact point (within 0.8–1.3×)
double rigid_cost(const Model& model, const SolverOptions& options) {
  const ModelSize n = model_size(model);
  const double step =
      0.5e-6 * (n.segments + n.joint_rows) + 0.08e-6 * n.limit_rows + 0.25e-6 * n.contact_points;
  return step * std::max(1, options.bullet.iterations) / 10.0 / kBudgetDt;
}

}  // namespace

Engine bullet_multibody_engine() {
  return {
      .name = "bullet-multibody",
      .summary = "Bullet's btMultiBody: Featherstone, reduced coordinates, soft limits and pins",
      .constraints =
          "a box limit is a row per angle; limits, contacts and moving pins are "
          "speculative or Baumgarte impulses iterated ten sweeps (a limit giving back "
          "about 2% of an impact's speed, a moving pin aimed at its target's "
          "velocity); a contact's friction impulses are clamped per direction",
      .model_problem = reference::bullet_multibody_model_problem,
      .second_cost = multibody_cost,
      .make = make<reference::Kind::kMultibody>,
      .add_flags = add_flags,
      .replay_flags = replay_flags,
      .search = search};
}

Engine bullet_rigid_engine() {
  // its flags are bullet-multibody's row's
  return {.name = "bullet-rigid",
          .summary = "a Bullet btRigidBody ragdoll: maximal coordinates, the games' ragdoll",
          .constraints =
              "each joint is a constraint between two free bodies, its impulses "
              "iterated ten sweeps, so joints open under load",
          .model_problem = reference::bullet_rigid_model_problem,
          .second_cost = rigid_cost,
          .make = make<reference::Kind::kRigid>,
          .search = search};
}

}  // namespace puppet::compare
