// A command's --out folder, replaced whole or not at all (docs/reliability.md). The command
// writes into a staging folder beside it; commit() swaps the two in one rename (Linux's
// RENAME_EXCHANGE), so that whatever stops the command first (an error, a full disk, SIGINT,
// SIGTERM, a crash) leaves the folder as it was. A lock beside the folder refuses a second
// command on the same folder while the first runs.
//
//   <parent>/<name>/                  the results: only the files the command writes
//   <parent>/.<name>.lock             held while a command writes <name> (removed after)
//   <parent>/.<name>.staging-<pid>    the new results while they are written (removed after; a
//                                     crashed command's is removed by the next one)
#pragma once

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "puppet/compare/cancel.h"

namespace puppet::compare {

// a folder that cannot be used: bad input, before anything runs
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class OutputFolder {
 public:
  // `owned`: the entries the command writes (e.g. summary.csv and traces); a folder holding
  // anything else is refused, since it is replaced whole. Takes the lock, clears stale staging
  // folders, makes the staging folder. Throws OutputError naming `flag`.
  OutputFolder(const std::string& flag, const std::string& path, std::vector<std::string> owned);
  // without commit(): removes the staging folder; always releases the lock
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  // where the command writes
  const std::filesystem::path& staging() const { return staging_; }
  // where the results will be
  const std::filesystem::path& path() const { return path_; }
  // replaces the folder by the staging folder in one rename; throws std::runtime_error
  void commit();

 private:
  std::filesystem::path path_, staging_, lock_;
  CancelPoint tidy_;  // from here on a signal stops the command, which removes its staging
  // what the stop watchdog removes when a step does not return after a signal (cancel.h)
  std::optional<TidyPath> tidy_lock_, tidy_staging_;
  int lock_fd_ = -1;
  bool committed_ = false;
};

}  // namespace puppet::compare
