// The engine `mujoco`: MuJoCo 2.2 (reference/mujoco.h), where the build has it, with its flag
// (--mujoco-integrator).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <array>
#include <string>
#include <utility>
#include <vector>

#include "puppet/compare/engines.h"
#include "puppet/reference/mujoco.h"
#include "reference_adapter.h"

namespace puppet::compare {
namespace {

using reference::MujocoIntegrator;

constexpr std::array<std::pair<const char*, MujocoIntegrator>, 3> kIntegrators = {
    {{"euler", MujocoIntegrator::kEuler},
     {"implicit", MujocoIntegrator::kImplicit},
     {"rk4", MujocoIntegrator::kRk4}}};

const char* integrator_name(MujocoIntegrator integrator) {
  for (const auto& [name, value] : kIntegrators) {
    if (value == integrator) return name;
  }
  return "euler";
}

std::unique_ptr<Simulator> make(const SolverOptions& options) {
  const reference::MujocoSettings settings = options.mujoco;
  return make_reference_simulator(
      "mujoco",
      [settings](const Model& model, const Environment& environment) {
        return reference::make_mujoco(model, environment, settings);
      },
      /*exact_armature=*/true);
}

void add_flags(CLI::App& command, SolverOptions& options) {
  std::vector<std::string> names;
  for (const auto& [name, value] : kIntegrators) names.emplace_back(name);
  command
      .add_option_function<std::string>(
          "--mujoco-integrator",
          [&options](const std::string& text) {
            for (const auto& [name, value] : kIntegrators) {
              if (text == name) options.mujoco.integrator = value;
            }
          },
          "mujoco: euler (MuJoCo's semi-implicit Euler), implicit or rk4")
      ->check(CLI::IsMember(names))
      ->default_str(integrator_name(options.mujoco.integrator));
}

void replay_flags(const SolverOptions& options, std::string& out) {
  if (options.mujoco.integrator != SolverOptions{}.mujoco.integrator) {
    out += std::string(" --mujoco-integrator ") + integrator_name(options.mujoco.integrator);
  }
}

// its default integrator (semi-implicit Euler) and its most accurate (RK4)
void search(const SolverOptions& base, std::vector<Setting>& out) {
  for (const auto& [integrator, label] :
       {std::pair{MujocoIntegrator::kEuler, "Euler"}, std::pair{MujocoIntegrator::kRk4, "RK4"}}) {
    Setting s{std::string("--mujoco-integrator ") + integrator_name(integrator), label, base};
    s.options.mujoco.integrator = integrator;
    out.push_back(std::move(s));
  }
}

// Measured on the reference machine (docs/reliability.md): MuJoCo's Newton solver factors a
// dense matrix over the degrees of freedom and its constraint rows, dofs × max(dofs, rows)²
// (a comb of 25 four-link arms, 306 dofs and 300 limit rows all acting: 0.1 s a step, 3.5 ns
// each). The rows count the contacts too, three each, up to the contacts the testbed's MJCF
// lets MuJoCo keep (nconmax, 4 a segment and 8). Figures folded onto the ground (bench_budget:
// chains of capsules, boxes and box-limited boxes, four rods of many boxes, Pinocchio and
// humanoid.xml, each let go curled and timed 1.5 s later; scripts/budget_table.py
// results/bench/budget.json --fit gives the terms, docs/reliability.md the ratios): 4.5 ns each
// keeps every one under its estimate by at most 2× (its cost on a pile is its Newton iterations',
// which the counts do not tell: 0.04 to 55 ms a step at the same size, so the estimate is as much
// as 177× the cost of an easy pile). RK4 steps four times.
double mujoco_cost(const Model& model, const SolverOptions& options) {
  const ModelSize n = model_size(model);
  const double contacts = std::min(n.contact_points, 4 * n.segments + 8);
  const double dofs = n.dofs, rows = std::max<double>(n.dofs, n.limit_rows + 3.0 * contacts);
  const double stages = options.mujoco.integrator == MujocoIntegrator::kRk4 ? 4.0 : 1.0;
  return stages * 4.5e-9 * dofs * rows * rows / kBudgetDt;
}

}  // namespace

Engine mujoco_engine() {
  return {.name = "mujoco",
          .summary = "MuJoCo 2.2: reduced coordinates, soft constraints solved as a convex problem",
          .constraints =
              "a box limit is three hinges, a swing–twist limit a cone on the whole "
              "rotation angle; limits, contacts and moving pins are soft (time constant "
              "2·dt, a limit damped at ratio 2 giving back about 1% of an impact's "
              "speed); a contact's friction cone is elliptic",
          .built = reference::have_mujoco(),
          .missing =
              [] {
                return std::string(
                    "this build has no MuJoCo (Debian: libmujoco-dev; scripts/setup.sh installs "
                    "it, then build again)");
              },
          .exact_armature = true,
          .model_problem = reference::mujoco_model_problem,
          .second_cost = mujoco_cost,
          .make = make,
          .add_flags = add_flags,
          .replay_flags = replay_flags,
          .search = search};
}

}  // namespace puppet::compare
