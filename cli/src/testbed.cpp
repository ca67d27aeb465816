// The testbed's command line as a function (testbed.h): the command parsed, run, and its error as
// one line.
#include "puppet/testbed/testbed.h"

#include <csignal>

#include "cli.h"
#include "commands.h"
#include "puppet/compare/cancel.h"
#include "puppet/compare/gate.h"
#include "puppet/compare/output_folder.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/shard.h"
#include "puppet/model/text.h"

namespace puppet::testbed {

Outcome run_testbed(const std::vector<std::string>& args, bool signals) {
  const auto error = [](const char* prefix, const std::string& what, int status = kBadInput) {
    return Outcome{status, one_line(prefix + what, kMessageLength)};
  };
  // a command line cannot hold a NUL byte; a caller's argument with one would be read only up to
  // it (a path cut short names another file)
  for (size_t k = 1; k < args.size(); ++k) {
    if (args[k].find('\0') != std::string::npos) {
      return error("testbed: ", "argument " + shown(args[k]) + " holds a NUL byte");
    }
  }
  std::vector<char*> argv;
  for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
  const int argc = static_cast<int>(argv.size());
  CLI::App app{"testbed: the seed's procedural solver for articulated bodies, measured"};
  app.require_subcommand(1);
  app.fallthrough(false);
  const std::vector<Command> commands = add_commands(app);

  // CLI11 says "A subcommand is required" of a mistyped one: name it
  std::string known;
  bool is_command = false;
  for (const Command& command : commands) {
    known += (known.empty() ? "" : ", ") + command.app->get_name();
    is_command = is_command || (argc > 1 && command.app->get_name() == argv[1]);
  }
  if (argc > 1 && argv[1][0] != '-' && !is_command) {
    return error("testbed: ", "unknown command " + shown(argv[1]) + " (expected " + known + ")");
  }
  try {
    app.parse(argc, argv.data());
  } catch (const CLI::CallForHelp& e) {
    return {app.exit(e), ""};
  } catch (const CLI::CallForAllHelp& e) {
    return {app.exit(e), ""};
  } catch (const CLI::ParseError& e) {
    return error("testbed: ", e.what());
  }

  if (signals) stop_on_signals();
  try {
    for (const Command& command : commands) {
      if (command.app->parsed()) return {command.run(), ""};
    }
  } catch (const compare::Cancelled&) {
    const int signal = compare::cancel_signal();
    return {128 + signal, std::string("testbed: stopped by ") +
                              (signal == SIGTERM ? "SIGTERM" : "SIGINT") +
                              "; the output folder is as it was"};
  } catch (const compare::OutputError& e) {
    return error("testbed: ", e.what());
  } catch (const UsageError& e) {
    return error("testbed: ", e.what());
  } catch (const ModelError& e) {
    return error("testbed: ", e.what());
  } catch (const compare::ScenarioError& e) {
    // the library names the option; the command line adds its flag
    return error("testbed: ", compare::with_flag(e));
  } catch (const compare::ShardError& e) {
    return error("testbed merge: ", e.what());
  } catch (const compare::GateError& e) {
    return error("testbed gate: ", e.what());
  } catch (const std::exception& e) {
    return error("testbed: ", e.what(), 1);
  }
  return {kBadInput, ""};
}

}  // namespace puppet::testbed
