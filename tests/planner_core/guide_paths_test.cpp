// Guide paths: a path to the goal that steers around the others' flows. On two parallel lanes,
// the second agent's path takes the other lane rather than meet the first head on; an agent that
// moves along its path keeps it, one that leaves it gets a new one.
#include <gtest/gtest.h>

#include <cstdlib>

#include "planner_core/dist_table.hpp"
#include "planner_core/guide_paths.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

GuidePaths::Heuristic manhattan(const Graph& graph) {
  return [&graph](Vertex goal, Vertex cell) {
    const Cell a = graph.cell_of(goal);
    const Cell b = graph.cell_of(cell);
    return std::abs(a.x - b.x) + std::abs(a.y - b.y);
  };
}

TEST(GuidePaths, TheSecondAgentTakesTheOtherLaneRatherThanMeetTheFirstHeadOn) {
  const auto graph = testing::grid_from_rows({"......", "......"});
  const auto at = [&](int x, int y) { return graph->vertex_at({x, y}); };
  GuidePaths guides(*graph, {.on = true, .crowd_weight = 0});
  const Config positions{at(0, 0), at(5, 0)};
  const Config goals{at(5, 0), at(0, 0)};
  guides.update(positions, goals, manhattan(*graph), Deadline::in_seconds(10));

  EXPECT_EQ(guides.next(0, at(0, 0)), at(1, 0)) << "the first path is the straight one";
  EXPECT_EQ(guides.next(1, at(5, 0)), at(5, 1)) << "the second steps to the free lane";
  EXPECT_EQ(guides.next(1, at(3, 1)), at(2, 1));
  EXPECT_EQ(guides.next(1, at(0, 1)), at(0, 0)) << "and back up at the end";
  EXPECT_EQ(guides.contraflow_moves(), 0);
}

TEST(GuidePaths, WithoutItsFlowsTheOtherLaneIsNotWorthTheDetour) {
  const auto graph = testing::grid_from_rows({"......", "......"});
  const auto at = [&](int x, int y) { return graph->vertex_at({x, y}); };
  GuidePaths guides(*graph, {.on = true, .crowd_weight = 0});
  // Both go the same way: no contraflow, so both take the straight lane.
  guides.update({at(0, 0), at(1, 0)}, {at(5, 0), at(4, 0)}, manhattan(*graph), Deadline::in_seconds(10));
  EXPECT_EQ(guides.next(0, at(0, 0)), at(1, 0));
  EXPECT_EQ(guides.next(1, at(1, 0)), at(2, 0));
}

TEST(GuidePaths, AnAgentAlongItsPathKeepsItAndOneOffItGetsANewOne) {
  const auto graph = testing::grid_from_rows({"......", "......"});
  const auto at = [&](int x, int y) { return graph->vertex_at({x, y}); };
  GuidePaths guides(*graph, {.on = true, .crowd_weight = 0, .replans_per_step = 0});
  const auto heuristic = manhattan(*graph);
  guides.update({at(0, 0)}, {at(5, 0)}, heuristic, Deadline::in_seconds(10));
  EXPECT_EQ(guides.paths_searched(), 1);

  guides.update({at(2, 0)}, {at(5, 0)}, heuristic, Deadline::in_seconds(10));
  EXPECT_EQ(guides.paths_searched(), 1) << "two cells along: the same path";
  EXPECT_EQ(guides.next(0, at(2, 0)), at(3, 0));
  EXPECT_EQ(guides.next(0, at(1, 0)), kNoVertex) << "cells passed are no longer looked at";

  guides.update({at(2, 1)}, {at(5, 0)}, heuristic, Deadline::in_seconds(10));
  EXPECT_EQ(guides.paths_searched(), 2) << "pushed off it: a new path from where it stands";
  EXPECT_NE(guides.next(0, at(2, 1)), kNoVertex);

  guides.update({at(2, 1)}, {at(0, 0)}, heuristic, Deadline::in_seconds(10));
  EXPECT_EQ(guides.paths_searched(), 3) << "a new goal: a new path";
  EXPECT_EQ(guides.next(0, at(5, 0)), kNoVertex);
}

TEST(GuidePaths, AGoalWithNoWayToItLeavesTheAgentWithoutAGuide) {
  const auto graph = testing::grid_from_rows({"..@..", "..@.."});
  const auto at = [&](int x, int y) { return graph->vertex_at({x, y}); };
  GuidePaths guides(*graph, {.on = true});
  const GuidePaths::Heuristic unreachable_across = [&](Vertex goal, Vertex cell) {
    return (graph->cell_of(goal).x > 2) != (graph->cell_of(cell).x > 2) ? kUnreachable
                                                                          : manhattan(*graph)(goal, cell);
  };
  guides.update({at(0, 0)}, {at(4, 0)}, unreachable_across, Deadline::in_seconds(10));
  EXPECT_EQ(guides.next(0, at(0, 0)), kNoVertex);
}

}  // namespace
}  // namespace planner_core
