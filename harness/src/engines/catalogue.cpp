// The engine catalogue (engines.h): the rows, and what every client asks of them.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "puppet/compare/engines.h"
#include "puppet/compare/number.h"
#include "puppet/model/text.h"
#include "puppet/procedural/solver.h"

namespace puppet::compare {

// the rows, one per engine file (engines/<name>.cpp; Bullet's two worlds share bullet.cpp)
Engine procedural_engine();
Engine bullet_multibody_engine();
Engine bullet_rigid_engine();
Engine mujoco_engine();
Engine ode_engine();
Engine jolt_engine();

std::span<const Engine> engines() {
  static const std::vector<Engine> rows = {procedural_engine(),   bullet_multibody_engine(),
                                           bullet_rigid_engine(), mujoco_engine(),
                                           ode_engine(),          jolt_engine()};
  return rows;
}

std::string unbuilt_engine_problem(const std::vector<std::string>& names) {
  for (const std::string& name : names) {
    for (const Engine& engine : engines()) {
      if (engine.name != name || engine.built) continue;
      return name + " is not built here: " + (engine.missing ? engine.missing() : "");
    }
  }
  return {};
}

const Engine* find_engine(std::string_view name) {
  for (const Engine& engine : engines()) {
    if (engine.name == name && engine.built) return &engine;
  }
  return nullptr;
}

const std::vector<std::string>& solver_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const Engine& engine : engines()) {
      if (engine.built) out.emplace_back(engine.name);
    }
    return out;
  }();
  return names;
}

bool has_rules(std::string_view solver) {
  const Engine* engine = find_engine(solver);
  return engine && engine->has_rules;
}

std::vector<Setting> settings_searched(std::string_view solver, const SolverOptions& base) {
  std::vector<Setting> out;
  const Engine* engine = find_engine(solver);
  if (engine && engine->search) engine->search(base, out);
  if (out.empty()) out.push_back({"", "", base});  // dt is all there is to choose
  return out;
}

namespace {
constexpr double kPi = std::numbers::pi;
}  // namespace

ModelSize model_size(const Model& model) {
  ModelSize size;
  size.segments = model.segment_count();
  size.dofs = 6;  // the root, free
  // segments come parent before child (the loader's order): one pass gives the depths
  std::vector<int> parent(static_cast<size_t>(model.segment_count()), -1);
  for (const Joint& joint : model.joints) {
    parent[static_cast<size_t>(joint.child)] = joint.parent;
    switch (joint.type) {
      case JointType::kBall: {
        size.dofs += 3;
        size.joint_rows += 3;
        // a limit of half a turn or more never acts, and no engine builds it
        const bool open = joint.ball_limit == BallLimit::kSwingTwist && joint.swing_x >= kPi &&
                          joint.swing_y >= kPi && joint.twist >= kPi;
        size.limit_rows += open ? 0 : joint.ball_limit == BallLimit::kEulerBox ? 3 : 2;
        size.box_limits += !open && joint.ball_limit == BallLimit::kEulerBox ? 1 : 0;
        break;
      }
      case JointType::kHinge:
        size.dofs += 1;
        size.joint_rows += 5;
        size.limit_rows += joint.lower <= -kPi && joint.upper >= kPi ? 0 : 1;
        break;
      case JointType::kFixed:
        size.joint_rows += 6;
        break;
      case JointType::kSlide:
        size.dofs += 1;
        size.joint_rows += 5;
        size.limit_rows += std::isfinite(joint.lower) ? 1 : 0;
        break;
    }
  }
  for (const Segment& segment : model.segments) {
    for (const Shape& shape : segment.shapes) {
      switch (shape.type) {
        case ShapeType::kSphere:
        case ShapeType::kEllipsoid:
          size.contact_points += 1;
          break;
        case ShapeType::kCapsule:
          size.contact_points += 2;
          break;
        case ShapeType::kBox:
        case ShapeType::kCylinder:
          size.contact_points += 4;
          break;
      }
    }
  }
  std::vector<int> depth(parent.size(), 0);
  for (size_t s = 0; s < parent.size(); ++s) {
    if (parent[s] >= 0) depth[s] = depth[static_cast<size_t>(parent[s])] + 1;
    size.depth = std::max(size.depth, depth[s]);
  }
  return size;
}

std::string engine_model_note(std::string_view name, const Model& model) {
  const Engine* engine = find_engine(name);
  if (!engine || engine->exact_armature || !has_armature(model)) return {};
  return "joint armature is added to each child's inertia about its joint's axes at rest "
         "(MuJoCo adds it to the joint itself; docs/model-format.md measures the difference)";
}

std::string engine_model_problem(std::string_view name, const Model& model,
                                 const SolverOptions& options, double budget) {
  const Engine* engine = find_engine(name);
  if (!engine) return "unknown solver " + shown(name);
  if (!(std::isfinite(budget) && budget > 0.0)) {
    return "the engine budget must be a finite positive number of seconds, not " +
           shown(std::to_string(budget));
  }
  if (std::string problem = engine->model_problem(model); !problem.empty()) return problem;
  if (engine->has_rules) {
    const procedural::Rule rule = procedural::rule_defaults(options.procedural).rule;
    if (std::string problem = procedural::rule_model_problem(model, rule); !problem.empty()) {
      return problem;
    }
  }
  if (!engine->second_cost) return {};
  const double cost = engine->second_cost(model, options);
  if (cost <= budget) return {};
  const ModelSize size = model_size(model);
  char line[360];
  std::snprintf(line, sizeof line,
                "one simulated second at dt 1/240 s would take it about %.3g s of CPU (%d degrees "
                "of freedom, %d limit rows, %d contact points on the ground, joints %d deep), "
                "past the budget of %.3g s (--engine-budget)",
                cost, size.dofs, size.limit_rows, size.contact_points, size.depth, budget);
  return line;
}

std::unique_ptr<Simulator> make_simulator(const std::string& solver, const SolverOptions& options) {
  const Engine* engine = find_engine(solver);
  if (!engine) throw ScenarioError("unknown solver " + shown(solver), "solver");
  return engine->make(options);
}

const CLI::Validator& finite_number_check() {
  static const CLI::Validator validator(
      [](std::string& text) {
        double value = 0.0;
        return parse_finite(text, &value) ? std::string() : "must be a finite number";
      },
      "NUMBER");
  return validator;
}

const CLI::Validator& whole_number_check() {
  static const CLI::Validator validator(
      [](std::string& text) {
        const bool digits =
            !text.empty() && text.size() <= 9 && (text.size() == 1 || text[0] != '0') &&
            std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
        return digits ? std::string() : "expected a whole number, got " + shown(text);
      },
      "N");
  return validator;
}

}  // namespace puppet::compare
