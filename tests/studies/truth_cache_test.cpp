// truth_cache.cpp: a stored truth is read back bit for bit, a damaged file is a miss, and the key
// changes with each thing a truth's trajectory depends on; a sweep with a cache gives the same
// summary as one without.
#include "puppet/compare/truth_cache.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>

#include "puppet/compare/output.h"
#include "puppet/compare/sweep.h"

namespace puppet::compare {
namespace {

namespace fs = std::filesystem;

fs::path fresh_folder(const std::string& name) {
  const fs::path folder = fs::temp_directory_path() / ("truth_cache_test_" + name);
  fs::remove_all(folder);
  return folder;
}

// a short truth of a four-link chain hanging (MuJoCo when built, else bullet-multibody)
struct Case {
  Model model = make_chain(4);
  Scenario scenario = make_scenario("hang", model);
  Truth truth = truths_for(model, kDefaultEngineBudget).front();
  double duration = 0.4;

  std::string key() const {
    return truth_key(model, scenario, truth.solver, truth.options, truth.dt, duration);
  }
  Trajectory compute() const {
    auto simulator = make_simulator(truth.solver, truth.options);
    return record_trajectory(*simulator, model, scenario, truth.dt, duration);
  }
};

bool same_bits(const Trajectory& a, const Trajectory& b) {
  if (a.diverged != b.diverged || a.samples.size() != b.samples.size()) return false;
  for (size_t k = 0; k < a.samples.size(); ++k) {
    if (a.samples[k].size() != b.samples[k].size()) return false;
    for (size_t i = 0; i < a.samples[k].size(); ++i) {
      const BodyState &p = a.samples[k][i], &q = b.samples[k][i];
      const double x[13] = {p.x.x(), p.x.y(), p.x.z(), p.q.w(), p.q.x(), p.q.y(), p.q.z(),
                            p.v.x(), p.v.y(), p.v.z(), p.w.x(), p.w.y(), p.w.z()};
      const double y[13] = {q.x.x(), q.x.y(), q.x.z(), q.q.w(), q.q.x(), q.q.y(), q.q.z(),
                            q.v.x(), q.v.y(), q.v.z(), q.w.x(), q.w.y(), q.w.z()};
      if (std::memcmp(x, y, sizeof x) != 0) return false;
    }
  }
  return true;
}

TEST(TruthCache, AStoredTruthIsReadBackBitForBitWithoutComputingIt) {
  const Case c;
  const TruthCache cache(fresh_folder("hit").string());
  int computed = 0;
  auto compute = [&] {
    ++computed;
    return c.compute();
  };
  const Trajectory first = cache.get(c.key(), compute);
  const Trajectory second = cache.get(c.key(), compute);
  EXPECT_EQ(computed, 1);
  ASSERT_GE(first.samples.size(), 12u);  // 0.4 s at 30 Hz, and t = 0
  EXPECT_TRUE(same_bits(first, second));
  EXPECT_TRUE(same_bits(first, c.compute()));
  // one file and no temporary left behind
  EXPECT_EQ(std::distance(fs::directory_iterator(cache.folder()), fs::directory_iterator()), 1);
}

TEST(TruthCache, NoFolderComputesEveryTime) {
  const Case c;
  const TruthCache cache;
  int computed = 0;
  for (int i = 0; i < 2; ++i) {
    cache.get(c.key(), [&] {
      ++computed;
      return Trajectory{};
    });
  }
  EXPECT_EQ(computed, 2);
}

TEST(TruthCache, ADamagedFileIsAMissAndIsWrittenAnew) {
  const Case c;
  const TruthCache cache(fresh_folder("damaged").string());
  const Trajectory truth = cache.get(c.key(), [&] { return c.compute(); });
  const fs::path file = fs::path(cache.folder()) / (c.key() + ".truth");
  ASSERT_TRUE(fs::exists(file));
  const auto size = fs::file_size(file);
  std::string bytes(size, '\0');
  std::ifstream(file, std::ios::binary).read(bytes.data(), static_cast<std::streamsize>(size));

  auto write = [&](const std::string& content) {
    std::ofstream(file, std::ios::binary | std::ios::trunc) << content;
  };
  std::string other_key = bytes;
  other_key[std::strlen("puppet truth trajectory 1\n")] ^= 1;
  std::string huge_count = bytes;  // the sample count's top byte: 2^56 samples
  huge_count[std::strlen("puppet truth trajectory 1\n") + 16 + 8 + 7] = 1;
  const std::vector<std::string> damaged = {
      "",         bytes.substr(0, size / 2), bytes + "x", "puppet truth trajectory 1\n", other_key,
      huge_count, std::string(size, '\xff')};
  for (const std::string& content : damaged) {
    write(content);
    int computed = 0;
    const Trajectory read = cache.get(c.key(), [&] {
      ++computed;
      return c.compute();
    });
    EXPECT_EQ(computed, 1) << content.size() << " bytes";
    EXPECT_TRUE(same_bits(read, truth));
    EXPECT_EQ(fs::file_size(file), size) << "written anew";
  }
  // a folder where the file should be: computed, and nothing stored
  fs::remove(file);
  fs::create_directory(file);
  int computed = 0;
  EXPECT_TRUE(same_bits(cache.get(c.key(),
                                  [&] {
                                    ++computed;
                                    return c.compute();
                                  }),
                        truth));
  EXPECT_EQ(computed, 1);
}

// A file of the right key and shape whose states are not finite, though it says the run did not
// diverge, is a miss: it is computed again, never handed to the accuracy as a truth
TEST(TruthCache, AFileOfNonFiniteStatesIsAMiss) {
  const Case c;
  const TruthCache cache(fresh_folder("nan").string());
  const Trajectory truth = cache.get(c.key(), [&] { return c.compute(); });
  ASSERT_FALSE(truth.diverged);
  Trajectory poisoned = truth;
  poisoned.samples.back().back().x.x() = std::numeric_limits<double>::quiet_NaN();
  // stored by a cache of its own under the same key: the file a planted one would be
  const TruthCache planter(cache.folder());
  const fs::path file = fs::path(cache.folder()) / (c.key() + ".truth");
  fs::remove(file);
  planter.get(c.key(), [&] { return poisoned; });
  ASSERT_TRUE(fs::exists(file));
  int computed = 0;
  const Trajectory read = cache.get(c.key(), [&] {
    ++computed;
    return c.compute();
  });
  EXPECT_EQ(computed, 1);
  EXPECT_TRUE(same_bits(read, truth));
}

// A symbolic link planted at a truth's name is never written through: its target keeps its bytes
TEST(TruthCache, ALinkAtATruthsNameIsNeverWrittenThrough) {
  const Case c;
  const fs::path folder = fresh_folder("link");
  const TruthCache cache(folder.string());
  const fs::path victim = folder / "victim.txt";
  std::ofstream(victim) << "not a truth";
  fs::create_symlink(victim, folder / (c.key() + ".truth"));
  int computed = 0;
  cache.get(c.key(), [&] {
    ++computed;
    return c.compute();
  });
  EXPECT_EQ(computed, 1);
  std::ifstream in(victim);
  EXPECT_EQ(std::string((std::istreambuf_iterator<char>(in)), {}), "not a truth");
}

TEST(TruthCache, TheKeyChangesWithEachInputOfTheTruth) {
  const Case base;
  std::set<std::string> keys = {base.key()};
  EXPECT_EQ(base.key(), Case{}.key()) << "the same inputs, the same key";
  auto differs = [&](const Case& c, const char* what) {
    EXPECT_TRUE(keys.insert(c.key()).second) << what;
  };
  Case c = base;
  c.duration = 0.5;
  differs(c, "duration");
  c = base;
  c.truth.dt *= 0.5;
  differs(c, "dt");
  c = base;
  c.truth.solver = "bullet-multibody";
  differs(c, "solver");
  c = base;
  c.truth.options.mujoco.integrator = reference::MujocoIntegrator::kEuler;
  differs(c, "options");
  c = base;
  c.model.joints[1].swing_x *= 0.9;
  differs(c, "a joint's limit");
  c = base;
  c.model.segments[2].mass *= 1.01;
  differs(c, "a segment's mass");
  c = base;
  c.scenario.initial[3].w.x() += 1e-12;
  differs(c, "an initial velocity");
  c = base;
  c.scenario.environment.air_drag += 0.1;
  differs(c, "air drag");
  c = base;
  c.scenario.pins[0].pin.compliance = 1e-4;
  differs(c, "a pin's compliance");
  c = base;
  ScenarioOptions tilted;
  tilted.tilt_deg = 20.0;
  c.scenario = make_scenario("hang", c.model, tilted);
  differs(c, "the tilt");
  c = base;
  c.scenario = make_scenario("spin", c.model);
  differs(c, "the scenario");
}

TEST(TruthCache, ASweepWithTheCacheGivesTheSameSummaryAsWithout) {
  const Model model = make_chain(4);
  SweepSpec spec;
  spec.model = &model;
  spec.scenarios = {make_scenario("hang", model)};
  spec.configs = {{"procedural", {}}};
  spec.dts = {1.0 / 60};
  spec.run.duration = 0.6;  // a re-seeded run of 0.5 s fits
  spec.run.timing = false;
  spec.jobs = 2;
  const OutputContext context{"chain:4", "abc", "machine"};
  const std::string without = summary_csv(run_sweep(spec), context);
  spec.truth_cache = fresh_folder("sweep").string();
  const std::string filled = summary_csv(run_sweep(spec), context);
  const size_t files =
      static_cast<size_t>(std::distance(fs::directory_iterator(spec.truth_cache), {}));
  const std::string read = summary_csv(run_sweep(spec), context);
  EXPECT_EQ(filled, without);
  EXPECT_EQ(read, without);
  // every truth at h, h/2 and 2h (one or two truths)
  EXPECT_EQ(files, 3 * truths_for(model, kDefaultEngineBudget).size());
}

}  // namespace
}  // namespace puppet::compare
