#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "planner_core/dist_table.hpp"
#include "test_helpers.hpp"

namespace planner_core {
namespace {

// Full breadth-first search from `target`, written here independently of DistTable.
std::vector<int> reference_distances(const Graph& graph, Vertex target) {
  std::vector<int> dist(graph.vertex_count(), kUnreachable);
  std::vector<Vertex> queue{target};
  dist[target] = 0;
  for (size_t head = 0; head < queue.size(); ++head) {
    for (Vertex u : graph.neighbours(queue[head])) {
      if (dist[u] == kUnreachable) {
        dist[u] = dist[queue[head]] + 1;
        queue.push_back(u);
      }
    }
  }
  return dist;
}

std::vector<std::string> random_rows(int width, int height, double wall_share, std::mt19937& rng) {
  std::bernoulli_distribution wall(wall_share);
  std::vector<std::string> rows(height, std::string(width, '.'));
  for (std::string& row : rows) {
    for (char& cell : row) cell = wall(rng) ? '@' : '.';
  }
  return rows;
}

// Queries in a random order (so that searches are paused and resumed at every depth) agree with a
// full search, including cells cut off from the target.
void expect_agrees_with_full_search(const Graph& graph, std::mt19937& rng, int targets, int queries_per_target) {
  DistTable dist(graph);
  std::uniform_int_distribution<Vertex> any(0, graph.vertex_count() - 1);
  for (int k = 0; k < targets; ++k) {
    const Vertex target = any(rng);
    const std::vector<int> expected = reference_distances(graph, target);
    for (int q = 0; q < queries_per_target; ++q) {
      const Vertex from = any(rng);
      ASSERT_EQ(dist.get(target, from), expected[from]) << "target " << target << " from " << from;
    }
    for (Vertex from = 0; from < graph.vertex_count(); from += 7) ASSERT_EQ(dist.get(target, from), expected[from]);
  }
}

TEST(DistTable, LazySearchesAgreeWithFullSearchesOnRandomMaps) {
  std::mt19937 rng(7);
  for (int map = 0; map < 20; ++map) {
    const auto graph = testing::grid_from_rows(random_rows(40, 30, 0.3, rng));  // many disconnected pockets
    if (graph->vertex_count() == 0) continue;
    expect_agrees_with_full_search(*graph, rng, 10, 50);
  }
}

TEST(DistTable, WideDistancesOnMapsWithMoreThan65535Cells) {
  // A serpentine corridor on a 400x400 grid: more cells than 16 bits can number and distances
  // far above 65535, so the table must switch to 32-bit entries.
  std::vector<std::string> rows(400, std::string(400, '.'));
  for (int y = 1; y < 400; y += 2) {
    rows[y] = std::string(400, '@');
    rows[y][(y / 2) % 2 == 0 ? 399 : 0] = '.';
  }
  const auto graph = testing::grid_from_rows(rows);
  ASSERT_GE(graph->vertex_count(), 0xFFFF);
  DistTable dist(*graph);
  const Vertex corner = graph->vertex_at({0, 0});
  const Vertex far_end = graph->vertex_at({0, 398});
  const std::vector<int> expected = reference_distances(*graph, corner);
  EXPECT_GT(expected[far_end], 0xFFFF);
  EXPECT_EQ(dist.get(corner, far_end), expected[far_end]);
  std::mt19937 rng(3);
  expect_agrees_with_full_search(*graph, rng, 3, 200);
}

TEST(DistTable, AgentsWithOneTargetShareOneSearchInSixteenBits) {
  std::vector<std::string> rows(250, std::string(250, '.'));
  const auto graph = testing::grid_from_rows(rows);
  DistTable dist(*graph);
  const Vertex target = graph->vertex_at({0, 0});
  EXPECT_EQ(dist.get(target, graph->vertex_at({1, 1})), 2);
  EXPECT_EQ(dist.get(target, graph->vertex_at({3, 0})), 3);
  EXPECT_EQ(dist.targets_searched(), 1);
  EXPECT_EQ(dist.get(target, graph->vertex_at({249, 249})), 498);
  EXPECT_EQ(dist.targets_searched(), 1);
  // Per cell: the table's slot for a search from it and one 16-bit distance; besides, at most a
  // frontier (the consumed part of the queue is dropped every 4096 cells). A table of ints, or
  // one that kept its whole queue, would be over this.
  const size_t cells = static_cast<size_t>(graph->vertex_count());
  EXPECT_LE(dist.memory_bytes(), cells * (sizeof(void*) + sizeof(uint16_t)) + 2 * 4096 * sizeof(Vertex) + 256);
}

TEST(DistTable, CellsOfAnotherComponentAreUnreachable) {
  const auto graph = testing::grid_from_rows({"..@..", "..@..", "..@.."});
  DistTable dist(*graph);
  EXPECT_EQ(dist.get(graph->vertex_at({0, 0}), graph->vertex_at({4, 2})), kUnreachable);
  EXPECT_EQ(dist.get(graph->vertex_at({0, 0}), graph->vertex_at({1, 2})), 3);
  EXPECT_EQ(dist.get(graph->vertex_at({0, 0}), graph->vertex_at({3, 0})), kUnreachable);  // after completion too
}

}  // namespace
}  // namespace planner_core
