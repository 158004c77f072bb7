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

// A random 64-bit number, never 0.
uint64_t new_incarnation() {
  std::random_device device;
  uint64_t value = 0;
  while (value == 0) value = (static_cast<uint64_t>(device()) << 32) ^ device();
  return value;
}

std::string hex(uint64_t value) { return fmt::format("{:016x}", value); }

// How often the heartbeat goes out, and the progress when nothing changed; progress changes go out
// at most every kProgressGapS.
constexpr double kStatusPeriodS = 0.25;
constexpr double kProgressPeriodS = 0.5;
constexpr double kProgressGapS = 0.05;
constexpr double kStoodStillS = 1.0;  // a step this long after the last one heard nobody
// How long a step waits for a plan it just started before it lets the loop go on (see step()).
constexpr std::chrono::milliseconds kQuickPlanWait{50};
// Robots judge a command's deadline on their own clock through an offset they estimate from send
// stamps; this much is allowed for that estimate's error.
constexpr double kClockMarginS = 1.0;

}  // namespace

FleetCoordinator::FleetCoordinator(const FleetConfig& config, planner_core::Instance mission,
                                   CoordinatorOptions options)
    : config_(config),
      mission_(std::move(mission)),
      options_(options),
      incarnation_(new_incarnation()),
      claimed_ms_(fleet_transport::wall_clock_ms()),
      mission_id_(mission_fingerprint(mission_)),
      progress_(mission_),
      started_(Clock::now()),
      last_silence_check_(started_) {
  summary_.tasks_total = mission_.task_count();
  mission_task_count_ = mission_.task_count();
  if (options_.standby) {
    role_ = fleet_transport::CoordinatorRole::kStandby;
    phase_ = Phase::kStandby;
  }
  if (MissionJournal* journal = options_.journal) {
    term_ = journal->highest_term() + 1;
    if (const auto& resume = journal->resumable()) {
      for (const JournalResume::AddedTask& added : resume->added_tasks) {
        const Vertex cell = mission_vertex(added.x, added.y);
        if (added.task != mission_.task_count() || cell == planner_core::kNoVertex || added.role < 0 ||
            added.role >= mission_.agent_count()) {
          throw JournalError("--journal " + journal->path() + ": added task " + std::to_string(added.task) +
                             " does not fit the mission (task count " + std::to_string(mission_.task_count()) +
                             ", cell (" + std::to_string(added.x) + "," + std::to_string(added.y) + "))");
        }
        mission_.tasks.push_back({cell, {added.role}});
        mission_.index_tasks();
        progress_.add_task();
      }
      const auto does_not_fit = [&](const std::string& what) {
        return JournalError("--journal " + journal->path() + ": " + what + " does not fit mission " + mission_id_ +
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
                   journal->path(), resume->run, mission_id_, resume->visits.size(), progress_.tasks_done(),
                   progress_.task_count(), epoch_, resume->last_term);
    }
    if (!options_.standby) journal->claim(term_, incarnation_, claimed_ms_);
  }
  summary_.tasks_done = summary_.tasks_done_before = progress_.tasks_done();
  summary_.tasks_total = progress_.tasks_to_do();
  journaled_tasks_ = mission_.task_count();
  summary_.term = term_;
  spdlog::info("coordinator {} ({}), term {}, mission {}", hex(incarnation_), fleet_transport::to_string(role_), term_,
               mission_id_);
}

void FleetCoordinator::queue(Event event) {
  const std::lock_guard<std::mutex> lock(events_mutex_);
  events_.push_back(std::move(event));
}

void FleetCoordinator::on_coordinator_status(const fleet_transport::CoordinatorStatus& status) {
  if (status.coordinator == incarnation_) return;  // our own, heard back
  Event event{Event::Kind::kStatus};
  event.status = status;
  event.received = Clock::now();
  queue(std::move(event));
}

void FleetCoordinator::on_fleet_status(const fleet_transport::FleetStatus& progress) {
  if (progress.coordinator == incarnation_ || role_ != fleet_transport::CoordinatorRole::kStandby) return;
  Event event{Event::Kind::kProgress};
  event.progress = progress;
  queue(std::move(event));
}

void FleetCoordinator::on_mission_info(const fleet_transport::MissionInfo& info) {
  if (info.coordinator == incarnation_ || role_ != fleet_transport::CoordinatorRole::kStandby) return;
  Event event{Event::Kind::kMission};
  event.mission = info;
  queue(std::move(event));
}

void FleetCoordinator::on_refused(const std::string& what) {
  Event event{Event::Kind::kRefused};
  event.refusal = what;
  queue(std::move(event));
}

void FleetCoordinator::on_task_request(const fleet_transport::TaskRequest& request) {
  Event event{Event::Kind::kTaskRequest};
  event.request = request;
  queue(std::move(event));
}

void FleetCoordinator::on_announcement(const fleet_transport::Announcement& announcement) {
  Event event{Event::Kind::kAnnouncement};
  event.announcement = announcement;
  event.robot_id = announcement.robot_id;
  queue(std::move(event));
}

void FleetCoordinator::on_state(const fleet_transport::RobotState& state) {
  Event event{Event::Kind::kState};
  event.state = state;
  event.robot_id = state.robot_id;
  event.received = Clock::now();
  queue(std::move(event));
}

void FleetCoordinator::on_robot_gone(const std::string& robot_id, fleet_transport::GoneReason reason) {
  Event event{Event::Kind::kGone};
  event.robot_id = robot_id;
  event.reason = reason;
  queue(std::move(event));
}

// The robot that drives agent `a` of the current plan, or nullptr: a robot that left and came
// back after the plan was made is not in it until the next plan.
const RobotRecord* FleetCoordinator::robot_of_agent(int a) const {
  const RobotRecord* robot = robots_.find(plan_->agent(a).robot_id);
  return robot != nullptr && robot->plan_agent == a ? robot : nullptr;
}

RobotRecord* FleetCoordinator::robot_of_agent(int a) {
  return const_cast<RobotRecord*>(std::as_const(*this).robot_of_agent(a));
}

Vertex FleetCoordinator::mission_vertex(int x, int y) const { return mission_.graph->vertex_at({x, y}); }

void FleetCoordinator::request_replan(const std::string& why) {
  if (!driving()) return;
  ++replan_requests_;  // a plan under way no longer fits
  spdlog::info("replanning: {}", why);
  if (!replan_requested_) {
    replan_requested_at_ = Clock::now();
    awaiting_replan_latency_ = true;
  }
  replan_requested_ = true;
}

void FleetCoordinator::lose(RobotRecord& robot, const std::string& why, const char* kind) {
  if (!robot.active) return;
  robot.active = false;
  report(kind, robot.id, why);
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
  if (robot.role >= 0 && phase_ != Phase::kStandby) {  // a standby mirrors the bindings
    unbind_role(robot.role);
    robot.role = -1;
  }
  if (robot.plan_agent >= 0) request_replan("robot " + robot.id + " lost");
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

void FleetCoordinator::handle(const Event& event) {
  if (event.kind == Event::Kind::kStatus) {
    handle_status(event.status, event.received);
    return;
  }
  if (event.kind == Event::Kind::kProgress) {
    others_[event.progress.coordinator].progress = event.progress;
    return;
  }
  if (event.kind == Event::Kind::kRefused) {
    report("refused", "", event.refusal);
    return;
  }
  if (event.kind == Event::Kind::kMission) {
    others_[event.mission.coordinator].mission = event.mission;
    return;
  }
  if (!fleet_transport::is_valid_robot_id(event.robot_id)) {
    // A name, not markup: refused before it becomes a record, a role or an event's robot.
    if (bad_robot_ids_.size() < kBadRobotIdsReported && bad_robot_ids_.insert(event.robot_id).second) {
      const std::string why = fmt::format("a message from robot id '{}' refused: robot ids are {}",
                                          fleet_transport::printable(event.robot_id, 40), fleet_transport::kRobotIdRule);
      spdlog::error("{}", why);
      report("refused", "", why);
    }
    return;
  }
  RobotRecord& robot = robots_[event.robot_id];
  switch (event.kind) {
    case Event::Kind::kAnnouncement: handle_announcement(robot, event.announcement); return;
    case Event::Kind::kGone:
      robot.said_goodbye = event.reason == fleet_transport::GoneReason::kGoodbye;
      lose(robot, robot.said_goodbye ? "said goodbye" : "liveliness lost");
      return;
    case Event::Kind::kState: handle_state(robot, event.state, event.received); return;
    case Event::Kind::kStatus:
    case Event::Kind::kProgress:
    case Event::Kind::kTaskRequest:
    case Event::Kind::kMission:
    case Event::Kind::kRefused: return;
  }
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
  if (!accept_incarnation(robot, state, received)) return;
  if (robot.has_state && state.seq_number <= robot.last.seq_number) return;  // stale, within one incarnation
  robot.last_heard = now;
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
                    "), the plan has it on (" + std::to_string(expected.x) + "," + std::to_string(expected.y) + ")",
         "off_plan");
    return;
  }
  if (!robot.active) {
    // A robot (re)joins once it stands still on a cell.
    if (state.status == RobotStatus::kMoving || now < robot.rejoin_not_before) return;
    robot.active = true;
    // The current plan was made without it (or with it elsewhere): its reports are not checked
    // against that plan, nor is it commanded by it, until the replan places it.
    robot.plan_agent = -1;
    // It is where it reports, no longer where it was lost.
    std::erase_if(blocked_, [&](const auto& entry) { return entry.second == robot.id || entry.first == cell; });
    if (driving()) {
      ++summary_.robots_joined;
      replanned_after_finish_ = false;
      bind_roles({&robot});
      report("join", robot.id, "back on the grid at (" + std::to_string(state.cell_x) + "," +
                                   std::to_string(state.cell_y) + ")");
      request_replan("robot " + robot.id + " joined");
    }
  }
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
    if (robot.refused_incarnations.insert(state.incarnation).second) {
      spdlog::error("duplicate robot id {}: a second process (incarnation {:016x}) at ({},{}) is refused while "
                    "incarnation {:016x} at ({},{}) is driven; it is told so and kept clear of where it is heard",
                    robot.id, state.incarnation, state.cell_x, state.cell_y, robot.incarnation, robot.last.cell_x,
                    robot.last.cell_y);
      report("duplicate", robot.id,
             fmt::format("a second process (incarnation {:016x}) claims this id at ({},{}): refused",
                         state.incarnation, state.cell_x, state.cell_y));
    }
    // It stands somewhere all the same: its cell is kept clear, wherever it is heard.
    const Cell cell{state.cell_x, state.cell_y};
    if (refused_processes_.heard(robot.id, state.incarnation, cell, mission_vertex(cell.x, cell.y), received)) {
      request_replan("a duplicate of robot " + robot.id + " stands on " + planner_core::to_string(cell));
    }
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

void FleetCoordinator::tell_refused_processes(fleet_transport::Transport& transport, Clock::time_point now) {
  for (const RefusedProcess& gone : refused_processes_.forget_silent(now, config_.silence_timeout_s)) {
    spdlog::info("the refused second process of robot {} (incarnation {:016x}) is no longer heard", gone.robot_id,
                 gone.incarnation);
  }
  if (role_ != fleet_transport::CoordinatorRole::kActive || !driving()) return;
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
    refusal.coordinator = incarnation_;
    refusal.robot_incarnation = process.incarnation;
    refusal.refused = true;
    transport.send_command(refusal);
  }
}

