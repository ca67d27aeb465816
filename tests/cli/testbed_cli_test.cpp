// The testbed command as a user meets it: exit codes, one-line errors, nothing half-written.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Outcome {
  int status;
  std::string output;  // stdout and stderr
};

// a shell command line's status and what it printed on standard output
Outcome shell(const std::string& command) {
  Outcome outcome{-1, ""};
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return outcome;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe)) outcome.output += buffer.data();
  const int raw = pclose(pipe);
  outcome.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return outcome;
}

Outcome testbed(const std::string& arguments) {
  return shell(std::string(TESTBED_BINARY) + " " + arguments + " 2>&1");
}

fs::path fresh_folder(const std::string& name) {
  const fs::path folder = fs::temp_directory_path() / ("testbed_cli_" + name);
  fs::remove_all(folder);
  return folder;
}

// exit 2 with one line that names the flag or file
void expect_bad(const std::string& arguments, const std::string& names) {
  const Outcome o = testbed(arguments);
  EXPECT_EQ(o.status, 2) << arguments << "\n" << o.output;
  EXPECT_NE(o.output.find(names), std::string::npos) << arguments << "\n" << o.output;
  EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << arguments << "\n" << o.output;
  EXPECT_LE(o.output.size(), 401u) << "at most 400 characters, \"testbed: \" included\n"
                                   << o.output;
}

TEST(TestbedCli, HelpAndList) {
  EXPECT_EQ(testbed("--help").status, 0);
  EXPECT_EQ(testbed("run --help").status, 0);
  const Outcome list = testbed("list");
  EXPECT_EQ(list.status, 0);
  EXPECT_NE(list.output.find("yank"), std::string::npos);
  EXPECT_NE(list.output.find("subtree"), std::string::npos);
}

