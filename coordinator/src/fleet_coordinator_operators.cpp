// FleetCoordinator's side facing operators: tasks added, cancelled and listed at runtime, and what
// it publishes for dashboards (the mission, the plan, events). See fleet_coordinator.hpp.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <sstream>

#include "coordinator/fleet_coordinator.hpp"
#include "planner_core/dist_table.hpp"

namespace coordinator {

using fleet_transport::TaskAction;
using fleet_transport::TaskReply;
using fleet_transport::TaskRequest;
using planner_core::Vertex;

namespace {

constexpr int kMaxPendingAddedTasks = 1000;  // tasks added at runtime and not done yet: more is refused

std::string cell_text(int x, int y) { return fmt::format("({},{})", x, y); }

TaskReply refusal(const TaskRequest& request, const std::string& reason) {
  TaskReply reply;
  reply.request_id = request.request_id;
  reply.reason = reason;
  reply.task = request.action == TaskAction::kCancel ? request.task : -1;
  return reply;
}

TaskReply acceptance(const TaskRequest& request, int task, const std::string& reason, const std::string& robot_id = "") {
  TaskReply reply;
  reply.request_id = request.request_id;
  reply.accepted = true;
  reply.task = task;
  reply.robot_id = robot_id;
  reply.reason = reason;
  return reply;
}

}  // namespace

void FleetCoordinator::handle_task_request(const TaskRequest& request, fleet_transport::Transport& transport) {
  if (identity_.role != fleet_transport::CoordinatorRole::kActive) return;  // the active coordinator answers
  if (request.request_id.empty()) {
    spdlog::warn("task request without a request id ignored (it could not be answered)");
    return;
  }
  if (const TaskReply* known = desk_.answer_to(request.request_id)) {
    desk_.publish("task replies", [&] { transport.reply_task(*known); });  // unheard: say it again
    return;
  }
  const TaskReply reply = answer(request);
  if (request.action != TaskAction::kList) {
    if (reply.accepted) {
      spdlog::info("task request {} ({}): {}", request.request_id, to_string(request.action), reply.reason);
    } else {
      spdlog::warn("task request {} ({}) refused: {}", request.request_id, to_string(request.action), reply.reason);
      report("task_refused", request.robot_id, reply.reason);
    }
  }
  desk_.remember(reply);
  desk_.publish("task replies", [&] { transport.reply_task(reply); });
}

TaskReply FleetCoordinator::answer(const TaskRequest& request) {
  TaskReply reply;
  const int action = static_cast<int>(request.action);
  if (action < static_cast<int>(TaskAction::kAdd) || action > static_cast<int>(TaskAction::kList)) {
    reply = refusal(request, "unknown action " + std::to_string(action) + " (add, cancel or list)");
  } else switch (request.action) {
    case TaskAction::kAdd: reply = add_task(request); break;
    case TaskAction::kCancel: reply = cancel_task(request); break;
    case TaskAction::kList:
      reply = acceptance(request, -1, std::to_string(progress_.task_count()) + " tasks");
      reply.listing = task_listing();
      break;
  }
  reply.coordinator = identity_.incarnation;
  return reply;
}

std::vector<Tour> FleetCoordinator::current_tours() const {
  std::vector<Tour> tours;
  for (const auto& [id, robot] : robots_) {
    if (!robot.active || !robot.has_state || robot.role < 0) continue;
    const Vertex here = mission_vertex(robot.last.cell_x, robot.last.cell_y);
    if (here == planner_core::kNoVertex) continue;
    // The cells its plan still takes it through, in order.
    std::vector<Vertex> ahead;
    const int a = robot.plan_agent;
    if (plan_ && a >= 0 && a < plan_->agent_count()) {
      for (int m = plan_->agent(a).finished; m < plan_->move_count(a); ++m) {
        const planner_core::Cell cell = plan_->target(a, m);
        ahead.push_back(mission_vertex(cell.x, cell.y));
      }
    }
    std::vector<std::pair<size_t, Vertex>> due;  // (where on the plan, task cell)
    for (int t : mission_.tasks_of_agent[robot.role]) {
      const std::vector<int>& roles = mission_.tasks[t].agents;
      for (size_t k = 0; k < roles.size(); ++k) {
        if (roles[k] != robot.role || progress_.visited(t, k)) continue;
        const Vertex at = mission_.tasks[t].at;
        due.emplace_back(std::find(ahead.begin(), ahead.end(), at) - ahead.begin(), at);
      }
    }
    std::stable_sort(due.begin(), due.end());
    Tour tour{id, robot.role, {here}};
    for (const auto& [order, cell] : due) tour.stops.push_back(cell);
    tour.stops.push_back(mission_.goals[robot.role]);
    tours.push_back(std::move(tour));
  }
  return tours;
}

std::string FleetCoordinator::add_task_refusal(const TaskRequest& request, std::vector<Tour>& tours) const {
  if (!driving()) {
    return phase_ == Phase::kWaiting
               ? "the mission has not started: robots are not bound to roles yet; add tasks once it runs"
               : "the mission has ended";
  }
  if (const std::string wrong = task_cell_refusal(mission_, request.x, request.y); !wrong.empty()) return wrong;
  int pending_added = 0;
  for (int t = progress_.mission_task_count(); t < progress_.task_count(); ++t) {
    pending_added += !progress_.task_done(t) && !progress_.cancelled(t) ? 1 : 0;
  }
  if (pending_added >= kMaxPendingAddedTasks) {
    return "already " + std::to_string(pending_added) + " tasks added at runtime wait to be done (at most " +
           std::to_string(kMaxPendingAddedTasks) + "): add more once some are done";
  }
  if (!request.robot_id.empty()) {
    const RobotRecord* robot = robots_.find(request.robot_id);
    if (robot == nullptr || !robot->announced) return "unknown robot '" + request.robot_id + "'";
    if (!robot->active) return "robot " + request.robot_id + " is out (lost, in fault or off its plan)";
    if (robot->role < 0) {
      return "robot " + request.robot_id + " has no role (an extra robot, parked): give the task to a robot with a "
             "role, or to any";
    }
    std::erase_if(tours, [&](const Tour& tour) { return tour.robot_id != request.robot_id; });
    if (tours.empty()) return "robot " + request.robot_id + " has not reported a cell yet";
  }
  if (tours.empty()) return "no robot with a role is active to take it";
  // The same cell pending for the same robot (or, for any robot, for anyone) is a duplicate. Not
  // in a lifelong fleet: there a task is an order of its own, and a station gets many at once.
  if (config_.lifelong) return "";
  const Vertex cell = mission_vertex(request.x, request.y);
  for (int t = 0; t < mission_.task_count(); ++t) {
    if (mission_.tasks[t].at != cell || progress_.cancelled(t) || progress_.task_done(t)) continue;
    for (int role : mission_.tasks[t].agents) {
      if (request.robot_id.empty() || progress_.robot_of(role) == request.robot_id) {
        return "duplicate: task " + std::to_string(t) + " at " + cell_text(request.x, request.y) +
               " is already pending" +
               (progress_.robot_of(role).empty() ? "" : " for robot " + progress_.robot_of(role));
      }
    }
  }
  return "";
}

planner_core::DistTable& FleetCoordinator::task_distances() {
  // Kept between requests and windows: a fresh table per request searched again from every task
  // cell in every robot's queue (at 200 robots on a 500 x 140 map, most of the coordinator's CPU).
  // Started afresh once it holds much memory (a lifelong stream reaches every cell in time).
  constexpr size_t kMostTaskSearchBytes = size_t{256} << 20;
  if (!task_distances_ || task_distances_->memory_bytes() > kMostTaskSearchBytes) {
    task_distances_ = std::make_unique<planner_core::DistTable>(*mission_.graph);
  }
  return *task_distances_;
}

TaskReply FleetCoordinator::add_task(const TaskRequest& request) {
  std::vector<Tour> tours = current_tours();
  if (const std::string why = add_task_refusal(request, tours); !why.empty()) return refusal(request, why);
  const Vertex cell = mission_vertex(request.x, request.y);
  planner_core::DistTable& distances = task_distances();
  // Lifelong: the robot that gets there soonest, so that loads stay even; else the one whose tour
  // grows least (the mission's flowtime).
  const TaskPlacement placement =
      config_.lifelong ? earliest_arrival(distances, cell, tours) : cheapest_insertion(distances, cell, tours);
  if (placement.tour < 0) {
    return refusal(request, cell_text(request.x, request.y) + " cannot be reached from " +
                                (request.robot_id.empty() ? "any robot's cell" : "robot " + request.robot_id + "'s cell"));
  }
  const Tour& chosen = tours[placement.tour];
  const int task = mission_.task_count();
  const bool journaled = journal_write("task added", [&](MissionJournal& journal) {
    journal.record_task_added(task, request.x, request.y, chosen.role, request.request_id);
  });
  if (!request.robot_id.empty()) {  // the operator named the robot: the pool leaves the task with it
    pinned_tasks_.insert(task);
    journal_write("task pinned", [&](MissionJournal& journal) { journal.record_task_pinned(task); });
  }
  mission_.tasks.push_back({cell, {chosen.role}});
  mission_.index_tasks();
  progress_.add_task();
  if (options_.journal && journaled) journaled_tasks_ = mission_.task_count();
  summary_.tasks_total = progress_.tasks_to_do();
  desk_.mission_changed();
  schedule_.progress_changed();
  plan_end_.lifelong_idle = false;
  plan_end_.replanned = false;
  const TaskReply reply = acceptance(
      request, task,
      "task " + std::to_string(task) + " at " + cell_text(request.x, request.y) + " given to robot " + chosen.robot_id +
          " (role " + std::to_string(chosen.role) + "); " +
          (config_.lifelong ? "it gets there in about " : "its tour grows by ") + std::to_string(placement.added_steps) +
          " steps",
      chosen.robot_id);
  report("task_added", chosen.robot_id, reply.reason, task);
  if (grows_by_windows(chosen.robot_id)) {
    spdlog::info("lifelong: the plan takes task {} up as it grows", task);
  } else {
    request_replan("task " + std::to_string(task) + " added for robot " + chosen.robot_id);
  }
  return reply;
}

TaskReply FleetCoordinator::cancel_task(const TaskRequest& request) {
  const int task = request.task;
  if (task < 0 || task >= progress_.task_count()) {
    return refusal(request, "no task " + std::to_string(task) + " (the mission has tasks 0 to " +
                                std::to_string(progress_.task_count() - 1) + ")");
  }
  if (progress_.cancelled(task)) return refusal(request, "task " + std::to_string(task) + " is cancelled already");
  if (progress_.task_done(task)) return refusal(request, "task " + std::to_string(task) + " is done already");
  journal_write("task cancelled", [&](MissionJournal& journal) { journal.record_task_cancelled(task, request.request_id); });
  progress_.cancel(task);
  summary_.tasks_total = progress_.tasks_to_do();
  desk_.mission_changed();
  schedule_.progress_changed();
  const TaskReply reply = acceptance(request, task, "task " + std::to_string(task) + " cancelled");
  report("task_cancelled", "", reply.reason, task);
  request_replan(reply.reason);
  return reply;
}

void FleetCoordinator::adopt_tasks(const fleet_transport::MissionInfo& info) {
  if (info.mission_id != identity_.mission_id) return;
  for (size_t t = mission_.tasks.size(); t < info.tasks.size(); ++t) {
    const fleet_transport::MissionTask& task = info.tasks[t];
    const Vertex cell = mission_vertex(task.x, task.y);
    const bool roles_ok = !task.roles.empty() && std::all_of(task.roles.begin(), task.roles.end(), [&](int role) {
      return role >= 0 && role < mission_.agent_count();
    });
    if (cell == planner_core::kNoVertex || !roles_ok) {
      spdlog::error("standby: task {} of the active coordinator's mission is not on this map or names no role of "
                    "it: not mirrored", t);
      return;
    }
    mission_.tasks.push_back({cell, task.roles});
    mission_.index_tasks();
    progress_.add_task();
    spdlog::info("standby: mirrors task {} at {} added at runtime", t, cell_text(task.x, task.y));
  }
  bool roles_changed = false;  // lifelong mode's pool moves tasks added at runtime between roles
  for (size_t t = 0; t < info.tasks.size() && t < mission_.tasks.size(); ++t) {
    if (info.tasks[t].cancelled) progress_.cancel(static_cast<int>(t));
    const std::vector<int>& roles = info.tasks[t].roles;
    const bool moved = static_cast<int>(t) >= progress_.mission_task_count() && roles.size() == 1 &&
                       mission_.tasks[t].agents.size() == 1 && roles.front() != mission_.tasks[t].agents.front() &&
                       roles.front() >= 0 && roles.front() < mission_.agent_count() &&
                       !progress_.visited(static_cast<int>(t), 0);
    if (moved) {
      mission_.tasks[t].agents = roles;
      roles_changed = true;
    }
  }
  if (roles_changed) mission_.index_tasks();
  summary_.tasks_total = progress_.tasks_to_do();
}

void FleetCoordinator::journal_added_tasks() {
  // Tasks it journaled before may have moved to other roles since (lifelong mode's pool).
  for (int t = progress_.mission_task_count(); t < journaled_tasks_ && t < mission_.task_count(); ++t) {
    if (progress_.task_done(t) || progress_.cancelled(t) || mission_.tasks[t].agents.size() != 1) continue;
    journal_write("task role", [&](MissionJournal& journal) { journal.record_task_role(t, mission_.tasks[t].agents.front()); });
  }
  for (int t = journaled_tasks_; t < mission_.task_count(); ++t) {
    const planner_core::Cell at = mission_.graph->cell_of(mission_.tasks[t].at);
    journal_write("task added", [&](MissionJournal& journal) {
      journal.record_task_added(t, at.x, at.y, mission_.tasks[t].agents.front(), "mirrored");
    });
  }
  journaled_tasks_ = mission_.task_count();
  for (int t = 0; t < progress_.task_count(); ++t) {
    if (progress_.cancelled(t)) {
      journal_write("task cancelled", [&](MissionJournal& journal) { journal.record_task_cancelled(t, "mirrored"); });
    }
  }
}

std::string FleetCoordinator::task_listing() const {
  std::ostringstream out;
  for (int t = 0; t < mission_.task_count(); ++t) {
    const planner_core::Cell at = mission_.graph->cell_of(mission_.tasks[t].at);
    out << "task " << t << " at " << cell_text(at.x, at.y) << ": "
        << (progress_.cancelled(t) ? "cancelled" : progress_.task_done(t) ? "done" : "pending");
    const std::vector<int>& roles = mission_.tasks[t].agents;
    for (size_t k = 0; k < roles.size(); ++k) {
      const std::string& robot = progress_.robot_of(roles[k]);
      out << (k == 0 ? "; " : ", ") << "role " << roles[k] << " (" << (robot.empty() ? "no robot" : "robot " + robot)
          << (progress_.visited(t, k) && !progress_.cancelled(t) ? ", visited" : "") << ")";
    }
    out << "\n";
  }
  return out.str();
}

void FleetCoordinator::publish_mission(fleet_transport::Transport& transport) {
  const planner_core::Graph& map = *mission_.graph;
  fleet_transport::MissionInfo info;
  info.coordinator = identity_.incarnation;
  info.mission_id = identity_.mission_id;
  info.width = map.width();
  info.height = map.height();
  for (int y = 0; y < map.height(); ++y) {
    if (y > 0) info.map_rows += '\n';
    for (int x = 0; x < map.width(); ++x) info.map_rows += map.is_free({x, y}) ? '.' : '@';
  }
  for (Vertex goal : mission_.goals) {
    const planner_core::Cell cell = map.cell_of(goal);
    info.goals.push_back({cell.x, cell.y});
  }
  for (int t = 0; t < mission_.task_count(); ++t) {
    const planner_core::Cell cell = map.cell_of(mission_.tasks[t].at);
    info.tasks.push_back({cell.x, cell.y, mission_.tasks[t].agents, progress_.cancelled(t)});
  }
  info.lifelong = config_.lifelong;
  desk_.publish("mission", [&] { transport.publish_mission_info(info); });
  desk_.mission_published();
}

void FleetCoordinator::publish_plan(fleet_transport::Transport& transport, int64_t flowtime, double planning_ms) {
  fleet_transport::FleetPlan plan;
  plan.coordinator = identity_.incarnation;
  plan.plan_epoch = epoch_;
  plan.made_ms = fleet_transport::wall_clock_ms();
  plan.planning_ms = planning_ms;
  plan.flowtime = flowtime;
  for (int a = 0; a < plan_->agent_count(); ++a) {
    fleet_transport::RobotPlan robot;
    robot.robot_id = plan_->agent(a).robot_id;
    const RobotRecord* record = robots_.find(robot.robot_id);
    robot.role = record != nullptr ? record->role : -1;
    const planner_core::Cell start = plan_->position(a);
    robot.path.push_back({start.x, start.y});
    for (int m = plan_->agent(a).finished; m < plan_->move_count(a); ++m) {  // from where it stands
      const planner_core::Cell cell = plan_->target(a, m);
      robot.path.push_back({cell.x, cell.y});
    }
    plan.robots.push_back(std::move(robot));
  }
  desk_.publish("plan", [&] { transport.publish_fleet_plan(plan); });
}

}  // namespace coordinator
