// Traffic costs: a cell's occupancy is a moving average of the steps it was taken; past the
// threshold it costs more, up to the largest cost, recomputed once a period. A lifelong run that
// counts them steps validly and, with its work counted, runs the same twice.
#include <gtest/gtest.h>

#include <stdexcept>

#include "planner_core/lifelong.hpp"
#include "planner_core/lifelong_auto_rules.hpp"
#include "planner_core/pibt_lifelong.hpp"
#include "planner_core/lorr_problem.hpp"
#include "planner_core/traffic_costs.hpp"

namespace planner_core {
namespace {

const std::string kRandom = std::string(CTSFLEET_BENCHMARKS_DIR) + "/lorr-2023/random.domain/";

TEST(TrafficCosts, ACellAlwaysTakenCostsMostAndOneNeverTakenNothing) {
  const TrafficSettings settings{.on = true, .horizon_steps = 20, .period_steps = 5};
  TrafficCosts traffic(3, settings, 10);
  const Config always_cell_0{0};
  for (int step = 1; step <= 4; ++step) EXPECT_FALSE(traffic.observe(always_cell_0)) << step;
  EXPECT_EQ(traffic.costs(), (std::vector<int>{0, 0, 0})) << "nothing before the first period";
  EXPECT_TRUE(traffic.observe(always_cell_0));
  for (int step = 6; step <= 200; ++step) traffic.observe(always_cell_0);
  EXPECT_NEAR(traffic.occupancy(0), 1.0, 1e-3);
  EXPECT_EQ(traffic.costs()[0], settings.max_moves * 10) << "capped";
  EXPECT_EQ(traffic.costs()[1], 0);
  EXPECT_EQ(traffic.costs()[2], 0);
}

TEST(TrafficCosts, OnlyOccupancyAboveTheThresholdCosts) {
  // Cell 0 taken every other step (about half the time), cell 1 four steps of five (0.8).
  TrafficCosts traffic(2, {.on = true, .threshold = 0.6, .slope_moves = 6.0, .horizon_steps = 50, .period_steps = 10}, 10);
  for (int step = 0; step < 1000; ++step) {
    Config taken;
    if (step % 2 == 0) taken.push_back(0);
    if (step % 5 != 0) taken.push_back(1);
    traffic.observe(taken);
  }
  EXPECT_NEAR(traffic.occupancy(0), 0.5, 0.02);
  EXPECT_NEAR(traffic.occupancy(1), 0.8, 0.02);
  EXPECT_EQ(traffic.costs()[0], 0);
  EXPECT_NEAR(traffic.costs()[1], 12, 1) << "0.2 above the threshold at 6 moves a unit: 1.2 moves";
}

// Auto: with the ring road only; from 60% of the time taken, or 10 points above the map's mean
// fill where that is more.
TEST(TrafficCosts, AutoTakesThemWithTheRingRoadFromAboveTheMapsMeanFill) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_400.json");
  const Graph& graph = *problem.graph;
  EXPECT_TRUE(lifelong_traffic(graph, 400, Guidance::kRing).on);
  EXPECT_FALSE(lifelong_traffic(graph, 400, Guidance::kLanes).on);
  EXPECT_FALSE(lifelong_traffic(graph, 400, Guidance::kNone).on);
  EXPECT_DOUBLE_EQ(lifelong_traffic(graph, 400, Guidance::kRing).threshold, 0.6) << "819 cells, 49% full";
  EXPECT_NEAR(lifelong_traffic(graph, 600, Guidance::kRing).threshold, 600.0 / 819 + 0.1, 1e-9);
  EXPECT_DOUBLE_EQ(lifelong_traffic(graph, 819, Guidance::kRing).threshold, 0.95) << "below 1, always";
}

TEST(TrafficCosts, SettingsOutOfRangeAreRefused) {
  EXPECT_THROW(TrafficCosts(1, {.threshold = 1.0}, 1), std::invalid_argument);
  EXPECT_THROW(TrafficCosts(1, {.threshold = -0.1}, 1), std::invalid_argument);
  EXPECT_THROW(TrafficCosts(1, {.slope_moves = -1}, 1), std::invalid_argument);
  EXPECT_THROW(TrafficCosts(1, {.horizon_steps = 0}, 1), std::invalid_argument);
  EXPECT_THROW(TrafficCosts(1, {.period_steps = 0}, 1), std::invalid_argument);
  EXPECT_THROW(PibtLifelong(*load_lorr_problem(kRandom + "random_20.json").graph, 1,
                            {.traffic = {.on = true, .max_moves = GuidedDistances::kMaxTrafficMoves + 1}}),
               std::invalid_argument);
}

// With traffic costs the guidance changes every period: every step stays valid, agents finish
// errands, and with the work counted the same seed gives the same run.
TEST(TrafficCosts, ALifelongRunCountingThemStepsValidlyAndTheSameSeedRunsTheSame) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_400.json");
  const PibtLifelongSettings crowded{.guidance = Guidance::kRing,
                                     .stay_cost = 3,
                                     .actions = ActionModel::kRotate,
                                     .rollouts = 4,
                                     .rollout_steps = 8,
                                     .lns = true,
                                     .keep_window = true,
                                     .lns_rounds = 200,
                                     .traffic = {.on = true, .horizon_steps = 10, .period_steps = 5}};
  std::vector<LifelongResult> results;
  for (int run = 0; run < 2; ++run) {
    PibtLifelong planner(*problem.graph, 7, crowded);
    LifelongSettings settings{.steps = 40, .step_time_s = 60};
    settings.actions = ActionModel::kRotate;
    settings.late_steps_taken = true;
    results.push_back(run_lifelong(problem, planner, settings));
    EXPECT_EQ(results.back().invalid_steps, 0) << results.back().first_invalid;
    int crowded_cells = 0;
    for (Vertex v = 0; v < problem.graph->vertex_count(); ++v) crowded_cells += planner.distances().traffic_cost(v) > 0;
    EXPECT_GT(crowded_cells, 10) << "the guidance did change";
  }
  EXPECT_GT(results[0].errands_finished, 20);
  EXPECT_EQ(results[0].errands_per_step, results[1].errands_per_step);
}

}  // namespace
}  // namespace planner_core
