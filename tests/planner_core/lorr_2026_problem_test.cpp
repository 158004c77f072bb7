// The league's 2024 and 2026 problems read as they are written: comment lines, a pool of
// numTasksReveal x teamSize tasks, multi-errand tasks, and the 2026 execution settings
// (agentCounter, agentSize, delayConfig), every fault named by its file and line or key.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "planner_core/input_error.hpp"
#include "planner_core/lorr_problem.hpp"
#include "tiny_lorr_problem.hpp"

namespace planner_core {
namespace {

const std::string k2026 = std::string(CTSFLEET_BENCHMARKS_DIR) + "/lorr-2026/";

const std::string kDelays =
    R"("version": "2026 LoRR", "agentCounter": 3, "agentSize": 1.0, "delayConfig": {"seed": 7, "minDelay": 2,
       "maxDelay": 5, "eventModel": "poisson", "pDelay": 0.02, "durationModel": "gaussian", "gaussMeanRatio": 0.5,
       "gaussStdRatio": 0.22})";

TEST(LorrProblem2026, EveryStartKitExampleReadsWhole) {
  struct Example {
    std::string file;
    size_t team;
  };
  const std::vector<Example> examples = {
      {"city.domain/bos-example_600.json", 600},        {"game.domain/orz-example_1800.json", 1800},
      {"maze.domain/maze-example_40.json", 40},         {"random.domain/random-example_400.json", 400},
      {"room.domain/room-example_150.json", 150},       {"warehouse.domain/fulfill-example_2500.json", 2500},
  };
  for (const Example& example : examples) {
    const LorrProblem problem = load_lorr_problem(k2026 + example.file);
    EXPECT_EQ(problem.starts.size(), example.team) << example.file;
    EXPECT_EQ(problem.version, "2026 LoRR") << example.file;
    EXPECT_GE(problem.ticks_per_action, 1) << example.file;
    ASSERT_TRUE(problem.delays.has_value()) << example.file;
    EXPECT_LE(problem.delays->min_ticks, problem.delays->max_ticks) << example.file;
    EXPECT_EQ(problem.assignment, TaskAssignment::kPool) << example.file;  // no strategy: the pool
    EXPECT_DOUBLE_EQ(problem.tasks_revealed_per_agent, 1.5) << example.file;
    size_t longest = 0;
    for (const auto& task : problem.tasks) longest = std::max(longest, task.size());
    EXPECT_GT(longest, 1u) << example.file << ": tasks of several errands";
  }
  const LorrProblem random = load_lorr_problem(k2026 + "random.domain/random-example_400.json");
  EXPECT_EQ(random.ticks_per_action, 3);
  EXPECT_EQ(random.delays->events, LeagueDelays::Events::kBernoulli);
  EXPECT_EQ(random.delays->min_ticks, 1);
  EXPECT_EQ(random.delays->max_ticks, 4);
  EXPECT_DOUBLE_EQ(random.delays->probability, 0.01);
  const LorrProblem room = load_lorr_problem(k2026 + "room.domain/room-example_150.json");
  EXPECT_EQ(room.delays->events, LeagueDelays::Events::kPoisson);
}

TEST(LorrProblem2026, TenThousandAgentsOfIronHarvestRead) {
  const LorrProblem problem = load_lorr_problem(k2026 + "iron_harvest.domain/iron-example_10000.json");
  EXPECT_EQ(problem.starts.size(), 10000u);
  EXPECT_TRUE(problem.delays.has_value());
}

