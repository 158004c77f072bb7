// The lifelong planner's settings file (config/lifelong.yaml): the shipped file is the planner's
// defaults, every bad value is named by file, line and key, and "auto" is settled by the rules.
#include <gtest/gtest.h>

#include "planner_core/input_error.hpp"
#include "planner_core/lifelong_auto_rules.hpp"
#include "planner_core/lifelong_config.hpp"
#include "planner_core/lorr_problem.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

const std::string kRandom = std::string(CTSFLEET_BENCHMARKS_DIR) + "/lorr-2023/random.domain/";
const std::string kShipped = std::string(CTSFLEET_BENCHMARKS_DIR) + "/../config/lifelong.yaml";

std::string error_of(const std::string& text) {
  const std::string path = testing::write_temp_file("lifelong.yaml", text);
  try {
    load_lifelong_config(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(LifelongConfig, TheShippedFileIsThePlannersDefaults) {
  EXPECT_EQ(load_lifelong_config(kShipped), LifelongConfig{});
  EXPECT_EQ(error_of(""), "");  // an empty file: every default
}

TEST(LifelongConfig, EveryKeyIsReadAndAutoMeansZeroForCounts) {
  const std::string path = testing::write_temp_file(
      "lifelong.yaml",
      "lns: off\nguidance: ring\nstay_cost: 4\nrollouts: 7\nrollout_steps: auto\nlns_rounds: 300\n"
      "keep_window: on\nkeep_equal_cost: off\nneighbourhoods: nearest\nhold_plans: always\nkeep_targets: false\n"
      "park_dead_ends: on\ntraffic_costs: off\n");
  const LifelongConfig config = load_lifelong_config(path);
  EXPECT_EQ(config.lns, "off");
  EXPECT_EQ(config.guidance, "ring");
  EXPECT_EQ(config.stay_cost, 4);
  EXPECT_EQ(config.rollouts, 7);
  EXPECT_EQ(config.rollout_steps, 0);
  EXPECT_EQ(config.lns_rounds, 300);
  EXPECT_EQ(config.keep_window, "on");
  EXPECT_EQ(config.keep_equal_cost, "off");
  EXPECT_EQ(config.neighbourhoods, "nearest");
  EXPECT_EQ(config.hold_plans, "always");
  EXPECT_FALSE(config.keep_targets);
  EXPECT_EQ(config.park_dead_ends, "on");
  EXPECT_EQ(config.traffic_costs, "off");
}

TEST(LifelongConfig, EveryBadValueNamesItsFileLineAndKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"rollouts: 128\nrollouts_steps: 8\n", ":2:"},                       // a misspelt key
      {"lns: maybe\n", "lns"},
      {"guidance: sideways\n", "guidance"},
      {"stay_cost: 9\n", "stay_cost"},
      {"stay_cost: -1\n", "stay_cost"},
      {"rollouts: 0\n", "rollouts"},
      {"rollouts: 99999999999999999999\n", "rollouts"},
      {"rollouts: many\n", "rollouts"},
      {"rollout_steps: 2.5\n", "rollout_steps"},
      {"lns_rounds: -3\n", "lns_rounds"},
      {"keep_window: [on]\n", "keep_window"},
      {"neighbourhoods: widest\n", "neighbourhoods"},
      {"hold_plans: sometimes\n", "hold_plans"},
      {"keep_targets: perhaps\n", "keep_targets"},
      {"park_dead_ends: yes please\n", "park_dead_ends"},
      {"traffic_costs: 3\n", "traffic_costs"},
      {"- lns\n- on\n", "top level"},
      {"lns: [on\n", "lifelong.yaml"},  // not YAML at all
  };
  for (const auto& [text, named] : cases) {
    const std::string error = error_of(text);
    EXPECT_NE(error.find("lifelong.yaml"), std::string::npos) << text << " -> " << error;
    EXPECT_NE(error.find(named), std::string::npos) << text << " -> " << error;
  }
  EXPECT_NE(error_of("\n\nguidance: sideways\n").find(":3:"), std::string::npos);
}

TEST(LifelongConfig, CommandLineValuesAreCheckedToo) {
  LifelongConfig config;
  config.rollouts = 0;
  EXPECT_THROW(check_lifelong_config(config, "options"), InputError);
  config = {};
  config.hold_plans = "often";
  EXPECT_THROW(check_lifelong_config(config, "options"), InputError);
  EXPECT_NO_THROW(check_lifelong_config(LifelongConfig{}, "options"));
}

TEST(LifelongConfig, AutoTurnsWindowLnsOnInTheRotationModelUnlessCrowded) {
  const LorrProblem few = load_lorr_problem(kRandom + "random_100.json");
  const LorrProblem crowded = load_lorr_problem(kRandom + "random_800.json");
  const LifelongConfig defaults;
  const PibtLifelongSettings rotate_few = settle_lifelong_config(defaults, *few.graph, 100, ActionModel::kRotate);
  EXPECT_TRUE(rotate_few.lns);
  EXPECT_EQ(rotate_few.guidance, Guidance::kNone);  // agents few: shortest paths
  EXPECT_EQ(rotate_few.rollout_steps, 16);
  EXPECT_TRUE(rotate_few.keep_window);
  const PibtLifelongSettings rotate_400 = settle_lifelong_config(defaults, *few.graph, 400, ActionModel::kRotate);
  EXPECT_TRUE(rotate_400.lns);
  EXPECT_EQ(rotate_400.guidance, Guidance::kRing);
  EXPECT_TRUE(rotate_400.traffic.on);
  EXPECT_EQ(rotate_400.stay_cost, 3);
  const PibtLifelongSettings rotate_800 = settle_lifelong_config(defaults, *crowded.graph, 800, ActionModel::kRotate);
  EXPECT_FALSE(rotate_800.lns);
  EXPECT_EQ(rotate_800.hold_plans, PlanHolding::kAlways);
  EXPECT_TRUE(rotate_800.park_dead_end_errands);
  EXPECT_EQ(rotate_800.rollout_steps, kRolloutStepsWhereHeld);
  const PibtLifelongSettings move4 = settle_lifelong_config(defaults, *few.graph, 400, ActionModel::kMove4);
  EXPECT_FALSE(move4.lns);
  EXPECT_EQ(move4.guidance, Guidance::kLanes);
  // A key set overrides its rule; the others still follow theirs.
  LifelongConfig off = defaults;
  off.lns = "off";
  EXPECT_FALSE(settle_lifelong_config(off, *few.graph, 400, ActionModel::kRotate).lns);
  EXPECT_EQ(settle_lifelong_config(off, *few.graph, 400, ActionModel::kRotate).guidance, Guidance::kLanes);
  LifelongConfig on = defaults;
  on.lns = "on";
  EXPECT_TRUE(settle_lifelong_config(on, *crowded.graph, 800, ActionModel::kRotate).lns);
}

TEST(LifelongConfig, TheRulesReadTheFleetOnTheMap) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_100.json");
  const FleetOnMap fleet = measure_fleet_on_map(*problem.graph, 205);
  EXPECT_EQ(fleet.free_cells, problem.graph->vertex_count());
  EXPECT_EQ(fleet.shorter_side, 32);
  EXPECT_NEAR(fleet.fill(), 205.0 / problem.graph->vertex_count(), 1e-12);
  // The thresholds sit where the rules say: a quarter full, and 90% full.
  const size_t quarter = static_cast<size_t>(problem.graph->vertex_count()) / 4;
  EXPECT_FALSE(lifelong_lns(*problem.graph, quarter, ActionModel::kMove4));
  EXPECT_EQ(lifelong_guidance(*problem.graph, quarter, true, ActionModel::kRotate), Guidance::kNone);
  EXPECT_NE(lifelong_guidance(*problem.graph, quarter + 1, true, ActionModel::kRotate), Guidance::kNone);
  const size_t nine_tenths = static_cast<size_t>(problem.graph->vertex_count()) * 9 / 10;
  EXPECT_TRUE(lifelong_lns(*problem.graph, nine_tenths, ActionModel::kRotate));
  EXPECT_FALSE(lifelong_lns(*problem.graph, nine_tenths + 1, ActionModel::kRotate));
}

}  // namespace
}  // namespace planner_core
