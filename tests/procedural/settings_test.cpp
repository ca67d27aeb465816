// The rules' names and the settings' ranges and defaults (settings.cpp): names parse back to
// their rule and nothing else parses; every range is closed at its stated ends and refuses NaN;
// a rule's defaults fill only what was left to the rule.
#include "puppet/procedural/settings.h"

#include <gtest/gtest.h>

#include <limits>
#include <set>

#include "puppet/procedural/solver.h"
#include "rules/catalogue.h"

namespace puppet::procedural {
namespace {

TEST(Settings, EveryRuleNameParsesBackAndNothingElseParses) {
  std::set<std::string_view> names;
  for (Rule rule : kAllRules) {
    const std::string_view name = rule_name(rule);
    names.insert(name);
    ASSERT_TRUE(parse_rule(name).has_value()) << name;
    EXPECT_EQ(*parse_rule(name), rule);
  }
  EXPECT_EQ(names.size(), kAllRules.size());
  using namespace std::string_view_literals;
  for (std::string_view other : {""sv, "Relaxed"sv, "relaxed "sv, " relaxed"sv, "xpbd\n"sv,
                                 "tree\0x"sv, "all"sv, "literal,weighted"sv, "?"sv}) {
    EXPECT_FALSE(parse_rule(other).has_value()) << other;
  }
}

TEST(Settings, RangesAreClosedAtTheirEndsAndRefuseNaN) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const auto problem = [](auto change) {
    Settings settings;
    change(settings);
    return validate(settings);
  };
  EXPECT_EQ(problem([](Settings&) {}), "");
  EXPECT_EQ(problem([](Settings& s) { s.iterations = 0; }), "");
  EXPECT_EQ(problem([](Settings& s) { s.iterations = kMaxIterations; }), "");
  EXPECT_EQ(problem([](Settings& s) { s.iterations = kMaxIterations + 1; }),
            "iterations must be in [0, 1000]");
  EXPECT_EQ(problem([](Settings& s) { s.iterations = -2; }), "iterations must be in [0, 1000]");
  EXPECT_EQ(problem([](Settings& s) { s.substeps = 1; }), "");
  EXPECT_EQ(problem([](Settings& s) { s.substeps = kMaxSubsteps; }), "");
  EXPECT_EQ(problem([](Settings& s) { s.substeps = 0; }), "substeps must be in [1, 1000]");
  EXPECT_EQ(problem([](Settings& s) { s.substeps = kMaxSubsteps + 1; }),
            "substeps must be in [1, 1000]");
  EXPECT_EQ(problem([](Settings& s) { s.joint_compliance = kMaxCompliance; }), "");
  for (double bad : {-1e-300, nan, inf, 2 * kMaxCompliance}) {
    EXPECT_EQ(problem([&](Settings& s) { s.joint_compliance = bad; }),
              "joint compliance must be in [0, 1e6] m/N")
        << bad;
    EXPECT_EQ(problem([&](Settings& s) { s.limit_compliance = bad; }),
              "limit compliance must be in [0, 1e6] rad/(N m)")
        << bad;
  }
}

TEST(Settings, ASolverRefusesWhatValidateRefuses) {
  const Model model = parse_model(
      R"({"name":"one","segments":[{"name":"s","mass":1,"position":[0,0,1],
          "shape":{"type":"sphere","radius":0.1}}],"joints":[]})",
      "one");
  Settings settings;
  settings.substeps = 0;
  EXPECT_THROW(Solver(model, settings, Environment{}), std::invalid_argument);
}

TEST(Settings, ARulesDefaultsFillOnlyWhatWasLeftToTheRule) {
  for (Rule rule : kAllRules) {
    Settings settings;
    settings.rule = rule;
    const Settings defaults = rule_defaults(settings);
    EXPECT_GE(defaults.iterations, 1) << rule_name(rule);
    EXPECT_GE(defaults.substeps, 1) << rule_name(rule);
    settings.iterations = 7;
    settings.substeps = 3;
    const Settings chosen = rule_defaults(settings);
    EXPECT_EQ(chosen.iterations, 7);
    EXPECT_EQ(chosen.substeps, 3);
    EXPECT_EQ(validate(defaults), "");
  }
  EXPECT_EQ(Settings{}.rule, Rule::kXpbd);  // the default: the rule the verdict picks
  Settings relaxed;
  relaxed.rule = Rule::kRelaxed;
  EXPECT_EQ(rule_defaults(relaxed).iterations, 4);  // the four sweeps of docs/design.md
  EXPECT_EQ(rule_defaults(relaxed).substeps, 1);
}

// the rule catalogue (rules/catalogue.cpp): every stage reads a rule's row, so a row out of the
// enum's order or missing a function would run another rule's code
TEST(RuleCatalogue, OneRowPerRuleInTheEnumsOrder) {
  ASSERT_EQ(rule_rows().size(), kAllRules.size());
  std::set<std::string_view> names;
  for (size_t i = 0; i < kAllRules.size(); ++i) {
    const RuleRow& row = rule_rows()[i];
    EXPECT_EQ(row.rule, kAllRules[i]);
    EXPECT_EQ(&rule_row(kAllRules[i]), &row);
    EXPECT_NE(row.adjust, nullptr) << row.info.name;
    EXPECT_NE(row.forced_rotation, nullptr) << row.info.name;
    EXPECT_EQ(parse_rule(row.info.name), kAllRules[i]);
    EXPECT_EQ(rule_name(kAllRules[i]), row.info.name);
    EXPECT_TRUE(names.insert(row.info.name).second) << row.info.name << " twice";
  }
}

TEST(RuleCatalogue, TheDefaultsAreTheRowsOwn) {
  for (const Rule rule : kAllRules) {
    Settings settings;
    settings.rule = rule;
    const Settings filled = rule_defaults(settings);
    EXPECT_EQ(filled.iterations, rule_info(rule).iterations) << rule_name(rule);
    EXPECT_EQ(filled.substeps, rule_info(rule).substeps) << rule_name(rule);
    EXPECT_GE(filled.iterations, 0);
    EXPECT_GE(filled.substeps, 1);
  }
}

}  // namespace
}  // namespace puppet::procedural
