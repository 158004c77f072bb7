#include "coordinator/window_planner.hpp"

#include <stdexcept>
#include <string>

namespace coordinator {

using planner_core::Config;
using planner_core::Vertex;

namespace {

planner_core::PibtLifelongSettings for_robots(planner_core::PibtLifelongSettings settings, planner_core::ActionModel actions) {
  settings.actions = actions;
  settings.forbid_rotations = true;
  settings.lns = false;
  return settings;
}

}  // namespace

planner_core::PibtLifelongSettings window_settings(const std::optional<planner_core::LifelongConfig>& settings,
                                                   const planner_core::Graph& graph, size_t robots,
                                                   planner_core::ActionModel actions) {
  if (!settings) return for_robots({}, actions);
  planner_core::LifelongConfig without_lns = *settings;
  without_lns.lns = "off";  // and so the auto rules settle the rest as for rollouts alone
  return for_robots(planner_core::settle_lifelong_config(without_lns, graph, robots, actions), actions);
}

WindowPlanner::WindowPlanner(std::shared_ptr<const planner_core::Graph> graph, uint32_t seed,
                             planner_core::ActionModel actions, planner_core::PibtLifelongSettings pibt)
    : graph_(std::move(graph)), actions_(actions), pibt_(*graph_, seed, for_robots(pibt, actions)), distances_(*graph_) {}

PlanWindow WindowPlanner::plan(const planner_core::Poses& start, const std::vector<WindowAgent>& agents, int steps,
                               const planner_core::Deadline& deadline) {
  const bool turning = actions_ == planner_core::ActionModel::kRotate;
  if (agents.size() != start.cells.size()) throw std::invalid_argument("a window needs one WindowAgent per agent");
  std::vector<int> planned;  // the agents not held, in order
  for (size_t a = 0; a < agents.size(); ++a) {
    if (agents[a].held) continue;
    if (!graph_->is_open(start.cells[a])) {
      throw std::logic_error("agent " + std::to_string(a) + " starts the window on a cell kept clear for a robot that is out");
    }
    planned.push_back(static_cast<int>(a));
  }
  if (planned.size() == agents.size()) return plan_all(start, agents, steps, deadline);
  planner_core::Poses some;
  std::vector<WindowAgent> their_errands;
  for (const int a : planned) {
    some.cells.push_back(start.cells[a]);
    if (turning && a < static_cast<int>(start.headings.size())) some.headings.push_back(start.headings[a]);
    their_errands.push_back(agents[a]);
  }
  const PlanWindow part = plan_all(some, their_errands, steps, deadline);
  // Every agent, the held ones standing where they are.
  PlanWindow window;
  window.unreachable = part.unreachable;
  window.reached.resize(agents.size());
  for (size_t step = 0; step < part.steps.size(); ++step) {
    window.steps.push_back(start.cells);
    if (turning) window.headings.push_back(start.headings);
    for (size_t k = 0; k < planned.size(); ++k) {
      window.steps.back()[planned[k]] = part.steps[step][k];
      if (turning) window.headings.back()[planned[k]] = part.headings[step][k];
    }
  }
  for (size_t k = 0; k < planned.size(); ++k) window.reached[planned[k]] = part.reached[k];
  for (const int k : part.stalled) window.stalled.push_back(planned[k]);
  return window;
}

PlanWindow WindowPlanner::plan_all(const planner_core::Poses& start, const std::vector<WindowAgent>& agents, int steps,
                                   const planner_core::Deadline& deadline) {
  const Config& from = start.cells;
  const bool turning = actions_ == planner_core::ActionModel::kRotate;
  if (turning && start.headings.size() != from.size()) {
    throw std::invalid_argument("a window of robots that turn needs every agent's heading");
  }
  const int n = static_cast<int>(from.size());
  if (static_cast<int>(agents.size()) != n) throw std::invalid_argument("a window needs one WindowAgent per agent");
  if (static_cast<int>(heading_for_.size()) != n) {
    heading_for_.assign(n, planner_core::kNoVertex);
    nearest_.assign(n, 0);
    steps_without_gain_.assign(n, 0);
  }
  PlanWindow window;
  window.steps.push_back(from);
  if (turning) window.headings.push_back(start.headings);
  window.reached.resize(n);
  std::vector<std::vector<Vertex>> left(n);  // errands still to reach, reachable ones only
  Config park(n);
  for (int a = 0; a < n; ++a) {
    for (Vertex errand : agents[a].errands) {
      if (distances_.get(errand, from[a]) == planner_core::kUnreachable) {
        ++window.unreachable;
      } else {
        left[a].push_back(errand);
      }
    }
    park[a] = agents[a].park;
    if (park[a] == planner_core::kNoVertex || distances_.get(park[a], from[a]) == planner_core::kUnreachable) {
      window.unreachable += park[a] != planner_core::kNoVertex ? 1 : 0;
      park[a] = from[a];  // nowhere else to wait
    }
  }
  planner_core::Poses at{from, turning ? start.headings : planner_core::Headings{}};
  // Settles the errands an agent stands on; then aims it at the nearest one left, or its parking cell.
  const auto aim = [&](int a) {
    for (size_t k = 0; k < left[a].size();) {
      if (left[a][k] == at.cells[a]) {
        window.reached[a].push_back(at.cells[a]);
        left[a].erase(left[a].begin() + static_cast<std::ptrdiff_t>(k));
      } else {
        ++k;
      }
    }
    Vertex goal = park[a];
    int nearest = planner_core::kUnreachable;
    for (Vertex errand : left[a]) {
      const int d = distances_.get(errand, at.cells[a]);
      if (d < nearest) {
        nearest = d;
        goal = errand;
      }
    }
    return goal;
  };
  Config goals(n);
  // A window in which nobody moves or turns adds nothing to the plan, and a plan every robot has
  // carried out with a robot not yet parked would be replanned whole: so until someone moves, the
  // window goes on (PIBT boosts an agent stuck for a few steps, and kStalledSteps ends it).
  bool moved = false;
  for (int step = 0; step < steps || (!moved && step < kStalledSteps); ++step) {
    bool settled = true;
    for (int a = 0; a < n; ++a) {
      goals[a] = aim(a);
      settled = settled && left[a].empty() && at.cells[a] == park[a];
    }
    if (settled) break;
    planner_core::Poses next = pibt_.next_step(at, goals, deadline);
    planner_core::StepFault fault = planner_core::find_pose_fault(*graph_, actions_, at, next);
    if (fault.what.empty()) fault = planner_core::find_rotation(at.cells, next.cells);
    if (!fault.what.empty()) throw std::logic_error("the lifelong window's step " + std::to_string(step + 1) + " is invalid: " + fault.what);
    moved = moved || next.cells != at.cells || next.headings != at.headings;
    at = std::move(next);
    window.steps.push_back(at.cells);
    if (turning) window.headings.push_back(at.headings);
    note_gains(at.cells, goals);
    if (deadline.expired()) break;  // a shorter window, every step of it whole
  }
  for (int a = 0; a < n; ++a) {
    aim(a);  // errands reached on the last step
    if (steps_without_gain_[a] >= kStalledSteps) window.stalled.push_back(a);
  }
  return window;
}

void WindowPlanner::note_gains(const Config& at, const Config& goals) {
  for (size_t a = 0; a < at.size(); ++a) {
    const int distance = distances_.get(goals[a], at[a]);
    if (goals[a] != heading_for_[a] || distance < nearest_[a] || distance == 0) {
      heading_for_[a] = goals[a];
      nearest_[a] = distance;
      steps_without_gain_[a] = 0;
    } else {
      ++steps_without_gain_[a];
    }
  }
}

}  // namespace coordinator
