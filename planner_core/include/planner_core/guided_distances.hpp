// Distances to goals over a guidance graph (Zhang et al., "Guidance Graph Optimization for
// Lifelong MAPF", 2024): every move has a cost, and an agent that ranks its moves by cost plus
// distance keeps to the cheap ones. With one-way lanes, rows take turns running east and west and
// columns south and north; a move against its lane costs more, so streams of agents pass each other
// in neighbouring lanes instead of meeting head on. Moving against a lane stays allowed (a dead end
// or a single corridor has only one way), it is only dearer.
//
// In the rotation model (action_model.hpp) a table holds a cost per cell and heading: an agent
// facing away from its way pays its turns as well.
//
// A wait, and in the rotation model a quarter turn, costs `stay_cost` (1 unless asked). The 2023
// winner's learned weights for random-32-32-20 with 400 agents (DiligentPanda/MAPF-LRR2023,
// scripts/random_weight_040.w) are one-way lanes like these, with a wait or turn costing about
// twice a move along the lane; dearer waits send window LNS paths round a queue rather than into
// it, and make turns worth avoiding (figures: docs/RESULTS.md).
//
// Which lines take turns depends on the map: on a sortation floor only every other row is a
// street, so rows taking turns one by one would send every street east. Rows therefore change
// direction every p rows, for the smallest p in 1..4 that gives about as many east moves as west
// moves (within a quarter), and columns likewise.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "planner_core/action_model.hpp"
#include "planner_core/deadline.hpp"
#include "planner_core/graph.hpp"

namespace planner_core {

enum class Guidance {
  kNone,   // every move costs 1: distances are shortest paths
  kLanes,  // one-way lanes: rows take turns east and west, columns south and north (lane_period)
  kRing,   // one-way lanes and a ring road: near the map's edge, moves and waits cost less
};

// "none", "lanes" or "ring"; throws InputError naming `what` otherwise.
Guidance parse_guidance(const std::string& text, const std::string& what);
std::string to_string(Guidance guidance);

class GuidedDistances {
 public:
  static constexpr int kAgainstLaneCost = 3;
  static constexpr int kMaxStayCost = 6;
  // The ring road (Guidance::kRing): a move or wait from a cell `depth` cells from the map's
  // edge costs ring_discount_at(depth) units (of kRingUnit to a move along a lane) less: 6 at the
  // edge, falling by half a unit a cell to 0 at kRingDepth.
  static constexpr int kRingUnit = 10;
  static constexpr int kRingDepth = 12;
  static constexpr int kRingDiscountAtEdge = 6;
  static constexpr int ring_discount_at(int depth) {
    return depth >= kRingDepth ? 0 : (kRingDiscountAtEdge * (kRingDepth - depth) + kRingDepth - 1) / kRingDepth;
  }
  // Throws std::invalid_argument unless 1 <= stay_cost <= kMaxStayCost and 0 <= max_traffic_moves
  // <= kMaxTrafficMoves.
  GuidedDistances(const Graph& graph, Guidance guidance, ActionModel actions = ActionModel::kMove4,
                  int stay_cost = 1, int max_traffic_moves = 0);

  // The cost of the move from `from` to its neighbour `to`.
  int move_cost(Vertex from, Vertex to) const {
    if (guidance_ == Guidance::kNone) return 1 + traffic_cost(to);
    const Cell a = graph_.cell_of(from);
    const Cell b = graph_.cell_of(to);
    const bool with_lane = a.y == b.y ? (b.x > a.x) == (a.y / row_period_ % 2 == 0)
                                      : (b.y > a.y) == (a.x / column_period_ % 2 == 0);
    return (with_lane ? 1 : kAgainstLaneCost) * unit_ - ring_discount(from) + traffic_cost(to);
  }
  // The cost of a wait, and in the rotation model of a quarter turn, on `cell`.
  int stay_cost(Vertex cell) const { return stay_cost_ * unit_ - ring_discount(cell) + traffic_cost(cell); }

