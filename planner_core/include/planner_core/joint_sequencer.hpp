// JointSequencer: K-best joint task sequences (one order per agent) in non-decreasing total cost,
// generated lazily by best-first search over tuples of per-agent ranks (CTS-PIBT's upper level).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <queue>
#include <vector>

#include "planner_core/deadline.hpp"
#include "planner_core/kbest_orders.hpp"

namespace planner_core {

struct JointSequence {
  std::vector<std::vector<int>> orders;  // agent -> task ids in visiting order
  std::vector<int> ranks;                // agent -> rank of its order among its own K-best
  int64_t cost = 0;                      // sum of the agents' tour costs
  int index = 0;                         // 0 for the best joint sequence, 1 for the next, ...
};

class JointSequencer {
 public:
  // Builds every agent's task orders; when `deadline` passes first, next() gives nothing.
  JointSequencer(const Instance& instance, DistTable& dist, const TaskOrderConfig& config,
                 const Deadline& deadline = {});

  // The next joint sequence, or nullopt when every combination has been produced (or, when not
  // ready(), none can be).
  std::optional<JointSequence> next();
  // Every agent's orders were built before the deadline given to the constructor.
  bool ready() const { return ready_; }

  // Sum over agents of their single-agent lower bounds (exact tours within the exact limit);
  // 0 when the deadline cut the orders short.
  int64_t lower_bound() const;
  int agent_count() const { return static_cast<int>(per_agent_.size()); }
  KBestOrders& orders_of(int agent) { return *per_agent_[agent]; }

 private:
  // A rank tuple is stored as its parent tuple plus one agent's rank advanced by one, so a node
  // costs O(1) memory however many agents there are.
  struct TupleStep {
    int parent;        // index in steps_, -1 for the all-zero tuple
    int changed_agent; // the agent whose rank is one more than in the parent
  };
  struct Node {
    int64_t cost;
    int step;          // index in steps_
    int last_changed;  // successors only advance agents >= this, so each tuple is made once
  };
  struct CostGreater {
    bool operator()(const Node& a, const Node& b) const { return a.cost > b.cost; }
  };

  std::vector<int> ranks_of(int step) const;

  std::vector<std::unique_ptr<KBestOrders>> per_agent_;
  std::vector<TupleStep> steps_;
  std::priority_queue<Node, std::vector<Node>, CostGreater> open_;
  int produced_ = 0;
  bool ready_ = false;  // every agent's orders were built
};

}  // namespace planner_core
