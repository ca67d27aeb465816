// The engines and rules the tests of roots the world holds and of slide joints run alike
// (held_root_test.cpp, slide_joint_test.cpp), and what single precision costs Jolt there
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "puppet/compare/engines.h"
#include "puppet/compare/simulator.h"
#include "puppet/procedural/rule.h"

namespace puppet::compare {

// Every engine and the rules that hold a root and a slide: mujoco, xpbd and tree at their default
// substeps, and btMultiBody, the bullet-rigid and ode ragdolls and jolt where this build has them
struct Holder {
  std::string name, solver;
  SolverOptions options;
  int substeps = 1;  // the integrator's steps per step
};

// Jolt steps in single precision: over n steps of a state of size |x| its rounding adds up to at
// most n ε |x|, with ε = 6e-8 (float's half ulp): 480 steps at 3 m or 3 rad/s is 9e-5, so 1e-4
// bounds what the double-precision engines hold to 1e-9
inline bool single_precision(const Holder& holder) { return holder.name == "jolt"; }
constexpr double kSingleRounding = 1e-4;
inline std::vector<Holder> holders() {
  Holder mujoco{"mujoco", "mujoco", {}, 1};
  Holder xpbd{"xpbd", std::string(kProceduralEngine), {}, 1};
  xpbd.options.procedural.rule = procedural::Rule::kXpbd;
  xpbd.substeps = procedural::rule_info(procedural::Rule::kXpbd).substeps;
  Holder tree{"tree", std::string(kProceduralEngine), {}, 1};
  tree.options.procedural.rule = procedural::Rule::kTree;
  tree.substeps = procedural::rule_info(procedural::Rule::kTree).substeps;
  std::vector<Holder> all = {mujoco, xpbd, tree};
  for (const char* engine : {"bullet-multibody", "bullet-rigid", "ode", "jolt"}) {
    if (find_engine(engine) &&
        std::find(solver_names().begin(), solver_names().end(), engine) != solver_names().end()) {
      all.push_back({engine, engine, {}, 1});
    }
  }
  return all;
}

}  // namespace puppet::compare