void FleetCoordinator::bind_role(int role, RobotRecord& robot) {
  robot.role = role;
  progress_.bind(role, robot.id);
  progress_changed_ = true;
  if (role_ == fleet_transport::CoordinatorRole::kActive) {
    journal_write("role binding", [&](MissionJournal& journal) { journal.record_binding(role, robot.id); });
  }
}

bool FleetCoordinator::journal_write(const char* what, const std::function<void(MissionJournal&)>& write) {
  if (options_.journal == nullptr || summary_.journal_failed) return options_.journal == nullptr;
  try {
    write(*options_.journal);
    return true;
  } catch (const JournalError& e) {
    // A full disk, a file gone: the mission goes on from memory; only a restart could not resume it.
    summary_.journal_failed = true;
    const std::string why = fmt::format("the journal could not record a {} ({}): the mission goes on from memory and is "
                                        "no longer recorded; a restart of this coordinator would start it over (a "
                                        "standby keeps following it)", what, e.what());
    spdlog::critical("{}", why);
    report("journal_failed", "", why);
    return false;
  }
}

void FleetCoordinator::unbind_role(int role) {
  progress_.unbind(role);
  progress_changed_ = true;
  if (role_ == fleet_transport::CoordinatorRole::kActive) {
    journal_write("role binding", [&](MissionJournal& journal) { journal.record_binding(role, ""); });
  }
}

