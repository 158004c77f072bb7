#include <gtest/gtest.h>

#include "planner_core/guided_distances.hpp"
#include "planner_core/instance_generator.hpp"
#include "planner_core/lacam.hpp"
#include "planner_core/solver.hpp"
#include "planner_core/validator.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

LacamResult run_lacam(const Instance& instance, const std::vector<char>& blocked = {}, bool refine = false,
                      double seconds = 30) {
  std::mt19937 rng(1);
  DistTable dist(*instance.graph);
  Lacam lacam(*instance.graph, dist, LacamConfig{refine}, rng);
  return lacam.solve(instance.starts, instance.goals, blocked, Deadline::in_seconds(seconds));
}

TEST(Lacam, SwapThroughAPocket) {
  const Instance instance = testing::make_instance({"@@@@.@@@@", "........."}, {{{0, 1}, {8, 1}}, {{8, 1}, {0, 1}}});
  const LacamResult result = run_lacam(instance);
  ASSERT_TRUE(result.solved);
  const ValidationReport report = validate(instance, result.solution);
  EXPECT_TRUE(report.ok()) << report.summary();
}

TEST(Lacam, ImpossibleCorridorSwapIsReportedAsExhausted) {
  const Instance instance = testing::make_instance({"....."}, {{{0, 0}, {4, 0}}, {{4, 0}, {0, 0}}});
  const LacamResult result = run_lacam(instance);
  EXPECT_FALSE(result.solved);
  EXPECT_TRUE(result.exhausted);
}

TEST(Lacam, NeverEntersBlockedCells) {
  // The direct row is blocked at (2,1); the agents must go round through row 0 or 2.
  const Instance instance =
      testing::make_instance({".....", ".....", "....."}, {{{0, 1}, {4, 1}}, {{4, 1}, {0, 1}}});
  std::vector<char> blocked(instance.graph->vertex_count(), 0);
  const Vertex wall = instance.graph->vertex_at({2, 1});
  blocked[wall] = 1;
  const LacamResult result = run_lacam(instance, blocked);
  ASSERT_TRUE(result.solved);
  EXPECT_TRUE(validate(instance, result.solution).ok());
  for (const Config& config : result.solution) {
    for (Vertex v : config) EXPECT_NE(v, wall);
  }
}

TEST(Lacam, ManyAgentsOnRandomMap) {
  auto graph = std::make_shared<const Graph>(load_movingai_map(testing::data_path("maps/random-32-32-20.map")));
  const Instance instance = generate_instance(graph, {200, 0, 1, 7});
  const LacamResult result = run_lacam(instance);
  ASSERT_TRUE(result.solved);
  const ValidationReport report = validate(instance, result.solution);
  EXPECT_TRUE(report.ok()) << report.summary();
}

TEST(Lacam, StarRefinementKeepsAValidPlanNoWorse) {
  auto graph = std::make_shared<const Graph>(load_movingai_map(testing::data_path("maps/maze-32-32-2.map")));
  const Instance instance = generate_instance(graph, {20, 0, 1, 3});
  const LacamResult plain = run_lacam(instance);
  const LacamResult refined = run_lacam(instance, {}, true, 1.0);
  ASSERT_TRUE(plain.solved);
  ASSERT_TRUE(refined.solved);
  EXPECT_TRUE(validate(instance, refined.solution).ok());
  EXPECT_LE(refined.cost, plain.cost);
}

TEST(LacamSolver, PlansFiveHundredAgentsInAWarehouseWithOneCellAisles) {
  // Head-on meetings pile up in the aisles between shelves. The swap's clear operation backs an
  // agent off for a neighbour that must get past it even when that neighbour already has its move;
  // before it did, `lacam` found no plan for this instance in 10 s (now about 0.1 s).
  const Instance instance =
      load_instance(std::string(CTSFLEET_BENCHMARKS_DIR) + "/mapf/warehouse-10-20-10-2-1-N500-0.yaml");
  SolverConfig config;
  config.solver = "lacam";
  const SolveResult result = make_solver(config)->solve(instance, {Deadline::in_seconds(30), {}});
  ASSERT_TRUE(result.solved) << result.failure_reason;
  EXPECT_TRUE(validate(instance, result.solution).ok());
}

TEST(LacamSolver, RejectsInstancesWithTasks) {
  const Instance instance = testing::make_instance({"....."}, {{{0, 0}, {4, 0}}}, {{{2, 0}, {0}}});
  SolverConfig config;
  config.solver = "lacam";
  const SolveResult result = make_solver(config)->solve(instance, {Deadline::in_seconds(5), {}});
  EXPECT_FALSE(result.solved);
  EXPECT_NE(result.failure_reason.find("tasks"), std::string::npos);
}

// LaCAM in the rotation model: configurations with headings, constraints on actions.
class TurningLacam : public ::testing::Test {
 protected:
  // Plans `instance` (put in the rotation model; its start headings, east if none) with the
  // agents' task cells, in the order given, as waypoints.
  LacamResult plan(Instance& instance, const Waypoints& waypoints = {}, bool refine = false, double seconds = 30,
                   uint32_t seed = 1) {
    instance.actions = ActionModel::kRotate;
    if (instance.start_headings.empty()) instance.start_headings.assign(instance.agent_count(), 0);
    std::mt19937 rng(seed);
    DistTable dist(*instance.graph);
    GuidedDistances turning(*instance.graph, Guidance::kNone, ActionModel::kRotate);
    LacamConfig config{refine};
    config.turning = &turning;
    LacamSearch search(*instance.graph, dist, config, rng, instance.starts, instance.goals, {}, waypoints,
                       instance.start_headings);
    return search.run(Deadline::in_seconds(seconds));
  }
  static void expect_valid(const Instance& instance, const LacamResult& result) {
    ASSERT_TRUE(result.solved);
    ASSERT_EQ(result.headings.size(), result.solution.size());
    const ValidationReport report = validate(instance, result.solution, {}, result.headings);
    EXPECT_TRUE(report.ok()) << report.summary();
  }
};

