// FleetCoordinator's robots: inputs from the transport, announcements and states, one process per
// robot id, robots lost, or deaf to their commands.
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

// The robot that drives agent `a` of the current plan, or nullptr: a robot that left and came
// back after the plan was made is not in it until the next plan.
const RobotRecord* FleetCoordinator::robot_of_agent(int a) const {
  const RobotRecord* robot = robots_.find(plan_->agent(a).robot_id);
  return robot != nullptr && robot->plan_agent == a ? robot : nullptr;
}

RobotRecord* FleetCoordinator::robot_of_agent(int a) {
  return const_cast<RobotRecord*>(std::as_const(*this).robot_of_agent(a));
}

void FleetCoordinator::request_replan(const std::string& why) {
  if (!driving()) return;
  replans_.ask(Clock::now());  // a plan under way no longer fits
  spdlog::info("replanning: {}", why);
}

void FleetCoordinator::lose(RobotRecord& robot, const std::string& why, const char* kind) {
  if (!robot.active) return;
  robot.active = false;
  report(kind, robot.id, why);
  plan_end_.replanned = false;
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
  if (robot.role >= 0 && phase_ != Phase::kStandby) {  // a standby mirrors the bindings
    unbind_role(robot.role);
    robot.role = -1;
  }
  if (robot.plan_agent >= 0 && !plan_around(robot, kind)) request_replan("robot " + robot.id + " lost");
}

// A robot whose states arrive but that has not acknowledged its move for timing.command_timeout_s
// (resent all along) cannot be commanded: its command channel is broken (seen with Fast DDS when a
// writer never matched its robot's reader). Waiting for it would hold its dependents, or a replan,
// for ever; it is taken out like a robot that fell silent, its cell and its move's target kept
// clear, and it may rejoin only once that move's last command has expired, so that it cannot
// start a move the next plan does not know of.
void FleetCoordinator::take_out_robots_deaf_to_commands(Clock::time_point now) {
  if (!plan_) return;
  for (int a = 0; a < plan_->agent_count(); ++a) {
    RobotRecord* robot = robot_of_agent(a);
    if (robot == nullptr || !robot->active || !plan_->unacknowledged(a)) continue;
    const PlanExecution::Agent& agent = plan_->agent(a);
    const double waited_s = seconds_between(agent.first_sent_at, now);
    if (waited_s < config_.command_timeout_s) continue;
    robot->rejoin_not_before = agent.sent_at + seconds(config_.command_lifetime_s() + kClockMarginS);
    lose(*robot, fmt::format("move {} of plan epoch {} not acknowledged in {:.1f} s though its states arrive (its "
                             "command channel may be broken)", agent.sent, plan_->epoch(), waited_s),
         "unresponsive");
  }
}

RobotRecord* FleetCoordinator::record_of(const std::string& robot_id) {
  return robots_.valid_record(robot_id, [&](const std::string& why) {
    spdlog::error("{}", why);
    report("refused", "", why);
  });
}

void FleetCoordinator::handle(const inputs::Announced& input, fleet_transport::Transport& transport) {
  RobotRecord* robot = record_of(input.announcement.robot_id);
  if (robot == nullptr) return;
  handle_announcement(*robot, input.announcement);
  // Match the robot's command channel now, long before its first command.
  if (!input.announcement.leaving) transport.prepare_commands_for(robot->id);
}

void FleetCoordinator::handle(const inputs::StateHeard& input, fleet_transport::Transport&) {
  if (RobotRecord* robot = record_of(input.state.robot_id)) handle_state(*robot, input.state, input.received);
}

void FleetCoordinator::handle(const inputs::RobotGone& input, fleet_transport::Transport&) {
  RobotRecord* robot = record_of(input.robot_id);
  if (robot == nullptr) return;
  robot->said_goodbye = input.reason == fleet_transport::GoneReason::kGoodbye;
  lose(*robot, robot->said_goodbye ? "said goodbye" : "liveliness lost");
}

void FleetCoordinator::handle(const inputs::CoordinatorHeard& input, fleet_transport::Transport&) {
  others_.heard_status(input.status, input.received);
}

void FleetCoordinator::handle(const inputs::ProgressHeard& input, fleet_transport::Transport&) {
  others_.heard_progress(input.progress);
}

void FleetCoordinator::handle(const inputs::MissionHeard& input, fleet_transport::Transport&) {
  others_.heard_mission(input.mission);
}

void FleetCoordinator::handle(const inputs::TaskRequested& input, fleet_transport::Transport& transport) {
  handle_task_request(input.request, transport);
}

void FleetCoordinator::handle(const inputs::Refused& input, fleet_transport::Transport&) {
  report("refused", "", input.what);
}

