#include <gtest/gtest.h>

#include "planner_core/instance_generator.hpp"
#include "planner_core/lacam.hpp"
#include "planner_core/scatter.hpp"
#include "planner_core/solver.hpp"
#include "planner_core/validator.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

// Follows the agent's scatter path from its start with next(): the cells it visits.
Path follow(const Scatter& scatter, const Instance& instance, int agent) {
  Path path{instance.starts[agent]};
  for (Vertex v = scatter.next(agent, path.back()); v != kNoVertex; v = scatter.next(agent, path.back())) {
    path.push_back(v);
    if (path.size() > static_cast<size_t>(instance.graph->vertex_count())) break;  // a loop would be a bug
  }
  return path;
}

// Two agents crossing a 3-row room head-on along its middle row: the only shortest paths meet.
const std::vector<std::string> kRoom = {"..........", "..........", ".........."};
const std::vector<testing::AgentSpec> kHeadOn = {{{0, 1}, {9, 1}}, {{9, 1}, {0, 1}}};

// The scatter paths of an instance, built with a generous deadline.
struct Built {
  Built(const Instance& instance, int cost_margin)
      : dist(*instance.graph),
        scatter(*instance.graph, dist, instance.starts, instance.goals, cost_margin, 1),
        stats(scatter.build(Deadline::in_seconds(10))) {}
  DistTable dist;
  Scatter scatter;
  ScatterStats stats;
};

TEST(Scatter, HeadOnAgentsTakeParallelRowsWhenTheMarginAllows) {
  const Instance instance = testing::make_instance(kRoom, kHeadOn);
  const Built built(instance, /*cost_margin=*/2);
  EXPECT_TRUE(built.stats.complete);
  EXPECT_EQ(built.stats.collisions, 0);
  for (int agent = 0; agent < 2; ++agent) {
    const Path path = follow(built.scatter, instance, agent);
    EXPECT_EQ(path.back(), instance.goals[agent]);
    EXPECT_LE(static_cast<int>(path.size()) - 1, 9 + 2);  // the shortest (9) plus the margin
    for (size_t t = 1; t < path.size(); ++t) EXPECT_TRUE(instance.graph->adjacent(path[t - 1], path[t]));
  }
}

TEST(Scatter, WithoutAMarginTheOnlyShortestPathsStillCollide) {
  const Built built(testing::make_instance(kRoom, kHeadOn), /*cost_margin=*/0);
  EXPECT_TRUE(built.stats.complete);
  EXPECT_GT(built.stats.collisions, 0);  // the count is honest: they must meet in the middle row
  EXPECT_EQ(built.stats.sum_of_lengths, 18);
}

TEST(Scatter, AnExpiredDeadlineLeavesNoGuidanceAndNoCrash) {
  const Instance instance = testing::make_instance(kRoom, kHeadOn);
  DistTable dist(*instance.graph);
  Scatter scatter(*instance.graph, dist, instance.starts, instance.goals, 2, 1);
  const ScatterStats stats = scatter.build(Deadline::in_seconds(-1));
  EXPECT_FALSE(stats.complete);
  EXPECT_EQ(scatter.next(0, instance.starts[0]), kNoVertex);
}

TEST(Scatter, AnUnreachableGoalGetsNoPath) {
  const Instance instance = testing::make_instance({"..@..", "..@.."}, {{{0, 0}, {0, 1}}, {{3, 0}, {4, 1}}});
  const Built reachable(instance, 2);
  EXPECT_TRUE(reachable.stats.complete);
  EXPECT_EQ(follow(reachable.scatter, instance, 1).back(), instance.goals[1]);
  // A wall between start and goal: no path, so no guidance (LaCAM decides alone).
  const Instance walled = testing::make_instance({"..@..", "..@.."}, {{{0, 0}, {4, 0}}});
  const Built none(walled, 2);
  EXPECT_FALSE(none.stats.complete);
  EXPECT_EQ(none.scatter.next(0, walled.starts[0]), kNoVertex);
}

// Follows one leg of the agent's scatter path from `from` with next(agent, leg, v).
Path follow_leg(const Scatter& scatter, int agent, int leg, Vertex from, int limit) {
  Path path{from};
  for (Vertex v = scatter.next(agent, leg, from); v != kNoVertex && static_cast<int>(path.size()) <= limit;
       v = scatter.next(agent, leg, path.back())) {
    path.push_back(v);
  }
  return path;
}

