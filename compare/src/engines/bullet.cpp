// The engines `bullet-multibody` (btMultiBody, reduced coordinates) and `bullet-rigid` (a
// btRigidBody ragdoll): one library, two worlds (reference/bullet.h), and one set of flags
// (--bullet-iterations, --bullet-euler-limits) that both read.
#include <CLI/CLI.hpp>

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
      .model_problem = reference::bullet_model_problem,
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
          .model_problem = reference::bullet_model_problem,
          .make = make<reference::Kind::kRigid>,
          .search = search};
}

}  // namespace puppet::compare