  // Traffic costs (traffic_costs.hpp): per cell, what moving onto it or waiting or turning on it
  // costs more, in cost units, at most max_traffic_cost(); 0 everywhere until set. Setting other
  // costs than those in force drops every table held (each is searched again when next asked for,
  // or prepared) and returns true; the same costs change nothing. Throws std::invalid_argument
  // unless there is one per cell, each within 0..max_traffic_cost().
  bool set_traffic_costs(std::vector<int> costs);
  int traffic_cost(Vertex cell) const { return traffic_.empty() ? 0 : traffic_[cell]; }
  int max_traffic_cost() const { return max_traffic_cost_; }
  static constexpr int kMaxTrafficMoves = 4;
  // ... away from the ring road: the stay cost asked for, in cost units.
  int stay_cost() const { return stay_cost_ * unit_; }
  // What a move along a lane costs away from the ring road: 1, or kRingUnit with a ring road
  // (whose discounts are fractions of a move). Distances are in these units.
  int cost_unit() const { return unit_; }
  int row_period() const { return row_period_; }
  int column_period() const { return column_period_; }

  // The cheapest cost from `from` to `target` (kUnreachable if none); searches the target's table
  // first if it is not held. In the rotation model, from `from` facing `heading` (any heading at
  // the target will do).
  int get(Vertex target, Vertex from, int heading = 0) {
    const Table* table = by_target_[target].get();
    if (table == nullptr) table = &search(target);
    const size_t state = static_cast<size_t>(from) * headings_ + static_cast<size_t>(heading);
    const uint32_t d = table->narrow.empty() ? table->wide[state] : table->narrow[state];
    return d == unreachable() ? kUnreachable : static_cast<int>(d);
  }
  // The cheapest cost in the rotation model when the agent at `from` may first turn either way
  // or not at all: the best heading it can face after one step spent in place.
  int get_after_turning(Vertex target, Vertex from, int heading) {
    return std::min({get(target, from, heading), get(target, from, turned_clockwise(heading)),
                     get(target, from, turned_counter_clockwise(heading))});
  }
  ActionModel actions() const { return actions_; }

  // Searches the tables of `targets` not held yet, on `threads` threads, until the deadline.
  void prepare(const std::vector<Vertex>& targets, const Deadline& deadline, int threads);

  bool held(Vertex target) const { return by_target_[target] != nullptr; }
  void forget(Vertex target) { by_target_[target].reset(); }
  size_t bytes_per_target() const {
    return static_cast<size_t>(graph_.vertex_count()) * headings_ * (narrow_ ? 2 : 4);
  }
  static constexpr int kUnreachable = 1 << 30;

 private:
  struct Table {
    std::vector<uint16_t> narrow;  // when every cost fits in 16 bits
    std::vector<uint32_t> wide;
  };
  uint32_t unreachable() const { return narrow_ ? 0xFFFFu : 0xFFFFFFFFu; }
  int ring_discount(Vertex cell) const { return discount_.empty() ? 0 : discount_[cell]; }
  // The dearest single action, in cost units.
  int dearest_action() const {
    return std::max(guidance_ == Guidance::kNone ? 1 : kAgainstLaneCost, stay_cost_) * unit_ + max_traffic_cost_;
  }
  const Table& search(Vertex target);

  const Graph& graph_;
  Guidance guidance_;
  ActionModel actions_;
  size_t headings_;  // states per cell: 1, or 4 in the rotation model
  int row_period_ = 1;
  int column_period_ = 1;
  int stay_cost_ = 1;
  int unit_ = 1;
  std::vector<uint8_t> discount_;  // per vertex, Guidance::kRing only
  int max_traffic_cost_ = 0;       // in cost units
  std::vector<int> traffic_;       // per vertex, empty until set_traffic_costs
  bool narrow_;
  std::vector<std::unique_ptr<Table>> by_target_;
};

}  // namespace planner_core
