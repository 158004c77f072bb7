// DistTable: shortest-path distances on the grid, one BFS per target, computed on first use and shared.
#pragma once

#include <memory>
#include <vector>

#include "planner_core/graph.hpp"

namespace planner_core {

constexpr int kUnreachable = 1 << 29;

class DistTable {
 public:
  explicit DistTable(const Graph& graph);

  // Distance from `from` to `target` (kUnreachable if disconnected). Not thread-safe:
  // one table per solver thread.
  int get(Vertex target, Vertex from) { return of(target)[from]; }
  const std::vector<int>& of(Vertex target);

 private:
  const Graph& graph_;
  std::vector<std::unique_ptr<std::vector<int>>> by_target_;
};

}  // namespace planner_core
