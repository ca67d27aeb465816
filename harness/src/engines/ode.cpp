// The engine `ode`: the Open Dynamics Engine 0.16 (reference/ode.h), where the build has it, with
// its flags (--ode-stepper, --ode-iterations).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "puppet/compare/engines.h"
#include "puppet/reference/ode.h"
#include "reference_adapter.h"

namespace puppet::compare {
namespace {

using reference::OdeStepper;

constexpr std::array<std::pair<const char*, OdeStepper>, 2> kSteppers = {
    {{"quick", OdeStepper::kQuick}, {"step", OdeStepper::kStep}}};

const char* stepper_name(OdeStepper stepper) {
  return stepper == OdeStepper::kStep ? "step" : "quick";
}

std::unique_ptr<Simulator> make(const SolverOptions& options) {
  const reference::OdeSettings settings = options.ode;
  const std::string problem = reference::validate(settings);
  if (!problem.empty()) throw ScenarioError(problem, "ode_iterations");
  return make_reference_simulator("ode",
                                  [settings](const Model& model, const Environment& environment) {
                                    return reference::make_ode(model, environment, settings);
                                  });
}

void add_flags(CLI::App& command, SolverOptions& options) {
  std::vector<std::string> names;
  for (const auto& [name, value] : kSteppers) names.emplace_back(name);
  command
      .add_option_function<std::string>(
          "--ode-stepper",
          [&options](const std::string& text) {
            for (const auto& [name, value] : kSteppers) {
              if (text == name) options.ode.stepper = value;
            }
          },
          "ode: quick (dWorldQuickStep, projected Gauss–Seidel) or step (dWorldStep, the exact "
          "LCP)")
      ->check(CLI::IsMember(names))
      ->default_str(stepper_name(options.ode.stepper));
  command
      .add_option("--ode-iterations", options.ode.iterations,
                  "ode: dWorldQuickStep's sweeps per step")
      ->check(whole_number_check())
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
}

void replay_flags(const SolverOptions& options, std::string& out) {
  const SolverOptions defaults;
  if (options.ode.stepper != defaults.ode.stepper) {
    out += std::string(" --ode-stepper ") + stepper_name(options.ode.stepper);
  }
  if (options.ode.iterations != defaults.ode.iterations) {
    out += " --ode-iterations " + std::to_string(options.ode.iterations);
  }
}

// the stepper a game ships (QuickStep at ODE's default 20 sweeps, and at 100 where its limits
// converge further) and the exact one
void search(const SolverOptions& base, std::vector<Setting>& out) {
  for (const int n : {20, 100}) {
    Setting s{"--ode-stepper quick --ode-iterations " + std::to_string(n),
              "quick, " + std::to_string(n) + " sweeps", base};
    s.options.ode.stepper = OdeStepper::kQuick;
    s.options.ode.iterations = n;
    out.push_back(std::move(s));
  }
  Setting exact{"--ode-stepper step", "exact LCP", base};
  exact.options.ode.stepper = OdeStepper::kStep;
  out.push_back(std::move(exact));
}

// Measured on the reference machine (docs/reliability.md, "Engines bounded by what they can
// step"): chains of ball joints with 1° box limits, all acting, 20 steps in shake at 1/240 s.
// dWorldStep factors the dense matrix of all rows: 200, 400 and 800 links (1,194, 2,394 and 4,794
// rows) took 9, 81 and 623 ms a step, 6e-12 s per row³. dWorldQuickStep is linear in its rows
// per sweep: 1.2 and 3.3 ms a step at 400 and 800 links and 20 sweeps, 25–35 ns per row and
// sweep (40 taken). The rest is about 1 µs a body. Figures folded onto the ground (bench_budget:
// chains of capsules, boxes and box-limited boxes, four rods of many boxes, Pinocchio and
// humanoid.xml, each let go curled and timed 1.5 s later; scripts/budget_table.py
// results/bench/budget.json --fit gives the terms, docs/reliability.md the ratios): contacts are
// rows too, three a point: dWorldQuickStep takes 0.25 µs a body or joint row and 0.9 µs a point
// at 20 sweeps (within 0.75–1.5×); dWorldStep's pivots on a pile cost up to 200 times its
// hanging chains' 6e-12 s per row³ (four rods of 32 boxes each: 1,545 rows, 4.6 s a step), so
// it takes 1.5e-10 s per row³, which keeps every figure under its estimate by at most 2× (an
// easy pile's cost is as little as 1/15 of it).
double ode_cost(const Model& model, const SolverOptions& options) {
  const ModelSize n = model_size(model);
  if (options.ode.stepper == OdeStepper::kStep) {
    const double rows = n.joint_rows + n.limit_rows + 3.0 * n.contact_points;
    return (1e-6 * n.segments + 1.5e-10 * rows * rows * rows) / kBudgetDt;
  }
  const double step = 0.25e-6 * (n.segments + n.joint_rows) + 0.9e-6 * n.contact_points +
                      40e-9 * n.limit_rows * 20.0;
  return step * std::max(1, options.ode.iterations) / 20.0 / kBudgetDt;
}

}  // namespace

Engine ode_engine() {
  return {.name = "ode",
          .summary = "the Open Dynamics Engine 0.16: maximal coordinates, the classic ragdoll",
          .constraints =
              "each joint is rows between two free bodies, its error reduced 20% a step "
              "(ERP 0.2); a box limit is an Euler-mode angular motor's stops, a swing–twist "
              "limit a user-mode motor's aimed each step; rows solved exactly (dWorldStep) or "
              "by Gauss–Seidel sweeps (dWorldQuickStep); a contact's friction is a pyramid",
          .built = reference::have_ode(),
          .missing =
              [] {
                return std::string(
                    "this build has no ODE (Debian: libode-dev; scripts/setup.sh installs it, then "
                    "build again)");
              },
          .model_problem = reference::ode_model_problem,
          .second_cost = ode_cost,
          .make = make,
          .add_flags = add_flags,
          .replay_flags = replay_flags,
          .search = search};
}

}  // namespace puppet::compare
