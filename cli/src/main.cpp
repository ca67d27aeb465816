// testbed: runs the scenarios in the solvers and writes what it measured.
//
// The commands are one file each under testbed/ (commands.h lists them); their shared flags are
// defined once in testbed/flags.cpp. Bad input (an unknown name, a malformed flag, a bad model
// file, an unwritable folder) exits with status 2 and one line naming the flag or file and the
// problem, before anything is written.
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <iostream>

#include "cli.h"
#include "commands.h"
#include "puppet/compare/cancel.h"
#include "puppet/compare/gate.h"
#include "puppet/compare/output_folder.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/shard.h"
#include "puppet/model/text.h"

namespace {

using namespace puppet;
using namespace puppet::testbed;

// the command's exit status; every error it throws becomes one line on standard error
int run_command(int argc, char** argv) {
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
    std::cerr << "testbed: unknown command " << shown(argv[1]) << " (expected " << known << ")\n";
    return kBadInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    print_error("testbed: ", e.what());
    return kBadInput;
  }

  stop_on_signals();
  try {
    for (const Command& command : commands) {
      if (command.app->parsed()) return command.run();
    }
  } catch (const compare::Cancelled&) {
    const int signal = compare::cancel_signal();
    std::fprintf(stderr, "\ntestbed: stopped by %s; the output folder is as it was\n",
                 signal == SIGTERM ? "SIGTERM" : "SIGINT");
    return 128 + signal;
  } catch (const compare::OutputError& e) {
    print_error("testbed: ", e.what());
  } catch (const UsageError& e) {
    print_error("testbed: ", e.what());
  } catch (const ModelError& e) {
    print_error("testbed: ", e.what());
  } catch (const compare::ScenarioError& e) {
    // the library names the option; the command line adds its flag
    print_error("testbed: ", compare::with_flag(e));
  } catch (const compare::ShardError& e) {
    print_error("testbed merge: ", e.what());
  } catch (const compare::GateError& e) {
    print_error("testbed gate: ", e.what());
  } catch (const std::exception& e) {
    print_error("testbed: ", e.what());
    return 1;
  }
  return kBadInput;
}

}  // namespace

// what a command printed reached standard output, or the command fails: a full disk or a closed
// file there is not success
int main(int argc, char** argv) {
  const int status = run_command(argc, argv);
  std::cout.flush();
  errno = 0;
  if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout) {
    const int error = errno;
    print_error("testbed: ", std::string("cannot write to standard output (") +
                                 (error ? std::strerror(error) : "write failed") + ")");
    return status == 0 ? 1 : status;
  }
  return status;
}
