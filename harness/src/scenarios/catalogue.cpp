// The scenario catalogue: the rows (one file each), the names every client reads, and
// make_scenario, which builds a row and applies the command line's overrides.
#include <algorithm>

#include "builders.h"
#include "puppet/model/text.h"

namespace puppet::compare {

// the rows, one per file (scenarios/<name>.cpp)
ScenarioRow hang_scenario();
ScenarioRow drag_scenario();
ScenarioRow shake_scenario();
ScenarioRow spin_scenario();
ScenarioRow drop_scenario();
ScenarioRow collapse_scenario();
ScenarioRow water_scenario();
ScenarioRow tremble_scenario();
ScenarioRow yank_scenario();
ScenarioRow marionette_scenario();

namespace {

const std::vector<ScenarioRow>& rows() {
  static const std::vector<ScenarioRow> all = {
      hang_scenario(),    drag_scenario(), marionette_scenario(), shake_scenario(),
      spin_scenario(),    drop_scenario(), collapse_scenario(),   water_scenario(),
      tremble_scenario(), yank_scenario()};
  return all;
}

}  // namespace

const std::vector<std::string>& scenario_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const ScenarioRow& row : rows()) out.emplace_back(row.name);
    return out;
  }();
  return names;
}

std::string scenario_asks(const std::string& name) {
  const auto row = std::find_if(rows().begin(), rows().end(),
                                [&](const ScenarioRow& r) { return r.name == name; });
  return row == rows().end() ? std::string() : std::string(row->asks);
}

bool judged_by_contact(const std::string& name) {
  const auto row = std::find_if(rows().begin(), rows().end(),
                                [&](const ScenarioRow& r) { return r.name == name; });
  return row != rows().end() && row->contact;
}

const std::string& headline_scenario() {
  static const std::string name = [] {
    const auto row =
        std::find_if(rows().begin(), rows().end(), [](const ScenarioRow& r) { return r.headline; });
    return row == rows().end() ? std::string() : std::string(row->name);
  }();
  return name;
}

Scenario make_scenario(const std::string& name, const Model& model,
                       const ScenarioOptions& options) {
  const auto row = std::find_if(rows().begin(), rows().end(),
                                [&](const ScenarioRow& r) { return r.name == name; });
  if (row == rows().end()) throw ScenarioError("unknown scenario " + shown(name), "scenario");
  Scenario s = row->make(model, options);
  s.name = name;
  // command-line overrides of the environment
  if (options.gravity) s.environment.gravity = *options.gravity;
  if (options.air_drag) s.environment.air_drag = *options.air_drag;
  if (options.ground) s.environment.ground = *options.ground;
  return s;
}

}  // namespace puppet::compare
