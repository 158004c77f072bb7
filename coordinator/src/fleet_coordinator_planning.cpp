// FleetCoordinator's plans: what a plan is made from, the planning worker's plan checked against
// the fleet as it is now and taken into use, progress, and the commands sent.
#include "coordinator/fleet_coordinator.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <tuple>
#include <utility>

#include "coordinator/plan_builder.hpp"
#include "coordinator/role_assignment.hpp"
#include "fleet_transport/lease_timeouts.hpp"
#include "planner_core/dist_table.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/solver.hpp"
#include "planner_core/validator.hpp"
#include "fleet_coordinator_detail.hpp"

namespace coordinator {

using fleet_transport::RobotStatus;
using planner_core::Cell;
using planner_core::Vertex;
using namespace fleet_coordinator_detail;

FleetCoordinator::PlanningInputs FleetCoordinator::planning_inputs() const {
  PlanningInputs inputs;
  for (const auto& [cell, robot_id] : blocked_) inputs.blocked.insert(cell);
  for (const auto& [id, robot] : robots_) {
    if (robot.unannounced_at) inputs.blocked.insert(*robot.unannounced_at);
  }
  for (planner_core::Vertex cell : refused_processes_.cells()) inputs.blocked.insert(cell);
  for (const RobotRecord* robot : robots_.ready_robots()) {
    inputs.members.push_back({robot->id, {robot->last.cell_x, robot->last.cell_y}, robot->role, robot->last.heading});
    inputs.incarnations.push_back(robot->incarnation);
  }
  inputs.replan_requests = replans_.count();
  inputs.tasks = mission_.task_count();
  inputs.tasks_done = progress_.tasks_done();
  return inputs;
}

std::string FleetCoordinator::what_changed_since(const PlanningInputs& then) const {
  const PlanningInputs now = planning_inputs();
  if (now.replan_requests != then.replan_requests) return "a replan was asked for meanwhile";
  if (now.members.size() != then.members.size()) {
    return fmt::format("{} robots ready, {} planned for", now.members.size(), then.members.size());
  }
  for (size_t k = 0; k < now.members.size(); ++k) {
    const PlanMember& was = then.members[k];
    const PlanMember& is = now.members[k];
    if (is.robot_id != was.robot_id) return "robot " + is.robot_id + " is ready, " + was.robot_id + " was";
    if (!(is.cell == was.cell)) {
      return "robot " + is.robot_id + " moved from " + planner_core::to_string(was.cell) + " to " +
             planner_core::to_string(is.cell);
    }
    if (is.role != was.role) return "robot " + is.robot_id + " changed role";
    if (config_.actions == planner_core::ActionModel::kRotate && is.heading != was.heading) {
      return "robot " + is.robot_id + " turned";
    }
    if (now.incarnations[k] != then.incarnations[k]) return "robot " + is.robot_id + " restarted";
  }
  if (now.blocked != then.blocked) return "the cells to keep clear changed";
  if (now.tasks != then.tasks || now.tasks_done != then.tasks_done) return "the tasks changed";
  return "";
}

void FleetCoordinator::start_planning() {
  // Extra robots take over the roles (and remaining tasks) of robots that left.
  std::vector<RobotRecord*> extras;
  for (RobotRecord* robot : robots_.ready_robots()) {
    if (robot->role < 0) extras.push_back(robot);
  }
  if (!extras.empty() && progress_.any_role_free()) bind_roles(extras);

  // Plan from where the robots stand, around lost robots and robots that cannot be commanded.
  plan_under_way_.from = planning_inputs();
  PlanningRequest request;
  request.built =
      build_plan_instance(mission_, progress_, plan_under_way_.from.members, plan_under_way_.from.blocked);
  for (const std::string& note : request.built.notes) spdlog::error("{}", note);
  // The mission's first plan gets the full solver and budget; a resumed or taken-over mission is a
  // replan (robots wait meanwhile), so it gets the fast one.
  const bool first_plan = plans_made_ == 0 && epoch_ == 0 && !summary_.took_over;
  request.solver = config_.solver_config(first_plan);
  // After a failure the robots hold (no new moves) and the next try gets a longer limit, up to 8x.
  request.time_limit_s = config_.plan_limit_s(first_plan) * plan_retry_.limit_factor;
  request.iterations = config_.iterations;
  // Lifelong: the plan starts with a window and grows by more (fleet_coordinator_windows.cpp);
  // after a window stalled, the complete solver makes it.
  request.lifelong_window = config_.lifelong && !plan_retry_.complete_solver;
  request.lifelong_planner = config_.lifelong_planner;
  plan_under_way_.first_plan = first_plan;
  plan_under_way_.lifelong_window = request.lifelong_window;
  planning_.start(std::move(request));
}

bool FleetCoordinator::planning_failed(const std::string& why) {
  plan_retry_.limit_factor = std::min(8.0, plan_retry_.limit_factor * 2);
  report("plan_failed", "", why);
  spdlog::error("planning failed ({}); the robots hold; retrying in 1 s with a limit of {:.1f} s", why,
                config_.plan_limit_s(plan_under_way_.first_plan) * plan_retry_.limit_factor);
  return false;
}

bool FleetCoordinator::finish_planning(PlanningOutcome outcome, fleet_transport::Transport& transport) {
  summary_.last_planning_ms = outcome.planning_ms;
  if (!outcome.error.empty()) return planning_failed(outcome.error);
  if (!outcome.result.solved) return planning_failed(outcome.result.failure_reason);
  if (!outcome.report.ok()) {
    spdlog::critical("the plan failed validation; it is not sent:\n{}", outcome.report.summary());
    return planning_failed("invalid plan");
  }
  plan_retry_.limit_factor = 1;
  take_plan(outcome);
  const planner_core::Instance& instance = outcome.built.instance;
  const planner_core::ValidationReport& report = outcome.report;
  const planner_core::SolverConfig solver_config = config_.solver_config(plan_under_way_.first_plan);
  int visits = 0;
  for (const auto& task : instance.tasks) visits += static_cast<int>(task.agents.size());
  spdlog::info("plan epoch {}: {} robots, {} task visits, flowtime {}, makespan {}{} ({}, seed {}, planned in {:.0f} ms)",
               epoch_, instance.agent_count(), visits, report.flowtime, report.makespan,
               instance.actions == planner_core::ActionModel::kRotate ? " with turns" : "",
               plan_under_way_.lifelong_window ? "a first lifelong window" : solver_config.solver,
               solver_config.seed, summary_.last_planning_ms);
  this->report("replan", "",
               fmt::format("epoch {}: {} robots, {} task visits, flowtime {}, planned in {:.0f} ms", epoch_,
                           instance.agent_count(), visits, report.flowtime, summary_.last_planning_ms),
               summary_.last_planning_ms);
  publish_plan(transport, report.flowtime, summary_.last_planning_ms);
  replans_.answered();
  phase_ = Phase::kExecuting;
  publish_status(transport);  // agents take only epochs their coordinator has announced
  dispatch(transport);
  return true;
}

void FleetCoordinator::take_plan(const PlanningOutcome& outcome) {
  plan_grew_at_ = Clock::now();
  const PlanInstance& built = outcome.built;
  const planner_core::Instance& instance = built.instance;
  for (auto& [id, robot] : robots_) robot.plan_agent = -1;
  for (int a = 0; a < instance.agent_count(); ++a) {
    RobotRecord& robot = robots_[built.robots[a]];
    robot.plan_agent = a;
    robot.finished_plan = false;
  }
  ++epoch_;
  if (plans_made_ > 0) ++summary_.replans;
  if (plans_made_ == 0) {
    summary_.first_plan_makespan = outcome.report.makespan;
    summary_.first_plan_flowtime = outcome.report.flowtime;
  }
  ++plans_made_;
  journal_write("plan epoch", [&](MissionJournal& journal) { journal.record_epoch(epoch_, identity_.term); });
  if (plan_) {
    for (int a = 0; a < plan_->agent_count(); ++a) summary_.steps_of_replaced_plans += plan_->agent(a).finished;
  }
  plan_ = std::make_unique<PlanExecution>(epoch_, instance.graph, outcome.result.solution, built.robots,
                                          identity_.incarnation, outcome.result.headings);
  for (int a = 0; a < plan_->agent_count(); ++a) summary_.steps_planned += plan_->move_count(a);
  agents_out_.clear();
  if (config_.lifelong) {  // the plan will grow by windows, which take up what it does not do
    restart_window_planner();  // a window under way for the plan replaced is cut short
    planned_visits_.clear();
    first_plan_steps_ = plan_->plan_steps();
    plan_retry_.complete_solver = false;
    mark_planned_visits(outcome.result.solution);
  }
  // Task visits count only when made under a plan: a start counts, being the plan's first step.
  for (int a = 0; a < instance.agent_count(); ++a) {
    const RobotRecord& robot = robots_[built.robots[a]];
    if (robot.role >= 0) credit_visits(robot.role, mission_vertex(robot.last.cell_x, robot.last.cell_y), robot.id);
  }
}

void FleetCoordinator::update_progress() {
  if (!plan_) return;
  for (int a = 0; a < plan_->agent_count(); ++a) {
    RobotRecord* robot = robot_of_agent(a);
    if (robot == nullptr) continue;
    if (const auto reached = plan_->confirm(a, robot->last); reached && robot->role >= 0) {
      credit_visits(robot->role, mission_vertex(reached->x, reached->y), robot->id);
    }
  }
}

void FleetCoordinator::dispatch(fleet_transport::Transport& transport, bool resend_only) {
  if (!plan_) return;
  const Clock::time_point now = Clock::now();
  const double resend_after_s = config_.resend_after_s();
  for (int a = 0; a < plan_->agent_count(); ++a) {
    RobotRecord* driver = robot_of_agent(a);
    if (driver == nullptr || !driver->active) continue;
    RobotRecord& robot = *driver;
    if (resend_only && !plan_->in_flight(a)) continue;
    if (plan_->done(a)) {
      if (!robot.finished_plan) {
        robot.finished_plan = true;
        summary_.sum_of_finish_s += clocks_.first_command ? seconds_between(*clocks_.first_command, now) : 0;
      }
      continue;
    }
    const int64_t deadline_ms =
        fleet_transport::wall_clock_ms() + static_cast<int64_t>(1000 * config_.command_lifetime_s());
    auto command = plan_->due_command(a, now, resend_after_s, deadline_ms);
    if (!command) continue;
    command->robot_incarnation = robot.incarnation;  // only that process of the id obeys it
    transport.send_command(*command);
    note_command_sent(now, resend_only);
  }
}

void FleetCoordinator::note_command_sent(Clock::time_point now, bool resend_only) {
  ++summary_.commands_sent;
  if (!clocks_.first_command) {
    clocks_.first_command = now;
    summary_.first_command_wall_ms = fleet_transport::wall_clock_ms();
    spdlog::info("first command of term {} sent at wall-clock ms {}", identity_.term, summary_.first_command_wall_ms);
  }
  if (resend_only) return;
  if (const auto latency_s = replans_.latency_until(now)) summary_.replan_latencies_s.push_back(*latency_s);
}

bool FleetCoordinator::plan_finished() const {
  if (!plan_) return false;
  for (int a = 0; a < plan_->agent_count(); ++a) {
    const RobotRecord* robot = robot_of_agent(a);
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

bool FleetCoordinator::moves_in_flight() {
  for (int a = 0; plan_ && a < plan_->agent_count(); ++a) {
    const RobotRecord* robot = robot_of_agent(a);
    if (plan_->in_flight(a) && robot != nullptr && robot->active) return true;
  }
  // Robots still carrying out another coordinator's last command (after a takeover or a restart).
  for (RobotRecord* robot : robots_.ready_robots()) {
    if (plans_made_ == 0 && robot->last.status == RobotStatus::kMoving) return true;
  }
  return false;
}

void FleetCoordinator::step_settling(fleet_transport::Transport& transport, Clock::time_point now) {
  update_progress();
  // Plan only from where robots really stand: every move in flight must have ended (a robot
  // that never finishes is taken out by the silence timeout or its lease).
  const bool in_flight = moves_in_flight();
  if (in_flight) dispatch(transport, /*resend_only=*/true);
  if (in_flight && now >= clocks_.settle_deadline) {
    spdlog::warn("replanning waits for moves still in flight");
    clocks_.settle_deadline = now + seconds(config_.replan_settle_s);
  }
  // The plan is made on the worker while this loop goes on; it is used only if the fleet is
  // still as it was planned from (robots, cells, roles, incarnations, walls, tasks).
  std::optional<PlanningOutcome> outcome = planning_.poll();
  if (!outcome && planning_.idle() && !in_flight && now >= plan_retry_.not_before) {
    start_planning();
    // A quick plan is used in this very step, as when planning ran inside it; a long one goes
    // on beside the loop. The wait is far below a heartbeat period.
    outcome = planning_.wait_for(kQuickPlanWait);
  }
  if (!outcome) return;
  if (outcome->cancelled) {
    spdlog::info("planning was interrupted");
  } else if (const std::string change = what_changed_since(plan_under_way_.from); !change.empty()) {
    ++summary_.plans_discarded;
    spdlog::info("the fleet changed while planning ({}): the plan is dropped and made again", change);
  } else if (!finish_planning(std::move(*outcome), transport)) {
    plan_retry_.not_before = now + seconds(1.0);
  }
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
