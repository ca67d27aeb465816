#include "panel.h"

#include <imgui.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <exception>
#include <vector>

#include "puppet/compare/engines.h"
#include "puppet/procedural/solver.h"
#include "renderer.h"

namespace puppet::viewer {
namespace {

// a combo over names; true when the choice changed
bool combo(const char* label, std::string& value, const std::vector<std::string>& names) {
  bool changed = false;
  if (ImGui::BeginCombo(label, value.empty() ? "none" : value.c_str())) {
    for (const std::string& name : names) {
      const bool selected = name == value;
      if (ImGui::Selectable(name.empty() ? "none" : name.c_str(), selected) && !selected) {
        value = name;
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  return changed;
}

ImVec4 colour(const Vector3f& c) { return {c.x(), c.y(), c.z(), 1.0f}; }

// applies a configuration, or keeps the old one and says why
void configure(Session& session, const SessionConfig& config, PanelState& state) {
  try {
    session.configure(config);
    state.error.clear();
  } catch (const std::exception& e) {
    state.error = e.what();
  }
}

// a slider over a count that may still be the rule's default: it shows the value in force
bool rule_count_slider(const char* label, const SessionConfig& config, int* count, int lo, int hi) {
  procedural::Settings settings;
  settings.rule = config.options.procedural.rule;
  settings.iterations = config.options.procedural.iterations;
  settings.substeps = config.options.procedural.substeps;
  settings = procedural::rule_defaults(settings);
  int shown =
      count == &config.options.procedural.iterations ? settings.iterations : settings.substeps;
  if (!ImGui::SliderInt(label, &shown, lo, hi)) return false;
  *count = shown;
  return true;
}

void solver_section(Session& session, PanelState& state) {
  SessionConfig config = session.config();
  bool changed = combo("solver", config.solver, compare::solver_names());
  if (compare::has_rules(config.solver) || compare::has_rules(config.ghost)) {
    std::vector<std::string> rules;
    for (const procedural::Rule r : procedural::kAllRules) {
      rules.emplace_back(procedural::rule_name(r));
    }
    std::string rule(procedural::rule_name(config.options.procedural.rule));
    if (combo("rule", rule, rules)) {
      config.options.procedural.rule = *procedural::parse_rule(rule);  // one of the combo's names
      // a new rule starts from its own sweeps and substeps
      config.options.procedural.iterations = procedural::kRuleDefault;
      config.options.procedural.substeps = procedural::kRuleDefault;
      changed = true;
    }
    // a rule that reads its iterations gets a slider, labelled with what they count (its row
    // in the rule catalogue: "two-sided sweeps per substep" reads "two-sided sweeps")
    const std::string_view counts =
        procedural::rule_info(config.options.procedural.rule).iterations_are;
    if (!counts.empty()) {
      const std::string label(counts.substr(0, counts.find(" per ")));
      changed |=
          rule_count_slider(label.c_str(), config, &config.options.procedural.iterations, 1, 16);
    }
  }
  changed |= combo("anchor", config.anchor, {"auto", "grab", "scenario"});
  if (ImGui::IsItemHovered()) {
    ImGui::SetTooltip(
        "the pin the procedural pass starts from while you hold a point:\n"
        "auto = the grab for literal, the scenario's pin for the others");
  }
  std::vector<std::string> ghosts = {""};
  for (const std::string& name : compare::solver_names()) ghosts.push_back(name);
  changed |= combo("ghost", config.ghost, ghosts);
  if (changed) configure(session, config, state);
}

void scenario_section(Session& session, PanelState& state) {
  SessionConfig config = session.config();
  if (combo("scenario", config.scenario, compare::scenario_names())) {
    configure(session, config, state);
  }
  ImGui::InputText("##model", state.model_path, sizeof(state.model_path));
  ImGui::SameLine();
  if (ImGui::Button("load model")) {
    config.model = state.model_path;
    configure(session, config, state);
  }
}

void world_section(Session& session) {
  Environment e = session.scenario().environment;
  std::array<float, 3> g = {static_cast<float>(e.gravity.x()), static_cast<float>(e.gravity.y()),
                            static_cast<float>(e.gravity.z())};
  float air = static_cast<float>(e.air_drag), level = static_cast<float>(e.water_level),
        density = static_cast<float>(e.water_density),
        water_drag = static_cast<float>(e.water_drag);
  bool changed = ImGui::DragFloat3("gravity m/s²", g.data(), 0.05f, -30.0f, 30.0f, "%.2f");
  changed |= ImGui::SliderFloat("air drag 1/s", &air, 0.0f, 5.0f, "%.2f");
  changed |= ImGui::Checkbox("water", &e.water);
  if (e.water) {
    changed |= ImGui::SliderFloat("level m", &level, -0.5f, 4.0f, "%.2f");
    changed |= ImGui::SliderFloat("density kg/m³", &density, 0.0f, 2000.0f, "%.0f");
    changed |= ImGui::SliderFloat("water drag 1/s", &water_drag, 0.0f, 10.0f, "%.1f");
  }
  changed |= ImGui::Checkbox("ground", &e.ground);
  ImGui::SameLine();
  changed |= ImGui::Checkbox("tremble", &e.tremble);
  if (ImGui::IsItemHovered()) {
    ImGui::SetTooltip(
        "the seed's tremble: a force on every segment, in every solver, that grows "
        "with the grab's pull");
  }
  if (!changed) return;
  e.gravity = {g[0], g[1], g[2]};
  e.air_drag = air;
  e.water_level = level;
  e.water_density = density;
  e.water_drag = water_drag;
  session.set_environment(e);
}

void time_section(Session& session, PanelState& state) {
  SessionConfig config = session.config();
  static const std::array<int, 6> kRates = {30, 60, 120, 240, 480, 960};
  int rate = static_cast<int>(std::lround(1.0 / config.dt));
  char label[32];
  std::snprintf(label, sizeof(label), "1/%d s", rate);
  bool changed = false;
  if (ImGui::BeginCombo("dt", label)) {
    for (const int r : kRates) {
      std::snprintf(label, sizeof(label), "1/%d s", r);
      if (ImGui::Selectable(label, r == rate) && r != rate) {
        config.dt = 1.0 / r;
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  if (compare::has_rules(config.solver) || compare::has_rules(config.ghost)) {
    changed |= rule_count_slider("substeps", config, &config.options.procedural.substeps, 1, 32);
  }
  // the mouse: the judged scenarios' grab (a capped spring–damper), or a pin on the cursor
  changed |= ImGui::Checkbox("grab with a pin", &config.grab_pin);
  if (ImGui::IsItemHovered()) {
    ImGui::SetTooltip(
        "off: the grab drag, shake, water and tremble judge, a spring-damper of frequency f and "
        "damping ratio, normalised by the segment's mass, its force capped in figure weights; "
        "on: a pin holds the point on the cursor (C = 0), or pulls it with stiffness 1/C");
  }
  if (config.grab_pin) {
    // compliance from 1e-5 (100 kN/m) to 0.01 m/N; 0 is the hard pin
    float compliance = static_cast<float>(config.grab_compliance);
    if (ImGui::SliderFloat("grab C (m/N)", &compliance, 0.0f, 0.01f, "%.1e",
                           ImGuiSliderFlags_Logarithmic)) {
      config.grab_compliance = compliance;
      changed = true;
    }
  } else {
    compare::GrabSettings& spring = config.grab_spring;
    float hz = static_cast<float>(spring.hz), ratio = static_cast<float>(spring.damping_ratio),
          cap = static_cast<float>(spring.cap_weights);
    if (ImGui::SliderFloat("grab f (Hz)", &hz, 0.25f, 20.0f, "%.2f",
                           ImGuiSliderFlags_Logarithmic)) {
      spring.hz = hz;
      changed = true;
    }
    if (ImGui::SliderFloat("grab damping ratio", &ratio, 0.0f, 2.0f, "%.2f")) {
      spring.damping_ratio = ratio;
      changed = true;
    }
    if (ImGui::SliderFloat("grab cap (weights)", &cap, 0.05f, 10.0f, "%.2f",
                           ImGuiSliderFlags_Logarithmic)) {
      spring.cap_weights = cap;
      changed = true;
    }
  }
  if (changed) configure(session, config, state);
}

// what the keys do, always in view: pause, follow, step, reset, shake
void controls_row(Session& session, Controller& controller, PanelState& state) {
  ImGui::Checkbox("pause [space]", &state.paused);
  ImGui::SameLine();
  ImGui::Checkbox("camera follows [f]", &state.follow);
  if (ImGui::Button("step [n]")) state.step_once = true;
  ImGui::SameLine();
  if (ImGui::Button("reset [r]")) session.reset();
  ImGui::SameLine();
  bool shaking = session.shaking();
  if (ImGui::Checkbox("shake [s]", &shaking)) controller.toggle_shake();
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("the grabbed point oscillates along the view");
}

void runs_section(const Session& session) {
  for (int r = 0; r < session.run_count(); ++r) {
    const Run& run = session.run(r);
    const Vector3f c = r == 0 ? Palette::kWood : Palette::kGhost;
    ImGui::PushID(r);
    ImGui::TextColored(colour(c), "%s%s", run.label.c_str(), r == 0 ? "" : "  (ghost)");
    if (run.diverged) {
      ImGui::TextColored({1.0f, 0.3f, 0.25f, 1.0f}, "diverged (%s) at t = %.2f s: reset [r]",
                         run.diverged_reason, run.diverged_at);
    } else if (session.grabbing()) {
      // how far the held point is from the mouse: not every solver closes a second pin
      ImGui::Text("pin gap %.1f mm", run.pin_gap_max * 1e3);
    }
    char overlay[64];
    std::snprintf(overlay, sizeof(overlay), "max joint gap %.3g mm", run.gap_mm.latest());
    ImGui::PushStyleColor(ImGuiCol_PlotLines, colour(c));
    ImGui::PlotLines("##gap", run.gap_mm.values().data(),
                     static_cast<int>(run.gap_mm.values().size()), run.gap_mm.offset(), overlay,
                     0.0f, std::max(1e-3f, run.gap_mm.max()),
                     ImVec2(ImGui::GetContentRegionAvail().x, 30));
    if (run.own_step_us >= 0.0f) {
      // jolt: Jolt's own step (WebAssembly), and what it costs here with the round trip
      std::snprintf(overlay, sizeof(overlay), "%.1f µs per step (%.1f in Jolt)",
                    run.step_us.latest(), run.own_step_us);
    } else {
      std::snprintf(overlay, sizeof(overlay), "%.1f µs per step", run.step_us.latest());
    }
    ImGui::PlotLines("##us", run.step_us.values().data(),
                     static_cast<int>(run.step_us.values().size()), run.step_us.offset(), overlay,
                     0.0f, std::max(1.0f, run.step_us.max()),
                     ImVec2(ImGui::GetContentRegionAvail().x, 30));
    ImGui::PopStyleColor();
    ImGui::PopID();
  }
}

}  // namespace

void draw_panel(Session& session, Controller& controller, PanelState& state, float window_width,
                float window_height) {
  ImGui::SetNextWindowPos({window_width - kPanelWidth - 8.0f, 8.0f}, ImGuiCond_Always);
  ImGui::SetNextWindowSize({kPanelWidth, window_height - 16.0f}, ImGuiCond_Always);
  ImGui::SetNextWindowBgAlpha(0.85f);
  ImGui::Begin("puppet", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  ImGui::PushItemWidth(-130.0f);
  ImGui::Text("%s, %s, t = %.2f s", session.model().name.c_str(), session.config().scenario.c_str(),
              session.time());
  if (session.grabbing()) {
    ImGui::TextColored(colour(Palette::kGrabbed), "holding %s%s",
                       session.model().segments[session.grabbed_segment()].name.c_str(),
                       session.shaking() ? ", shaking" : "");
  } else {
    ImGui::TextDisabled("holding nothing");
  }
  controls_row(session, controller, state);
  if (ImGui::CollapsingHeader("solvers", ImGuiTreeNodeFlags_DefaultOpen)) {
    solver_section(session, state);
  }
  if (ImGui::CollapsingHeader("scenario and model", ImGuiTreeNodeFlags_DefaultOpen)) {
    scenario_section(session, state);
  }
  if (!state.error.empty())
    ImGui::TextColored({1.0f, 0.35f, 0.3f, 1.0f}, "%s", state.error.c_str());
  // the world and the clock closed at first, so that the runs' measurements fit a 720-pixel window
  if (ImGui::CollapsingHeader("world")) world_section(session);
  if (ImGui::CollapsingHeader("time")) {
    time_section(session, state);
  }
  if (ImGui::CollapsingHeader("runs", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::Text("%.0f frames/s drawn", ImGui::GetIO().Framerate);
    runs_section(session);
  }
  ImGui::PopItemWidth();
  ImGui::Separator();
  ImGui::TextDisabled("left-drag the puppet: grab it");
  ImGui::TextDisabled("left-drag elsewhere, right-drag: orbit");
  ImGui::TextDisabled("middle or shift-drag: pan; wheel: zoom");
  ImGui::TextDisabled("space: pause; n: step; r: reset; s: shake;");
  ImGui::TextDisabled("f: the camera follows the figure, or not");
  ImGui::End();
}

}  // namespace puppet::viewer