// the catalogues as JSON, which the scripts read instead of keeping copies: every metric the
// committed main run wrote is in it (a stage's time by its pattern), in the unit it was written
TEST(TestbedCli, ListJsonHasEveryNameTheResultsUse) {
  const Outcome list = testbed("list --json");
  ASSERT_EQ(list.status, 0) << list.output;
  const auto json = nlohmann::json::parse(list.output);
  for (const char* key : {"scenarios", "engines", "rules", "stages", "truths", "metrics", "stats",
                          "summary_header", "tables", "trace"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  std::map<std::string, std::string> units;
  for (const auto& m : json["metrics"]) units[m["name"]] = m["unit"];
  std::ifstream summary(std::string(PUPPET_SOURCE_DIR) + "/results/main/summary.csv");
  std::string line;
  ASSERT_TRUE(std::getline(summary, line));
  EXPECT_EQ(line, json["summary_header"].get<std::string>());
  std::set<std::string> seen, stats_seen;
  while (std::getline(summary, line)) {
    std::vector<std::string> fields;
    std::stringstream in(line);
    for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
    ASSERT_GE(fields.size(), 9u) << line;
    stats_seen.insert(fields[6]);
    std::string metric = fields[5];
    for (const auto& stage : json["stages"]) {
      if (metric == stage.get<std::string>() + "_us") metric = "{stage}_us";
    }
    if (!seen.insert(metric).second) continue;
    ASSERT_TRUE(units.count(metric)) << fields[5] << " is not in the metric catalogue";
    EXPECT_EQ(units[metric], fields[8]) << metric;
  }
  EXPECT_GE(seen.size(), 15u);
  // the stats: the committed run wrote each of the catalogue's, and no other
  std::set<std::string> stats;
  for (const auto& st : json["stats"]) stats.insert(st["name"].get<std::string>());
  EXPECT_EQ(stats_seen, stats);
  // every other committed CSV has the columns the catalogue gives for its file
  const std::pair<const char*, const char*> tables[] = {
      {"frontier/frontier.csv", "frontier.csv"},
      {"verdict/candidates.csv", "candidates.csv"},
      {"verdict/verdict.csv", "verdict.csv"},
      {"robustness/robustness.csv", "robustness.csv"},
      {"robustness/robustness_summary.csv", "robustness_summary.csv"},
      {"robustness/worst.csv", "worst.csv"},
      {"main/traces/pinocchio__drag__bullet-multibody__-__0.00416666667.csv", "trace"}};
  for (const auto& [path, table] : tables) {
    std::ifstream file(std::string(PUPPET_SOURCE_DIR) + "/results/" + path);
    ASSERT_TRUE(std::getline(file, line)) << path;
    ASSERT_TRUE(json["tables"].contains(table)) << table;
    EXPECT_EQ(line, json["tables"][table].get<std::string>()) << path;
  }
  // what the scripts read is this build's catalogue (scripts/main.sh writes it), where the build
  // has every engine (the committed one was written by such a build)
  if (list.output.find("\"built\": false") != std::string::npos) return;
  std::ifstream committed(std::string(PUPPET_SOURCE_DIR) + "/results/catalogue.json");
  const std::string text((std::istreambuf_iterator<char>(committed)),
                         std::istreambuf_iterator<char>());
  EXPECT_EQ(text, list.output) << "results/catalogue.json is stale: run testbed list --json";
}

TEST(TestbedCli, Validate) {
  const Outcome ok = testbed("validate pinocchio");
  EXPECT_EQ(ok.status, 0);
  EXPECT_NE(ok.output.find("14 segments, 13 joints, total mass 69.600 kg"), std::string::npos);
  EXPECT_EQ(testbed("validate chain:3").status, 0);
  expect_bad("validate " + std::string(PUPPET_SOURCE_DIR) + "/tests/data/bad/negative_mass.json",
             "negative_mass.json: segment \"lower\": field \"mass\" must be positive");
  expect_bad("validate /no/such/file.json", "/no/such/file.json: cannot open");
  expect_bad("gate /no/such/bench.json --thresholds " + std::string(PUPPET_SOURCE_DIR) +
                 "/results/gate.json",
             "/no/such/bench.json: cannot open");
  expect_bad("gate /no/such/bench.json --thresholds /no/such/gate.json",
             "/no/such/gate.json: cannot open");
}

// A published-style MJCF file: what it has that the testbed does not model is one line on stderr,
// once, and the command goes on; with --strict it is refused (exit 2, one line) before anything
// runs; an include outside the model's folder needs --include-outside
TEST(TestbedCli, SkippedElementsAreOneNoteOrRefusedStrictly) {
  const std::string model = std::string(PUPPET_SOURCE_DIR) + "/tests/data/mjcf/published_style.xml";
  const std::string note =
      "skipped what the testbed does not model: 1 <camera>, 1 <jointpos>, 1 <light>, 2 <motor>, "
      "1 <numeric>";
  const Outcome validated = testbed("validate " + model);
  EXPECT_EQ(validated.status, 0) << validated.output;
  const auto at = validated.output.find(note);
  EXPECT_NE(at, std::string::npos) << validated.output;
  EXPECT_EQ(validated.output.find(note, at + 1), std::string::npos) << "once";
  const fs::path out = fresh_folder("skipped");
  const Outcome run = testbed("run --model " + model +
                              " --scenario hang --solver procedural --rule xpbd --duration 0.05 "
                              "--no-timing --out " +
                              out.string());
  EXPECT_EQ(run.status, 0) << run.output;
  EXPECT_NE(run.output.find(note), std::string::npos) << run.output;
  expect_bad("validate --strict " + model,
             "published_style.xml:28: <motor name=\"right_hip\">: is not modelled by the testbed");
  const fs::path strict = fresh_folder("strict");
  expect_bad("run --strict --model " + model + " --scenario hang --out " + strict.string(),
             "is not modelled by the testbed (skipped unless --strict)");
  EXPECT_FALSE(fs::exists(strict));
  const std::string outside =
      std::string(PUPPET_SOURCE_DIR) + "/tests/data/bad/mjcf_include_outside.xml";
  expect_bad("validate " + outside, "is outside the model's folder (--include-outside allows it)");
  EXPECT_EQ(testbed("validate --include-outside " + outside).status, 0);
  fs::remove_all(out);
}

// export-mjcf: the document to stdout, or whole to a file; a bad model or an unwritable path
// exits 2 with one line and leaves no file
TEST(TestbedCli, ExportMjcf) {
  const Outcome out = testbed("export-mjcf pinocchio");
  EXPECT_EQ(out.status, 0);
  EXPECT_EQ(out.output.rfind("<!-- pinocchio", 0), 0u);
  EXPECT_NE(out.output.find("<mujoco model=\"pinocchio\">"), std::string::npos);
  EXPECT_NE(out.output.find("</mujoco>\n"), std::string::npos);
  const fs::path folder = fresh_folder("export");
  fs::create_directories(folder);
  const fs::path file = folder / "pinocchio.xml";
  EXPECT_EQ(testbed("export-mjcf pinocchio -o " + file.string()).status, 0);
  EXPECT_TRUE(fs::exists(file));
  EXPECT_EQ(fs::file_size(file), out.output.size());
  expect_bad("export-mjcf /no/such/model.json -o " + (folder / "x.xml").string(),
             "/no/such/model.json: cannot open");
  EXPECT_FALSE(fs::exists(folder / "x.xml"));
  expect_bad("export-mjcf pinocchio -o /no/such/folder/x.xml", "/no/such/folder/x.xml");
  // what export-mjcf writes, validate takes, up to MJCF's depth; past it export refuses
  for (const char* chain : {"chain:1", "chain:2", "chain:96"}) {
    const fs::path xml = folder / "chain.xml";
    ASSERT_EQ(testbed(std::string("export-mjcf ") + chain + " -o " + xml.string()).status, 0);
    const Outcome back = testbed("validate " + xml.string());
    EXPECT_EQ(back.status, 0) << chain << "\n" << back.output;
    EXPECT_NE(back.output.find(std::string("model \"") + chain + "\""), std::string::npos);
  }
  expect_bad("export-mjcf chain:97 -o " + (folder / "deep.xml").string(), "97 segments deep");
  EXPECT_FALSE(fs::exists(folder / "deep.xml"));
  expect_bad("run --solver mujoco --mujoco-integrator rk5", "--mujoco-integrator");
}

std::string slurp(const fs::path& path);
void write_text(const fs::path& path, const std::string& text);

// One verdict per model, before any run: a model MuJoCo's compiler refuses (a hinge whose range
// is [0, 0], which the model allows) is named by validate, refused when --solver names mujoco, and
// leaves mujoco out with one note when --solver is all, the other runs going ahead
TEST(TestbedCli, AModelAnEngineRefusesIsJudgedBeforeAnyRun) {
  const fs::path folder = fresh_folder("verdict");
  fs::create_directories(folder);
  std::string json = slurp(std::string(PUPPET_SOURCE_DIR) + "/models/pinocchio.json");
  json.replace(json.find("\"range_deg\": [-5, 145]"), 23, "\"range_deg\": [0, 0]");
  const fs::path model = folder / "stiff_elbow.json";
  write_text(model, json);
  const Outcome validate = testbed("validate " + model.string());
  EXPECT_EQ(validate.status, 0) << validate.output;
  EXPECT_NE(validate.output.find("engines: procedural, bullet-multibody, bullet-rigid\n"),
            std::string::npos)
      << validate.output;
  EXPECT_NE(validate.output.find("not mujoco: the compiler rejected the model"), std::string::npos);
  const std::string out = " --out " + (folder / "out").string();
  const std::string run = "run --model " + model.string() +
                          " --scenario hang --dt 1/60 --duration 0.1 --no-timing --no-accuracy";
  expect_bad(run + " --solver mujoco" + out, "--solver: mujoco cannot run");
  expect_bad(run + " --solver procedural,mujoco" + out, "--solver: mujoco cannot run");
  EXPECT_FALSE(fs::exists(folder / "out"));
  const Outcome all = testbed(run + " --rule xpbd" + out);
  EXPECT_EQ(all.status, 0) << all.output;
  EXPECT_EQ(all.output.rfind("testbed: note: mujoco left out, it cannot run", 0), 0u) << all.output;
  const std::string summary = slurp(folder / "out" / "summary.csv");
  EXPECT_NE(summary.find(",bullet-rigid,"), std::string::npos);
  EXPECT_EQ(summary.find(",mujoco,"), std::string::npos);

  // a box limit: every engine builds it, so a run has every solver and a truth
  const std::string box = std::string(PUPPET_SOURCE_DIR) + "/tests/data/two_rods_box.json";
  const Outcome shown_box = testbed("validate " + box);
  EXPECT_NE(shown_box.output.find("box zxy [-50, 70] [-30, 40] [-20, 25]"), std::string::npos)
      << shown_box.output;
  EXPECT_NE(shown_box.output.find("engines: procedural, bullet-multibody, bullet-rigid, mujoco\n"),
            std::string::npos)
      << shown_box.output;
  const Outcome box_all = testbed("run --model " + box +
                                  " --scenario hang --dt 1/240 --duration 0.2 --no-timing"
                                  " --rule tree" +
                                  out);
  EXPECT_EQ(box_all.status, 0) << box_all.output;
  EXPECT_EQ(box_all.output.find("note:"), std::string::npos) << box_all.output;
  const std::string box_summary = slurp(folder / "out" / "summary.csv");
  for (const char* solver : {"procedural,tree", "bullet-multibody", "bullet-rigid", "mujoco"}) {
    EXPECT_NE(box_summary.find(std::string("hang,") + solver + ","), std::string::npos) << solver;
  }
  fs::remove_all(folder);
}

// A file the testbed writes (-o, --csv) is a new one or a regular file it replaces; a device,
// FIFO, folder or a link to one is refused before anything runs and left as it was
TEST(TestbedCli, OutputsNeverReplaceWhatIsNotOurs) {
  const fs::path folder = fresh_folder("not_ours");
  fs::create_directories(folder);
  ASSERT_EQ(::mkfifo((folder / "fifo").c_str(), 0644), 0);
  fs::create_directory(folder / "folder");
  fs::create_symlink("fifo", folder / "link_to_fifo");
  fs::create_symlink("missing", folder / "dangling");
  std::vector<std::string> refused = {"fifo", "folder", "link_to_fifo", "dangling"};
  if (::getuid() == 0) {  // a copy of /dev/null, as root would meet it
    ASSERT_EQ(::mknod((folder / "null").c_str(), S_IFCHR | 0666, makedev(1, 3)), 0);
    fs::create_symlink("null", folder / "link_to_null");
    refused.push_back("null");
    refused.push_back("link_to_null");
  }
  for (const std::string& name : refused) {
    const fs::file_status before = fs::symlink_status(folder / name);
    expect_bad("export-mjcf pinocchio -o " + (folder / name).string(), "-o: ");
    expect_bad("gate " + std::string(PUPPET_SOURCE_DIR) + "/results/bench/bench_step.json" +
                   " --csv " + (folder / name).string(),
               "--csv: ");
    EXPECT_EQ(fs::symlink_status(folder / name).type(), before.type()) << name;
  }
  // a regular file is replaced; a link, even to a regular file, is never written through
  std::ofstream(folder / "old.xml") << "old";
  ASSERT_EQ(testbed("export-mjcf chain:3 -o " + (folder / "old.xml").string()).status, 0);
  EXPECT_NE(slurp(folder / "old.xml").find("<mujoco model=\"chain:3\">"), std::string::npos);
  std::ofstream(folder / "victim.xml") << "victim";
  fs::create_symlink("victim.xml", folder / "link.xml");
  expect_bad("export-mjcf chain:3 -o " + (folder / "link.xml").string(),
             "is a symbolic link, which is never written through");
  EXPECT_TRUE(fs::is_symlink(folder / "link.xml"));
  EXPECT_EQ(slurp(folder / "victim.xml"), "victim");
  // standard output that cannot be written is a failure, not success
  for (const char* command : {"export-mjcf pinocchio", "validate pinocchio", "list"}) {
    const Outcome o = shell(std::string(TESTBED_BINARY) + " " + command + " 2>&1 >/dev/full");
    EXPECT_EQ(o.status, 1) << command << "\n" << o.output;
    EXPECT_NE(o.output.find("cannot write to standard output"), std::string::npos) << o.output;
  }
  fs::remove_all(folder);
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// "s" + the shard's index, built without operator+ (GCC 12's -Wrestrict misreads it)
std::string shard_name(const char* index) {
  std::string name = "s";
  name += index;
  return name;
}

// a small sweep: two scenarios, two solver configurations, two dts, 4 starts (32 runs)
const std::string kSweep =
    "robustness --model chain:4 --scenario hang,yank --solver procedural,bullet-rigid "
    "--rule xpbd --dt 1/60,1/120 --starts 4 --duration 0.5 --jobs 2";

// the small sweep as shards 0, 1 and 2 of 3, into FOLDER/s0, s1, s2, run in the order given
void run_shards(const fs::path& folder,
                std::initializer_list<const char*> order = {"0", "1", "2"}) {
  for (const char* shard : order) {
    std::string arguments = kSweep;
    arguments += " --shard ";
    arguments += shard;
    arguments += "/3 --out " + (folder / shard_name(shard)).string();
    const Outcome o = testbed(arguments);
    ASSERT_EQ(o.status, 0) << o.output;
  }
}

TEST(TestbedCli, RobustnessShardsMergeIntoTheUnshardedBytes) {
  const fs::path root = fresh_folder("shards");
  ASSERT_EQ(testbed(kSweep + " --out " + (root / "all").string()).status, 0);
  // shards run out of order, merged in another
  ASSERT_NO_FATAL_FAILURE(run_shards(root, {"2", "0", "1"}));
  const std::string shards =
      " " + (root / "s1").string() + " " + (root / "s2").string() + " " + (root / "s0").string();
  const Outcome merged = testbed("merge" + shards + " --out " + (root / "merged").string());
  ASSERT_EQ(merged.status, 0) << merged.output;
  for (const char* file : {"robustness.csv", "robustness_summary.csv", "worst.csv"}) {
    const std::string expected = slurp(root / "all" / file);
    EXPECT_FALSE(expected.empty()) << file;
    EXPECT_EQ(slurp(root / "merged" / file), expected) << file;
  }
  EXPECT_FALSE(fs::exists(root / "merged" / "shard.txt"));
  // the rows count every run once, and each worst start replays as a command
  const std::string rows = slurp(root / "all" / "robustness.csv");
  EXPECT_EQ(std::count(rows.begin(), rows.end(), '\n'), 33);
  EXPECT_NE(slurp(root / "all" / "worst.csv").find("testbed run --model chain:4 --scenario"),
            std::string::npos);
}

TEST(TestbedCli, MergeNamesAMissingForeignOrDamagedShard) {
  const fs::path root = fresh_folder("merge_bad");
  ASSERT_NO_FATAL_FAILURE(run_shards(root));
  const std::string s0 = (root / "s0").string(), s1 = (root / "s1").string(),
                    s2 = (root / "s2").string(), out = " --out " + (root / "m").string();
  expect_bad("merge " + s0 + " " + s2 + out, "1 of 3 shards missing: 1");
  expect_bad("merge " + s0 + " " + s0 + " " + s1 + " " + s2 + out, "are both shard 0/3");
  // a shard of another sweep (another seed)
  ASSERT_EQ(testbed(kSweep + " --seed 2 --shard 1/3 --out " + (root / "other").string()).status, 0);
  expect_bad("merge " + s0 + " " + (root / "other").string() + " " + s2 + out, "another sweep");
  // a shard whose rows were cut short
  {
    std::string rows = slurp(root / "s2" / "robustness.csv");
    rows.resize(rows.rfind('\n', rows.size() - 2) + 1);
    std::ofstream(root / "s2" / "robustness.csv", std::ios::binary) << rows;
  }
  expect_bad("merge " + s0 + " " + s1 + " " + s2 + out, "the file was changed or cut");
  expect_bad("merge " + (root / "none").string() + out, "shard.txt");
  EXPECT_FALSE(fs::exists(root / "m"));
}

// FNV-1a 64 of a file's bytes, as shard.txt's csv line gives it (written here again, to edit a
// shard as one who also rewrites its manifest would)
std::string fnv1a(const std::string& bytes) {
  uint64_t hash = 0xcbf29ce484222325ull;
  for (const char c : bytes) hash = (hash ^ static_cast<unsigned char>(c)) * 0x100000001b3ull;
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

// shard.txt's line KEY set to VALUE
void edit_manifest(const fs::path& shard, const std::string& key, const std::string& value) {
  std::string text = slurp(shard / "shard.txt");
  const size_t at = text.find("\n" + key + ": ") + 1;
  const size_t end = text.find('\n', at);
  text.replace(at, end - at, key + ": " + value);
  write_text(shard / "shard.txt", text);
}

// robustness.csv's data row ROW (0 first), field FIELD set to VALUE, and the manifest's size and
// checksum made to match
void edit_row(const fs::path& shard, int row, int field, const std::string& value) {
  std::string text = slurp(shard / "robustness.csv");
  size_t at = text.find('\n') + 1;
  for (int k = 0; k < row; ++k) at = text.find('\n', at) + 1;
  for (int k = 0; k < field; ++k) at = text.find(',', at) + 1;
  const size_t end = text.find_first_of(",\n", at);
  text.replace(at, end - at, value);
  write_text(shard / "robustness.csv", text);
  edit_manifest(shard, "csv", std::to_string(text.size()) + " " + fnv1a(text));
}

// merge trusts no shard: every number bounded, every row the job it claims, every file as its
// manifest says; and what reaches a replay command line is inert in a shell
TEST(TestbedCli, MergeVerifiesEveryShardBeforeWriting) {
  const fs::path root = fresh_folder("merge_hostile");
  ASSERT_NO_FATAL_FAILURE(run_shards(root / "good"));
  const fs::path out = root / "merged";
  int trial = 0;
  // a fresh copy of the good shards, `edit` applied to shard 1, merged: refused, naming `names`
  auto refused = [&](const std::function<void(const fs::path&)>& edit, const std::string& names) {
    const fs::path copy = root / ("t" + std::to_string(trial++));
    fs::copy(root / "good", copy, fs::copy_options::recursive);
    edit(copy / "s1");
    const auto begin = std::chrono::steady_clock::now();
    expect_bad("merge " + (copy / "s0").string() + " " + (copy / "s1").string() + " " +
                   (copy / "s2").string() + " --out " + out.string(),
               names);
    EXPECT_LT(std::chrono::steady_clock::now() - begin, std::chrono::seconds(5)) << names;
    EXPECT_FALSE(fs::exists(out)) << names;
  };
  using Edit = std::function<void(const fs::path&)>;
  const std::vector<std::pair<Edit, std::string>> cases = {
      // the manifest: bounds, names, the sweep's arithmetic, the flags
      {[](const fs::path& s) { edit_manifest(s, "shard", "1/999999999999999999"); }, "shard: "},
      {[](const fs::path& s) { edit_manifest(s, "shard", "1/100001"); }, "shard: "},
      {[](const fs::path& s) { edit_manifest(s, "jobs", "33"); }, "jobs: 33"},
      {[](const fs::path& s) { edit_manifest(s, "jobs", "99999999999999999999"); }, "jobs: "},
      {[](const fs::path& s) { edit_manifest(s, "rows", "12"); }, "rows: 12"},
      {[](const fs::path& s) { edit_manifest(s, "starts", "0"); }, "starts: "},
      {[](const fs::path& s) { edit_manifest(s, "scenarios", "hang,swim"); }, "\"swim\" is not"},
      {[](const fs::path& s) { edit_manifest(s, "configs", "procedural:xpbd,ode"); }, "\"ode\""},
      {[](const fs::path& s) { edit_manifest(s, "dts", "1/60,1/120"); }, "dts: "},
      {[](const fs::path& s) { edit_manifest(s, "seed", "2"); }, "another sweep"},
      {[](const fs::path& s) { edit_manifest(s, "replay", " --duration 0.5; touch x"); },
       "replay: "},
      {[](const fs::path& s) { edit_manifest(s, "replay", " --duration '$(id)'"); }, "replay: "},
      {[](const fs::path& s) { edit_manifest(s, "replay", " --starts 5"); }, "replay: "},
      {[](const fs::path& s) { edit_manifest(s, "replay", " --duration 1e9"); }, "replay: "},
      {[](const fs::path& s) { edit_manifest(s, "code", "$(id)"); }, "code: "},
      {[](const fs::path& s) { write_text(s / "shard.txt", slurp(s / "shard.txt") + "x: 1\n"); },
       "unknown line"},
      {[](const fs::path& s) {
         write_text(s / "shard.txt", slurp(s / "shard.txt") + "rows: 11\n");
       },
       "a second rows line"},
      // the rows, under a manifest rewritten to match them
      {[](const fs::path& s) { edit_row(s, 0, 20, "inf"); }, "finite metrics"},
      {[](const fs::path& s) { edit_row(s, 0, 20, "nan"); }, "not a number"},
      {[](const fs::path& s) { edit_row(s, 0, 20, "0x1p-3"); }, "not a number"},
      {[](const fs::path& s) { edit_row(s, 0, 16, "diverged"); }, "without a reason"},
      {[](const fs::path& s) { edit_row(s, 2, 5, "2"); }, "not the run"},
      {[](const fs::path& s) { edit_row(s, 2, 1, "swim"); }, "not the run"},
      {[](const fs::path& s) { edit_row(s, 2, 3, "relaxed"); }, "not the run"},
      {[](const fs::path& s) { edit_row(s, 2, 6, "0"); }, "not the run"},  // job 7: start 3
      {[](const fs::path& s) { edit_row(s, 2, 0, "4"); }, "job 4 where"},
      {[](const fs::path& s) { edit_row(s, 2, 22, "99999999999999"); }, "steps"},
      // a file changed without its manifest: two bytes cut, one digit changed
      {[](const fs::path& s) {
         std::string rows = slurp(s / "robustness.csv");
         write_text(s / "robustness.csv", rows.substr(0, rows.size() - 2));
       },
       "changed or cut"},
      {[](const fs::path& s) {
         std::string rows = slurp(s / "robustness.csv");
         rows[rows.size() - 2] = rows[rows.size() - 2] == '1' ? '2' : '1';
         write_text(s / "robustness.csv", rows);
       },
       "changed or cut"},
  };
  for (const auto& [edit, names] : cases) refused(edit, names);

  // a hostile model name agreed by every shard merges, and stays one inert word in a shell
  const fs::path proof = root / "pwned";
  const fs::path copy = root / "hostile";
  fs::copy(root / "good", copy, fs::copy_options::recursive);
  const std::string model = "chain:4; touch " + proof.string() + " $(touch " + proof.string() +
                            ") `touch " + proof.string() + "` it's";
  for (const char* shard : {"s0", "s1", "s2"}) edit_manifest(copy / shard, "model", model);
  const Outcome merged = testbed("merge " + (copy / "s0").string() + " " + (copy / "s1").string() +
                                 " " + (copy / "s2").string() + " --out " + out.string());
  ASSERT_EQ(merged.status, 0) << merged.output;
  const std::string worst = slurp(out / "worst.csv");
  const size_t at = worst.find("build/release/testbed run --model ");
  ASSERT_NE(at, std::string::npos);
  // the replay command (a plain CSV field: no comma or double quote in it), its program replaced
  // by one that prints its words, run by a POSIX shell
  std::string line = worst.substr(at, worst.find(",build/release/viewer", at) - at);
  line.replace(0, std::string("build/release/testbed").size(), "printf '%s\\n'");
  write_text(root / "replay.sh", line + "\n");
  const Outcome words = shell("sh " + (root / "replay.sh").string());
  EXPECT_EQ(words.status, 0) << line;
  EXPECT_NE(words.output.find("--model\n" + model + "\n--scenario"), std::string::npos)
      << line << "\n"
      << words.output;
  EXPECT_FALSE(fs::exists(proof)) << line;
  fs::remove_all(root);
}

TEST(TestbedCli, BadFlagsExitTwoBeforeWritingAnything) {
  const fs::path out = fresh_folder("bad");
  const std::string o = " --out " + out.string();
  expect_bad("run --scenario swim" + o, "--scenario");
  expect_bad("run --solver ode" + o, "--solver");
  expect_bad("run --rule magic" + o, "--rule");
  expect_bad("run --dt 0" + o, "--dt");
  expect_bad("run --dt -0.01" + o, "--dt");
  expect_bad("run --dt abc" + o, "--dt");
  expect_bad("run --dt nan" + o, "--dt");
  expect_bad("run --duration -1" + o, "--duration");
  expect_bad("run --pin head:1,2" + o, "--pin");
  expect_bad("run --pin tail --scenario hang" + o, "--pin");
  expect_bad("run --grab r_forearm:a,b,c" + o, "--grab");
  expect_bad("run --gravity 0,0" + o, "--gravity");
  expect_bad("run --ground maybe" + o, "--ground");
  expect_bad("run --model /no/such/model.json" + o, "--model");
  expect_bad("run --frobnicate" + o, "--frobnicate");
  expect_bad("run --bullet-iterations 0" + o, "--bullet-iterations");
  expect_bad("run --bullet-iterations 2.5" + o, "--bullet-iterations");
  expect_bad("run --limit-restitution 1.5" + o, "--limit-restitution");
  expect_bad("run --limit-restitution -0.1" + o, "--limit-restitution");
  expect_bad("run --limit-restitution nan" + o, "--limit-restitution");
  expect_bad("run --limit-restitution soft" + o, "--limit-restitution");
  expect_bad("run --dt 1/60,abc" + o, "--dt");
  expect_bad("run --jobs 0" + o, "--jobs");
  expect_bad("run --truth-cache /etc/passwd" + o, "--truth-cache");
  expect_bad("run --truth-cache /etc/passwd/truths" + o, "--truth-cache");
  expect_bad("run --truth-cache /proc/version/x --scenario swim" + o, "--scenario");
  expect_bad("frontier --jobs x" + o, "--jobs");
  // counts are plain decimal digits: CLI11 alone would read 0x10 as 16 and 010 as 8
  expect_bad("run --jobs 0x10" + o, "--jobs");
  expect_bad("run --jobs 010" + o, "--jobs");
  expect_bad("run --substeps -1" + o, "--substeps");
  expect_bad("frontier --solver ode" + o, "--solver");
  expect_bad("frontier --grab tail" + o, "--grab");
  expect_bad("robustness --shard 3/3" + o, "--shard");
  expect_bad("robustness --shard 1" + o, "--shard");
  expect_bad("robustness --shard a/b" + o, "--shard");
  expect_bad("robustness --shard 0/0" + o, "--shard");
  expect_bad("robustness --starts 0" + o, "--starts");
  expect_bad("robustness --starts 1.5" + o, "--starts");
  expect_bad("robustness --starts 1e3" + o, "--starts");
  expect_bad("robustness --starts 1000000 --solver all --rule all" + o, "use more shards");
  expect_bad("robustness --seed -1" + o, "--seed");
  expect_bad("robustness --seed 0x10" + o, "--seed");
  // a run's steps: the same check and words as run's
  expect_bad("robustness --starts 1 --duration 3600 --dt 1e-5" + o, "--duration: 3600 s at dt");
  expect_bad("robustness --starts 1 --duration 0.001 --dt 1/30" + o, "takes no step");
  expect_bad("robustness --scenario swim" + o, "--scenario");
  expect_bad("robustness --shard 0/2 --model \"$(printf '/tmp/caf\\303\\251.json')\"" + o,
             "printable ASCII");
  expect_bad("verdict --budget 1furlong" + o, "--budget");
  expect_bad("verdict --budget 0mm" + o, "--budget");
  expect_bad("verdict --budget 1cm,10mm" + o, "listed already");
  expect_bad("verdict --budget 1cm," + o, "--budget");
  expect_bad("verdict --budget nan" + o, "--budget");
  expect_bad("verdict --budget ' 1mm'" + o, "--budget");
  expect_bad("verdict --budget 1e3m" + o, "--budget");
  expect_bad("verdict --dt 1/100" + o, "1/30 s");
  expect_bad("verdict --starts 0" + o, "--starts");
  expect_bad("verdict --starts 2.5" + o, "--starts");
  expect_bad("verdict --frame-hz 0" + o, "--frame-hz");
  expect_bad("verdict --scenario swim" + o, "--scenario");
  expect_bad("verdict --substeps 4" + o, "--substeps");
  expect_bad("verdict --floors-from /no/such/summary.csv" + o, "--floors-from");
  expect_bad("verdict --floors-from /dev/zero" + o, "--floors-from");
  expect_bad("verdict --floors-from /tmp" + o, "--floors-from");
  expect_bad("verdict --floors-from " + std::string(PUPPET_SOURCE_DIR) + "/README.md" + o,
             "not a summary.csv");
  expect_bad("run --start 1" + o, "--start");
  expect_bad("run --start x:2" + o, "--start");
  expect_bad("run --start 1:-2" + o, "--start");
  EXPECT_FALSE(fs::exists(out));
  expect_bad("run --scenario hang --duration 0.1 --out /proc/forbidden", "--out");
  // what a flag implies, and its ranges: each of these ran (or crashed) before it was checked
  for (const auto& [arguments, names] : std::vector<std::pair<std::string, std::string>>{
           {"run --dt 1e-300", "--dt"},
           {"run --dt 4.9e-324", "--dt"},
           {"run --dt 1e300", "--dt"},
           {"run --dt 1/3/4", "--dt"},
           {"run --dt 0x10", "--dt"},
           {"run --dt ' 1/60'", "--dt"},
           {"run --dt 1/240,0.00416666667", "--dt"},
           {"run --dt 1/60,", "--dt"},
           {"run --dt 1e-9", "--dt"},
           {"run --duration 1e7", "--duration"},
           {"run --duration 0", "--duration"},
           {"run --duration 600 --dt 1e-5 --no-accuracy", "--duration"},
           {"run --duration 1000 --dt 1/60", "--duration"},
           {"run --scenario hang,hang --jobs 2", "--scenario"},
           {"run --solver mujoco,mujoco", "--solver"},
           {"run --scenario hang,", "--scenario"},
           {"run --air-drag 1e10", "--air-drag"},
           {"run --tilt 1e300", "--tilt"},
           {"run --hz 0", "--hz"},
           {"run --jobs 100000", "--jobs"},
           {"run --iterations 1000000", "--iterations"},
           {"run --grab r_forearm:1e9,0,0", "--grab"},
           {"run --gravity 0,0,-1e9", "--gravity"},
           {"run --grab-compliance 1e300", "--grab-compliance"},
           {"run --grab-hz -1", "--grab-hz"},
           {"run --grab-hz 0", "--grab-hz"},
           {"run --grab-ratio nan", "--grab-ratio"},
           {"run --grab-ratio -0.1", "--grab-ratio"},
           {"run --grab-cap 0", "--grab-cap"},
           {"verdict --grab-cap inf", "--grab-cap"},
           {"robustness --grab-hz 1/0", "--grab-hz"},
           {"run --model chain:20000 --sample-hz 0 --no-accuracy --scenario hang", "MiB"},
           {"run --model chain:150 --solver mujoco --scenario hang", "--solver: mujoco"},
           {"run --scenario \"$(printf 'a\\nb')\"", "--scenario"},
       }) {
    expect_bad(arguments + o, names);
  }
  expect_bad("explode", "\"explode\"");
  // a message that quotes a long path stays within its 400 characters, prefix included
  expect_bad("run --model /" + std::string(300, 'm') + "/" + std::string(200, 'x') + ".json" + o,
             "--model: /mmm");
  expect_bad("export-mjcf pinocchio -o /" + std::string(300, 'n') + "/" + std::string(200, 'y'),
             "-o: ");
  expect_bad("run --out ''", "--out");
  expect_bad("run --out /", "--out");
  // a folder that holds anything but the command's own files is not replaced
  const fs::path mine = fresh_folder("foreign");
  fs::create_directories(mine);
  std::ofstream(mine / "thesis.tex") << "years of work";
  expect_bad("run --scenario hang --duration 0.1 --out " + mine.string(), "thesis.tex");
  EXPECT_TRUE(fs::exists(mine / "thesis.tex"));
  fs::remove_all(mine);
  EXPECT_FALSE(fs::exists(out));
}

// a small verdict end to end: both files, a row per scenario × solver × view × budget, a budget
// below the truth's floor refused with its reason, the chosen rows naming a candidate that was
// put through every start
TEST(TestbedCli, AVerdictWritesEveryRowAndRefusesABudgetBelowTheFloor) {
  const fs::path out = fresh_folder("verdict_command");
  const Outcome o = testbed(
      "verdict --model chain:3 --scenario hang --solver procedural,bullet-rigid --rule "
      "xpbd,literal "
      "--dt 1/30,1/60,1/120 --budget 1um,5cm --starts 3 --out " +
      out.string());
  ASSERT_EQ(o.status, 0) << o.output;
  std::ifstream in(out / "verdict.csv");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 1u + 3 * 2 * 2) << "header, then 3 solvers x 2 views x 2 budgets";
  int refused = 0, met = 0;
  for (size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].find(",1e-06,refused,") != std::string::npos) {
      ++refused;
      EXPECT_NE(lines[i].find("below the truth's floor"), std::string::npos) << lines[i];
    }
    if (lines[i].find(",met,") != std::string::npos) {
      ++met;
      EXPECT_NE(lines[i].find(",3,"), std::string::npos) << "survived 3 starts: " << lines[i];
    }
  }
  EXPECT_EQ(refused, 6);
  EXPECT_GE(met, 2) << "bullet-rigid and xpbd hold a 3-link chain within 5 cm";
  std::ifstream candidates(out / "candidates.csv");
  size_t rows = 0;
  for (std::string line; std::getline(candidates, line);) ++rows;
  // xpbd: 5 substep counts, literal: 1, bullet-rigid: 2 sweep counts; 3 dts each
  EXPECT_EQ(rows, 1u + (5 + 1 + 2) * 3);
  fs::remove_all(out);
}

TEST(TestbedCli, ShortRunWritesSummaryAndTraces) {
  const fs::path out = fresh_folder("run");
  const Outcome o =
      testbed("run --scenario hang,spin --rule weighted --duration 0.2 --sample-hz 30 --out " +
              out.string());
  EXPECT_EQ(o.status, 0) << o.output;
  EXPECT_TRUE(fs::exists(out / "summary.csv"));
  EXPECT_TRUE(
      fs::exists(out / "traces" / "pinocchio__hang__procedural__weighted__0.00416666667.csv"));
  EXPECT_TRUE(fs::exists(out / "traces" /
                         "pinocchio__spin__procedural__weighted__0.00416666667__poses.csv"));
  // --solver all: the references run the same scenarios, without a rule
  for (const std::string solver : {"bullet-multibody", "bullet-rigid"}) {
    EXPECT_TRUE(fs::exists(out / "traces" /
                           ("pinocchio__spin__" + solver + "__-__0.00416666667__poses.csv")));
  }
  std::ifstream summary(out / "summary.csv");
  const std::string text((std::istreambuf_iterator<char>(summary)), {});
  EXPECT_NE(text.find("\nhang,bullet-multibody,,0.00416666667,1,joint_gap_m,max,"),
            std::string::npos);
  EXPECT_NE(text.find("\nspin,bullet-rigid,,0.00416666667,1,momentum_drift,angular_max,"),
            std::string::npos);
  EXPECT_NE(o.output.find("joint gap m"), std::string::npos);  // the table
  fs::remove_all(out);
}

// A testbed started in the background: its pid, and its exit status once it ends.
struct Child {
  pid_t pid = -1;
  // ends within `seconds` (true) or not; status is the exit code, or 128 + the signal
  bool wait(double seconds, int* status) const {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < until) {
      int raw = 0;
      if (::waitpid(pid, &raw, WNOHANG) == pid) {
        *status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
        return true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }
};

// `file_limit` > 0: the child may write no file larger than that (a full disk, as it meets it)
Child start(const std::vector<std::string>& arguments, long file_limit = 0) {
  Child child;
  child.pid = ::fork();
  if (child.pid == 0) {
    if (file_limit > 0) {
      const rlimit limit{static_cast<rlim_t>(file_limit), static_cast<rlim_t>(file_limit)};
      ::setrlimit(RLIMIT_FSIZE, &limit);
      ::signal(SIGXFSZ, SIG_IGN);  // a write past it fails with EFBIG instead
    }
    std::vector<char*> argv{const_cast<char*>(TESTBED_BINARY)};
    for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execv(TESTBED_BINARY, argv.data());
    ::_exit(127);
  }
  return child;
}

std::string read_all(const fs::path& path) {
  std::ifstream file(path);
  return std::string((std::istreambuf_iterator<char>(file)), {});
}

// what a folder's parent holds beside the folder: the staging folders and locks of its commands
std::vector<std::string> leftovers(const fs::path& folder) {
  std::string prefix = ".";  // appended, not "." + name + ".": GCC 12's -Wrestrict misfires
  prefix += folder.filename().string();
  prefix += '.';
  std::vector<std::string> out;
  for (const auto& entry : fs::directory_iterator(folder.parent_path())) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) == 0) out.push_back(name);
  }
  return out;
}

