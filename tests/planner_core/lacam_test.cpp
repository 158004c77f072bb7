#include <gtest/gtest.h>

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

}  // namespace
}  // namespace planner_core
