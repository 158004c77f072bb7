// DistTable: shortest-path distances on the grid to target cells, computed lazily (as lacam3's
// lazy distance table and LaCAM's "lazy BFS"): one breadth-first search per target cell, shared by
// every agent with that target, run only as far as the queries so far have needed and resumed
// from its frontier on the next query. Distances are stored in 16 bits when the map has fewer than
// 65535 cells, so 10,000 targets on a warehouse map fit in well under 1 GB.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "planner_core/deadline.hpp"
#include "planner_core/graph.hpp"

namespace planner_core {

constexpr int kUnreachable = 1 << 29;

class DistTable {
 public:
  explicit DistTable(const Graph& graph);

  // Distance from `from` to `target` (kUnreachable if disconnected). A query costs O(1) once the
  // search from `target` has reached `from`; otherwise it resumes that search until it does.
  // Not thread-safe: one table per solver thread.
  int get(Vertex target, Vertex from) {
    const TargetSearch* search = by_target_[target].get();
    if (search) {
      const uint32_t known = narrow_ ? search->narrow[from] : search->wide[from];
      if (known != unknown()) return static_cast<int>(known);
    }
    return resume(target, from);
  }

  // One target's distances, read straight from its array (one memory access fewer than get(),
  // for hot loops such as PIBT's); valid as long as the table.
  class Row {
   public:
    int get(Vertex from) const {
      const uint32_t known = narrow_ ? narrow_[from] : wide_[from];
      return known != unknown_ ? static_cast<int>(known) : table_->get(target_, from);
    }

   private:
    friend class DistTable;
    const uint16_t* narrow_ = nullptr;
    const uint32_t* wide_ = nullptr;
    uint32_t unknown_ = 0;
    Vertex target_ = kNoVertex;
    DistTable* table_ = nullptr;
  };
  Row row(Vertex target);

  // Runs the searches from each query's target at least as far as its `from`, on `threads`
  // threads (one target is never shared between threads), stopping when the deadline passes.
  // Returns false when it did not finish. The table may be read only after it returns.
  struct Query {
    Vertex target;
    Vertex from;
  };
  bool prepare(const std::vector<Query>& queries, const Deadline& deadline, int threads = default_threads());
  static int default_threads();  // the machine's cores, at most 8

  // Targets searched from so far, and the bytes their tables and frontiers hold.
  int targets_searched() const { return targets_searched_; }
  size_t memory_bytes() const;

 private:
  struct TargetSearch {
    std::vector<uint16_t> narrow;  // used when the graph has fewer than 65535 vertices
    std::vector<uint32_t> wide;
    std::vector<Vertex> queue;  // queue[head..] is the frontier still to expand
    size_t head = 0;
  };

  uint32_t unknown() const { return narrow_ ? 0xFFFFu : 0xFFFFFFFFu; }
  uint32_t distance_in(const TargetSearch& search, Vertex v) const {
    return narrow_ ? search.narrow[v] : search.wide[v];
  }
  TargetSearch& start_search(Vertex target);
  int resume(Vertex target, Vertex from);

  const Graph& graph_;
  bool narrow_;
  std::atomic<int> targets_searched_{0};
  std::vector<std::unique_ptr<TargetSearch>> by_target_;
};

}  // namespace planner_core
