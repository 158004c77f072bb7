// FleetCoordinator: construction, the loop's step and its phases, what it publishes, the end.
// The other parts: fleet_coordinator_robots.cpp (robots heard, bound, lost), _planning.cpp (plans
// made and carried out), _standby.cpp (other coordinators: follow, take over, stand down),
// _operators.cpp (tasks at runtime, what dashboards see).
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

FleetCoordinator::FleetCoordinator(const FleetConfig& config, planner_core::Instance mission,
                                   CoordinatorOptions options)
    : config_(config),
      mission_(std::move(mission)),
      options_(options),
      identity_{new_incarnation(), 1, fleet_transport::wall_clock_ms(), fleet_transport::CoordinatorRole::kActive,
                mission_fingerprint(mission_)},
      progress_(mission_),
      follower_(config_.lease_s, config_.silence_timeout_s, PublishSchedule::kStatusPeriodS),
      desk_(identity_.incarnation) {
  clocks_.started = clocks_.last_silence_check = Clock::now();
  mission_.actions = config_.actions;  // plans with turns or without: the fleet's choice, not the file's
  if (options_.standby) {
    identity_.role = fleet_transport::CoordinatorRole::kStandby;
    phase_ = Phase::kStandby;
  }
  if (MissionJournal* journal = options_.journal) {
    identity_.term = journal->highest_term() + 1;
    resume(*journal);
    if (!options_.standby) journal->claim(identity_.term, identity_.incarnation, identity_.claimed_ms);
  }
  summary_.tasks_done = summary_.tasks_done_before = progress_.tasks_done();
  summary_.tasks_total = progress_.tasks_to_do();
  journaled_tasks_ = mission_.task_count();
  summary_.term = identity_.term;
  spdlog::info("coordinator {} ({}), term {}, mission {}", hex(identity_.incarnation),
               fleet_transport::to_string(identity_.role), identity_.term, identity_.mission_id);
}

void FleetCoordinator::resume(MissionJournal& journal) {
  const auto& resume = journal.resumable();
  if (!resume) return;
  for (const JournalResume::AddedTask& added : resume->added_tasks) {
    const Vertex cell = mission_vertex(added.x, added.y);
    if (added.task != mission_.task_count() || cell == planner_core::kNoVertex || added.role < 0 ||
        added.role >= mission_.agent_count()) {
      throw JournalError("--journal " + journal.path() + ": added task " + std::to_string(added.task) +
                         " does not fit the mission (task count " + std::to_string(mission_.task_count()) +
                         ", cell (" + std::to_string(added.x) + "," + std::to_string(added.y) + "))");
    }
    mission_.tasks.push_back({cell, {added.role}});
    mission_.index_tasks();
    progress_.add_task();
  }
  pinned_tasks_.insert(resume->pinned_tasks.begin(), resume->pinned_tasks.end());
  const auto does_not_fit = [&](const std::string& what) {
    return JournalError("--journal " + journal.path() + ": " + what + " does not fit mission " + identity_.mission_id +
                        " (" + std::to_string(mission_.task_count()) + " tasks, " +
                        std::to_string(mission_.agent_count()) + " roles); it is left as it is");
  };
  for (int task : resume->cancelled_tasks) {
    if (task >= mission_.task_count()) throw does_not_fit("cancelled task " + std::to_string(task));
    progress_.cancel(task);
  }
  for (const fleet_transport::TaskVisit& visit : resume->visits) {
    const auto& roles = visit.task < mission_.task_count() ? mission_.tasks[visit.task].agents : std::vector<int>{};
    if (std::find(roles.begin(), roles.end(), visit.role) == roles.end()) {
      throw does_not_fit("the visit of task " + std::to_string(visit.task) + " by role " + std::to_string(visit.role));
    }
    progress_.mark(visit);
  }
  for (const auto& [role, robot] : resume->bindings) {
    if (role >= mission_.agent_count()) throw does_not_fit("the binding of role " + std::to_string(role));
  }
  epoch_ = resume->last_epoch;
  resumed_bindings_ = resume->bindings;
  spdlog::info("journal {}: resuming run {} of mission {}: {} task visits and {} of {} tasks done, last epoch {}, "
               "term {}",
               journal.path(), resume->run, identity_.mission_id, resume->visits.size(), progress_.tasks_done(),
               progress_.task_count(), epoch_, resume->last_term);
}

void FleetCoordinator::on_coordinator_status(const fleet_transport::CoordinatorStatus& status) {
  if (status.coordinator == identity_.incarnation) return;  // our own, heard back
  inputs_.push(inputs::CoordinatorHeard{status, Clock::now()});
}

void FleetCoordinator::on_fleet_status(const fleet_transport::FleetStatus& progress) {
  if (progress.coordinator == identity_.incarnation || identity_.role != fleet_transport::CoordinatorRole::kStandby) {
    return;
  }
  inputs_.push(inputs::ProgressHeard{progress});
}

void FleetCoordinator::on_mission_info(const fleet_transport::MissionInfo& info) {
  if (info.coordinator == identity_.incarnation || identity_.role != fleet_transport::CoordinatorRole::kStandby) return;
  inputs_.push(inputs::MissionHeard{info});
}

