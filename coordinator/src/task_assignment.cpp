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

namespace {

// Steps robot `robot` takes to reach `task` heading for the nearest of its errands first, then
// the nearest of the rest (kUnreachable when it cannot).
int way_through_errands(planner_core::DistTable& distances, const PoolRobot& robot, Vertex task) {
  std::vector<Vertex> left = robot.errands;
  Vertex here = robot.from;
  int64_t way = 0;
  while (!left.empty()) {
    size_t nearest = 0;
    for (size_t i = 1; i < left.size(); ++i) {
      if (distances.get(left[i], here) < distances.get(left[nearest], here)) nearest = i;
    }
    const int step = distances.get(left[nearest], here);
    if (step >= planner_core::kUnreachable) return planner_core::kUnreachable;
    way += step;
    here = left[nearest];
    if (here == task) return static_cast<int>(std::min<int64_t>(way, planner_core::kUnreachable));
    left.erase(left.begin() + static_cast<std::ptrdiff_t>(nearest));
  }
  return planner_core::kUnreachable;  // not among its errands
}

}  // namespace

std::vector<TaskMove> rebalance_pool(planner_core::DistTable& distances, std::vector<PoolRobot>& robots,
                                     std::vector<PooledTask>& tasks) {
  std::vector<TaskMove> moves;
  std::vector<int> takers;  // robots that have run out of tasks and may take one
  for (size_t r = 0; r < robots.size(); ++r) {
    if (!robots[r].out && robots[r].errands.empty()) takers.push_back(static_cast<int>(r));
  }
  while (!takers.empty()) {
    TaskMove best;
    for (size_t k = 0; k < tasks.size(); ++k) {
      const PooledTask& task = tasks[k];
      const PoolRobot& holder = robots[task.holder];
      int holder_way = -1;  // computed once a taker is nearer than any pair so far
      for (const int r : takers) {
        const int way = distances.get(task.at, robots[r].from);
        if (way >= planner_core::kUnreachable || (best.task >= 0 && way >= best.way)) continue;
        if (!holder.out) {
          if (holder_way < 0) holder_way = way_through_errands(distances, holder, task.at);
          if (way >= holder_way) continue;
        }
        best = {static_cast<int>(k), task.holder, r, way, holder.out ? -1 : holder_way};
      }
    }
    if (best.task < 0) break;
    PooledTask& task = tasks[best.task];
    std::vector<Vertex>& held = robots[task.holder].errands;
    if (const auto it = std::find(held.begin(), held.end(), task.at); it != held.end()) held.erase(it);
    robots[best.to].errands.push_back(task.at);
    std::erase(takers, best.to);
    task.holder = best.to;
    best.task = task.task;
    moves.push_back(best);
  }
  return moves;
}

std::string task_cell_refusal(const planner_core::Instance& mission, int x, int y) {
  const planner_core::Graph& map = *mission.graph;
  if (!map.inside({x, y})) return fmt::format("({},{}) is off the map ({} x {})", x, y, map.width(), map.height());
  if (!map.is_free({x, y})) return fmt::format("({},{}) is a wall", x, y);
  return "";
}

}  // namespace coordinator