// a long run on a folder that already holds a short run's results
std::vector<std::string> long_run(const fs::path& out) {
  return {"run",  "--scenario", "all",   "--solver",    "procedural", "--rule",
          "tree", "--dt",       "1/480", "--no-timing", "--out",      out.string()};
}

fs::path folder_with_results(const std::string& name) {
  const fs::path out = fresh_folder(name);
  const Outcome first = testbed(
      "run --scenario hang --solver procedural --rule literal --duration 0.1 "
      "--no-accuracy --no-timing --out " +
      out.string());
  EXPECT_EQ(first.status, 0) << first.output;
  return out;
}

// SIGINT and SIGTERM stop a run within a second; the folder keeps the old results, whole, and
// nothing else is left behind
TEST(TestbedCli, InterruptedRunsLeaveTheOldResults) {
  for (const int signal : {SIGINT, SIGTERM}) {
    const fs::path out = folder_with_results("interrupted");
    const std::string before = read_all(out / "summary.csv");
    const size_t traces_before = std::distance(fs::directory_iterator(out / "traces"), {});
    const Child child = start(long_run(out));
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // well into the truths
    ::kill(child.pid, signal);
    int status = 0;
    ASSERT_TRUE(child.wait(1.0, &status)) << "still running a second after signal " << signal;
    EXPECT_EQ(status, 128 + signal);
    EXPECT_EQ(read_all(out / "summary.csv"), before);
    EXPECT_EQ(static_cast<size_t>(std::distance(fs::directory_iterator(out / "traces"), {})),
              traces_before);
    EXPECT_TRUE(leftovers(out).empty()) << leftovers(out).front();
    fs::remove_all(out);
  }
}

