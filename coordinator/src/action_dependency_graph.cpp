#include "coordinator/action_dependency_graph.hpp"

#include <map>

namespace coordinator {

using planner_core::Vertex;

ActionDependencyGraph::ActionDependencyGraph(const planner_core::Solution& plan) {
  const int robots = plan.empty() ? 0 : static_cast<int>(plan[0].size());
  moves_.assign(robots, {});
  // Departures from each cell, in plan order: (arrival time elsewhere, robot, move index).
  std::map<Vertex, std::vector<std::tuple<int, int, int>>> departures;
  for (int r = 0; r < robots; ++r) {
    for (size_t t = 1; t < plan.size(); ++t) {
      if (plan[t][r] == plan[t - 1][r]) continue;
      const int index = static_cast<int>(moves_[r].size());
      moves_[r].push_back({plan[t - 1][r], plan[t][r], static_cast<int>(t), {}});
      departures[plan[t - 1][r]].emplace_back(static_cast<int>(t), r, index);
    }
  }
  for (int r = 0; r < robots; ++r) {
    for (Move& move : moves_[r]) {
      // For every other robot, its last departure from the target cell no later than our arrival.
      std::map<int, int> last_departure;
      for (const auto& [time, other, index] : departures[move.to]) {
        if (other != r && time <= move.plan_time) {
          auto [it, fresh] = last_departure.emplace(other, index);
          if (!fresh && index > it->second) it->second = index;
        }
      }
      for (const auto& [other, index] : last_departure) move.after.emplace_back(other, index);
    }
  }
}

}  // namespace coordinator
