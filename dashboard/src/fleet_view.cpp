#include "dashboard/fleet_view.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>

#include "dashboard/message_json.hpp"

namespace dashboard {

using fleet_transport::CoordinatorRole;
using fleet_transport::RobotStatus;

namespace {

constexpr int64_t kCoordinatorSilentMs = 3000;  // an active coordinator unheard this long is not followed
constexpr size_t kEventsKept = 500;
constexpr size_t kEventsPerFrame = 50;

std::string hex(uint64_t value) { return fmt::format("{:016x}", value); }

Json cell_json(const fleet_transport::GridCell& cell) { return Json::array({cell.x, cell.y}); }

}  // namespace

FleetView::Coordinator& FleetView::coordinator(uint64_t id) {
  Coordinator& c = coordinators_[id];
  c.status.coordinator = id;
  return c;
}

const FleetView::Coordinator* FleetView::followed() const {
  const auto found = coordinators_.find(followed_);
  return found == coordinators_.end() ? nullptr : &found->second;
}

void FleetView::refollow() {
  // The highest-ranked active coordinator heard lately; else keep the one followed; else any with a mission.
  const Coordinator* best = nullptr;
  int64_t newest = 0;
  for (const auto& [id, c] : coordinators_) newest = std::max(newest, c.heard_ms);
  for (const auto& [id, c] : coordinators_) {
    if (c.status.role != CoordinatorRole::kActive || c.heard_ms < newest - kCoordinatorSilentMs) continue;
    if (best == nullptr || fleet_transport::outranks(c.status, best->status)) best = &c;
  }
  uint64_t chosen = best != nullptr ? best->status.coordinator : followed_;
  if (chosen == 0 || !coordinators_.count(chosen)) {
    for (const auto& [id, c] : coordinators_) {
      if (c.mission) chosen = id;
    }
  }
  if (chosen != followed_) {
    followed_ = chosen;
    ++mission_version_;
    ++plan_version_;
  }
}

void FleetView::on_announcement(const fleet_transport::Announcement& announcement, int64_t heard_ms) {
  Robot& robot = robots_[announcement.robot_id];
  robot.backend = announcement.backend;
  robot.heard_ms = std::max(robot.heard_ms, heard_ms);
  robot.gone.reset();
  if (announcement.leaving) robot.gone = fleet_transport::GoneReason::kGoodbye;
}

void FleetView::on_robot_gone(const std::string& robot_id, fleet_transport::GoneReason reason, int64_t) {
  robots_[robot_id].gone = reason;
}

void FleetView::on_state(const fleet_transport::RobotState& state, int64_t heard_ms) {
  Robot& robot = robots_[state.robot_id];
  // Within one process, sequence numbers only grow; a new process (restart) starts afresh.
  if (robot.state && robot.state->incarnation == state.incarnation && state.seq_number <= robot.state->seq_number) return;
  // A move lasts from the first state heard moving to the first heard arrived, of the same command.
  const bool same_command = robot.state && robot.state->incarnation == state.incarnation &&
                            robot.state->plan_epoch == state.plan_epoch &&
                            robot.state->action_index == state.action_index;
  if (state.status == RobotStatus::kMoving) {
    if (!same_command || robot.moving_since_ms < 0) robot.moving_since_ms = heard_ms;
  } else {
    if (same_command && robot.moving_since_ms >= 0 && state.status == RobotStatus::kArrived) {
      move_ms_.push_back(heard_ms - robot.moving_since_ms);
      if (move_ms_.size() > kMovesKept) move_ms_.pop_front();
      typical_move_ms_.reset();
    }
    robot.moving_since_ms = -1;
  }
  robot.state = state;
  robot.heard_ms = heard_ms;
  if (robot.gone == fleet_transport::GoneReason::kLivelinessLost) robot.gone.reset();  // it is back
}

void FleetView::on_coordinator_status(const fleet_transport::CoordinatorStatus& status, int64_t heard_ms) {
  Coordinator& c = coordinator(status.coordinator);
  c.status = status;
  c.heard_ms = heard_ms;
  refollow();
}

void FleetView::on_fleet_status(const fleet_transport::FleetStatus& status, int64_t heard_ms) {
  Coordinator& c = coordinator(status.coordinator);
  c.progress = status;
  c.heard_ms = std::max(c.heard_ms, heard_ms);
  c.role_index.clear();
  for (const fleet_transport::Assignment& row : status.assignments) c.role_index.emplace(row.robot_id, row.role);
  c.visits_done.clear();
  for (const fleet_transport::TaskVisit& visit : status.done_visits) c.visits_done.emplace(visit.task, visit.role);
}

void FleetView::on_mission(const fleet_transport::MissionInfo& mission, int64_t heard_ms) {
  Coordinator& c = coordinator(mission.coordinator);
  c.mission = mission;
  c.heard_ms = std::max(c.heard_ms, heard_ms);
  c.tasks_of_role.clear();
  for (int t = 0; t < static_cast<int>(mission.tasks.size()); ++t) {
    for (int role : mission.tasks[t].roles) c.tasks_of_role[role].push_back(t);
  }
  if (mission.coordinator == followed_) ++mission_version_;
  refollow();
}

void FleetView::on_plan(const fleet_transport::FleetPlan& plan, int64_t heard_ms) {
  Coordinator& c = coordinator(plan.coordinator);
  c.plan = plan;
  c.heard_ms = std::max(c.heard_ms, heard_ms);
  c.plan_index.clear();
  for (size_t k = 0; k < plan.robots.size(); ++k) c.plan_index.emplace(plan.robots[k].robot_id, k);
  if (plan.coordinator == followed_) ++plan_version_;
  refollow();
}

void FleetView::on_event(const fleet_transport::FleetEvent& event, int64_t heard_ms) {
  if (!event.robot_id.empty()) {
    if (event.kind == "off_plan") robots_[event.robot_id].off_plan = true;
    if (event.kind == "join") robots_[event.robot_id].off_plan = false;
  }
  events_.push_back({{"stamp_ms", event.stamp_ms},
                     {"heard_ms", heard_ms},
                     {"kind", event.kind},
                     {"robot", event.robot_id},
                     {"text", event.text},
                     {"value", event.value},
                     {"coordinator", hex(event.coordinator)}});
  ++events_total_;
  if (events_.size() > kEventsKept) events_.pop_front();
}

const fleet_transport::RobotPlan* FleetView::plan_of(const std::string& robot_id) const {
  const Coordinator* c = followed();
  if (c == nullptr || !c->plan) return nullptr;
  const auto found = c->plan_index.find(robot_id);
  return found == c->plan_index.end() ? nullptr : &c->plan->robots[found->second];
}

int FleetView::role_of(const std::string& robot_id) const {
  const Coordinator* c = followed();
  if (c != nullptr && c->progress) {
    const auto found = c->role_index.find(robot_id);
    if (found != c->role_index.end()) return found->second;
  }
  const fleet_transport::RobotPlan* plan = plan_of(robot_id);
  return plan != nullptr ? plan->role : -1;
}

bool FleetView::visited(int task, int role) const {
  const Coordinator* c = followed();
  return c != nullptr && c->progress && c->visits_done.count({task, role}) > 0;
}

int FleetView::path_from(const std::string& robot_id) const {
  const fleet_transport::RobotPlan* plan = plan_of(robot_id);
  if (plan == nullptr) return -1;
  const auto found = robots_.find(robot_id);
  const Coordinator* c = followed();
  if (found == robots_.end() || !found->second.state) return 1;
  const fleet_transport::RobotState& state = *found->second.state;
  // A robot still on an older epoch has not started this plan: it is at the path's start.
  if (state.coordinator != c->plan->coordinator || state.plan_epoch != c->plan->plan_epoch) return 1;
  // Action k's target is path[k + 1]: moving, that is where it goes; else it stands there.
  const int k = state.action_index;
  const int next = state.status == RobotStatus::kMoving ? k + 1 : k + 2;
  return std::min(next, static_cast<int>(plan->path.size()));
}

std::string FleetView::robot_status(const std::string& robot_id, int64_t now_ms) const {
  const auto found = robots_.find(robot_id);
  if (found == robots_.end()) return "unknown";
  const Robot& robot = found->second;
  if (robot.gone == fleet_transport::GoneReason::kGoodbye) return "left";
  if (robot.gone || now_ms - robot.heard_ms > lost_after_ms_) return "lost";
  if (!robot.state) return "joining";
  if (robot.state->status == RobotStatus::kFault) return "fault";
  if (robot.off_plan) return "off_plan";
  if (robot.state->status == RobotStatus::kMoving) {
    const int64_t typical = typical_move_ms();
    const bool late = typical > 0 && robot.moving_since_ms >= 0 &&
                      static_cast<double>(now_ms - robot.moving_since_ms) > kLateFactor * static_cast<double>(typical);
    return late ? "delayed" : "moving";
  }
  const fleet_transport::RobotPlan* plan = plan_of(robot_id);
  if (plan != nullptr && path_from(robot_id) < static_cast<int>(plan->path.size())) return "waiting";
  return "parked";
}

int64_t FleetView::typical_move_ms() const {
  if (move_ms_.size() < kMovesForTypical) return -1;
  if (!typical_move_ms_) {  // asked for by every moving robot of every frame: once per new move
    std::vector<int64_t> sorted(move_ms_.begin(), move_ms_.end());
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    typical_move_ms_ = sorted[sorted.size() / 2];
  }
  return *typical_move_ms_;
}

std::vector<int> FleetView::next_tasks(const std::string& robot_id) const {
  std::vector<int> order;
  for (const Due& due : schedule(robot_id)) order.push_back(due.task);
  return order;
}

std::vector<FleetView::Due> FleetView::schedule(const std::string& robot_id) const {
  const Coordinator* c = followed();
  const int role = role_of(robot_id);
  if (c == nullptr || !c->mission || role < 0) return {};
  std::vector<fleet_transport::GridCell> ahead;
  if (const fleet_transport::RobotPlan* plan = plan_of(robot_id)) {
    const int from = std::max(0, path_from(robot_id) - 1);  // the cell it stands on or leaves counts too
    ahead.assign(plan->path.begin() + std::min<size_t>(from, plan->path.size()), plan->path.end());
  }
  std::vector<std::pair<size_t, int>> due;  // (place on the path, task)
  const auto& tasks = c->mission->tasks;
  const auto mine = c->tasks_of_role.find(role);
  if (mine == c->tasks_of_role.end()) return {};
  for (const int t : mine->second) {
    if (tasks[t].cancelled || visited(t, role)) continue;
    const fleet_transport::GridCell cell{tasks[t].x, tasks[t].y};
    due.emplace_back(std::find(ahead.begin(), ahead.end(), cell) - ahead.begin(), t);
  }
  std::stable_sort(due.begin(), due.end());
  std::vector<Due> order;
  for (const auto& [place, task] : due) {
    order.push_back({task, place < ahead.size() ? static_cast<int>(place) : kNotPlanned});
  }
  return order;
}

Json FleetView::mission_json() const {
  const Coordinator* c = followed();
  if (c == nullptr || !c->mission) return nullptr;
  const fleet_transport::MissionInfo& m = *c->mission;
  Json rows = Json::array();
  for (size_t start = 0; start <= m.map_rows.size();) {
    const size_t end = std::min(m.map_rows.find('\n', start), m.map_rows.size());
    rows.push_back(m.map_rows.substr(start, end - start));
    start = end + 1;
  }
  Json goals = Json::array();
  for (const auto& goal : m.goals) goals.push_back(cell_json(goal));
  Json tasks = Json::array();
  for (size_t t = 0; t < m.tasks.size(); ++t) {
    tasks.push_back({{"id", t}, {"x", m.tasks[t].x}, {"y", m.tasks[t].y}, {"roles", m.tasks[t].roles},
                     {"cancelled", m.tasks[t].cancelled}});
  }
  return {{"version", mission_version_}, {"mission_id", m.mission_id}, {"width", m.width}, {"height", m.height},
          {"rows", rows}, {"goals", goals}, {"tasks", tasks}, {"lifelong", m.lifelong}};
}

Json FleetView::plan_json() const {
  const Coordinator* c = followed();
  if (c == nullptr || !c->plan) return nullptr;
  Json robots = Json::object();
  for (const fleet_transport::RobotPlan& robot : c->plan->robots) {
    Json path = Json::array();
    for (const auto& cell : robot.path) path.push_back(cell_json(cell));
    robots[robot.robot_id] = {{"role", robot.role}, {"path", path}};
  }
  return {{"version", plan_version_}, {"epoch", c->plan->plan_epoch}, {"planning_ms", c->plan->planning_ms},
          {"flowtime", c->plan->flowtime}, {"made_ms", c->plan->made_ms}, {"robots", robots}};
}

Json FleetView::frame_json(int64_t now_ms) const {
  const Coordinator* c = followed();
  Json frame = {{"now_ms", now_ms}, {"mission_version", mission_version_}, {"plan_version", plan_version_}};
  frame["coordinator"] = nullptr;
  if (c != nullptr) {
    frame["coordinator"] = {{"id", hex(c->status.coordinator)}, {"term", c->status.term},
                            {"role", c->status.role}, {"epoch", c->status.plan_epoch},
                            {"heard_ago_ms", now_ms - c->heard_ms}};
  }
  Json robots = Json::array();
  std::set<int> planned_tasks;  // pending tasks some robot's plan reaches
  Json delayed = Json::array();
  for (const auto& [id, robot] : robots_) {
    const std::vector<Due> due = schedule(id);
    std::vector<int> next;
    int planned = 0;
    for (const Due& d : due) {
      next.push_back(d.task);
      if (d.steps != kNotPlanned) {
        ++planned;
        planned_tasks.insert(d.task);
      }
    }
    const std::string status = robot_status(id, now_ms);
    if (status == "delayed") delayed.push_back(id);
    Json r = {{"id", id}, {"status", status}, {"role", role_of(id)}, {"backend", robot.backend},
              {"heard_ms", robot.heard_ms}, {"path_from", path_from(id)}, {"next_tasks", next},
              {"planned_tasks", planned}, {"task_steps", due.empty() ? kNotPlanned : due.front().steps}};
    if (robot.moving_since_ms >= 0) r["moving_ms"] = now_ms - robot.moving_since_ms;
    if (robot.state) {
      const fleet_transport::RobotState& s = *robot.state;
      r.update({{"x", s.cell_x}, {"y", s.cell_y}, {"pose_x", s.pose_x}, {"pose_y", s.pose_y}, {"theta", s.pose_theta},
                {"battery", s.battery_percent}, {"seq", s.seq_number}, {"epoch", s.plan_epoch},
                {"action", s.action_index}});
    }
    robots.push_back(std::move(r));
  }
  frame["robots"] = std::move(robots);
  Json task_states = Json::array();
  int in_plans = 0, in_pool = 0, unassigned_tasks = 0;
  if (c != nullptr && c->mission) {
    std::map<int, bool> bound;  // roles with a robot
    if (c->progress) {
      for (const auto& row : c->progress->assignments) bound[row.role] = true;
    }
    for (int t = 0; t < static_cast<int>(c->mission->tasks.size()); ++t) {
      const fleet_transport::MissionTask& task = c->mission->tasks[t];
      bool done = true, unassigned = false;
      for (int role : task.roles) {
        if (!visited(t, role)) {
          done = false;
          if (!bound.count(role)) unassigned = true;
        }
      }
      // Lifelong, a pending task no plan reaches yet waits in the pool (the coordinator may still
      // give it to another robot); a one-shot mission's next plan takes every task.
      const bool pooled = c->mission->lifelong && !planned_tasks.count(t);
      const char* state = task.cancelled ? "cancelled"
                          : done         ? "done"
                          : unassigned   ? "unassigned"
                          : pooled       ? "pool"
                                         : "pending";
      task_states.push_back(state);
      if (!task.cancelled && !done) {
        if (unassigned) ++unassigned_tasks;
        else if (pooled) ++in_pool;
        else ++in_plans;
      }
    }
  }
  frame["tasks"] = std::move(task_states);
  const int64_t typical = typical_move_ms();
  frame["schedule"] = {{"in_plans", in_plans}, {"pool", in_pool}, {"unassigned", unassigned_tasks},
                       {"delayed", std::move(delayed)}, {"typical_move_ms", typical > 0 ? Json(typical) : Json()},
                       {"late_after_ms", typical > 0 ? Json(kLateFactor * static_cast<double>(typical)) : Json()}};
  frame["progress"] = nullptr;
  frame["figures"] = nullptr;
  if (c != nullptr && c->progress) {
    const fleet_transport::FleetStatus& p = *c->progress;
    frame["progress"] = {{"tasks_done", p.tasks_done}, {"tasks_total", p.tasks_total}, {"robots", p.robots},
                         {"epoch", p.plan_epoch}};
    frame["figures"] = {{"round_trip_p50_ms", p.round_trip_p50_ms}, {"round_trip_p99_ms", p.round_trip_p99_ms},
                        {"last_planning_ms", p.last_planning_ms}, {"last_replan_latency_ms", p.last_replan_latency_ms},
                        {"steps_done", p.steps_done}, {"steps_planned", p.steps_planned}};
  }
  Json events = Json::array();
  for (size_t i = events_.size() > kEventsPerFrame ? events_.size() - kEventsPerFrame : 0; i < events_.size(); ++i) {
    events.push_back(events_[i]);
  }
  frame["events"] = std::move(events);
  frame["events_total"] = events_total_;
  return frame;
}

}  // namespace dashboard