// a merge that is stopped, reading its shards or writing the merged files, ends within a second
// with 128 + the signal and writes nothing (a shard of 400,000 valid rows takes it seconds)
TEST(TestbedCli, AMergeStopsAtASignalAndWritesNothing) {
  const fs::path root = fresh_folder("merge_signal");
  fs::create_directories(root / "s0");
  const int64_t runs = 400000;
  std::string csv =
      "job,scenario,solver,rule,dt,seed,start,tilt_deg,hz,phase_deg,grab_segment,grab_x,grab_y,"
      "grab_z,joint_angle_rms_deg,joint_speed_rms,status,reason,diverged_at_s,peak_speed_mps,"
      "joint_gap_max_m,pin_gap_max_m,steps\n";
  for (int64_t job = 0; job < runs; ++job) {
    const std::string n = std::to_string(job);
    csv +=
        n + ",hang,bullet-rigid,,0.0166666667,1," + n + ",10,,,,,,,5,0.5,ok,,,1.5,0.001,0.002,30\n";
  }
  write_text(root / "s0" / "robustness.csv", csv);
  write_text(root / "s0" / "shard.txt",
             "puppet robustness shard\nmodel: pinocchio\nscenarios: hang\nconfigs: bullet-rigid\n"
             "dts: 0.0166666667\nstarts: 400000\nseed: 1\nreplay: \ncode: unknown\nshard: 0/1\n"
             "jobs: 400000\nrows: 400000\ncsv: " +
                 std::to_string(csv.size()) + " " + fnv1a(csv) + "\n");
  for (const int signal : {SIGINT, SIGTERM}) {
    const fs::path out = root / "merged";
    const Child child = start({"merge", (root / "s0").string(), "--out", out.string()});
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ::kill(child.pid, signal);
    int status = 0;
    ASSERT_TRUE(child.wait(1.0, &status)) << "still running a second after signal " << signal;
    EXPECT_EQ(status, 128 + signal);
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(leftovers(out).empty()) << leftovers(out).front();
  }
  // undisturbed, the same merge succeeds: the signal, not the shard, stopped it
  const Outcome merged =
      testbed("merge " + (root / "s0").string() + " --out " + (root / "merged").string());
  EXPECT_EQ(merged.status, 0) << merged.output;
  fs::remove_all(root);
}

