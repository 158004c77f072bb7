#include "coordinator/task_assignment.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>

namespace coordinator {

using planner_core::Vertex;

TaskPlacement cheapest_insertion(planner_core::DistTable& distances, Vertex task, const std::vector<Tour>& tours) {
  TaskPlacement best;
  for (size_t t = 0; t < tours.size(); ++t) {
    const std::vector<Vertex>& stops = tours[t].stops;
    if (stops.empty() || distances.get(task, stops.front()) >= planner_core::kUnreachable) continue;
    // The task goes after stop i - 1 and before stop i; after the goal makes no sense (the robot
    // ends on its goal), so a one-stop tour (standing on its goal) puts it before that stop.
    for (size_t i = 1; i <= std::max<size_t>(1, stops.size() - 1); ++i) {
      const Vertex before = stops[i - 1];
      const Vertex after = i < stops.size() ? stops[i] : stops[i - 1];
      const int added = distances.get(task, before) + distances.get(after, task) - distances.get(after, before);
      if (best.tour < 0 || added < best.added_steps) best = {static_cast<int>(t), i, added};
    }
  }
  return best;
}

TaskPlacement earliest_arrival(planner_core::DistTable& distances, Vertex task, const std::vector<Tour>& tours) {
  TaskPlacement best;
  for (size_t t = 0; t < tours.size(); ++t) {
    const std::vector<Vertex>& stops = tours[t].stops;
    if (stops.empty() || distances.get(task, stops.front()) >= planner_core::kUnreachable) continue;
    const size_t last_task = stops.size() >= 2 ? stops.size() - 2 : 0;  // the goal is the last stop
    int arrival = 0;
    for (size_t i = 1; i <= last_task; ++i) arrival += distances.get(stops[i], stops[i - 1]);
    arrival += distances.get(task, stops[last_task]);
    if (best.tour < 0 || arrival < best.added_steps) best = {static_cast<int>(t), last_task + 1, arrival};
  }
  return best;
}

std::string task_cell_refusal(const planner_core::Instance& mission, int x, int y) {
  const planner_core::Graph& map = *mission.graph;
  if (!map.inside({x, y})) return fmt::format("({},{}) is off the map ({} x {})", x, y, map.width(), map.height());
  if (!map.is_free({x, y})) return fmt::format("({},{}) is a wall", x, y);
  return "";
}

}  // namespace coordinator
