// testbed list: the names every other command accepts.
#include <iostream>

#include "commands.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"
#include "puppet/procedural/rule.h"

namespace puppet::testbed {

Command add_list_command(CLI::App& app) {
  CLI::App* command = app.add_subcommand("list", "list scenarios, solvers, rules and models");
  return {command, [] {
            std::cout << "scenarios:";
            for (const auto& s : compare::scenario_names()) std::cout << ' ' << s;
            std::cout << "\nsolvers:  ";
            for (const auto& s : compare::solver_names()) std::cout << ' ' << s;
            std::cout << "\nrules:    ";
            for (auto rule : procedural::kAllRules) std::cout << ' ' << procedural::rule_name(rule);
            std::cout << " (procedural only; default relaxed)\nmodels:    pinocchio ("
                      << compare::builtin_model_path() << "), chain:N, or any model file\n";
            return 0;
          }};
}

}  // namespace puppet::testbed