// while a model loads (chain:100000 takes seconds to build and check) nothing has been written:
// a signal ends the command at once with 128 + the signal
TEST(TestbedCli, ACommandLoadingAModelStopsAtASignal) {
  for (const int signal : {SIGINT, SIGTERM}) {
    const Child child = start({"validate", "chain:100000"});
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    const auto sent = std::chrono::steady_clock::now();
    ::kill(child.pid, signal);
    int status = 0;
    ASSERT_TRUE(child.wait(1.0, &status)) << "still loading a second after signal " << signal;
    EXPECT_EQ(status, 128 + signal);
    EXPECT_LT(std::chrono::steady_clock::now() - sent, std::chrono::seconds(1));
  }
}

// killed outright, a run leaves the old results and its staging folder beside them, which the
// next command on the folder removes
TEST(TestbedCli, ACrashLeavesTheOldResultsAndTheNextRunTidies) {
  const fs::path out = folder_with_results("crashed");
  const std::string before = read_all(out / "summary.csv");
  const Child child = start(long_run(out));
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  ::kill(child.pid, SIGKILL);
  int status = 0;
  ASSERT_TRUE(child.wait(5.0, &status));
  EXPECT_EQ(read_all(out / "summary.csv"), before);
  EXPECT_FALSE(leftovers(out).empty());  // its staging folder, and its lock file
  const Outcome next = testbed(
      "run --scenario spin --solver procedural --rule literal "
      "--duration 0.1 --no-accuracy --no-timing --out " +
      out.string());
  EXPECT_EQ(next.status, 0) << next.output;
  EXPECT_NE(read_all(out / "summary.csv").find("\nspin,"), std::string::npos);
  EXPECT_EQ(read_all(out / "summary.csv").find("\nhang,"), std::string::npos);  // no mix
  EXPECT_TRUE(leftovers(out).empty());
  fs::remove_all(out);
}

