#include "planner_core/dist_table.hpp"

namespace planner_core {

namespace {
// The consumed part of a frontier queue is dropped once it is this long and at least half the
// queue, so a paused search holds about its frontier, not every vertex it has seen.
constexpr size_t kCompactAfter = 4096;
}  // namespace

DistTable::DistTable(const Graph& graph)
    : graph_(graph), narrow_(graph.vertex_count() < 0xFFFF), by_target_(graph.vertex_count()) {}

DistTable::TargetSearch& DistTable::start_search(Vertex target) {
  auto search = std::make_unique<TargetSearch>();
  if (narrow_) {
    search->narrow.assign(graph_.vertex_count(), 0xFFFFu);
  } else {
    search->wide.assign(graph_.vertex_count(), 0xFFFFFFFFu);
  }
  set_distance(*search, target, 0);
  search->queue.push_back(target);
  ++targets_searched_;
  by_target_[target] = std::move(search);
  return *by_target_[target];
}

int DistTable::resume(Vertex target, Vertex from) {
  TargetSearch& search = by_target_[target] ? *by_target_[target] : start_search(target);
  const uint32_t none = unknown();
  while (distance_in(search, from) == none && search.head < search.queue.size()) {
    const Vertex v = search.queue[search.head++];
    const uint32_t next = distance_in(search, v) + 1;
    for (Vertex u : graph_.neighbours(v)) {
      if (distance_in(search, u) == none) {
        set_distance(search, u, next);
        search.queue.push_back(u);
      }
    }
    if (search.head >= kCompactAfter && 2 * search.head >= search.queue.size()) {
      search.queue.erase(search.queue.begin(), search.queue.begin() + static_cast<std::ptrdiff_t>(search.head));
      search.head = 0;
    }
  }
  if (search.head >= search.queue.size() && !search.queue.empty()) {
    search.queue.clear();  // the search is complete: every vertex left unknown is unreachable
    search.queue.shrink_to_fit();
    search.head = 0;
  }
  const uint32_t d = distance_in(search, from);
  return d == none ? kUnreachable : static_cast<int>(d);
}

size_t DistTable::memory_bytes() const {
  size_t bytes = by_target_.size() * sizeof(by_target_[0]);
  for (const auto& search : by_target_) {
    if (!search) continue;
    bytes += sizeof(TargetSearch) + search->narrow.capacity() * sizeof(uint16_t) +
             search->wide.capacity() * sizeof(uint32_t) + search->queue.capacity() * sizeof(Vertex);
  }
  return bytes;
}

}  // namespace planner_core