void FleetCoordinator::on_refused(const std::string& what) { inputs_.push(inputs::Refused{what}); }

void FleetCoordinator::on_task_request(const fleet_transport::TaskRequest& request) {
  inputs_.push(inputs::TaskRequested{request});
}

void FleetCoordinator::on_announcement(const fleet_transport::Announcement& announcement) {
  inputs_.push(inputs::Announced{announcement});
}

void FleetCoordinator::on_state(const fleet_transport::RobotState& state) {
  inputs_.push(inputs::StateHeard{state, Clock::now()});
}

void FleetCoordinator::on_robot_gone(const std::string& robot_id, fleet_transport::GoneReason reason) {
  inputs_.push(inputs::RobotGone{robot_id, reason});
}

Vertex FleetCoordinator::mission_vertex(int x, int y) const { return mission_.graph->vertex_at({x, y}); }

fleet_transport::CoordinatorStatus FleetCoordinator::own_status() const {
  return {identity_.incarnation, identity_.term, identity_.claimed_ms, identity_.role, identity_.mission_id, epoch_};
}

void FleetCoordinator::publish_status(fleet_transport::Transport& transport) {
  transport.publish_coordinator_status(own_status());
  schedule_.status_sent(Clock::now());
}

void FleetCoordinator::publish_progress(fleet_transport::Transport& transport) {
  fleet_transport::FleetStatus status;
  status.coordinator = identity_.incarnation;
  status.plan_epoch = epoch_;
  status.tasks_total = summary_.tasks_total;
  status.tasks_done = progress_.tasks_done();
  status.done_visits = progress_.done_visits();
  for (const auto& [id, robot] : robots_) {
    if (!robot.active) continue;
    ++status.robots;
    fleet_transport::Assignment row{id, robot.role, 0, 0};
    if (robot.role >= 0) std::tie(row.tasks_total, row.tasks_done) = progress_.role_tasks(robot.role);
    status.assignments.push_back(row);
  }
  status.tasks_total = progress_.tasks_to_do();
  const std::vector<double>& trips = summary_.round_trips_ms;
  if (!trips.empty()) {
    std::vector<double> recent(trips.end() - std::min<size_t>(trips.size(), 200), trips.end());
    std::sort(recent.begin(), recent.end());
    status.round_trip_p50_ms = recent[recent.size() / 2];
    status.round_trip_p99_ms = recent[std::min(recent.size() - 1, recent.size() * 99 / 100)];
  }
  status.last_planning_ms = summary_.last_planning_ms;
  if (!summary_.replan_latencies_s.empty()) status.last_replan_latency_ms = 1000 * summary_.replan_latencies_s.back();
  status.steps_done = summary_.steps_of_replaced_plans;
  for (int a = 0; plan_ && a < plan_->agent_count(); ++a) status.steps_done += plan_->agent(a).finished;
  status.steps_planned = summary_.steps_planned;
  transport.publish_fleet_status(status);
  schedule_.progress_sent(Clock::now());
}

std::string FleetCoordinator::progress_line() const {
  std::ostringstream out;
  out << "robots " << robots_.active_count() << "  tasks " << summary_.tasks_done << "/" << summary_.tasks_total
      << "  epoch " << epoch_ << "  replans " << summary_.replans;
  return out.str();
}

bool FleetCoordinator::step(fleet_transport::Transport& transport) {
  take_in_inputs(transport);
  const Clock::time_point now = Clock::now();
  if (interrupt_ != nullptr && interrupt_->load()) planning_.cancel();
  if (identity_.role == fleet_transport::CoordinatorRole::kActive) {
    const double gone_after_s = fleet_transport::LeaseTimeouts{config_.lease_s}.coordinator_gone_s();
    if (const OtherCoordinator* other = others_.stronger_active(own_status(), now, gone_after_s)) {
      stand_down(*other, transport);
      return false;
    }
  }
  check_robots(transport, now);
  summary_.tasks_done = progress_.tasks_done();
  switch (phase_) {
    case Phase::kWaiting: step_waiting(now); break;
    case Phase::kStandby: follow(transport, now); break;
    case Phase::kExecuting: step_executing(transport, now); break;
    case Phase::kSettling: step_settling(transport, now); break;
    case Phase::kDone: break;
  }
  publish(transport, now);
  if (clocks_.first_command) summary_.seconds = seconds_between(*clocks_.first_command, now);
  if (phase_ == Phase::kDone) return false;
  if (phase_ != Phase::kStandby && !config_.lifelong && seconds_between(clocks_.started, now) > config_.mission_timeout_s) {
    spdlog::error("mission timeout after {} s", config_.mission_timeout_s);
    list_pending();
    return false;
  }
  return true;
}

void FleetCoordinator::take_in_inputs(fleet_transport::Transport& transport) {
  for (const inputs::Input& input : inputs_.take_all()) {
    std::visit([&](const auto& one) { handle(one, transport); }, input);
  }
}