// a JSON chain of n spheres joined by ball joints, each limited to ±limit_deg about every axis of
// a box: at 1° every limit acts at once in shake, and one btMultiBody step of 300 links takes
// seconds (its rows span the whole tree)
fs::path limited_chain(const fs::path& folder, int n, double limit_deg) {
  std::string json = "{\"name\": \"limited\", \"segments\": [";
  for (int i = 0; i < n; ++i) {
    json += (i ? ", " : "") + std::string("{\"name\": \"s") + std::to_string(i) +
            "\", \"mass\": 1, \"position\": [0, 0, " + std::to_string(-0.1 * i) +
            "], \"orientation\": [1, 0, 0, 0], \"shape\": {\"type\": \"sphere\", "
            "\"radius\": 0.04}}";
  }
  json += "], \"joints\": [";
  const std::string d = std::to_string(limit_deg);
  for (int i = 1; i < n; ++i) {
    json += (i > 1 ? ", " : "") + std::string("{\"name\": \"j") + std::to_string(i) +
            "\", \"parent\": \"s" + std::to_string(i - 1) + "\", \"child\": \"s" +
            std::to_string(i) + "\", \"anchor\": [0, 0, " + std::to_string(-0.1 * i + 0.05) +
            "], \"type\": \"ball\", \"box_deg\": {\"order\": \"yxz\", \"lower\": [-" + d + ", -" +
            d + ", -" + d + "], \"upper\": [" + d + ", " + d + ", " + d + "]}}";
  }
  json += "]}";
  fs::create_directories(folder);
  const fs::path path = folder / ("limited" + std::to_string(n) + ".json");
  write_text(path, json);
  return path;
}