void FleetCoordinator::bind_roles(const std::vector<RobotRecord*>& robots) {
  std::vector<RobotRecord*> unbound;
  std::vector<RobotRecord*> candidates;
  // A resumed mission gives each robot back the role the journal has for it.
  for (RobotRecord* robot : robots) {
    int kept = -1;
    for (const auto& [role, id] : resumed_bindings_) {
      if (id == robot->id && role < mission_.agent_count() && progress_.robot_of(role).empty()) kept = role;
    }
    if (kept >= 0) {
      bind_role(kept, *robot);
      spdlog::info("robot {} keeps role {} (from the journal)", robot->id, kept);
    } else {
      candidates.push_back(robot);
    }
  }
  resumed_bindings_.clear();
  for (RobotRecord* robot : candidates) {
    const Vertex cell = mission_vertex(robot->last.cell_x, robot->last.cell_y);
    int taken = -1;
    for (int role = 0; role < mission_.agent_count() && taken < 0; ++role) {
      if (progress_.robot_of(role).empty() && mission_.starts[role] == cell) taken = role;
    }
    if (taken >= 0) {
      bind_role(taken, *robot);
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
    bind_role(role, *unbound[r]);
    spdlog::info("robot {} takes role {} ({} steps from its start)", unbound[r]->id, role, cost[r][assignment[r]]);
  }
}

FleetCoordinator::PlanningInputs FleetCoordinator::planning_inputs() const {
  PlanningInputs inputs;
  for (const auto& [cell, robot_id] : blocked_) inputs.blocked.insert(cell);
  for (const auto& [id, cell] : unknown_cells_) inputs.blocked.insert(cell);
  for (planner_core::Vertex cell : refused_processes_.cells()) inputs.blocked.insert(cell);
  for (const RobotRecord* robot : robots_.ready_robots()) {
    inputs.members.push_back({robot->id, {robot->last.cell_x, robot->last.cell_y}, robot->role});
    inputs.incarnations.push_back(robot->incarnation);
  }
  inputs.replan_requests = replan_requests_;
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
  planned_from_ = planning_inputs();
  PlanningRequest request;
  request.built = build_plan_instance(mission_, progress_, planned_from_.members, planned_from_.blocked);
  for (const std::string& note : request.built.notes) spdlog::error("{}", note);
  // The mission's first plan gets the full solver and budget; a resumed or taken-over mission is a
  // replan (robots wait meanwhile), so it gets the fast one.
  const bool first_plan = plans_made_ == 0 && epoch_ == 0 && !summary_.took_over;
  request.solver = config_.solver_config(first_plan);
  // After a failure the robots hold (no new moves) and the next try gets a longer limit, up to 8x.
  request.time_limit_s = config_.plan_limit_s(first_plan) * plan_limit_factor_;
  request.iterations = config_.iterations;
  planning_first_plan_ = first_plan;
  planning_.start(std::move(request));
}

bool FleetCoordinator::finish_planning(PlanningOutcome outcome, fleet_transport::Transport& transport) {
  const bool first_plan = planning_first_plan_;
  const auto failed = [&](const std::string& why) {
    plan_limit_factor_ = std::min(8.0, plan_limit_factor_ * 2);
    report("plan_failed", "", why);
    spdlog::error("planning failed ({}); the robots hold; retrying in 1 s with a limit of {:.1f} s", why,
                  config_.plan_limit_s(first_plan) * plan_limit_factor_);
    return false;
  };
  last_planning_ms_ = outcome.planning_ms;
  if (!outcome.error.empty()) return failed(outcome.error);
  if (!outcome.result.solved) return failed(outcome.result.failure_reason);
  if (!outcome.report.ok()) {
    spdlog::critical("the plan failed validation; it is not sent:\n{}", outcome.report.summary());
    return failed("invalid plan");
  }
  plan_limit_factor_ = 1;
  const PlanInstance& built = outcome.built;
  const planner_core::Instance& instance = built.instance;
  const planner_core::SolveResult& result = outcome.result;
  const planner_core::ValidationReport& report = outcome.report;
  const planner_core::SolverConfig solver_config = config_.solver_config(first_plan);
  for (auto& [id, robot] : robots_) robot.plan_agent = -1;
  for (int a = 0; a < instance.agent_count(); ++a) {
    RobotRecord& robot = robots_[built.robots[a]];
    robot.plan_agent = a;
    robot.finished_plan = false;
  }
  ++epoch_;
  if (plans_made_ > 0) ++summary_.replans;
  if (plans_made_ == 0) {
    summary_.first_plan_makespan = report.makespan;
    summary_.first_plan_flowtime = report.flowtime;
  }
  ++plans_made_;
  journal_write("plan epoch", [&](MissionJournal& journal) { journal.record_epoch(epoch_, term_); });
  if (plan_) {
    for (int a = 0; a < plan_->agent_count(); ++a) steps_of_earlier_plans_ += plan_->agent(a).finished;
  }
  plan_ = std::make_unique<PlanExecution>(epoch_, instance.graph, result.solution, built.robots, incarnation_);
  // Task visits count only when made under a plan: a start counts, being the plan's first step.
  for (int a = 0; a < instance.agent_count(); ++a) {
    const RobotRecord& robot = robots_[built.robots[a]];
    if (robot.role >= 0) credit_visits(robot.role, mission_vertex(robot.last.cell_x, robot.last.cell_y), robot.id);
  }
  int visits = 0;
  for (const auto& task : instance.tasks) visits += static_cast<int>(task.agents.size());
  spdlog::info("plan epoch {}: {} robots, {} task visits, flowtime {}, makespan {} ({}, seed {}, planned in {:.0f} ms)",
               epoch_, instance.agent_count(), visits, report.flowtime, report.makespan, solver_config.solver,
               solver_config.seed, last_planning_ms_);
  for (int a = 0; a < plan_->agent_count(); ++a) steps_planned_ += static_cast<int64_t>(plan_->moves(a).size());
  this->report("replan", "",
               fmt::format("epoch {}: {} robots, {} task visits, flowtime {}, planned in {:.0f} ms", epoch_,
                           instance.agent_count(), visits, report.flowtime, last_planning_ms_),
               last_planning_ms_);
  publish_plan(transport, report.flowtime, last_planning_ms_);
  replan_requested_ = false;
  phase_ = Phase::kExecuting;
  publish_status(transport);  // agents take only epochs their coordinator has announced
  dispatch(transport);
  return true;
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
        summary_.sum_of_finish_s += first_command_sent_ ? seconds_between(first_command_, now) : 0;
      }
      continue;
    }
    const int64_t deadline_ms =
        fleet_transport::wall_clock_ms() + static_cast<int64_t>(1000 * config_.command_lifetime_s());
    auto command = plan_->due_command(a, now, resend_after_s, deadline_ms);
    if (!command) continue;
    command->robot_incarnation = robot.incarnation;  // only that process of the id obeys it
    transport.send_command(*command);
    ++summary_.commands_sent;
    if (!first_command_sent_) {
      first_command_sent_ = true;
      first_command_ = now;
      summary_.first_command_wall_ms = fleet_transport::wall_clock_ms();
      spdlog::info("first command of term {} sent at wall-clock ms {}", term_, summary_.first_command_wall_ms);
    }
    if (awaiting_replan_latency_ && !resend_only) {
      awaiting_replan_latency_ = false;
      summary_.replan_latencies_s.push_back(seconds_between(replan_requested_at_, now));
    }
  }
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

