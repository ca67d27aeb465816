// The engine catalogue (engines.h): the rows, and what every client asks of them.
#include <CLI/CLI.hpp>
#include <algorithm>

#include "puppet/compare/engines.h"
#include "puppet/model/text.h"

namespace puppet::compare {

// the rows, one per engine file (engines/<name>.cpp; Bullet's two worlds share bullet.cpp)
Engine procedural_engine();
Engine bullet_multibody_engine();
Engine bullet_rigid_engine();
Engine mujoco_engine();

std::span<const Engine> engines() {
  static const std::vector<Engine> rows = {procedural_engine(), bullet_multibody_engine(),
                                           bullet_rigid_engine(), mujoco_engine()};
  return rows;
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

std::string engine_model_problem(std::string_view name, const Model& model) {
  const Engine* engine = find_engine(name);
  if (!engine) return "unknown solver " + shown(name);
  return engine->model_problem(model);
}

std::unique_ptr<Simulator> make_simulator(const std::string& solver, const SolverOptions& options) {
  const Engine* engine = find_engine(solver);
  if (!engine) throw ScenarioError("unknown solver " + shown(solver), "solver");
  return engine->make(options);
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