// a run of bullet-multibody on a 300-link chain whose limits all act: each step takes seconds,
// so a signal arrives inside one (--engine-budget lifts the engine's own refusal)
std::vector<std::string> long_step_run(const fs::path& model, const fs::path& out) {
  return {"run",      "--model",          model.string(), "--scenario",      "shake",
          "--solver", "bullet-multibody", "--dt",         "1/240",           "--duration",
          "1",        "--no-accuracy",    "--no-timing",  "--engine-budget", "1e9",
          "--out",    out.string()};
}

// a second command on a folder being written is refused at once, naming the first one, which
// goes on undisturbed
TEST(TestbedCli, ASecondCommandOnTheSameFolderIsRefused) {
  // the first command: one whose steps take seconds, so that it surely holds the folder when
  // the second one comes, however fast the machine
  const fs::path model = limited_chain(fresh_folder("contended_model"), 300, 1.0);
  const fs::path out = fresh_folder("contended");
  const Child first = start(long_step_run(model, out));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const Outcome second = testbed("run --scenario hang --duration 0.1 --out " + out.string());
  EXPECT_EQ(second.status, 2) << second.output;
  EXPECT_NE(second.output.find("is being written by another command (pid " +
                               std::to_string(first.pid) + ")"),
            std::string::npos)
      << second.output;
  // the first one was not disturbed: it runs on until it is stopped, and then tidies
  int status = -1;
  EXPECT_FALSE(first.wait(0.2, &status));
  ::kill(first.pid, SIGINT);
  ASSERT_TRUE(first.wait(5.0, &status));
  EXPECT_EQ(status, 128 + SIGINT);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_TRUE(leftovers(out).empty());
  fs::remove_all(model.parent_path());
}

