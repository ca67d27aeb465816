// testbed validate: a model loaded and printed (segments, joints and limits), with what each
// engine makes of it, or the model's error.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include "commands.h"
#include "flags.h"
#include "puppet/compare/engines.h"
#include "puppet/compare/scenario.h"
#include "puppet/model/euler_box.h"
#include "puppet/model/root_joint.h"
#include "puppet/model/text.h"
#include "puppet/procedural/rule.h"

namespace puppet::testbed {
namespace {

// what each engine makes of the model: the verdict every command applies before it runs. The
// procedural engine's is per rule: which rules run it, when not all of them do
void print_engines(const Model& model, double budget) {
  std::string engines, refusals;
  const auto add_engine = [&](const std::string& text) {
    engines += (engines.empty() ? "" : ", ") + text;
  };
  for (const std::string& solver : compare::solver_names()) {
    std::string problem = compare::engine_model_problem(solver, model, {}, budget);
    if (solver == compare::kProceduralEngine) {
      std::string rules, refused;  // the rules that run it; the first refusal of another
      int running = 0;
      for (const procedural::Rule rule : procedural::kAllRules) {
        compare::SolverOptions options;
        options.procedural.rule = rule;
        const std::string why = compare::engine_model_problem(solver, model, options, budget);
        if (why.empty()) {
          rules += (rules.empty() ? "" : ", ") + std::string(procedural::rule_name(rule));
          ++running;
        } else if (refused.empty()) {
          refused = why;
        }
      }
      if (running > 0 && !refused.empty()) {
        add_engine(solver + " (rules " + rules + ")");
        refusals += "  not procedural with the other rules: " + one_line(refused, 300) + "\n";
        problem.clear();
      } else if (running == 0) {
        problem = refused;
      }
    } else if (problem.empty()) {
      add_engine(solver);
    }
    if (problem.empty()) {
      if (solver == compare::kProceduralEngine && engines.find(solver) == std::string::npos) {
        add_engine(solver);
      }
      if (std::string note = compare::engine_model_note(solver, model); !note.empty()) {
        refusals += "  " + solver + " approximates: " + note + "\n";
      }
    } else {
      refusals += "  not " + solver + ": " + one_line(problem, 300) + "\n";
    }
  }
  std::printf("engines: %s\n%s", engines.c_str(), refusals.c_str());
}

int validate(const std::string& path, const ReadOptions& reading, double budget) {
  const Model model = compare::load_named_model(path, reading);
  std::printf("model \"%s\": %d segments, %d joints, total mass %.3f kg, rest height %.3f m\n",
              model.name.c_str(), model.segment_count(), model.joint_count(), model.total_mass,
              model.rest_height);
  if (const RootJoint& root = model.root; root.hold == RootHold::kFree) {
    std::printf("root \"%s\": free\n", model.segments[0].name.c_str());
  } else {
    // the world's hold: its joints, each with its axis, range and spring
    std::printf("root \"%s\": held by the world, %s at (%.4g, %.4g, %.4g)\n",
                model.segments[0].name.c_str(), root_hold_name(root.hold),
                root.anchor_world.x() + 0.0, root.anchor_world.y() + 0.0,
                root.anchor_world.z() + 0.0);
    const int count = root.hold == RootHold::kWeld ? 0 : root.hold == RootHold::kPlanar ? 3 : 1;
    for (int k = 0; k < count; ++k) {
      const size_t dof = static_cast<size_t>(k);
      const bool slide = k < root_slide_count(root.hold);
      const Vector3d& a = root.axes[dof];
      const JointPassive& p = root.passive[dof];
      const double unit = slide ? 1.0 : 180.0 / M_PI;
      char range[64] = "unlimited";
      if (root.limited) {
        std::snprintf(range, sizeof range, "range [%.4g, %.4g] %s", root.lower * unit + 0.0,
                      root.upper * unit + 0.0, slide ? "m" : "deg");
      }
      std::printf(
          "  %-14s %-6s axis (%.4g, %.4g, %.4g), %s; stiffness %g, damping %g, armature %g\n",
          root.names[dof].c_str(),
          root.hold == RootHold::kBall ? "ball"
          : slide                      ? "slide"
                                       : "hinge",
          a.x() + 0.0, a.y() + 0.0, a.z() + 0.0, range, p.stiffness, p.damping, p.armature);
    }
  }
  std::printf("  %-14s %-14s %8s  %s\n", "segment", "parent", "mass kg", "shape");
  for (const Segment& s : model.segments) {
    std::string shapes;
    for (const Shape& shape : s.shapes) {
      if (!shapes.empty()) shapes += ", ";
      shapes += shape_type_name(shape.type);
    }
    std::printf("  %-14s %-14s %8.3f  %s\n", s.name.c_str(),
                s.parent >= 0 ? model.segments[s.parent].name.c_str() : "-", s.mass,
                shapes.c_str());
  }
  std::printf("  %-14s %-6s %-14s %-14s %s\n", "joint", "type", "parent", "child", "limits (deg)");
  for (const Joint& j : model.joints) {
    const double d = 180.0 / M_PI;
    char limits[160];
    if (j.type == JointType::kBall && j.ball_limit == BallLimit::kEulerBox) {
      std::snprintf(limits, sizeof limits, "box %s [%.0f, %.0f] [%.0f, %.0f] [%.0f, %.0f]",
                    euler_order_name(j.box_order).c_str(), j.box_lower[0] * d, j.box_upper[0] * d,
                    j.box_lower[1] * d, j.box_upper[1] * d, j.box_lower[2] * d, j.box_upper[2] * d);
      if (has_box_offsets(j)) {
        // hinges at different points (MJCF): how far each is from the one before
        const size_t used = std::strlen(limits);
        std::snprintf(limits + used, sizeof limits - used, ", hinges %.3g and %.3g cm apart",
                      100.0 * j.box_offsets[0].norm(), 100.0 * j.box_offsets[1].norm());
      }
    } else if (j.type == JointType::kBall) {
      std::snprintf(limits, sizeof limits, "swing %.0f x %.0f, twist %.0f", j.swing_x * d,
                    j.swing_y * d, j.twist * d);
    } else if (j.type == JointType::kHinge) {
      std::snprintf(limits, sizeof limits, "range [%.0f, %.0f]", j.lower * d, j.upper * d);
    } else if (j.type == JointType::kSlide) {
      if (std::isfinite(j.lower)) {
        std::snprintf(limits, sizeof limits, "range [%.3g, %.3g] m", j.lower, j.upper);
      } else {
        std::snprintf(limits, sizeof limits, "not limited");
      }
    } else {
      std::snprintf(limits, sizeof limits, "fixed");
    }
    const char* type = joint_type_name(j.type);
    // its springs, dampers and armature: a box's per angle where its angles' differ
    std::string passive;
    const auto describe = [&](const JointPassive& p, const std::string& which) {
      if (p == JointPassive{}) return;
      char line[200];
      std::snprintf(line, sizeof line, "; %sstiffness %g, damping %g, springref %.4g, armature %g",
                    which.c_str(), p.stiffness, p.damping,
                    p.spring_ref * (j.type == JointType::kSlide ? 1.0 : d) + 0.0, p.armature);
      passive += line;
    };
    const bool box = j.type == JointType::kBall && j.ball_limit == BallLimit::kEulerBox;
    if (box && !(j.passive[1] == j.passive[0] && j.passive[2] == j.passive[0])) {
      for (size_t k = 0; k < 3; ++k) describe(j.passive[k], "angle " + std::to_string(k) + ": ");
    } else if (j.type != JointType::kFixed) {
      describe(j.passive[0], "");
    }
    std::printf("  %-14s %-6s %-14s %-14s %s%s\n", j.name.c_str(), type,
                model.segments[j.parent].name.c_str(), model.segments[j.child].name.c_str(), limits,
                passive.c_str());
  }
  print_engines(model, budget);
  return 0;
}

}  // namespace

Command add_validate_command(CLI::App& app) {
  struct Args {
    std::string path;
    double budget = compare::kDefaultEngineBudget;
    ReadOptions reading;
  };
  auto args = std::make_shared<Args>();
  CLI::App* command = app.add_subcommand("validate", "load a model and print it, or its error");
  command->add_option("MODEL", args->path, "model file, pinocchio, or chain:N")->required();
  add_engine_budget_flag(command, args->budget);
  add_model_reading_flags(command, args->reading);
  return {command, [args] { return validate(args->path, args->reading, args->budget); }};
}

}  // namespace puppet::testbed
