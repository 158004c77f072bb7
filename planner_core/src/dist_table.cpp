#include "planner_core/dist_table.hpp"

#include <algorithm>
#include <atomic>
#include <thread>
#include <unordered_map>

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
  if (narrow_) {
    search->narrow[target] = 0;
  } else {
    search->wide[target] = 0;
  }
  search->queue.push_back(target);
  ++targets_searched_;
  by_target_[target] = std::move(search);
  return *by_target_[target];
}

namespace {

// Breadth-first expansion from the frontier queue[head..] until `from` has a distance or the
// queue runs out; `Distance` is the entry type (16 or 32 bits), `none` its "not reached yet".
template <class Distance>
void expand_until(const Graph& graph, std::vector<Distance>& dist, std::vector<Vertex>& queue, size_t& head,
                  Vertex from, Distance none) {
  while (dist[from] == none && head < queue.size()) {
    const Vertex v = queue[head++];
    const Distance next = static_cast<Distance>(dist[v] + 1);
    for (Vertex u : graph.neighbours(v)) {
      if (dist[u] == none) {
        dist[u] = next;
        queue.push_back(u);
      }
    }
    if (head >= kCompactAfter && 2 * head >= queue.size()) {
      queue.erase(queue.begin(), queue.begin() + static_cast<std::ptrdiff_t>(head));
      head = 0;
    }
  }
}

}  // namespace

int DistTable::resume(Vertex target, Vertex from) {
  TargetSearch& search = by_target_[target] ? *by_target_[target] : start_search(target);
  const uint32_t none = unknown();
  if (narrow_) {
    expand_until<uint16_t>(graph_, search.narrow, search.queue, search.head, from, 0xFFFFu);
  } else {
    expand_until<uint32_t>(graph_, search.wide, search.queue, search.head, from, 0xFFFFFFFFu);
  }
  if (search.head >= search.queue.size() && !search.queue.empty()) {
    search.queue.clear();  // the search is complete: every vertex left unknown is unreachable
    search.queue.shrink_to_fit();
    search.head = 0;
  }
  const uint32_t d = distance_in(search, from);
  return d == none ? kUnreachable : static_cast<int>(d);
}

DistTable::Row DistTable::row(Vertex target) {
  TargetSearch& search = by_target_[target] ? *by_target_[target] : start_search(target);
  Row row;
  // The arrays are allocated at full size when a search starts and never move.
  row.narrow_ = narrow_ ? search.narrow.data() : nullptr;
  row.wide_ = narrow_ ? nullptr : search.wide.data();
  row.unknown_ = unknown();
  row.target_ = target;
  row.table_ = this;
  return row;
}

int DistTable::default_threads() {
  return static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 8u));
}

bool DistTable::prepare(const std::vector<Query>& queries, const Deadline& deadline, int threads) {
  // Per target, the query that reaches farthest is enough: the search stops only once it has
  // reached `from`, so ask for every `from` of that target in turn on one thread.
  // (Grouped in a map, not a vector over the vertices: on a 4000 x 4000 map that vector alone
  // was 384 MB for a few dozen targets.)
  std::unordered_map<Vertex, std::vector<Vertex>> from_of;
  std::vector<Vertex> targets;
  for (const Query& query : queries) {
    std::vector<Vertex>& froms = from_of[query.target];
    if (froms.empty()) targets.push_back(query.target);
    froms.push_back(query.from);
  }
  std::atomic<size_t> next{0};
  std::atomic<bool> finished{true};
  const auto work = [&] {
    for (size_t k = next++; k < targets.size(); k = next++) {
      if (deadline.expired()) {
        finished = false;
        return;
      }
      // Each target is handled by one thread only, so its slot and search are this thread's.
      for (Vertex from : from_of.at(targets[k])) resume(targets[k], from);
    }
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < threads; ++t) helpers.emplace_back(work);
  work();
  for (std::thread& helper : helpers) helper.join();
  return finished;
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
