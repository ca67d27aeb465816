// The testbed's commands, one file each (command_*.cpp): each adds its subcommand and its flags
// to the application and returns what runs it once the command line is parsed. A command checks
// every flag before it runs anything or writes anything, and throws UsageError (exit status 2)
// for a bad one.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <vector>

namespace puppet::testbed {

struct Command {
  CLI::App* app;             // the subcommand, its flags bound to what `run` reads
  std::function<int()> run;  // the exit status
};

Command add_list_command(CLI::App& app);
Command add_validate_command(CLI::App& app);
Command add_export_mjcf_command(CLI::App& app);
Command add_run_command(CLI::App& app);
Command add_frontier_command(CLI::App& app);
Command add_robustness_command(CLI::App& app);
Command add_verdict_command(CLI::App& app);
Command add_merge_command(CLI::App& app);
Command add_gate_command(CLI::App& app);

// every command, in the order --help lists them
inline std::vector<Command> add_commands(CLI::App& app) {
  return {add_list_command(app),    add_validate_command(app), add_export_mjcf_command(app),
          add_run_command(app),     add_frontier_command(app), add_robustness_command(app),
          add_verdict_command(app), add_merge_command(app),    add_gate_command(app)};
}

}  // namespace puppet::testbed
