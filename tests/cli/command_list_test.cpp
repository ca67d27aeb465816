// The list command: its help, and its JSON naming everything the results use
#include "cli/cli_support.h"

namespace puppet::cli_test {
namespace {

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

}  // namespace
}  // namespace puppet::cli_test
