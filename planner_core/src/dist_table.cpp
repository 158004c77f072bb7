#include "planner_core/dist_table.hpp"

namespace planner_core {

DistTable::DistTable(const Graph& graph) : graph_(graph), by_target_(graph.vertex_count()) {}

const std::vector<int>& DistTable::of(Vertex target) {
  auto& slot = by_target_[target];
  if (slot) return *slot;
  slot = std::make_unique<std::vector<int>>(graph_.vertex_count(), kUnreachable);
  std::vector<int>& dist = *slot;
  std::vector<Vertex> queue;
  queue.reserve(graph_.vertex_count());
  dist[target] = 0;
  queue.push_back(target);
  for (size_t head = 0; head < queue.size(); ++head) {
    const Vertex v = queue[head];
    for (Vertex u : graph_.neighbours(v)) {
      if (dist[u] == kUnreachable) {
        dist[u] = dist[v] + 1;
        queue.push_back(u);
      }
    }
  }
  return dist;
}

}  // namespace planner_core