TEST(Scatter, PathsThroughWaypointsGoLegByLegInTheirOrder) {
  const Instance instance = testing::make_instance(kRoom, {{{0, 1}, {9, 2}}, {{5, 0}, {5, 2}}});
  const auto v = [&](int x, int y) { return instance.graph->vertex_at({x, y}); };
  // Agent 0: to the far end, back, then to the far end again (the legs cross the same cells).
  // Agent 1: its first waypoint is where it stands (a leg of length 0).
  const std::vector<std::vector<Vertex>> waypoints = {{v(9, 0), v(0, 2)}, {v(5, 0), v(0, 0)}};
  DistTable dist(*instance.graph);
  Scatter scatter(*instance.graph, dist, instance.starts, instance.goals, 2, 1, waypoints);
  ASSERT_TRUE(scatter.build(Deadline::in_seconds(10)).complete);
  const int limit = instance.graph->vertex_count();
  const std::vector<std::vector<Vertex>> targets = {{v(9, 0), v(0, 2), v(9, 2)}, {v(5, 0), v(0, 0), v(5, 2)}};
  for (int agent = 0; agent < 2; ++agent) {
    Vertex at = instance.starts[agent];
    for (int leg = 0; leg < 3; ++leg) {
      const Path path = follow_leg(scatter, agent, leg, at, limit);
      const Vertex target = targets[agent][leg];
      EXPECT_EQ(path.back(), target) << "agent " << agent << " leg " << leg;
      EXPECT_LE(static_cast<int>(path.size()) - 1, dist.get(target, at) + 2) << "agent " << agent << " leg " << leg;
      for (size_t t = 1; t < path.size(); ++t) EXPECT_TRUE(instance.graph->adjacent(path[t - 1], path[t]));
      at = path.back();
    }
    EXPECT_EQ(scatter.next(agent, 2, at), kNoVertex);  // the goal ends the last leg
  }
  EXPECT_EQ(scatter.next(1, 0, v(5, 0)), kNoVertex);  // standing on its first waypoint: leg 0 is empty
  // Without waypoints, leg 0 is the whole path (what LaCAM's guide reads).
  EXPECT_EQ(scatter.next(0, v(0, 1)), scatter.next(0, 0, v(0, 1)));
}

TEST(Scatter, CtsPllPlansGuidedByScatterAreValid) {
  const Instance instance = load_instance(testing::data_path("instances/random-32-32-20-N10-M30-00.yaml"));
  for (const char* solver : {"cts-pll-v2", "cts-pll-v3"}) {
    SolverConfig config;
    config.solver = solver;
    config.pibt.scatter = true;
    const SolveResult result = make_solver(config)->solve(instance, {Deadline::in_seconds(2), {}});
    ASSERT_TRUE(result.solved) << solver << ": " << result.failure_reason;
    const ValidationReport report = validate(instance, result.solution);
    EXPECT_TRUE(report.ok()) << solver << ": " << report.summary();
    EXPECT_EQ(report.flowtime, result.flowtime);
  }
}

TEST(Scatter, GuidedLacamPlansAreValidAndSpreadFewerCollisionsThanShortestPaths) {
  auto graph = std::make_shared<const Graph>(load_movingai_map(testing::data_path("maps/random-32-32-20.map")));
  const Instance instance = generate_instance(graph, {200, 0, 1, 7});
  DistTable dist(*instance.graph);
  Scatter shortest(*instance.graph, dist, instance.starts, instance.goals, 0, 3);
  Scatter spread(*instance.graph, dist, instance.starts, instance.goals, 10, 3);
  const ScatterStats tight = shortest.build(Deadline::in_seconds(30));
  const ScatterStats loose = spread.build(Deadline::in_seconds(30));
  ASSERT_TRUE(loose.complete);
  EXPECT_LT(loose.collisions, tight.collisions);

  std::mt19937 rng(1);
  LacamConfig config{/*refine=*/false, false, /*swap=*/true, /*prefer_free_cells=*/true};
  config.guide = &spread;
  LacamSearch search(*instance.graph, dist, config, rng, instance.starts, instance.goals);
  const LacamResult result = search.run(Deadline::in_seconds(30));
  ASSERT_TRUE(result.solved);
  const ValidationReport report = validate(instance, result.solution);
  EXPECT_TRUE(report.ok()) << report.summary();
}

}  // namespace
}  // namespace planner_core
