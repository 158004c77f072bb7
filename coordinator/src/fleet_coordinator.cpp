#include "coordinator/fleet_coordinator.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <tuple>

#include "coordinator/plan_builder.hpp"
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
    : config_(config), mission_(std::move(mission)), progress_(mission_), started_(Clock::now()) {
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

void FleetCoordinator::lose(RobotRecord& robot, const std::string& why) {
  if (!robot.active) return;
  robot.active = false;
  replanned_after_finish_ = false;
  ++summary_.robots_lost;
  if (robot.has_state) {
    spdlog::warn("robot {} taken out: {} (last at ({},{}))", robot.id, why, robot.last.cell_x, robot.last.cell_y);
  } else {
    spdlog::warn("robot {} taken out: {}", robot.id, why);
  }
  if (robot.has_state) {
    const Vertex last = mission_vertex(robot.last.cell_x, robot.last.cell_y);
    if (last != planner_core::kNoVertex) blocked_[last] = robot.id;  // it may still stand there
  }
  // A robot that fell silent mid-move may have arrived at its target: keep that cell clear too.
  const int a = robot.plan_agent;
  if (a >= 0 && plan_ && a < plan_->agent_count() && plan_->in_flight(a)) {
    const Cell target = plan_->target(a, plan_->agent(a).finished);
    blocked_[mission_vertex(target.x, target.y)] = robot.id;
  }
  if (robot.role >= 0) {
    progress_.unbind(robot.role);
    robot.role = -1;
  }
  if (robot.plan_agent >= 0) request_replan("robot " + robot.id + " lost");
}

void FleetCoordinator::handle(const Event& event) {
  RobotRecord& robot = robots_[event.robot_id];
  switch (event.kind) {
    case Event::Kind::kAnnouncement: handle_announcement(robot, event.announcement); return;
    case Event::Kind::kGone:
      lose(robot, event.reason == fleet_transport::GoneReason::kGoodbye ? "said goodbye" : "liveliness lost");
      return;
    case Event::Kind::kState: handle_state(robot, event.state, event.received); return;
  }
}

void FleetCoordinator::handle_announcement(RobotRecord& robot, const fleet_transport::Announcement& announcement) {
  if (announcement.leaving) {
    lose(robot, "said goodbye");
    return;
  }
  const std::string backend_before = robot.backend;
  switch (robots_.admit(announcement, config_)) {
    case RobotRegistry::Admission::kRepeat: return;  // robots repeat their announcement every second
    case RobotRegistry::Admission::kDuplicate:
      spdlog::warn("robot id {} announced by a second {} robot while a {} robot is active: duplicate id, the "
                   "second is ignored",
                   robot.id, announcement.backend, backend_before);
      return;
    case RobotRegistry::Admission::kRefused:
      spdlog::warn("robot {} refused: not in robots.expected of {}", robot.id, config_.source);
      return;
    case RobotRegistry::Admission::kRefusedAgain: return;
    case RobotRegistry::Admission::kAdmitted:
      spdlog::info("robot {} announced ({} backend, version {})", robot.id, announcement.backend, announcement.version);
      return;
  }
}

void FleetCoordinator::handle_state(RobotRecord& robot, const fleet_transport::RobotState& state,
                                    Clock::time_point received) {
  ++summary_.states_received;
  if (!robot.announced) {
    if (warned_unknown_.insert(robot.id).second) {
      spdlog::warn("state from unknown robot {} ignored until it announces itself; its cell is kept clear", robot.id);
    }
    const Vertex cell = mission_vertex(state.cell_x, state.cell_y);
    if (cell != planner_core::kNoVertex) unknown_cells_[robot.id] = cell;
    return;
  }
  unknown_cells_.erase(robot.id);
  if (robot.refused) return;
  const Vertex cell = mission_vertex(state.cell_x, state.cell_y);
  if (cell == planner_core::kNoVertex) {
    spdlog::error("robot {} refused: it reports cell ({},{}), which is outside the map or blocked", robot.id,
                  state.cell_x, state.cell_y);
    robot.refused = true;
    lose(robot, "reported a cell off the map");
    return;
  }
  const Clock::time_point now = Clock::now();
  if (!accept_incarnation(robot, state, now)) return;
  if (robot.has_state && state.seq_number <= robot.last.seq_number) return;  // stale, within one incarnation
  robot.last_heard = now;
  if (state.status == RobotStatus::kFault) {
    // A robot in fault (a toio cube lifted, disconnected, between cells...) is out until it reports
    // a cell again; its last good cell and the cell it was moving to stay blocked meanwhile.
    if (robot.active) lose(robot, "reports a fault");
    return;
  }
  const bool had_state = robot.has_state;
  const fleet_transport::RobotState previous = robot.last;
  robot.has_state = true;
  robot.last = state;
  const int a = robot.plan_agent;
  const bool in_plan = a >= 0 && plan_ && a < plan_->agent_count();
  if (in_plan) {
    if (const auto round_trip = plan_->acknowledge(a, state, received)) summary_.round_trips_ms.push_back(*round_trip);
  }
  // Every report is checked against the plan: a robot on a cell the plan does not have it on (moved
  // by hand, or by commands from elsewhere) is taken out at once and planned around.
  if (robot.active && in_plan && !plan_->allows(a, {state.cell_x, state.cell_y})) {
    const Cell expected = plan_->position(a);
    if (had_state) {  // it may be anywhere between where it was and where it is
      const Vertex before = mission_vertex(previous.cell_x, previous.cell_y);
      if (before != planner_core::kNoVertex) blocked_[before] = robot.id;
    }
    ++summary_.off_plan;
    lose(robot, "off its plan: reports (" + std::to_string(state.cell_x) + "," + std::to_string(state.cell_y) +
                    "), the plan has it on (" + std::to_string(expected.x) + "," + std::to_string(expected.y) + ")");
    return;
  }
  if (!robot.active) {
    // A robot (re)joins once it stands still on a cell.
    if (state.status == RobotStatus::kMoving) return;
    robot.active = true;
    // It is where it reports, no longer where it was lost.
    std::erase_if(blocked_, [&](const auto& entry) { return entry.second == robot.id || entry.first == cell; });
    if (phase_ != Phase::kWaiting) {
      ++summary_.robots_joined;
      replanned_after_finish_ = false;
      bind_roles({&robot});
      request_replan("robot " + robot.id + " joined");
    }
  }
}

// Sequence numbers count within one incarnation of a robot's process. A state from another
// incarnation is a restart when the accepted one has gone quiet (or is out already): the new one
// takes over at once. While the accepted one is still heard, it is a second process claiming the
// same id: refused, and reported once.
bool FleetCoordinator::accept_incarnation(RobotRecord& robot, const fleet_transport::RobotState& state,
                                          Clock::time_point now) {
  constexpr double kQuietS = 1.0;  // ten missed periodic states
  if (state.incarnation == robot.incarnation) return true;
  if (!robot.has_state) {  // the first state heard from this id
    robot.incarnation = state.incarnation;
    return true;
  }
  if (robot.active && seconds_between(robot.last_heard, now) <= kQuietS) {
    if (robot.refused_incarnations.insert(state.incarnation).second) {
      spdlog::error("duplicate robot id {}: a second process (incarnation {:016x}) at ({},{}) is refused while "
                    "incarnation {:016x} at ({},{}) is driven",
                    robot.id, state.incarnation, state.cell_x, state.cell_y, robot.incarnation, robot.last.cell_x,
                    robot.last.cell_y);
      // It stands somewhere all the same: keep its cell clear, like a robot never enrolled.
      const Vertex cell = mission_vertex(state.cell_x, state.cell_y);
      if (cell != planner_core::kNoVertex) {
        unknown_cells_[robot.id + " (duplicate)"] = cell;
        request_replan("a duplicate of robot " + robot.id + " stands on (" + std::to_string(state.cell_x) + "," +
                       std::to_string(state.cell_y) + ")");
      }
    }
    return false;
  }
  spdlog::warn("robot {} restarted: incarnation {:016x} replaces {:016x}", robot.id, state.incarnation,
               robot.incarnation);
  if (robot.active) lose(robot, "restarted");
  robot.incarnation = state.incarnation;
  robot.refused_incarnations.erase(state.incarnation);
  robot.has_state = false;  // its sequence numbers start again
  return true;
}

void FleetCoordinator::bind_roles(const std::vector<RobotRecord*>& robots) {
  std::vector<RobotRecord*> unbound;
  for (RobotRecord* robot : robots) {
    const Vertex cell = mission_vertex(robot->last.cell_x, robot->last.cell_y);
    int taken = -1;
    for (int role = 0; role < mission_.agent_count() && taken < 0; ++role) {
      if (progress_.robot_of(role).empty() && mission_.starts[role] == cell) taken = role;
    }
    if (taken >= 0) {
      robot->role = taken;
      progress_.bind(taken, robot->id);
      spdlog::info("robot {} takes role {} (it stands on the role's start)", robot->id, taken);
    } else {
      unbound.push_back(robot);
    }
  }
  std::vector<int> free_roles;
  for (int role = 0; role < mission_.agent_count(); ++role) {
    if (progress_.robot_of(role).empty()) free_roles.push_back(role);
  }
  if (unbound.empty() || free_roles.empty()) {
    for (RobotRecord* robot : unbound) spdlog::info("robot {} has no role: it stays as an extra robot", robot->id);
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
    progress_.bind(role, unbound[r]->id);
    spdlog::info("robot {} takes role {} ({} steps from its start)", unbound[r]->id, role, cost[r][assignment[r]]);
  }
}

bool FleetCoordinator::replan(fleet_transport::Transport& transport) {
  // Extra robots take over the roles (and remaining tasks) of robots that left.
  std::vector<RobotRecord*> extras;
  for (RobotRecord* robot : robots_.ready_robots()) {
    if (robot->role < 0) extras.push_back(robot);
  }
  if (!extras.empty() && progress_.any_role_free() && phase_ != Phase::kWaiting) bind_roles(extras);

  // Plan from where the robots stand, around lost robots and robots that cannot be commanded.
  std::set<Vertex> blocked;
  for (const auto& [cell, robot_id] : blocked_) blocked.insert(cell);
  for (const auto& [id, cell] : unknown_cells_) blocked.insert(cell);
  std::vector<PlanMember> members;
  for (auto& [id, robot] : robots_) robot.plan_agent = -1;
  for (RobotRecord* robot : robots_.ready_robots()) {
    members.push_back({robot->id, {robot->last.cell_x, robot->last.cell_y}, robot->role});
  }
  PlanInstance built = build_plan_instance(mission_, progress_, members, blocked);
  for (const std::string& note : built.notes) spdlog::error("{}", note);
  const planner_core::Instance& instance = built.instance;
  for (int a = 0; a < instance.agent_count(); ++a) {
    RobotRecord& robot = robots_[built.robots[a]];
    robot.plan_agent = a;
    robot.finished_plan = false;
  }

  planner_core::SolverConfig solver_config;
  const bool first_plan = epoch_ == 0;
  solver_config.solver = first_plan ? config_.solver : config_.replan_solver;
  solver_config.forbid_rotations = true;  // robots execute one move at a time
  solver_config.pibt.swap = config_.pibt_swap;
  // After a failure the robots hold (no new moves) and the next try gets a longer limit, up to 8x.
  const double limit_s = (first_plan ? config_.plan_time_s : config_.replan_time_s) * plan_limit_factor_;
  const auto failed = [&](const std::string& why) {
    plan_limit_factor_ = std::min(8.0, plan_limit_factor_ * 2);
    spdlog::error("planning failed ({}); the robots hold; retrying in 1 s with a limit of {:.1f} s", why,
                  (first_plan ? config_.plan_time_s : config_.replan_time_s) * plan_limit_factor_);
    return false;
  };
  planner_core::SolveResult result;
  try {
    result = planner_core::make_solver(solver_config)->solve(instance, {planner_core::Deadline::in_seconds(limit_s, interrupt_), {}});
  } catch (const std::exception& e) {  // a solver bug must not end the mission
    return failed(std::string("the solver threw: ") + e.what());
  }
  if (!result.solved) return failed(result.failure_reason);
  const planner_core::ValidationReport report =
      planner_core::validate(instance, result.solution, planner_core::ValidationOptions{true});
  if (!report.ok()) {
    spdlog::critical("the plan failed validation; it is not sent:\n{}", report.summary());
    return failed("invalid plan");
  }
  plan_limit_factor_ = 1;
  ++epoch_;
  if (epoch_ > 1) ++summary_.replans;
  if (epoch_ == 1) {
    summary_.first_plan_makespan = report.makespan;
    summary_.first_plan_flowtime = report.flowtime;
  }
  plan_ = std::make_unique<PlanExecution>(epoch_, instance.graph, result.solution, built.robots);
  // Task visits count only when made under a plan: a start counts, being the plan's first step.
  for (int a = 0; a < instance.agent_count(); ++a) {
    const RobotRecord& robot = robots_[built.robots[a]];
    if (robot.role >= 0) progress_.visit(robot.role, mission_vertex(robot.last.cell_x, robot.last.cell_y));
  }
  int visits = 0;
  for (const auto& task : instance.tasks) visits += static_cast<int>(task.agents.size());
  spdlog::info("plan epoch {}: {} robots, {} task visits, flowtime {}, makespan {}", epoch_, instance.agent_count(),
               visits, report.flowtime, report.makespan);
  replan_requested_ = false;
  phase_ = Phase::kExecuting;
  dispatch(transport);
  return true;
}

void FleetCoordinator::update_progress() {
  if (!plan_) return;
  for (int a = 0; a < plan_->agent_count(); ++a) {
    RobotRecord& robot = robots_[plan_->agent(a).robot_id];
    if (const auto reached = plan_->confirm(a, robot.last); reached && robot.role >= 0) {
      progress_.visit(robot.role, mission_vertex(reached->x, reached->y));
    }
  }
}

void FleetCoordinator::dispatch(fleet_transport::Transport& transport) {
  if (!plan_) return;
  const Clock::time_point now = Clock::now();
  const double resend_after_s = std::max(1.0, 5 * config_.step_s);
  for (int a = 0; a < plan_->agent_count(); ++a) {
    RobotRecord& robot = robots_[plan_->agent(a).robot_id];
    if (!robot.active) continue;
    if (plan_->done(a)) {
      if (!robot.finished_plan) {
        robot.finished_plan = true;
        summary_.sum_of_finish_s += first_command_sent_ ? seconds_between(first_command_, now) : 0;
      }
      continue;
    }
    const int64_t deadline_ms = fleet_transport::wall_clock_ms() + static_cast<int64_t>(4000 * config_.step_s) + 1000;
    const auto command = plan_->due_command(a, now, resend_after_s, deadline_ms);
    if (!command) continue;
    transport.send_command(*command);
    ++summary_.commands_sent;
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
  if (!plan_) return false;
  for (int a = 0; a < plan_->agent_count(); ++a) {
    const RobotRecord* robot = robots_.find(plan_->agent(a).robot_id);
    if (robot == nullptr || !robot->active) continue;
    if (!plan_->done(a)) return false;
  }
  return true;
}

bool FleetCoordinator::mission_complete() const {
  if (!progress_.all_tasks_done()) return false;
  for (int role = 0; role < mission_.agent_count(); ++role) {
    if (progress_.robot_of(role).empty()) continue;
    const RobotRecord& robot = *robots_.find(progress_.robot_of(role));
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
    if (robot.role >= 0) std::tie(row.tasks_total, row.tasks_done) = progress_.role_tasks(robot.role);
    status.assignments.push_back(row);
  }
  transport.publish_fleet_status(status);
}

std::string FleetCoordinator::progress_line() const {
  std::ostringstream out;
  out << "robots " << robots_.active_count() << "  tasks " << summary_.tasks_done << "/" << summary_.tasks_total
      << "  epoch " << epoch_ << "  replans " << summary_.replans;
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
  for (RobotRecord* robot : robots_.silent_robots(now, config_.silence_timeout_s)) {
    lose(*robot, "no state for " + std::to_string(config_.silence_timeout_s) + " s");
  }
  summary_.tasks_done = progress_.tasks_done();

  switch (phase_) {
    case Phase::kWaiting: {
      const std::vector<RobotRecord*> ready = robots_.ready_robots();
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
        const bool waiting_for_robot = replanned_after_finish_ || progress_.work_waits_for_a_robot();
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
      for (int a = 0; plan_ && a < plan_->agent_count(); ++a) {
        const RobotRecord* robot = robots_.find(plan_->agent(a).robot_id);
        if (plan_->in_flight(a) && robot != nullptr && robot->active) moves_in_flight = true;
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
    if (progress_.robot_of(role).empty()) continue;
    const RobotRecord& robot = *robots_.find(progress_.robot_of(role));
    if (mission_vertex(robot.last.cell_x, robot.last.cell_y) != mission_.goals[role]) {
      summary_.pending.push_back("role " + std::to_string(role) + ": robot " + robot.id +
                                 " could not reach its goal (blocked)");
    }
  }
  for (const std::string& line : progress_.pending_visits()) summary_.pending.push_back(line);
}

}  // namespace coordinator
