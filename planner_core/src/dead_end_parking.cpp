// PibtLifelong on maps nearly full of agents: an agent whose errand is a dead end is parked
// (pibt_lifelong.hpp, park_dead_end_errands).
#include "planner_core/pibt_lifelong.hpp"

namespace planner_core {

Config PibtLifelong::planning_goals(const Poses& now, const Config& errands) {
  const size_t n = errands.size();
  parked_agent_.assign(n, 0);
  if (!settings_.park_dead_end_errands) return errands;
  released_for_.resize(n, kNoVertex);
  Config planned = errands;
  for (size_t a = 0; a < n; ++a) {
    const bool dead_end = errands[a] != now.cells[a] && graph_.neighbours(errands[a]).size() <= 1;
    if (dead_end && released_for_[a] != errands[a]) {
      planned[a] = now.cells[a];
      parked_agent_[a] = 1;
    }
  }
  // A parked agent standing on the errand of one stuck for stuck_steps_ may be unable to make way
  // (in a dead end behind it): it is let go for that errand of its own.
  if (still_.size() == n) {
    for (size_t a = 0; a < n; ++a) standing_on_[now.cells[a]] = static_cast<int>(a);
    for (size_t b = 0; b < n; ++b) {
      const int there = standing_on_[errands[b]];
      if (parked_agent_[b] || still_[b] < stuck_steps_ || there == -1 || !parked_agent_[there]) continue;
      released_for_[there] = errands[there];
      parked_agent_[there] = 0;
      planned[there] = errands[there];
    }
    for (size_t a = 0; a < n; ++a) standing_on_[now.cells[a]] = -1;
  }
  return planned;
}

}  // namespace planner_core