void FleetCoordinator::handle_announcement(RobotRecord& robot, const fleet_transport::Announcement& announcement) {
  if (announcement.leaving) {
    robot.said_goodbye = true;
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
      report("refused", robot.id, "a second robot announced this id: duplicate, ignored");
      return;
    case RobotRegistry::Admission::kRefused:
      spdlog::warn("robot {} refused: not in robots.expected of {}", robot.id, config_.source);
      report("refused", robot.id, "not in robots.expected of " + config_.source);
      return;
    case RobotRegistry::Admission::kRefusedAgain: return;
    case RobotRegistry::Admission::kAdmitted:
      spdlog::info("robot {} announced ({} backend, version {})", robot.id, announcement.backend, announcement.version);
      report("join", robot.id, "announced (" + announcement.backend + " backend, version " + announcement.version + ")");
      return;
  }
}

void FleetCoordinator::handle_state(RobotRecord& robot, const fleet_transport::RobotState& state,
                                    Clock::time_point received) {
  ++summary_.states_received;
  if (!robot.announced) {
    heard_unannounced(robot, state);
    return;
  }
  robot.unannounced_at.reset();
  if (robot.refused) return;
  const Vertex cell = mission_vertex(state.cell_x, state.cell_y);
  if (cell == planner_core::kNoVertex) {
    spdlog::error("robot {} refused: it reports cell ({},{}), which is outside the map or blocked", robot.id,
                  state.cell_x, state.cell_y);
    robot.refused = true;
    lose(robot, "reported a cell off the map");
    return;
  }
  if (!accept_incarnation(robot, state, received)) return;
  if (robot.has_state && state.seq_number <= robot.last.seq_number) return;  // stale, within one incarnation
  robot.last_heard = Clock::now();
  robot.last_state_received = std::max(robot.last_state_received, received);
  robot.said_goodbye = false;
  if (state.status == RobotStatus::kFault) {
    // A robot in fault (a toio cube lifted, disconnected, between cells...) is out until it reports
    // a cell again; its last good cell and the cell it was moving to stay blocked meanwhile.
    if (robot.active) lose(robot, "reports a fault", "fault");
    return;
  }
  const bool had_state = robot.has_state;
  const fleet_transport::RobotState previous = robot.last;
  robot.has_state = true;
  robot.last = state;
  const int a = robot.plan_agent;
  if (a >= 0 && plan_ && a < plan_->agent_count()) {
    if (const auto round_trip = plan_->acknowledge(a, state, received)) summary_.round_trips_ms.push_back(*round_trip);
  }
  if (took_out_off_plan(robot, previous, had_state)) return;
  // A robot (re)joins once it stands still on a cell.
  if (!robot.active && state.status != RobotStatus::kMoving && Clock::now() >= robot.rejoin_not_before) {
    rejoin(robot, cell);
  }
}

void FleetCoordinator::heard_unannounced(RobotRecord& robot, const fleet_transport::RobotState& state) {
  if (!robot.warned_unannounced) {
    robot.warned_unannounced = true;
    spdlog::warn("state from unknown robot {} ignored until it announces itself; its cell is kept clear", robot.id);
  }
  const Vertex cell = mission_vertex(state.cell_x, state.cell_y);
  if (cell != planner_core::kNoVertex) robot.unannounced_at = cell;
}

// Every report is checked against the plan: a robot on a cell the plan does not have it on (moved
// by hand, or by commands from elsewhere) is taken out at once and planned around.
bool FleetCoordinator::took_out_off_plan(RobotRecord& robot, const fleet_transport::RobotState& previous,
                                         bool had_state) {
  const int a = robot.plan_agent;
  const fleet_transport::RobotState& state = robot.last;
  if (!robot.active || a < 0 || !plan_ || a >= plan_->agent_count()) return false;
  if (plan_->allows(a, {state.cell_x, state.cell_y})) return false;
  const Cell expected = plan_->position(a);
  if (had_state) {  // it may be anywhere between where it was and where it is
    const Vertex before = mission_vertex(previous.cell_x, previous.cell_y);
    if (before != planner_core::kNoVertex) blocked_[before] = robot.id;
  }
  ++summary_.off_plan;
  lose(robot, "off its plan: reports (" + std::to_string(state.cell_x) + "," + std::to_string(state.cell_y) +
                  "), the plan has it on (" + std::to_string(expected.x) + "," + std::to_string(expected.y) + ")",
       "off_plan");
  return true;
}

void FleetCoordinator::rejoin(RobotRecord& robot, Vertex cell) {
  if (take_back(robot, {robot.last.cell_x, robot.last.cell_y}) || join_plan(robot, {robot.last.cell_x, robot.last.cell_y})) {
    return;
  }
  robot.active = true;
  // The current plan was made without it (or with it elsewhere): its reports are not checked
  // against that plan, nor is it commanded by it, until the replan places it.
  robot.plan_agent = -1;
  // It is where it reports, no longer where it was lost.
  std::erase_if(blocked_, [&](const auto& entry) { return entry.second == robot.id || entry.first == cell; });
  if (!driving()) return;
  ++summary_.robots_joined;
  plan_end_.replanned = false;
  bind_roles({&robot});
  report("join", robot.id, "back on the grid at (" + std::to_string(robot.last.cell_x) + "," +
                               std::to_string(robot.last.cell_y) + ")");
  request_replan("robot " + robot.id + " joined");
}