TEST_F(TurningLacam, TwoAgentsPassThroughAPocketTurningAsTheyGo) {
  // Head on in a corridor with one pocket: one agent must turn into the pocket, wait, turn out.
  Instance instance = testing::make_instance({"@@@@.@@@@", "........."}, {{{0, 1}, {8, 1}}, {{8, 1}, {0, 1}}});
  instance.start_headings = {0, 2};  // facing each other
  const LacamResult result = plan(instance);
  expect_valid(instance, result);
  // Every turn costs a step: 8 moves forward for each, and the one that steps aside turns at least
  // 4 times (towards the pocket, round to face out, back along the corridor).
  EXPECT_GE(result.solution.size(), 9u + 4u);
}

TEST_F(TurningLacam, ACorridorSwapIsSearchedToTheEndAndReportedImpossible) {
  Instance instance = testing::make_instance({"....."}, {{{0, 0}, {4, 0}}, {{4, 0}, {0, 0}}});
  const LacamResult result = plan(instance);
  EXPECT_FALSE(result.solved);
  EXPECT_TRUE(result.exhausted);
}

TEST_F(TurningLacam, AnAgentFacingAWallTurnsBeforeItMoves) {
  // Facing west at the west edge: two quarter turns, then three steps east.
  Instance instance = testing::make_instance({"...."}, {{{0, 0}, {3, 0}}});
  instance.start_headings = {2};
  const LacamResult result = plan(instance, {}, /*refine=*/true, 2);
  expect_valid(instance, result);
  EXPECT_EQ(result.cost, 5);
}

TEST_F(TurningLacam, HeadingsAreNotPartOfTheGoal) {
  // The agent arrives facing south and the plan ends there: no turn to any particular heading.
  Instance instance = testing::make_instance({"..", ".."}, {{{0, 0}, {0, 1}}});
  instance.start_headings = {1};
  const LacamResult result = plan(instance, {}, true, 2);
  expect_valid(instance, result);
  EXPECT_EQ(result.solution.size(), 2u);
  EXPECT_EQ(result.headings.back()[0], 1);
}

TEST_F(TurningLacam, VisitsEveryWaypointInOrderBeforeItsGoal) {
  // Agent 0 must fetch from the dead end at (2,1) and end at (4,0); agent 1 is in the way at (3,0).
  Instance instance = testing::make_instance({".....", "@@.@@"}, {{{0, 0}, {4, 0}}, {{3, 0}, {1, 0}}},
                                             {{{2, 1}, {0}}, {{4, 0}, {1}}});
  const Graph& graph = *instance.graph;
  const LacamResult result = plan(instance, {{graph.vertex_at({2, 1})}, {graph.vertex_at({4, 0})}});
  expect_valid(instance, result);  // the validator checks each task is visited by its agents
}

TEST_F(TurningLacam, ManyAgentsOnARandomMapAndTheSameSeedGivesTheSamePlan) {
  auto graph = std::make_shared<const Graph>(load_movingai_map(testing::data_path("maps/random-32-32-20.map")));
  Instance instance = generate_instance(graph, {100, 0, 1, 7});
  const LacamResult first = plan(instance);
  expect_valid(instance, first);
  const LacamResult again = plan(instance);
  EXPECT_EQ(first.solution, again.solution);
  EXPECT_EQ(first.headings, again.headings);
}

TEST_F(TurningLacam, StarRefinementIsNoWorse) {
  auto graph = std::make_shared<const Graph>(load_movingai_map(testing::data_path("maps/maze-32-32-2.map")));
  Instance instance = generate_instance(graph, {10, 0, 1, 3});
  const LacamResult first = plan(instance);
  const LacamResult refined = plan(instance, {}, true, 1.0);
  expect_valid(instance, first);
  expect_valid(instance, refined);
  EXPECT_LE(refined.cost, first.cost);
}

TEST_F(TurningLacam, RefusesBlockedCellsAndMissingOrBadHeadings) {
  Instance instance = testing::make_instance({"...."}, {{{0, 0}, {3, 0}}});
  std::mt19937 rng(1);
  DistTable dist(*instance.graph);
  GuidedDistances turning(*instance.graph, Guidance::kNone, ActionModel::kRotate);
  LacamConfig config;
  config.turning = &turning;
  EXPECT_THROW(LacamSearch(*instance.graph, dist, config, rng, instance.starts, instance.goals), std::invalid_argument);
  const std::vector<char> blocked(instance.graph->vertex_count(), 0);
  EXPECT_THROW(LacamSearch(*instance.graph, dist, config, rng, instance.starts, instance.goals, blocked, {}, {0}),
               std::invalid_argument);
  EXPECT_THROW(LacamSearch(*instance.graph, dist, config, rng, instance.starts, instance.goals, {}, {}, {4}),
               std::invalid_argument);
  EXPECT_THROW(LacamSearch(*instance.graph, dist, config, rng, instance.starts, instance.goals, {}, {}, {-1}),
               std::invalid_argument);
}

}  // namespace
}  // namespace planner_core
