// A folder of truth trajectories already computed, so that the runs of one job that judge against
// the same truth compute it once (the main job's ablation runs ten configurations against the
// main run's truth; docs/reliability.md, "The truth cache trusts no file").
//
// A trajectory is filed under a key over everything it is a function of: the program that made
// it (its executable's size and modification time, so that a rebuilt testbed never reads an
// older build's files), the truth (engine, options, dt, duration), every field of the model and
// every field of the scenario (environment, initial states, pins and their paths). A file that is
// missing, short, corrupt or of another key is a miss: the truth is computed and the file
// written anew, atomically (a temporary file renamed), so that concurrent runs on one folder
// never read half a file. A hit is bit for bit the trajectory that was stored.
#pragma once

#include <functional>
#include <string>

#include "puppet/compare/accuracy.h"
#include "puppet/compare/scenario.h"
#include "puppet/compare/simulator.h"

namespace puppet::compare {

// the key of a truth's trajectory (16 hex digits)
std::string truth_key(const Model& model, const Scenario& scenario, const std::string& solver,
                      const SolverOptions& options, double dt, double duration);

class TruthCache {
 public:
  // an empty folder: no cache, compute() every time. Otherwise the folder is made if missing;
  // throws std::runtime_error when it cannot be
  explicit TruthCache(std::string folder = {});

  // the stored trajectory of this key, or compute()'s, stored (a failure to store is ignored:
  // the cache only saves time)
  Trajectory get(const std::string& key, const std::function<Trajectory()>& compute) const;

  const std::string& folder() const { return folder_; }

 private:
  std::string folder_;
};

}  // namespace puppet::compare