TEST(LorrProblem2026, CommentLinesAreSkippedAndTheSettingsRead) {
  TinyProblem tiny({"....."}, {"# version for LoRR 2026", "2", "0", "  # a comment after the count", "4"},
                   {"# tasks", "2", "1,3", "2"}, kDelays);
  tiny.write("tiny.json", {R"({"mapFile": "tiny.map", "agentFile": "tiny.agents", "teamSize": 2, "taskFile": "tiny.tasks", "numTasksReveal": 1.5, )" + kDelays + "}"});
  const LorrProblem problem = load_lorr_problem(tiny.path());
  EXPECT_EQ(problem.starts.size(), 2u);
  ASSERT_EQ(problem.tasks.size(), 2u);
  EXPECT_EQ(problem.tasks[0].size(), 2u);
  EXPECT_EQ(problem.ticks_per_action, 3);
  ASSERT_TRUE(problem.delays.has_value());
  EXPECT_EQ(problem.delays->seed, 7u);
  EXPECT_EQ(problem.delays->durations, LeagueDelays::Durations::kGaussian);
  EXPECT_DOUBLE_EQ(problem.delays->gauss_spread_share, 0.22);
  EXPECT_EQ(problem.assignment, TaskAssignment::kPool);  // no strategy named: a pool
  EXPECT_DOUBLE_EQ(problem.tasks_revealed_per_agent, 1.5);
  // A '#' that is not at the start of a line is no comment.
  TinyProblem inline_hash({"....."}, {"2", "0", "4 # here"}, {"1", "1"}, kDelays);
  EXPECT_NE(lorr_error_of(inline_hash.path()).find("tiny.agents:3"), std::string::npos);
}

TEST(LorrProblem2026, EveryBadExecutionSettingNamesItsKey) {
  const auto with = [](const std::string& settings) {
    return TinyProblem({"....."}, {"2", "0", "4"}, {"1", "1"}, settings);
  };
  const std::string good_delays =
      R"("seed": 0, "minDelay": 1, "maxDelay": 4, "eventModel": "bernoulli", "pDelay": 0.01, "durationModel": "uniform", "gaussMeanRatio": 0.5, "gaussStdRatio": 0.2)";
  const auto delays_with = [&](const std::string& key, const std::string& value) {
    std::string text = good_delays;
    const size_t at = text.find("\"" + key + "\": ");
    const size_t end = text.find_first_of(",}", at);
    text.replace(at, (end == std::string::npos ? text.size() : end) - at, "\"" + key + "\": " + value);
    return "\"delayConfig\": {" + text + "}";
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {delays_with("minDelay", "-2"), "\"minDelay\""},
      {delays_with("minDelay", "0"), "\"minDelay\""},
      {delays_with("maxDelay", "0"), "\"maxDelay\""},
      {delays_with("pDelay", "1.5"), "\"pDelay\""},
      {delays_with("pDelay", "-0.1"), "\"pDelay\""},
      {delays_with("pDelay", "\"often\""), "\"pDelay\""},
      {delays_with("eventModel", "\"gamma\""), "\"eventModel\""},
      {delays_with("durationModel", "\"exponential\""), "\"durationModel\""},
      {delays_with("gaussMeanRatio", "2"), "\"gaussMeanRatio\""},
      {delays_with("seed", "-1"), "\"seed\""},
      {delays_with("minDelay", "1.5"), "\"minDelay\""},
      {"\"delayConfig\": {\"seed\": 0}", "\"minDelay\" missing"},
      {"\"delayConfig\": [1, 2]", "\"delayConfig\" must be an object"},
      {"\"agentCounter\": 0", "\"agentCounter\""},
      {"\"agentCounter\": 2.5", "\"agentCounter\""},
      {"\"agentSize\": 0", "\"agentSize\""},
      {"\"agentSize\": 3", "\"agentSize\""},
      {"\"version\": 2026", "\"version\""},
  };
  for (const auto& [settings, named] : cases) {
    const TinyProblem tiny = with(settings);
    const std::string error = lorr_error_of(tiny.path());
    EXPECT_NE(error.find("tiny.json"), std::string::npos) << settings << " -> " << error;
    EXPECT_NE(error.find(named), std::string::npos) << settings << " -> " << error;
  }
}

TEST(LorrProblem2026, ATeamLargerThanItsAgentsFileOrATaskOffTheMapIsNamed) {
  TinyProblem team({"....."}, {"2", "0", "4"}, {"1", "1"}, kDelays);
  team.write("tiny.json", {R"({"mapFile": "tiny.map", "agentFile": "tiny.agents", "teamSize": 3, "taskFile": "tiny.tasks"})"});
  EXPECT_NE(lorr_error_of(team.path()).find("\"teamSize\" is 3"), std::string::npos);
  TinyProblem off({"....."}, {"2", "0", "4"}, {"1", "2,17"}, kDelays);
  EXPECT_NE(lorr_error_of(off.path()).find("tiny.tasks:2: location 17 is off the 5x1 map"), std::string::npos);
}

}  // namespace
}  // namespace planner_core
