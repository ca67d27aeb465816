// testbed export-mjcf: the model as MJCF (mjcf.h), to a file (written whole or not at all) or to
// standard output.
#include <cstdio>
#include <iostream>
#include <memory>

#include "cli.h"
#include "commands.h"
#include "flags.h"
#include "puppet/compare/output.h"
#include "puppet/compare/scenario.h"
#include "puppet/model/file.h"
#include "puppet/model/mjcf.h"
#include "puppet/model/text.h"

namespace puppet::testbed {
namespace {

using namespace puppet::compare;

int export_mjcf(const std::string& path, const std::string& out, const ReadOptions& reading) {
  if (!out.empty() && out != "-") {
    if (std::string problem = output_file_problem(out); !problem.empty()) {
      throw UsageError("-o: " + shown(out) + " " + problem);
    }
  }
  const Model model = compare::load_named_model(path, reading);
  if (std::string problem = mjcf_write_problem(model); !problem.empty()) {
    throw UsageError("MODEL: " + shown(path) + ": " + problem);
  }
  MjcfOptions options;
  options.environment.gravity = model.gravity;
  const std::string xml = write_mjcf(model, options);
  if (out.empty() || out == "-") {
    std::cout << xml;
  } else {
    write_file_atomically(out, xml);
    std::fprintf(stderr, "wrote %s (MJCF of model \"%s\")\n", out.c_str(), model.name.c_str());
  }
  return 0;
}

}  // namespace

Command add_export_mjcf_command(CLI::App& app) {
  struct Args {
    std::string path, out;
    ReadOptions reading;
  };
  auto args = std::make_shared<Args>();
  CLI::App* command = app.add_subcommand(
      "export-mjcf", "write a model as MJCF, MuJoCo's XML format, to stdout or a file");
  command->add_option("MODEL", args->path, "model file, pinocchio, or chain:N")->required();
  command->add_option("-o,--out", args->out, "output file (default: stdout)");
  add_model_reading_flags(command, args->reading);
  return {command, [args] { return export_mjcf(args->path, args->out, args->reading); }};
}

}  // namespace puppet::testbed