// A run inside a step that takes seconds, sent `signals` 20 ms apart: it ends within `seconds` of
// the last with 128 + the first, the old results whole and nothing left beside them
// (`name`: the test's own folders, since tests run side by side)
void expect_a_long_step_stopped(const std::string& name, const std::vector<int>& signals,
                                double seconds) {
  const fs::path model = limited_chain(fresh_folder(name + "_model"), 300, 1.0);
  const fs::path out = folder_with_results(name);
  const std::string before = read_all(out / "summary.csv");
  const Child child = start(long_step_run(model, out));
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // inside a step
  for (size_t k = 0; k < signals.size(); ++k) {
    if (k > 0) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ::kill(child.pid, signals[k]);
  }
  int status = 0;
  ASSERT_TRUE(child.wait(seconds, &status))
      << "still running " << seconds << " s after " << signals.size() << " signal(s)";
  EXPECT_EQ(status, 128 + signals.front());
  EXPECT_EQ(read_all(out / "summary.csv"), before);
  EXPECT_TRUE(leftovers(out).empty()) << leftovers(out).front();
  fs::remove_all(out);
  fs::remove_all(model.parent_path());
}

// A step that does not return (Bullet cannot be asked to stop inside one) is not waited for: the
// process ends within a second of SIGINT or SIGTERM
TEST(TestbedCli, ALongEngineStepStopsWithinASecond) {
  for (const int signal : {SIGINT, SIGTERM}) expect_a_long_step_stopped("long_step", {signal}, 1.0);
}

// A second signal ends the process at once: well inside the grace the first one gives
// (compare::kStopGraceSeconds, 0.5 s)
TEST(TestbedCli, ASecondSignalEndsTheCommandAtOnce) {
  expect_a_long_step_stopped("second_signal", {SIGINT, SIGINT}, 0.3);
}

// A signal at any moment of a run (its truths, its runs, its writing, its swap) leaves the old
// results or the new ones whole, within a second, and nothing beside them
TEST(TestbedCli, ASignalAtAnyMomentLeavesTheOldResultsOrTheNew) {
  const std::vector<std::string> run = {"run",        "--scenario", "spin", "--solver",
                                        "procedural", "--rule",     "xpbd", "--dt",
                                        "1/240",      "--duration", "0.5",  "--no-timing"};
  int old_kept = 0, new_written = 0;
  for (int at_ms = 20; at_ms <= 2000; at_ms += 180) {
    const fs::path out = folder_with_results("any_moment");
    const std::string before = read_all(out / "summary.csv");
    std::vector<std::string> arguments = run;
    arguments.insert(arguments.end(), {"--out", out.string()});
    const Child child = start(arguments);
    std::this_thread::sleep_for(std::chrono::milliseconds(at_ms));
    ::kill(child.pid, at_ms % 360 == 20 ? SIGINT : SIGTERM);
    int status = 0;
    ASSERT_TRUE(child.wait(1.0, &status))
        << "still running a second after the signal, at " << at_ms << " ms";
    const std::string after = read_all(out / "summary.csv");
    if (status == 0) {
      ++new_written;
      EXPECT_NE(after.find("\nspin,"), std::string::npos) << at_ms;
      EXPECT_EQ(after.find("\nhang,"), std::string::npos) << at_ms;
    } else {
      ++old_kept;
      EXPECT_TRUE(status == 128 + SIGINT || status == 128 + SIGTERM) << status;
      EXPECT_EQ(after, before) << at_ms;
    }
    EXPECT_TRUE(leftovers(out).empty()) << at_ms << " ms: " << leftovers(out).front();
    fs::remove_all(out);
  }
  EXPECT_GT(old_kept, 0);  // the signals fell inside runs, not only after them
}

// A symbolic link planted at the lock's name is never written through: the command is refused
// in one line and the file it names keeps its bytes
TEST(TestbedCli, ALinkPlantedAtTheLockIsRefusedNotFollowed) {
  const fs::path root = fresh_folder("planted_lock");
  fs::create_directories(root);
  const fs::path victim = root / "victim.txt";
  write_text(victim, "precious");
  fs::create_symlink(victim, root / ".out.lock");
  expect_bad(
      "run --scenario hang --solver procedural --rule literal --duration 0.1 "
      "--no-accuracy --no-timing --out " +
          (root / "out").string(),
      "is a symbolic link, which is never written through");
  EXPECT_EQ(read_all(victim), "precious");
  EXPECT_FALSE(fs::exists(root / "out"));
  fs::remove_all(root);
}

// A folder name the file system allows but the staging name does not is refused before anything
// is made: the parent folders it would have needed are not left behind
TEST(TestbedCli, ATooLongFolderNameLeavesNothingBehind) {
  const fs::path root = fresh_folder("long_name");
  const fs::path out = root / "a" / "b" / std::string(250, 'n');
  expect_bad(
      "run --scenario hang --solver procedural --rule literal --duration 0.1 "
      "--no-accuracy --no-timing --out " +
          out.string(),
      "--out: ");
  EXPECT_FALSE(fs::exists(root));
  // a file name the file system allows (250 bytes) whose temporary name it would not
  fs::create_directories(root);
  expect_bad("export-mjcf chain:3 -o " + (root / std::string(250, 'f')).string(),
             "bytes; at most 229 (its temporary name is longer)");
  EXPECT_TRUE(fs::is_empty(root));
  fs::remove_all(root);
}

// Each engine refuses a model it cannot step one simulated second of within the budget, in one
// line naming it and its estimate; validate lists it among the refusals; --engine-budget lifts it
TEST(TestbedCli, AnEngineRefusesAModelPastItsBudget) {
  const fs::path folder = fresh_folder("budget");
  const fs::path model = limited_chain(folder, 3000, 30.0);
  const Outcome validate = testbed("validate " + model.string());
  EXPECT_EQ(validate.status, 0) << validate.output;
  EXPECT_NE(validate.output.find("not bullet-multibody: one simulated second"), std::string::npos)
      << validate.output;
  EXPECT_NE(validate.output.find("(--engine-budget)"), std::string::npos);
  EXPECT_NE(validate.output.find("engines: procedural, bullet-rigid"), std::string::npos);
  expect_bad("run --model " + model.string() +
                 " --scenario hang --solver bullet-multibody --duration 0.1 --out " +
                 (folder / "out").string(),
             "--solver: bullet-multibody cannot run");
  EXPECT_FALSE(fs::exists(folder / "out"));
  const Outcome lifted = testbed("validate --engine-budget 1e9 " + model.string());
  EXPECT_EQ(lifted.output.find("not bullet-multibody"), std::string::npos) << lifted.output;
  expect_bad("validate --engine-budget 0 " + model.string(), "--engine-budget");
  // Pinocchio and chain:3000 (no limits) are well within it everywhere
  for (const char* name : {"pinocchio", "chain:3000"}) {
    const Outcome o = testbed(std::string("validate ") + name);
    EXPECT_EQ(o.output.find("past the budget"), std::string::npos) << o.output;
  }
  fs::remove_all(folder);
}

// a disk that fills up mid-run (here: no file may pass 4 kB) fails the run, which says so, and
// leaves the old results
TEST(TestbedCli, AFullDiskLeavesTheOldResults) {
  const fs::path out = folder_with_results("full");
  const std::string before = read_all(out / "summary.csv");
  const Child child = start(
      {"run", "--scenario", "hang", "--solver", "procedural", "--rule", "literal", "--duration",
       "1", "--sample-hz", "0", "--no-accuracy", "--no-timing", "--out", out.string()},
      4096);
  int status = -1;
  ASSERT_TRUE(child.wait(60.0, &status));
  EXPECT_EQ(status, 1);
  EXPECT_EQ(read_all(out / "summary.csv"), before);
  EXPECT_TRUE(leftovers(out).empty());
  fs::remove_all(out);
}

}  // namespace
