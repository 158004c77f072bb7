// Traffic costs: how crowded each cell has been lately, as a cost for moving onto it or staying
// on it, so that lifelong guidance steers agents round a jam instead of into it.
//
// Fixed guidance (one-way lanes, a ring road) sends every agent the same way whatever the others
// do. On random-32-32-20 with 400 agents in the rotation model, a region where streams meet then
// fills up: past about 70% of its cells taken, agents there move less, those heading through it
// arrive later and queue, and the region grows. Over 500 steps a quarter of the map ended 80-95%
// full while the opposite corners emptied to 10-20%, and errands per 50 steps fell from 358 to
// about 230 (the 2023 winner held 40-60% everywhere and a steady rate). Counting each cell's
// occupancy and making crowded cells dearer keeps the map more even (docs/RESULTS.md).
//
// Occupancy is a moving average over about `horizon_steps` steps (each step weighs 1/horizon,
// older ones fade). Every `period_steps` steps a cell's cost becomes `slope_moves` moves per unit
// of occupancy above `threshold`, rounded to cost units and at most `max_moves` moves: with the
// defaults a cell taken 80% of the time costs 1.2 moves more, one always taken 2.
#pragma once

#include <cstddef>
#include <vector>

#include "planner_core/graph.hpp"

namespace planner_core {

struct TrafficSettings {
  bool on = false;
  double threshold = 0.6;    // the share of steps a cell is taken below which it costs nothing more
  double slope_moves = 6.0;  // moves more per unit of occupancy above the threshold
  int max_moves = 2;         // at most (GuidedDistances::kMaxTrafficMoves)
  int horizon_steps = 50;
  int period_steps = 10;
};

class TrafficCosts {
 public:
  // `cost_unit`: what a move costs in the guidance's units (GuidedDistances::cost_unit). Throws
  // std::invalid_argument on settings out of range (threshold within 0..1, positive steps).
  TrafficCosts(size_t cells, const TrafficSettings& settings, int cost_unit);

  // Counts one step: the cells the agents stand on. True when the costs were computed afresh
  // (every period_steps steps).
  bool observe(const Config& cells);
  // Per cell, in cost units: 0 until the first period has passed.
  const std::vector<int>& costs() const { return costs_; }
  double occupancy(Vertex cell) const { return occupancy_[cell]; }

 private:
  TrafficSettings settings_;
  int cost_unit_;
  std::vector<double> occupancy_;
  std::vector<int> costs_;
  int steps_ = 0;
};

}  // namespace planner_core
