#include "coordinator/fleet_coordinator.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "coordinator/role_assignment.hpp"
#include "planner_core/dist_table.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/solver.hpp"
#include "planner_core/validator.hpp"

namespace coordinator {

using fleet_transport::RobotStatus;
using planner_core::Cell;
using planner_core::Vertex;

namespace {

double seconds_between(FleetCoordinator::Clock::time_point a, FleetCoordinator::Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

FleetCoordinator::Clock::duration seconds(double s) {
  return std::chrono::duration_cast<FleetCoordinator::Clock::duration>(std::chrono::duration<double>(s));
}

}  // namespace

FleetCoordinator::FleetCoordinator(const FleetConfig& config, planner_core::Instance mission)
    : config_(config), mission_(std::move(mission)), started_(Clock::now()) {
  robot_of_role_.assign(mission_.agent_count(), "");
  for (const planner_core::Task& task : mission_.tasks) task_done_.emplace_back(task.agents.size(), 0);
  summary_.tasks_total = mission_.task_count();
}

void FleetCoordinator::on_announcement(const fleet_transport::Announcement& announcement) {
  const std::lock_guard<std::mutex> lock(events_mutex_);
  Event event;
  event.kind = Event::Kind::kAnnouncement;
  event.announcement = announcement;
  event.robot_id = announcement.robot_id;
  events_.push_back(std::move(event));
}

void FleetCoordinator::on_state(const fleet_transport::RobotState& state) {
  const std::lock_guard<std::mutex> lock(events_mutex_);
  Event event;
  event.kind = Event::Kind::kState;
  event.state = state;
  event.robot_id = state.robot_id;
  event.received = Clock::now();
  events_.push_back(std::move(event));
}

void FleetCoordinator::on_robot_gone(const std::string& robot_id, fleet_transport::GoneReason reason) {
  const std::lock_guard<std::mutex> lock(events_mutex_);
  Event event;
  event.kind = Event::Kind::kGone;
  event.robot_id = robot_id;
  event.reason = reason;
  events_.push_back(std::move(event));
}

Vertex FleetCoordinator::mission_vertex(int x, int y) const { return mission_.graph->vertex_at({x, y}); }

void FleetCoordinator::request_replan(const std::string& why) {
  if (phase_ == Phase::kWaiting || phase_ == Phase::kDone) return;
  spdlog::info("replanning: {}", why);
  if (!replan_requested_) {
    replan_requested_at_ = Clock::now();
    awaiting_replan_latency_ = true;
  }
  replan_requested_ = true;
}

void FleetCoordinator::lose(Robot& robot, const std::string& why) {
  if (!robot.active) return;
  robot.active = false;
  replanned_after_finish_ = false;
  ++summary_.robots_lost;
  spdlog::warn("robot {} taken out: {}", robot.id, why);
  if (robot.has_state) {
    const Vertex last = mission_vertex(robot.last.cell_x, robot.last.cell_y);
    if (last != planner_core::kNoVertex) blocked_[last] = robot.id;  // it may still stand there
  }
  // A robot that fell silent mid-move may have arrived at its target: keep that cell clear too.
  const int a = robot.plan_agent;
  if (a >= 0 && adg_ && a < static_cast<int>(sent_.size()) && sent_[a] == finished_[a] &&
      finished_[a] < static_cast<int>(adg_->moves(a).size())) {
    const Cell target = plan_graph_->cell_of(adg_->moves(a)[finished_[a]].to);
    blocked_[mission_vertex(target.x, target.y)] = robot.id;
  }
  if (robot.role >= 0) {
    robot_of_role_[robot.role] = "";
    robot.role = -1;
  }
  if (robot.plan_agent >= 0) request_replan("robot " + robot.id + " lost");
}

void FleetCoordinator::handle(const Event& event) {
  auto [it, fresh] = robots_.try_emplace(event.robot_id);
  Robot& robot = it->second;
  robot.id = event.robot_id;
  switch (event.kind) {
    case Event::Kind::kAnnouncement:
      if (event.announcement.leaving) {
        lose(robot, "said goodbye");
        return;
      }
      if (robot.announced && robot.active) {
        if (robot.backend != event.announcement.backend) {
          spdlog::warn("robot id {} announced by a second {} robot while a {} robot is active: duplicate id, the "
                       "second is ignored",
                       robot.id, event.announcement.backend, robot.backend);
        }
        return;  // robots repeat their announcement every second
      }
      if (!config_.any_robots && std::find(config_.expected_robots.begin(), config_.expected_robots.end(),
                                           robot.id) == config_.expected_robots.end()) {
        if (!robot.refused) spdlog::warn("robot {} refused: not in robots.expected of {}", robot.id, config_.source);
        robot.refused = true;
        return;
      }
      robot.announced = true;
      robot.refused = false;
      robot.backend = event.announcement.backend;
      spdlog::info("robot {} announced ({} backend, version {})", robot.id, event.announcement.backend,
                   event.announcement.version);
      return;
    case Event::Kind::kGone:
      lose(robot, event.reason == fleet_transport::GoneReason::kGoodbye ? "said goodbye" : "liveliness lost");
      return;
    case Event::Kind::kState: break;
  }
  ++summary_.states_received;
  if (!robot.announced) {
    if (warned_unknown_.insert(robot.id).second) {
      spdlog::warn("state from unknown robot {} ignored until it announces itself; its cell is kept clear", robot.id);
    }
    const Vertex cell = mission_vertex(event.state.cell_x, event.state.cell_y);
    if (cell != planner_core::kNoVertex) unknown_cells_[robot.id] = cell;
    return;
  }
  unknown_cells_.erase(robot.id);
  if (robot.refused) return;
  const fleet_transport::RobotState& state = event.state;
  const Vertex cell = mission_vertex(state.cell_x, state.cell_y);
  if (cell == planner_core::kNoVertex) {
    if (!robot.refused) {
      spdlog::error("robot {} refused: it reports cell ({},{}), which is outside the map or blocked", robot.id,
                    state.cell_x, state.cell_y);
    }
    robot.refused = true;
    lose(robot, "reported a cell off the map");
    return;
  }
  if (robot.has_state && state.seq_number <= robot.last.seq_number && state.seq_number != 1) return;  // stale
  robot.last_heard = Clock::now();
  if (state.status == RobotStatus::kFault) {
    // A robot in fault (a toio cube lifted, disconnected, between cells...) is out until it reports
    // a cell again; its last good cell and the cell it was moving to stay blocked meanwhile.
    if (robot.active) lose(robot, "reports a fault");
    return;
  }
  robot.has_state = true;
  robot.last = state;
  if (const int a = robot.plan_agent; a >= 0 && adg_ && state.plan_epoch == epoch_ && a < static_cast<int>(sent_.size()) &&
                                      state.action_index == sent_[a] && !acknowledged_[a]) {
    acknowledged_[a] = 1;
    summary_.round_trips_ms.push_back(std::chrono::duration<double, std::milli>(event.received - first_sent_at_[a]).count());
  }
  if (!robot.active) {
    robot.active = true;
    // It is where it reports, no longer where it was lost.
    std::erase_if(blocked_, [&](const auto& entry) { return entry.second == robot.id || entry.first == cell; });
    if (phase_ != Phase::kWaiting) {
      ++summary_.robots_joined;
      replanned_after_finish_ = false;
      std::vector<Robot*> joining{&robot};
      bind_roles(joining);
      request_replan("robot " + robot.id + " joined");
    }
  }
  if (robot.role >= 0) mark_visit(robot, {state.cell_x, state.cell_y});
}

void FleetCoordinator::mark_visit(Robot& robot, Cell cell) {
  const Vertex v = mission_vertex(cell.x, cell.y);
  for (int t : mission_.tasks_of_agent[robot.role]) {
    const planner_core::Task& task = mission_.tasks[t];
    if (task.at != v) continue;
    for (size_t k = 0; k < task.agents.size(); ++k) {
      if (task.agents[k] == robot.role) task_done_[t][k] = 1;
    }
  }
}

void FleetCoordinator::bind_roles(const std::vector<Robot*>& robots) {
  std::vector<Robot*> unbound;
  for (Robot* robot : robots) {
    const Vertex cell = mission_vertex(robot->last.cell_x, robot->last.cell_y);
    int taken = -1;
    for (int role = 0; role < mission_.agent_count() && taken < 0; ++role) {
      if (robot_of_role_[role].empty() && mission_.starts[role] == cell) taken = role;
    }
    if (taken >= 0) {
      robot->role = taken;
      robot_of_role_[taken] = robot->id;
      spdlog::info("robot {} takes role {} (it stands on the role's start)", robot->id, taken);
    } else {
      unbound.push_back(robot);
    }
  }
  std::vector<int> free_roles;
  for (int role = 0; role < mission_.agent_count(); ++role) {
    if (robot_of_role_[role].empty()) free_roles.push_back(role);
  }
  if (unbound.empty() || free_roles.empty()) {
    for (Robot* robot : unbound) spdlog::info("robot {} has no role: it stays as an extra robot", robot->id);
    return;
  }
  planner_core::DistTable dist(*mission_.graph);
  std::vector<std::vector<int64_t>> cost(unbound.size(), std::vector<int64_t>(free_roles.size()));
  for (size_t r = 0; r < unbound.size(); ++r) {
    const Vertex cell = mission_vertex(unbound[r]->last.cell_x, unbound[r]->last.cell_y);
    for (size_t k = 0; k < free_roles.size(); ++k) cost[r][k] = dist.get(mission_.starts[free_roles[k]], cell);
  }
  const std::vector<int> assignment = min_cost_assignment(cost);
  for (size_t r = 0; r < unbound.size(); ++r) {
    if (assignment[r] < 0) {
      spdlog::info("robot {} has no role: it stays as an extra robot", unbound[r]->id);
      continue;
    }
    const int role = free_roles[assignment[r]];
    unbound[r]->role = role;
    robot_of_role_[role] = unbound[r]->id;
    spdlog::info("robot {} takes role {} ({} steps from its start)", unbound[r]->id, role, cost[r][assignment[r]]);
  }
}

bool FleetCoordinator::replan(fleet_transport::Transport& transport) {
  // Extra robots take over the roles (and remaining tasks) of robots that left.
  std::vector<Robot*> extras;
  for (auto& [id, robot] : robots_) {
    if (robot.active && robot.has_state && robot.role < 0) extras.push_back(&robot);
  }
  const bool free_role = std::find(robot_of_role_.begin(), robot_of_role_.end(), "") != robot_of_role_.end();
  if (!extras.empty() && free_role && phase_ != Phase::kWaiting) bind_roles(extras);

  // The planning map: the mission map with the cells of lost robots blocked.
  std::vector<std::string> rows = mission_.graph->rows();
  std::set<Vertex> obstacles;
  for (const auto& [cell, robot_id] : blocked_) obstacles.insert(cell);
  for (const auto& [id, cell] : unknown_cells_) obstacles.insert(cell);  // robots we cannot command
  for (Vertex v : obstacles) {
    const Cell c = mission_.graph->cell_of(v);
    rows[c.y][c.x] = '@';
  }
  auto graph = std::make_shared<const planner_core::Graph>(mission_.graph->width(), mission_.graph->height(), rows);
  planner_core::DistTable dist(*graph);
  planner_core::Instance instance;
  instance.graph = graph;
  instance.source = "replan";
  std::vector<Robot*> members;
  for (auto& [id, robot] : robots_) {
    robot.plan_agent = -1;
    if (robot.active && robot.has_state) members.push_back(&robot);
  }
  std::set<Vertex> goals_taken;
  for (Robot* robot : members) {
    if (robot->role >= 0) goals_taken.insert(graph->vertex_at(mission_.graph->cell_of(mission_.goals[robot->role])));
  }
  std::vector<int> plan_role;
  for (Robot* robot : members) {
    const Vertex start = graph->vertex_at({robot->last.cell_x, robot->last.cell_y});
    if (start == planner_core::kNoVertex) continue;  // cannot happen: active robots' cells are free
    Vertex goal = planner_core::kNoVertex;
    if (robot->role >= 0) {
      goal = graph->vertex_at(mission_.graph->cell_of(mission_.goals[robot->role]));
      if (goal == planner_core::kNoVertex || dist.get(goal, start) >= planner_core::kUnreachable) {
        spdlog::error("role {}: goal blocked or unreachable for robot {}; it holds its cell", robot->role, robot->id);
        goal = planner_core::kNoVertex;
      }
    }
    if (goal == planner_core::kNoVertex) {
      // Extra robots (and robots that cannot reach their goal) rest on the nearest cell nobody needs.
      int best = planner_core::kUnreachable;
      for (Vertex v = 0; v < graph->vertex_count(); ++v) {
        const int from_start = dist.get(start, v);
        if (from_start < best && !goals_taken.count(v)) best = from_start, goal = v;
      }
      goals_taken.insert(goal);
    }
    robot->plan_agent = instance.agent_count();
    instance.starts.push_back(start);
    instance.goals.push_back(goal);
    plan_role.push_back(robot->role);
    plan_robots_.resize(instance.agent_count());
    plan_robots_[robot->plan_agent] = robot->id;
  }
  plan_robots_.resize(instance.agent_count());
  // Remaining tasks of the roles in the plan.
  for (int t = 0; t < mission_.task_count(); ++t) {
    const planner_core::Task& task = mission_.tasks[t];
    planner_core::Task remaining;
    remaining.at = graph->vertex_at(mission_.graph->cell_of(task.at));
    for (size_t k = 0; k < task.agents.size(); ++k) {
      if (task_done_[t][k]) continue;
      for (int a = 0; a < instance.agent_count(); ++a) {
        if (plan_role[a] != task.agents[k]) continue;
        if (remaining.at == planner_core::kNoVertex || dist.get(remaining.at, instance.starts[a]) >= planner_core::kUnreachable) {
          spdlog::error("task {} unreachable for robot {} (blocked by a lost robot): left pending", t,
                        plan_robots_[a]);
          continue;
        }
        remaining.agents.push_back(a);
      }
    }
    if (!remaining.agents.empty()) instance.tasks.push_back(remaining);
  }
  instance.index_tasks();
  for (Robot* robot : members) robot->finished_plan = false;

  planner_core::SolverConfig solver_config;
  const bool first_plan = epoch_ == 0;
  solver_config.solver = first_plan ? config_.solver : config_.replan_solver;
  solver_config.forbid_rotations = true;  // robots execute one move at a time
  solver_config.pibt.swap = config_.pibt_swap;
  const auto solver = planner_core::make_solver(solver_config);
  const planner_core::SolveResult result = solver->solve(
      instance, {planner_core::Deadline::in_seconds(first_plan ? config_.plan_time_s : config_.replan_time_s), {}});
  if (!result.solved) {
    spdlog::error("planning failed ({}); retrying", result.failure_reason);
    return false;
  }
  const planner_core::ValidationReport report =
      planner_core::validate(instance, result.solution, planner_core::ValidationOptions{true});
  if (!report.ok()) {
    spdlog::critical("the plan failed validation; it is not sent:\n{}", report.summary());
    return false;
  }
  ++epoch_;
  if (epoch_ > 1) ++summary_.replans;
  if (epoch_ == 1) {
    summary_.first_plan_makespan = report.makespan;
    summary_.first_plan_flowtime = report.flowtime;
  }
  plan_graph_ = graph;
  adg_ = std::make_unique<ActionDependencyGraph>(result.solution);
  finished_.assign(instance.agent_count(), 0);
  sent_.assign(instance.agent_count(), -1);
  sent_at_.assign(instance.agent_count(), Clock::time_point{});
  first_sent_at_.assign(instance.agent_count(), Clock::time_point{});
  acknowledged_.assign(instance.agent_count(), 0);
  spdlog::info("plan epoch {}: {} robots, {} task visits, flowtime {}, makespan {}", epoch_, instance.agent_count(),
               [&] {
                 int visits = 0;
                 for (const auto& task : instance.tasks) visits += static_cast<int>(task.agents.size());
                 return visits;
               }(),
               report.flowtime, report.makespan);
  replan_requested_ = false;
  phase_ = Phase::kExecuting;
  dispatch(transport);
  return true;
}

void FleetCoordinator::update_progress() {
  if (!adg_) return;
  for (size_t a = 0; a < plan_robots_.size(); ++a) {
    Robot& robot = robots_[plan_robots_[a]];
    const std::vector<Move>& moves = adg_->moves(static_cast<int>(a));
    if (finished_[a] >= static_cast<int>(moves.size()) || sent_[a] != finished_[a]) continue;
    const fleet_transport::RobotState& s = robot.last;
    const Cell target = plan_graph_->cell_of(moves[finished_[a]].to);
    if (s.plan_epoch == epoch_ && s.action_index == finished_[a] && s.status != RobotStatus::kMoving &&
        s.cell_x == target.x && s.cell_y == target.y) {
      ++finished_[a];
      if (robot.role >= 0) mark_visit(robot, target);
    }
  }
}

void FleetCoordinator::dispatch(fleet_transport::Transport& transport) {
  if (!adg_) return;
  const Clock::time_point now = Clock::now();
  for (size_t a = 0; a < plan_robots_.size(); ++a) {
    Robot& robot = robots_[plan_robots_[a]];
    if (!robot.active) continue;
    const std::vector<Move>& moves = adg_->moves(static_cast<int>(a));
    const int next = finished_[a];
    if (next >= static_cast<int>(moves.size())) {
      if (!robot.finished_plan) {
        robot.finished_plan = true;
        summary_.sum_of_finish_s += first_command_sent_ ? seconds_between(first_command_, now) : 0;
      }
      continue;
    }
    const bool in_flight = sent_[a] == next;
    const double resend_after = std::max(1.0, 5 * config_.step_s);
    if (in_flight && seconds_between(sent_at_[a], now) < resend_after) continue;
    if (!in_flight && !adg_->ready(static_cast<int>(a), next, finished_)) continue;
    const Cell target = plan_graph_->cell_of(moves[next].to);
    fleet_transport::StepCommand command;
    command.robot_id = robot.id;
    command.plan_epoch = epoch_;
    command.action_index = next;
    command.target_x = target.x;
    command.target_y = target.y;
    command.target_pose_x = target.x;
    command.target_pose_y = target.y;
    command.deadline_ms = fleet_transport::wall_clock_ms() + static_cast<int64_t>(4000 * config_.step_s) + 1000;
    transport.send_command(command);
    ++summary_.commands_sent;
    if (!in_flight) {
      first_sent_at_[a] = now;
      acknowledged_[a] = 0;
    }
    sent_[a] = next;
    sent_at_[a] = now;
    if (!first_command_sent_) {
      first_command_sent_ = true;
      first_command_ = now;
    }
    if (awaiting_replan_latency_) {
      awaiting_replan_latency_ = false;
      summary_.replan_latencies_s.push_back(seconds_between(replan_requested_at_, now));
    }
  }
}

bool FleetCoordinator::plan_finished() const {
  if (!adg_) return false;
  for (size_t a = 0; a < plan_robots_.size(); ++a) {
    const auto found = robots_.find(plan_robots_[a]);
    if (found == robots_.end() || !found->second.active) continue;
    if (finished_[a] < static_cast<int>(adg_->moves(static_cast<int>(a)).size())) return false;
  }
  return true;
}

bool FleetCoordinator::mission_complete() const {
  for (const auto& done : task_done_) {
    if (std::find(done.begin(), done.end(), 0) != done.end()) return false;
  }
  for (int role = 0; role < mission_.agent_count(); ++role) {
    if (robot_of_role_[role].empty()) continue;
    const Robot& robot = robots_.at(robot_of_role_[role]);
    if (mission_vertex(robot.last.cell_x, robot.last.cell_y) != mission_.goals[role]) return false;
  }
  return plan_finished();
}

void FleetCoordinator::publish_status(fleet_transport::Transport& transport) {
  fleet_transport::FleetStatus status;
  status.plan_epoch = epoch_;
  status.tasks_total = summary_.tasks_total;
  status.tasks_done = summary_.tasks_done;
  for (const auto& [id, robot] : robots_) {
    if (!robot.active) continue;
    ++status.robots;
    fleet_transport::Assignment row{id, robot.role, 0, 0};
    if (robot.role >= 0) {
      for (int t : mission_.tasks_of_agent[robot.role]) {
        const planner_core::Task& task = mission_.tasks[t];
        ++row.tasks_total;
        for (size_t k = 0; k < task.agents.size(); ++k) {
          if (task.agents[k] == robot.role && task_done_[t][k]) ++row.tasks_done;
        }
      }
    }
    status.assignments.push_back(row);
  }
  transport.publish_fleet_status(status);
}

std::string FleetCoordinator::progress_line() const {
  int active = 0;
  for (const auto& [id, robot] : robots_) active += robot.active ? 1 : 0;
  std::ostringstream out;
  out << "robots " << active << "  tasks " << summary_.tasks_done << "/" << summary_.tasks_total << "  epoch "
      << epoch_ << "  replans " << summary_.replans;
  return out.str();
}

bool FleetCoordinator::step(fleet_transport::Transport& transport) {
  std::deque<Event> events;
  {
    const std::lock_guard<std::mutex> lock(events_mutex_);
    events.swap(events_);
  }
  for (const Event& event : events) {
    handle(event);
    // Match the robot's command channel now, long before its first command.
    if (event.kind == Event::Kind::kAnnouncement && !event.announcement.leaving) {
      transport.prepare_commands_for(event.robot_id);
    }
  }
  const Clock::time_point now = Clock::now();
  for (auto& [id, robot] : robots_) {
    if (robot.active && seconds_between(robot.last_heard, now) > config_.silence_timeout_s) {
      lose(robot, "no state for " + std::to_string(config_.silence_timeout_s) + " s");
    }
  }
  summary_.tasks_done = 0;
  for (const auto& done : task_done_) summary_.tasks_done += std::find(done.begin(), done.end(), 0) == done.end();

  switch (phase_) {
    case Phase::kWaiting: {
      std::vector<Robot*> ready;
      for (auto& [id, robot] : robots_) {
        if (robot.active && robot.has_state) ready.push_back(&robot);
      }
      const bool all_expected = !config_.any_robots && static_cast<int>(ready.size()) ==
                                                            static_cast<int>(config_.expected_robots.size());
      const bool quorum = config_.any_robots && static_cast<int>(ready.size()) >= config_.quorum;
      const bool timed_out = seconds_between(started_, now) > config_.wait_timeout_s && !ready.empty();
      if (all_expected || quorum || timed_out) {
        spdlog::info("{} robots ready: binding roles and planning", ready.size());
        bind_roles(ready);
        phase_ = Phase::kSettling;
        settle_deadline_ = now;
      }
      break;
    }
    case Phase::kExecuting:
      update_progress();
      if (replan_requested_) {
        phase_ = Phase::kSettling;
        settle_deadline_ = now + seconds(config_.replan_settle_s);
        break;
      }
      dispatch(transport);
      if (mission_complete()) {
        phase_ = Phase::kDone;
        summary_.completed = true;
      } else if (plan_finished()) {
        // Everyone active is done. What is left belongs to roles without robots, or is blocked by a
        // lost robot (a replan from here changed nothing): wait for a robot, then end.
        bool waiting_for_robot = replanned_after_finish_;
        for (int t = 0; t < mission_.task_count(); ++t) {
          for (size_t k = 0; k < task_done_[t].size(); ++k) {
            if (!task_done_[t][k] && robot_of_role_[mission_.tasks[t].agents[k]].empty()) waiting_for_robot = true;
          }
        }
        if (!waiting_for_robot) {
          replanned_after_finish_ = true;
          request_replan("plan finished with tasks left");
        } else if (!waiting_for_robot_since_) {
          waiting_for_robot_since_ = now;
          spdlog::warn("what is left cannot be done by the robots here: waiting {} s for a robot to join",
                       config_.replacement_timeout_s);
        } else if (seconds_between(*waiting_for_robot_since_, now) > config_.replacement_timeout_s) {
          list_pending();
          phase_ = Phase::kDone;
        }
      } else {
        waiting_for_robot_since_.reset();
      }
      break;
    case Phase::kSettling: {
      update_progress();
      bool moves_in_flight = false;
      for (size_t a = 0; a < sent_.size(); ++a) {
        if (sent_[a] == finished_[a] && robots_[plan_robots_[a]].active) moves_in_flight = true;
      }
      // Plan only from where robots really stand: every move in flight must have ended (a robot
      // that never finishes is taken out by the silence timeout or its lease).
      if (moves_in_flight && now >= settle_deadline_) {
        spdlog::warn("replanning waits for moves still in flight");
        settle_deadline_ = now + seconds(config_.replan_settle_s);
      }
      if (!moves_in_flight && now >= retry_plan_at_) {
        if (!replan(transport)) retry_plan_at_ = now + seconds(1.0);
      }
      break;
    }
    case Phase::kDone: break;
  }
  if (now >= next_status_) {
    publish_status(transport);
    next_status_ = now + seconds(0.5);
  }
  if (first_command_sent_) summary_.seconds = seconds_between(first_command_, now);
  if (phase_ == Phase::kDone) return false;
  if (seconds_between(started_, now) > config_.mission_timeout_s) {
    spdlog::error("mission timeout after {} s", config_.mission_timeout_s);
    list_pending();
    return false;
  }
  return true;
}

void FleetCoordinator::list_pending() {
  summary_.pending.clear();
  for (int role = 0; role < mission_.agent_count(); ++role) {
    if (robot_of_role_[role].empty()) continue;
    const Robot& robot = robots_.at(robot_of_role_[role]);
    if (mission_vertex(robot.last.cell_x, robot.last.cell_y) != mission_.goals[role]) {
      summary_.pending.push_back("role " + std::to_string(role) + ": robot " + robot.id +
                                 " could not reach its goal (blocked)");
    }
  }
  for (int t = 0; t < mission_.task_count(); ++t) {
    for (size_t k = 0; k < task_done_[t].size(); ++k) {
      if (task_done_[t][k]) continue;
      const int role = mission_.tasks[t].agents[k];
      summary_.pending.push_back("task " + std::to_string(t) + " for role " + std::to_string(role) +
                                 (robot_of_role_[role].empty() ? " (no robot)" : " (robot " + robot_of_role_[role] + ")"));
    }
  }
}

}  // namespace coordinator