// Sequence numbers count within one incarnation of a robot's process. A state from another
// incarnation is a restart when the accepted one has gone quiet (or is out already): the new one
// takes over at once. While the accepted one is still heard, it is a second process claiming the
// same id: refused, and reported once.
bool FleetCoordinator::accept_incarnation(RobotRecord& robot, const fleet_transport::RobotState& state,
                                          Clock::time_point received) {
  constexpr double kQuietS = 1.0;  // ten missed periodic states
  if (state.incarnation == robot.incarnation) return true;
  if (!robot.has_state) {  // the first state heard from this id
    robot.incarnation = state.incarnation;
    refused_processes_.forget(robot.id, state.incarnation);
    return true;
  }
  // Which process drives the id is decided on when each one's states arrived (stamped by the
  // transport as they came), which stays true however long this loop was busy: the driven process
  // keeps the id for as long as it is heard.
  const double driven_quiet_s = seconds_between(robot.last_state_received, received);
  if (robot.active && driven_quiet_s <= kQuietS) {
    refuse_second_process(robot, state, received);
    return false;
  }
  spdlog::warn("robot {} restarted: incarnation {:016x} replaces {:016x} (not heard for {:.1f} s)", robot.id,
               state.incarnation, robot.incarnation, driven_quiet_s);
  if (robot.active) lose(robot, "restarted");
  robot.incarnation = state.incarnation;
  robot.refused_incarnations.erase(state.incarnation);
  refused_processes_.forget(robot.id, state.incarnation);
  robot.has_state = false;  // its sequence numbers start again
  return true;
}

void FleetCoordinator::refuse_second_process(RobotRecord& robot, const fleet_transport::RobotState& state,
                                             Clock::time_point received) {
  if (robot.refused_incarnations.insert(state.incarnation).second) {
    spdlog::error("duplicate robot id {}: a second process (incarnation {:016x}) at ({},{}) is refused while "
                  "incarnation {:016x} at ({},{}) is driven; it is told so and kept clear of where it is heard",
                  robot.id, state.incarnation, state.cell_x, state.cell_y, robot.incarnation, robot.last.cell_x,
                  robot.last.cell_y);
    report("duplicate", robot.id,
           fmt::format("a second process (incarnation {:016x}) claims this id at ({},{}): refused", state.incarnation,
                       state.cell_x, state.cell_y));
  }
  // It stands somewhere all the same: its cell is kept clear, wherever it is heard.
  const Cell cell{state.cell_x, state.cell_y};
  if (refused_processes_.heard(robot.id, state.incarnation, cell, mission_vertex(cell.x, cell.y), received)) {
    request_replan("a duplicate of robot " + robot.id + " stands on " + planner_core::to_string(cell));
  }
}

void FleetCoordinator::tell_refused_processes(fleet_transport::Transport& transport, Clock::time_point now) {
  for (const RefusedProcess& gone : refused_processes_.forget_silent(now, config_.silence_timeout_s)) {
    spdlog::info("the refused second process of robot {} (incarnation {:016x}) is no longer heard", gone.robot_id,
                 gone.incarnation);
  }
  if (identity_.role != fleet_transport::CoordinatorRole::kActive || !driving()) return;
  constexpr double kRefusalEveryS = 2.0;
  for (const RefusedProcess& process : refused_processes_.refusals_due(now, kRefusalEveryS)) {
    fleet_transport::StepCommand refusal;
    refusal.robot_id = process.robot_id;
    refusal.plan_epoch = epoch_;
    refusal.action_index = -1;
    refusal.target_x = refusal.target_pose_x = process.cell.x;
    refusal.target_y = refusal.target_pose_y = process.cell.y;
    refusal.deadline_ms = fleet_transport::wall_clock_ms() + static_cast<int64_t>(1000 * config_.command_lifetime_s());
    refusal.sent_ms = fleet_transport::wall_clock_ms();
    refusal.coordinator = identity_.incarnation;
    refusal.robot_incarnation = process.incarnation;
    refusal.refused = true;
    transport.send_command(refusal);
  }
}

void FleetCoordinator::check_robots(fleet_transport::Transport& transport, Clock::time_point now) {
  // A step that came long after the last one (planning, or the middleware holding this thread:
  // a 200-robot Fast DDS fleet coming together held it for 9 s) heard nobody meanwhile, through no
  // fault of the robots: their silence counts from now. A robot that died meanwhile is taken out
  // one silence timeout later; robots without commands stand still.
  if (const double stood_still_s = seconds_between(clocks_.last_silence_check, now); stood_still_s > kStoodStillS) {
    robots_.restart_silence_clocks(now);
    if (stood_still_s > config_.silence_timeout_s) {
      spdlog::warn("this coordinator stood still for {:.1f} s: robots' silence is counted from now", stood_still_s);
    }
  }
  clocks_.last_silence_check = now;
  for (RobotRecord* robot : robots_.silent_robots(now, config_.silence_timeout_s)) {
    lose(*robot, "no state for " + std::to_string(config_.silence_timeout_s) + " s");
  }
  take_out_robots_deaf_to_commands(now);
  tell_refused_processes(transport, now);
}

}  // namespace coordinator