void FleetCoordinator::step_waiting(Clock::time_point now) {
  const std::vector<RobotRecord*> ready = robots_.ready_robots();
  const bool all_expected = !config_.any_robots && !ready.empty() &&
                            static_cast<int>(ready.size()) == static_cast<int>(config_.expected_robots.size());
  const bool quorum = config_.any_robots && static_cast<int>(ready.size()) >= config_.quorum;
  const bool timed_out = seconds_between(clocks_.started, now) > config_.wait_timeout_s && !ready.empty();
  // Listen for a lease first: another coordinator already active is heard, and this one stands down.
  const bool listened = seconds_between(clocks_.started, now) >= config_.lease_s;
  if (listened && (all_expected || quorum || timed_out)) {
    spdlog::info("{} robots ready: binding roles and planning", ready.size());
    bind_roles(ready);
    phase_ = Phase::kSettling;
    clocks_.settle_deadline = now;
  }
}

void FleetCoordinator::step_executing(fleet_transport::Transport& transport, Clock::time_point now) {
  update_progress();
  if (replans_.pending()) {
    phase_ = Phase::kSettling;
    clocks_.settle_deadline = now + seconds(config_.replan_settle_s);
    return;
  }
  extend_plan(transport);
  dispatch(transport);
  if (mission_complete()) {
    if (!plan_end_.lifelong_idle) {
      report("mission_done", "", fmt::format("every task done ({} of {}), every robot on its goal",
                                             progress_.tasks_done(), progress_.tasks_to_do()));
    }
    if (config_.lifelong) {
      if (!plan_end_.lifelong_idle) spdlog::info("every task done: the robots park on their goals; waiting for tasks (lifelong)");
      plan_end_.lifelong_idle = true;
    } else {
      phase_ = Phase::kDone;
      summary_.completed = true;
    }
  } else if (plan_finished() && !window_under_way()) {
    wait_for_a_robot_or_replan(now);
  } else if (plan_end_.waiting_for_robot) {
    plan_end_.waiting_for_robot.reset();  // a robot joined: the work goes on
    summary_.pending.clear();
  }
}

void FleetCoordinator::wait_for_a_robot_or_replan(Clock::time_point now) {
  // Everyone active is done. What is left belongs to roles without robots, or is blocked by a
  // lost robot (a replan from here changed nothing): wait for a robot, then end.
  const bool waiting_for_robot = plan_end_.replanned || progress_.work_waits_for_a_robot();
  if (!waiting_for_robot) {
    plan_end_.replanned = true;
    request_replan("plan finished with tasks left");
  } else if (!plan_end_.waiting_for_robot) {
    plan_end_.waiting_for_robot = WaitForRobot{now, now};
    if (config_.replacement_timeout_s) {
      spdlog::warn("what is left cannot be done by the robots here: waiting {} s for a robot to join",
                   *config_.replacement_timeout_s);
    } else {
      if (config_.lifelong) {
        spdlog::warn("what is left cannot be done by the robots here: the robots hold; waiting for a robot to join");
      } else {
        spdlog::warn("what is left cannot be done by the robots here: the robots hold; waiting for a robot to "
                     "join (the mission times out {:.0f} s after it started)", config_.mission_timeout_s);
      }
    }
    list_pending();
    for (const std::string& line : summary_.pending) spdlog::warn("  left: {}", line);
  } else if (config_.replacement_timeout_s &&
             seconds_between(plan_end_.waiting_for_robot->since, now) > *config_.replacement_timeout_s) {
    spdlog::error("no robot joined within timing.replacement_timeout_s ({} s): the mission ends",
                  *config_.replacement_timeout_s);
    list_pending();
    phase_ = Phase::kDone;
  } else if (seconds_between(plan_end_.waiting_for_robot->last_log, now) >= 10) {
    plan_end_.waiting_for_robot->last_log = now;
    spdlog::warn("still waiting for a robot to join ({:.0f} s so far)", seconds_between(plan_end_.waiting_for_robot->since, now));
  }
}

void FleetCoordinator::publish(fleet_transport::Transport& transport, Clock::time_point now) {
  if (identity_.role == fleet_transport::CoordinatorRole::kActive && phase_ != Phase::kStandby && desk_.mission_due()) {
    publish_mission(transport);
  }
  desk_.publish_events(transport);
  if (schedule_.status_due(now)) publish_status(transport);
  if (schedule_.progress_due(now)) publish_progress(transport);
}

void FleetCoordinator::finish(fleet_transport::Transport& transport) {
  if (identity_.role == fleet_transport::CoordinatorRole::kActive ||
      identity_.role == fleet_transport::CoordinatorRole::kStandby) {
    identity_.role = fleet_transport::CoordinatorRole::kEnded;
  }
  publish_status(transport);
  publish_progress(transport);
  if (options_.journal && summary_.completed) {
    try {
      options_.journal->finish("completed");
    } catch (const JournalError& e) {
      spdlog::error("{}", e.what());
    }
  } else if (options_.journal && !summary_.stood_down) {
    spdlog::info("journal {}: the run stays open; start again with --journal {} to resume it", options_.journal->path(),
                 options_.journal->path());
  }
}

}  // namespace coordinator