fleet_transport::CoordinatorStatus FleetCoordinator::own_status() const {
  fleet_transport::CoordinatorStatus status;
  status.coordinator = incarnation_;
  status.term = term_;
  status.claimed_ms = claimed_ms_;
  status.role = role_;
  status.mission_id = mission_id_;
  status.plan_epoch = epoch_;
  return status;
}

void FleetCoordinator::publish_status(fleet_transport::Transport& transport) {
  transport.publish_coordinator_status(own_status());
  next_status_ = Clock::now() + seconds(kStatusPeriodS);
}

void FleetCoordinator::publish_progress(fleet_transport::Transport& transport) {
  fleet_transport::FleetStatus status;
  status.coordinator = incarnation_;
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
  status.last_planning_ms = last_planning_ms_;
  if (!summary_.replan_latencies_s.empty()) status.last_replan_latency_ms = 1000 * summary_.replan_latencies_s.back();
  status.steps_done = steps_of_earlier_plans_;
  for (int a = 0; plan_ && a < plan_->agent_count(); ++a) status.steps_done += plan_->agent(a).finished;
  status.steps_planned = steps_planned_;
  transport.publish_fleet_status(status);
  progress_changed_ = false;
  last_progress_ = Clock::now();
  next_progress_ = last_progress_ + seconds(kProgressPeriodS);
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
    if (event.kind == Event::Kind::kTaskRequest) {
      handle_task_request(event.request, transport);
      continue;
    }
    handle(event);
    // Match the robot's command channel now, long before its first command.
    if (event.kind == Event::Kind::kAnnouncement && !event.announcement.leaving &&
        fleet_transport::is_valid_robot_id(event.robot_id)) {
      transport.prepare_commands_for(event.robot_id);
    }
  }
  const Clock::time_point now = Clock::now();
  if (interrupt_ != nullptr && interrupt_->load()) planning_.cancel();
  if (role_ == fleet_transport::CoordinatorRole::kActive) {
    if (const OtherCoordinator* other = stronger_active(now)) {
      stand_down(*other, transport);
      return false;
    }
  }
  // A step that came long after the last one (planning, or the middleware holding this thread:
  // a 200-robot Fast DDS fleet coming together held it for 9 s) heard nobody meanwhile, through no
  // fault of the robots: their silence counts from now. A robot that died meanwhile is taken out
  // one silence timeout later; robots without commands stand still.
  if (const double stood_still_s = seconds_between(last_silence_check_, now); stood_still_s > kStoodStillS) {
    robots_.restart_silence_clocks(now);
    if (stood_still_s > config_.silence_timeout_s) {
      spdlog::warn("this coordinator stood still for {:.1f} s: robots' silence is counted from now", stood_still_s);
    }
  }
  last_silence_check_ = now;
  for (RobotRecord* robot : robots_.silent_robots(now, config_.silence_timeout_s)) {
    lose(*robot, "no state for " + std::to_string(config_.silence_timeout_s) + " s");
  }
  take_out_robots_deaf_to_commands(now);
  tell_refused_processes(transport, now);
  summary_.tasks_done = progress_.tasks_done();

  switch (phase_) {
    case Phase::kWaiting: {
      const std::vector<RobotRecord*> ready = robots_.ready_robots();
      const bool all_expected = !config_.any_robots && !ready.empty() && static_cast<int>(ready.size()) ==
                                                            static_cast<int>(config_.expected_robots.size());
      const bool quorum = config_.any_robots && static_cast<int>(ready.size()) >= config_.quorum;
      const bool timed_out = seconds_between(started_, now) > config_.wait_timeout_s && !ready.empty();
      // Listen for a lease first: another coordinator already active is heard, and this one stands down.
      const bool listened = seconds_between(started_, now) >= config_.lease_s;
      if (listened && (all_expected || quorum || timed_out)) {
        spdlog::info("{} robots ready: binding roles and planning", ready.size());
        bind_roles(ready);
        phase_ = Phase::kSettling;
        settle_deadline_ = now;
      }
      break;
    }
    case Phase::kStandby: follow(transport, now); break;
    case Phase::kExecuting:
      update_progress();
      if (replan_requested_) {
        phase_ = Phase::kSettling;
        settle_deadline_ = now + seconds(config_.replan_settle_s);
        break;
      }
      dispatch(transport);
      if (mission_complete()) {
        if (!lifelong_idle_) {
          report("mission_done", "", fmt::format("every task done ({} of {}), every robot on its goal",
                                                 progress_.tasks_done(), progress_.tasks_to_do()));
        }
        if (config_.lifelong) {
          if (!lifelong_idle_) spdlog::info("every task done: the robots park on their goals; waiting for tasks (lifelong)");
          lifelong_idle_ = true;
        } else {
          phase_ = Phase::kDone;
          summary_.completed = true;
        }
      } else if (plan_finished()) {
        // Everyone active is done. What is left belongs to roles without robots, or is blocked by a
        // lost robot (a replan from here changed nothing): wait for a robot, then end.
        const bool waiting_for_robot = replanned_after_finish_ || progress_.work_waits_for_a_robot();
        if (!waiting_for_robot) {
          replanned_after_finish_ = true;
          request_replan("plan finished with tasks left");
        } else if (!waiting_for_robot_since_) {
          waiting_for_robot_since_ = now;
          last_waiting_log_ = now;
          if (config_.replacement_timeout_s) {
            spdlog::warn("what is left cannot be done by the robots here: waiting {} s for a robot to join",
                         *config_.replacement_timeout_s);
          } else {
            spdlog::warn("what is left cannot be done by the robots here: the robots hold; waiting for a robot to "
                         "join (the mission times out {:.0f} s after it started)", config_.mission_timeout_s);
          }
          list_pending();
          for (const std::string& line : summary_.pending) spdlog::warn("  left: {}", line);
        } else if (config_.replacement_timeout_s &&
                   seconds_between(*waiting_for_robot_since_, now) > *config_.replacement_timeout_s) {
          spdlog::error("no robot joined within timing.replacement_timeout_s ({} s): the mission ends",
                        *config_.replacement_timeout_s);
          list_pending();
          phase_ = Phase::kDone;
        } else if (seconds_between(last_waiting_log_, now) >= 10) {
          last_waiting_log_ = now;
          spdlog::warn("still waiting for a robot to join ({:.0f} s so far)", seconds_between(*waiting_for_robot_since_, now));
        }
      } else if (waiting_for_robot_since_) {
        waiting_for_robot_since_.reset();  // a robot joined: the work goes on
        summary_.pending.clear();
      }
      break;
    case Phase::kSettling: {
      update_progress();
      bool moves_in_flight = false;
      for (int a = 0; plan_ && a < plan_->agent_count(); ++a) {
        const RobotRecord* robot = robot_of_agent(a);
        if (plan_->in_flight(a) && robot != nullptr && robot->active) moves_in_flight = true;
      }
      // Robots still carrying out another coordinator's last command (after a takeover or a restart).
      for (RobotRecord* robot : robots_.ready_robots()) {
        if (plans_made_ == 0 && robot->last.status == RobotStatus::kMoving) moves_in_flight = true;
      }
      // Plan only from where robots really stand: every move in flight must have ended (a robot
      // that never finishes is taken out by the silence timeout or its lease).
      if (moves_in_flight) dispatch(transport, /*resend_only=*/true);
      if (moves_in_flight && now >= settle_deadline_) {
        spdlog::warn("replanning waits for moves still in flight");
        settle_deadline_ = now + seconds(config_.replan_settle_s);
      }
      // The plan is made on the worker while this loop goes on; it is used only if the fleet is
      // still as it was planned from (robots, cells, roles, incarnations, walls, tasks).
      std::optional<PlanningOutcome> outcome = planning_.poll();
      if (!outcome && planning_.idle() && !moves_in_flight && now >= retry_plan_at_) {
        start_planning();
        // A quick plan is used in this very step, as when planning ran inside it; a long one goes
        // on beside the loop. The wait is far below a heartbeat period.
        outcome = planning_.wait_for(kQuickPlanWait);
      }
      if (outcome) {
        if (outcome->cancelled) {
          spdlog::info("planning was interrupted");
        } else if (const std::string change = what_changed_since(planned_from_); !change.empty()) {
          ++summary_.plans_discarded;
          spdlog::info("the fleet changed while planning ({}): the plan is dropped and made again", change);
        } else if (!finish_planning(std::move(*outcome), transport)) {
          retry_plan_at_ = now + seconds(1.0);
        }
      }
      break;
    }
    case Phase::kDone: break;
  }
  if (role_ == fleet_transport::CoordinatorRole::kActive && phase_ != Phase::kStandby &&
      (!mission_published_ || mission_changed_)) {
    publish_mission(transport);
  }
  for_operators("events", [&] {
    for (const fleet_transport::FleetEvent& event : events_to_publish_) transport.publish_fleet_event(event);
  });
  events_to_publish_.clear();
  if (now >= next_status_) publish_status(transport);
  if (now >= next_progress_ || (progress_changed_ && seconds_between(last_progress_, now) >= kProgressGapS)) {
    publish_progress(transport);
  }
  if (first_command_sent_) summary_.seconds = seconds_between(first_command_, now);
  if (phase_ == Phase::kDone) return false;
  if (phase_ != Phase::kStandby && !config_.lifelong && seconds_between(started_, now) > config_.mission_timeout_s) {
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

// Task visits count once committed to the journal: a restart never redoes a visit it counted.
void FleetCoordinator::credit_visits(int role, Vertex cell, const std::string& robot_id) {
  for (const fleet_transport::TaskVisit& visit : progress_.visits_due_at(role, cell)) {
    // Committed to the journal before it counts; a journal that failed no longer stops it counting.
    journal_write("task visit", [&](MissionJournal& journal) { journal.record_visit(visit, robot_id, epoch_); });
    progress_.mark(visit);
    progress_changed_ = true;
    if (progress_.task_done(visit.task)) {
      report("task_done", robot_id, fmt::format("task {} done", visit.task), visit.task);
    }
  }
}

void FleetCoordinator::handle_status(const fleet_transport::CoordinatorStatus& status, Clock::time_point received) {
  OtherCoordinator& other = others_[status.coordinator];
  const bool first = other.status.coordinator == 0;
  other.status = status;
  other.heard = received;
  if (first) {
    spdlog::info("heard coordinator {} ({}, term {}, mission {}, epoch {})", hex(status.coordinator),
                 fleet_transport::to_string(status.role), status.term, status.mission_id, status.plan_epoch);
  }
}

const FleetCoordinator::OtherCoordinator* FleetCoordinator::stronger_active(Clock::time_point now) const {
  const fleet_transport::CoordinatorStatus mine = own_status();
  for (const auto& [id, other] : others_) {
    if (other.status.role != fleet_transport::CoordinatorRole::kActive) continue;
    if (seconds_between(other.heard, now) > fleet_transport::LeaseTimeouts{config_.lease_s}.coordinator_gone_s()) {
      continue;  // gone
    }
    if (fleet_transport::outranks(other.status, mine)) return &other;
  }
  return nullptr;
}

void FleetCoordinator::stand_down(const OtherCoordinator& other, fleet_transport::Transport& transport) {
  const fleet_transport::CoordinatorStatus& s = other.status;
  const std::string why =
      s.term > term_
          ? fmt::format("it has a higher term ({} > {})", s.term, term_)
          : fmt::format("it claimed the fleet first ({} ms before this one)", claimed_ms_ - s.claimed_ms);
  summary_.stood_down = true;
  summary_.stood_down_because = fmt::format(
      "coordinator {} is already active on {} domain {} (term {}, mission {}{}, epoch {}) and {}", hex(s.coordinator),
      config_.dds_vendor, config_.domain_id, s.term, s.mission_id,
      s.mission_id == mission_id_ ? ", the same mission" : ", ANOTHER mission", s.plan_epoch, why);
  spdlog::error("standing down: {}. One coordinator drives a fleet: run a second one with --standby to follow the "
                "active one and take over if it fails.", summary_.stood_down_because);
  role_ = fleet_transport::CoordinatorRole::kStoodDown;
  phase_ = Phase::kDone;
  for_operators("events", [&] {
    transport.publish_fleet_event(
        {incarnation_, fleet_transport::wall_clock_ms(), "stood_down", "", summary_.stood_down_because, 0});
  });
  plan_.reset();  // not one more command
  publish_status(transport);
}

const FleetCoordinator::OtherCoordinator* FleetCoordinator::followed() const {
  const OtherCoordinator* best = nullptr;
  for (const auto& [id, other] : others_) {
    if (other.status.role != fleet_transport::CoordinatorRole::kActive || other.status.mission_id != mission_id_) continue;
    if (best == nullptr || fleet_transport::outranks(other.status, best->status)) best = &other;
  }
  return best;
}

// A standby keeps the active coordinator's progress (its done visits, its bindings, its epoch) and
// takes over once that coordinator has been silent for a lease and a half.
void FleetCoordinator::follow(fleet_transport::Transport& transport, Clock::time_point now) {
  // The followed coordinator ended the mission (completed or not): so does its standby.
  if (const auto it = others_.find(mirrored_);
      it != others_.end() && it->second.status.role == fleet_transport::CoordinatorRole::kEnded) {
    for (const fleet_transport::TaskVisit& visit : it->second.progress.done_visits) progress_.mark(visit);
    summary_.tasks_done = progress_.tasks_done();
    summary_.completed = progress_.all_tasks_done();
    spdlog::info("standby: coordinator {} ended the mission ({} of {} tasks done); the standby ends too", hex(mirrored_),
                 summary_.tasks_done, summary_.tasks_total);
    phase_ = Phase::kDone;
    return;
  }
  const OtherCoordinator* active = followed();
  if (active == nullptr) {
    if (!logged_no_active_) {
      logged_no_active_ = true;
      spdlog::info("standby: waiting for an active coordinator of mission {}", mission_id_);
    }
    return;
  }
  if (active->status.coordinator != mirrored_) {
    mirrored_ = active->status.coordinator;
    spdlog::info("standby: follows coordinator {} (term {})", hex(mirrored_), active->status.term);
  }
  if (active->mission) adopt_tasks(*active->mission);
  for (const fleet_transport::TaskVisit& visit : active->progress.done_visits) progress_.mark(visit);
  mirrored_roles_.clear();
  std::set<std::string> driven;
  for (const fleet_transport::Assignment& row : active->progress.assignments) {
    driven.insert(row.robot_id);
    if (row.role >= 0 && row.role < mission_.agent_count()) mirrored_roles_[row.robot_id] = row.role;
  }
  std::erase_if(mirrored_since_, [&](const auto& entry) { return driven.count(entry.first) == 0; });
  for (const std::string& id : driven) mirrored_since_.emplace(id, now);
  epoch_ = std::max(epoch_, active->status.plan_epoch);
  summary_.tasks_done = progress_.tasks_done();
  // The command writers get the strength of the term a takeover would have now, so that changing
  // it (which DDS announces per writer) is not on the takeover's path.
  const int next_term = static_cast<int>(active->status.term) + 1;
  if (command_strength_ != next_term) {
    transport.set_command_strength(next_term);
    command_strength_ = next_term;
  }
  // The active coordinator is silent: dead, or cut off from this host. It may still drive robots
  // this standby cannot hear (a network split with robots on both sides), and a plan that takes
  // them for walls at their last cells would drive robots into them. So it takes over only once it
  // has heard, since the active one fell silent, every robot that one drove, and has heard them
  // for two status periods: when a split heals, the robots' states may come back a little before
  // the active one's status, which must not read as its death.
  const double silent_s = seconds_between(active->heard, now);
  const Clock::duration status_gap = seconds(2 * kStatusPeriodS);
  if (now - active->heard <= status_gap) {
    if (active_fell_silent_) {  // heard again after a silence; so are the robots, a moment apart
      for (auto& [id, since] : mirrored_since_) since = now;
    }
    active_fell_silent_ = false;
    logged_unheard_robots_ = false;
    every_robot_heard_since_.reset();
    warn_of_driven_robots_not_heard(now);
    return;
  }
  active_fell_silent_ = true;
  // "Since" leaves the same gap: a robot's last state from before a split may arrive after the
  // active one's last status (sent up to a period before the split).
  const std::vector<std::string> unheard = robots_unheard_since(active->heard + status_gap);
  if (!unheard.empty()) every_robot_heard_since_.reset();
  if (unheard.empty() && !every_robot_heard_since_) every_robot_heard_since_ = now;
  if (silent_s <= fleet_transport::LeaseTimeouts{config_.lease_s}.standby_takes_over_after_s()) return;
  if (every_robot_heard_since_ && now - *every_robot_heard_since_ >= status_gap) {
    take_over(transport, *active, now);
    return;
  }
  if (!unheard.empty() && !logged_unheard_robots_) {
    logged_unheard_robots_ = true;
    constexpr size_t kNamed = 8;
    std::string names;
    for (size_t i = 0; i < std::min(unheard.size(), kNamed); ++i) names += (i == 0 ? "" : ", ") + unheard[i];
    if (unheard.size() > kNamed) names += fmt::format(" and {} more", unheard.size() - kNamed);
    spdlog::warn("standby: coordinator {} (term {}) silent for {:.2f} s, but so {} {}: this host may be cut off "
                 "from part of the fleet, which that coordinator may still drive; taking over once every robot "
                 "is heard",
                 hex(active->status.coordinator), active->status.term, silent_s, unheard.size() == 1 ? "is" : "are",
                 names);
  }
}

void FleetCoordinator::warn_of_driven_robots_not_heard(Clock::time_point now) {
  if (now < next_not_heard_check_) return;  // a standby steps every few ms; robots report ten times a second
  next_not_heard_check_ = now + seconds(kStatusPeriodS);
  const Clock::duration silence = seconds(config_.silence_timeout_s);
  for (const auto& [id, since] : mirrored_since_) {
    const RobotRecord* robot = robots_.find(id);
    const bool heard = robot != nullptr && robot->has_state && now - robot->last_state_received <= silence;
    if (heard) {
      warned_not_heard_.erase(id);
    } else if (now - since > silence && warned_not_heard_.insert(id).second) {
      spdlog::warn("standby: robot {}, which coordinator {} drives, is not heard here: this standby could not take "
                   "over while it is not (check this host's network)",
                   id, hex(mirrored_));
    }
  }
}

std::vector<std::string> FleetCoordinator::robots_unheard_since(Clock::time_point since) const {
  std::set<std::string> drivable;
  for (const auto& [id, since] : mirrored_since_) drivable.insert(id);
  for (const auto& [id, robot] : robots_) {
    if (robot.active && robot.has_state) drivable.insert(id);  // joined after the last progress heard
  }
  std::vector<std::string> unheard;
  for (const std::string& id : drivable) {
    const RobotRecord* robot = robots_.find(id);
    if (robot != nullptr && robot->said_goodbye) continue;  // it left: nobody drives it any more
    if (robot == nullptr || !robot->has_state || robot->last_state_received <= since) unheard.push_back(id);
  }
  return unheard;
}

void FleetCoordinator::take_over(fleet_transport::Transport& transport, const OtherCoordinator& old,
                                 Clock::time_point now) {
  uint32_t highest = old.status.term;
  for (const auto& [id, other] : others_) highest = std::max(highest, other.status.term);
  if (options_.journal) highest = std::max(highest, options_.journal->highest_term());
  term_ = highest + 1;
  claimed_ms_ = fleet_transport::wall_clock_ms();
  role_ = fleet_transport::CoordinatorRole::kActive;
  summary_.took_over = true;
  summary_.term = term_;
  summary_.tasks_done_before = progress_.tasks_done();
  spdlog::warn("coordinator {} (term {}) silent for {:.2f} s: taking over as term {} at epoch {}; {} task visits "
               "and {} of {} tasks done",
               hex(old.status.coordinator), old.status.term, seconds_between(old.heard, now), term_, epoch_,
               progress_.done_visits().size(), progress_.tasks_done(), progress_.task_count());
  if (command_strength_ != static_cast<int>(term_)) {  // set ahead while following, normally
    const Clock::time_point before = Clock::now();
    transport.set_command_strength(static_cast<int>(term_));
    command_strength_ = static_cast<int>(term_);
    spdlog::info("command strength set to {} in {:.0f} ms", term_, 1000 * seconds_between(before, Clock::now()));
  }
  if (options_.journal) {
    journal_write("claim", [&](MissionJournal& journal) { journal.claim(term_, incarnation_, claimed_ms_); });
    journal_added_tasks();
    for (const fleet_transport::TaskVisit& visit : progress_.done_visits()) {
      journal_write("task visit",
                    [&](MissionJournal& journal) { journal.record_visit(visit, progress_.robot_of(visit.role), epoch_); });
    }
  }
  // The old coordinator's bindings hold for the robots still here; the others are bound afresh.
  for (int role = 0; role < mission_.agent_count(); ++role) progress_.unbind(role);
  for (auto& [id, robot] : robots_) robot.role = -1;
  std::vector<RobotRecord*> rest;
  for (RobotRecord* robot : robots_.ready_robots()) {
    const auto kept = mirrored_roles_.find(robot->id);
    if (kept != mirrored_roles_.end() && progress_.robot_of(kept->second).empty()) {
      bind_role(kept->second, *robot);
    } else {
      rest.push_back(robot);
    }
  }
  bind_roles(rest);
  report("takeover", "",
         fmt::format("coordinator {} silent for {:.2f} s: {} takes over as term {}", hex(old.status.coordinator),
                     seconds_between(old.heard, now), hex(incarnation_), term_));
  others_.erase(old.status.coordinator);
  phase_ = Phase::kSettling;
  settle_deadline_ = now;
  replan_requested_at_ = now;
  awaiting_replan_latency_ = true;
  publish_status(transport);
  publish_progress(transport);
}

void FleetCoordinator::finish(fleet_transport::Transport& transport) {
  if (role_ == fleet_transport::CoordinatorRole::kActive) role_ = fleet_transport::CoordinatorRole::kEnded;
  if (role_ == fleet_transport::CoordinatorRole::kStandby) role_ = fleet_transport::CoordinatorRole::kEnded;
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
