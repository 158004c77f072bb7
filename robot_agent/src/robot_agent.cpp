#include "robot_agent/robot_agent.hpp"

#include <random>

#include <spdlog/spdlog.h>

#include "planner_core/compass.hpp"

#include <cstdlib>

namespace robot_agent {

using fleet_transport::RobotStatus;
using fleet_transport::StepCommand;

namespace {

// A random 64-bit number, never 0 (0 means "not set" on the wire).
uint64_t new_incarnation() {
  std::random_device device;
  uint64_t value = 0;
  while (value == 0) value = (static_cast<uint64_t>(device()) << 32) ^ device();
  return value;
}

}  // namespace

RobotAgent::RobotAgent(const AgentSettings& settings, RobotBackend& backend)
    : settings_(settings),
      backend_(backend),
      next_start_(backend.poll().cell),
      seq_(settings.first_seq_number > 0 ? settings.first_seq_number - 1 : 0),
      incarnation_(settings.incarnation != 0 ? settings.incarnation : new_incarnation()) {}

fleet_transport::Announcement RobotAgent::announcement() const {
  return {settings_.robot_id, backend_.kind(), "grid-4,wait", settings_.version, false, incarnation_};
}

void RobotAgent::reject(const StepCommand& command, const std::string& why) {
  spdlog::warn("{}: rejected command epoch {} action {} to ({},{}): {}", settings_.robot_id, command.plan_epoch,
               command.action_index, command.target_x, command.target_y, why);
}

void RobotAgent::on_command(const StepCommand& command) {
  if (command.robot_id != settings_.robot_id) {
    reject(command, "addressed to robot '" + command.robot_id + "'");
    return;
  }
  bool accepted = false;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    consider(command);
    accepted = pending_.has_value();
  }
  if (accepted) start_accepted_command();
}

void RobotAgent::start_commands_where_they_arrive(fleet_transport::Transport& transport,
                                                  std::function<bool()> reporting) {
  if (!backend_.starts_moves_at_once()) return;  // a blocking backend must not hold DDS's thread
  start_here_reporting_ = std::move(reporting);
  start_here_transport_.store(&transport);
}

void RobotAgent::start_accepted_command() {
  fleet_transport::Transport* transport = start_here_transport_.load();
  std::unique_lock<std::mutex> stepping(step_mutex_, std::defer_lock);
  if (transport == nullptr || !stepping.try_lock()) {
    // The loop starts it: a backend that may block, or another thread stepping, which may have
    // looked for a command already (rare). Otherwise the loop is left asleep: waking it too
    // would cost every agent a second thread wake-up per command, in the burst of a plan's
    // first commands where 100 agents share two cores with the coordinator.
    command_arrived_.notify_one();
    return;
  }
  step_locked(*transport, start_here_reporting_());
  // The loop chose how long to sleep before this move began. It must look again, at the latest
  // when the move ends (to report the arrival at once): woken if it would sleep past that (a
  // move shorter than its sleep), otherwise when its sleep ends, which spares a wake-up.
  const auto arrival = backend_.time_to_arrival();
  const std::lock_guard<std::mutex> lock(mutex_);
  loop_must_look_again_ = true;
  if (arrival && std::chrono::steady_clock::now() + *arrival < loop_wakes_at_) command_arrived_.notify_one();
}

void RobotAgent::on_coordinator_status(const fleet_transport::CoordinatorStatus& status) {
  bool accepted = false;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    KnownCoordinator& known = coordinators_[status.coordinator];
    known.status = status;
    known.heard = std::chrono::steady_clock::now();
    choose_coordinator();
    if (held_) {  // its coordinator or epoch may be announced now
      const StepCommand command = *held_;
      held_.reset();
      consider(command);
      accepted = pending_.has_value();
    }
  }
  if (accepted) start_accepted_command();
}

uint64_t RobotAgent::followed_coordinator() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return followed_;
}

// Follows the highest-ranked active coordinator heard lately. A switch starts a new epoch space:
// the new coordinator plans from where the robot stands, so nothing of the old one's is kept.
void RobotAgent::choose_coordinator() {
  const auto now = std::chrono::steady_clock::now();
  const auto silence = std::chrono::duration<double>(settings_.coordinator_silence_s);
  const KnownCoordinator* best = nullptr;
  for (const auto& [id, known] : coordinators_) {
    if (known.status.role != fleet_transport::CoordinatorRole::kActive || now - known.heard > silence) continue;
    if (best == nullptr || fleet_transport::outranks(known.status, best->status)) best = &known;
  }
  if (best == nullptr || best->status.coordinator == followed_) return;
  spdlog::info("{}: follows coordinator {:016x} (term {}, mission {}){}", settings_.robot_id, best->status.coordinator,
               best->status.term, best->status.mission_id,
               followed_ == 0 ? "" : fmt::format(" instead of {:016x}", followed_));
  followed_ = best->status.coordinator;
  epoch_ = -1;
  accepted_index_ = -1;
  fault_epoch_ = in_fault_ ? 0 : -1;  // a robot in fault waits for the new coordinator's replan
  if (pending_) spdlog::warn("{}: dropped the old coordinator's command not yet started", settings_.robot_id);
  pending_.reset();
}

void RobotAgent::consider(const StepCommand& command) {
  // One robot id, one body: a command is for one process (the one whose states the coordinator
  // took). Another process with this id (an impostor, or this robot started twice) ignores it.
  if (command.robot_incarnation != incarnation_) {
    if (foreign_incarnations_.size() < 16 && foreign_incarnations_.insert(command.robot_incarnation).second) {
      spdlog::error("{}: a command for another process with this robot id (incarnation {:016x}; this process is "
                    "{:016x}) is ignored: two processes claim robot id {}",
                    settings_.robot_id, command.robot_incarnation, incarnation_, settings_.robot_id);
    }
    return;
  }
  // Checked first, so a late or replayed command can neither be held nor change the epoch.
  // The deadline is on the sender's clock: compared with ours through the offset learnt from its
  // send stamps, so a host whose clock is seconds off still takes the commands in time.
  const int64_t now = fleet_transport::wall_clock_ms();
  if (command.deadline_ms > 0) {
    int64_t offset = 0;  // a sender that stamps nothing is taken to share our clock
    if (command.sent_ms > 0) {
      if (clock_offsets_.size() > 16) clock_offsets_.clear();  // forged senders cannot grow it without bound
      ClockOffset& clock = clock_offsets_[command.coordinator];
      clock.add(command.sent_ms, now);
      offset = *clock.offset_ms();
    }
    if (command.deadline_ms + offset < now) {
      reject(command, "its deadline passed " + std::to_string(now - command.deadline_ms - offset) +
                          " ms ago (a late or replayed command)");
      return;
    }
  }
  choose_coordinator();
  const auto sender = coordinators_.find(command.coordinator);
  if (sender == coordinators_.end() || followed_ == 0) {
    held_ = command;  // its coordinator's status has not arrived yet
    return;
  }
  if (command.coordinator != followed_) {
    reject(command, fmt::format("from coordinator {:016x}; this robot follows {:016x}", command.coordinator, followed_));
    return;
  }
  if (command.refused) {
    if (!refused_) {
      spdlog::error("{}: refused by coordinator {:016x}: another process drives robot id {}; this process stands "
                    "still at ({},{}) and obeys no command (stop it, or start it with an id of its own)",
                    settings_.robot_id, command.coordinator, settings_.robot_id, next_start_.x, next_start_.y);
    }
    refused_ = true;
    refused_epoch_ = std::max(refused_epoch_, command.plan_epoch);
    pending_.reset();
    return;
  }
  if (command.plan_epoch > sender->second.status.plan_epoch) {
    held_ = command;  // an epoch its coordinator has not announced (yet): never jumped to
    return;
  }
  if (refused_) {
    // Only a plan made after the refusal drives it again (this process then drives the id).
    if (command.plan_epoch <= refused_epoch_) {
      reject(command, "this process was refused in epoch " + std::to_string(refused_epoch_));
      return;
    }
    spdlog::warn("{}: coordinator {:016x} drives this process again in epoch {} (its refusal is lifted)",
                 settings_.robot_id, command.coordinator, command.plan_epoch);
    refused_ = false;
  }
  if (command.plan_epoch < epoch_) {
    reject(command, "stale plan epoch (current epoch " + std::to_string(epoch_) + ")");
    return;
  }
  if (in_fault_) {
    reject(command, "the robot is in fault");
    return;
  }
  if (command.plan_epoch <= fault_epoch_) {
    reject(command, "plan epoch " + std::to_string(command.plan_epoch) +
                        " was made before the robot's fault; waiting for a new plan");
    return;
  }
  if (std::abs(command.target_x - next_start_.x) + std::abs(command.target_y - next_start_.y) > 1) {
    reject(command, "not a move to a neighbouring cell of (" + std::to_string(next_start_.x) + "," +
                        std::to_string(next_start_.y) + ") or a wait");
    return;
  }
  if (command.plan_epoch == epoch_ && command.action_index <= accepted_index_) return;  // a repeat
  epoch_ = command.plan_epoch;
  accepted_index_ = command.action_index;
  pending_ = command;  // a newer command (or epoch) supersedes one not yet started
}

void RobotAgent::wait_for_command(std::chrono::steady_clock::duration timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  loop_wakes_at_ = std::chrono::steady_clock::now() + timeout;
  command_arrived_.wait_for(lock, timeout, [this] { return pending_.has_value() || loop_must_look_again_; });
  loop_must_look_again_ = false;
}

int RobotAgent::moves_started_off_heading() const {
  const std::lock_guard<std::mutex> stepping(step_mutex_);
  return moves_started_off_heading_;
}

std::chrono::steady_clock::duration RobotAgent::idle_time() const {
  const std::lock_guard<std::mutex> stepping(step_mutex_);
  const auto now = std::chrono::steady_clock::now();
  auto until = next_publish_ - now;
  if (const auto arrival = backend_.time_to_arrival()) until = std::min(until, *arrival);
  return std::max(until, std::chrono::steady_clock::duration::zero());
}

void RobotAgent::step(fleet_transport::Transport& transport, bool reporting) {
  const std::lock_guard<std::mutex> stepping(step_mutex_);
  step_locked(transport, reporting);
}

void RobotAgent::step_locked(fleet_transport::Transport& transport, bool reporting) {
  BackendReport report = backend_.poll();
  // in_fault_ is written only here (under step_mutex_), so it may be read here without mutex_.
  bool publish_now = (was_moving_ && !report.moving) || report.fault != in_fault_;  // report changes at once
  if (report.fault != in_fault_) {
    // The coordinator takes a faulted robot out and replans; nothing of the old plan may move it.
    const std::lock_guard<std::mutex> lock(mutex_);
    in_fault_ = report.fault;
    if (report.fault) {
      fault_epoch_ = epoch_;
      if (pending_) spdlog::warn("{}: fault: dropped the command not yet started", settings_.robot_id);
      pending_.reset();
    }
  }
  if (!report.moving && !report.fault) {
    std::optional<StepCommand> command;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      command.swap(pending_);
    }
    if (command) {
      const int dx = std::abs(command->target_x - report.cell.x), dy = std::abs(command->target_y - report.cell.y);
      const Cell target{command->target_x, command->target_y};
      const int travel = planner_core::heading_between(report.cell, target);
      if (dx + dy > 1) {
        reject(*command, "not a neighbouring cell of (" + std::to_string(report.cell.x) + "," +
                             std::to_string(report.cell.y) + ")");
      } else if (command->target_heading < -1 || command->target_heading > 3) {
        reject(*command, "target heading " + std::to_string(command->target_heading) + " is not -1, 0, 1, 2 or 3");
      } else if (travel >= 0 && command->target_heading >= 0 && command->target_heading != travel) {
        reject(*command, "a move to (" + std::to_string(target.x) + "," + std::to_string(target.y) +
                             ") ends facing " + std::to_string(travel) + ", not " +
                             std::to_string(command->target_heading));
      } else if (backend_.start_move(target, command->target_heading)) {
        // The next move straight after the last one (not one with turns folded in: its index skips
        // theirs, and the robot is meant to turn first) must start facing its way.
        const bool next_in_line = command->plan_epoch == executing_epoch_ ? command->action_index == executing_index_ + 1
                                                                           : command->action_index == 0;
        if (next_in_line && travel >= 0 && command->target_heading >= 0 && report.heading >= 0 &&
            report.heading != travel) {
          ++moves_started_off_heading_;
          spdlog::warn("{}: the move to ({},{}) of epoch {} step {} goes facing {}, but the robot faced {}: it "
                       "turned first (the plan has it facing the wrong way)",
                       settings_.robot_id, target.x, target.y, command->plan_epoch, command->action_index, travel,
                       report.heading);
        }
        moving_to_ = {command->target_x, command->target_y};
        executing_epoch_ = command->plan_epoch;
        executing_index_ = command->action_index;
        executing_coordinator_ = command->coordinator;
        report = backend_.poll();
        publish_now = true;
      }
    }
  }
  was_moving_ = report.moving;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    next_start_ = report.moving ? moving_to_ : report.cell;
  }
  // Until the robot has once stood on a cell (a toio cube still connecting), it has no cell to
  // report, and the fleet must not see a made-up one.
  if (!report.fault) has_stood_on_a_cell_ = true;
  const auto now = std::chrono::steady_clock::now();
  if (!reporting || !has_stood_on_a_cell_ || (!publish_now && now < next_publish_)) return;
  next_publish_ = now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                            std::chrono::duration<double>(1.0 / settings_.state_rate_hz));
  fleet_transport::RobotState state;
  state.robot_id = settings_.robot_id;
  state.cell_x = report.cell.x;
  state.cell_y = report.cell.y;
  state.pose_x = report.pose_x;
  state.pose_y = report.pose_y;
  state.pose_theta = report.pose_theta;
  state.heading = report.heading;
  state.plan_epoch = executing_epoch_;
  state.action_index = executing_index_;
  state.status = report.fault ? RobotStatus::kFault
                 : report.moving ? RobotStatus::kMoving
                 : executing_index_ >= 0 ? RobotStatus::kArrived
                                          : RobotStatus::kIdle;
  state.battery_percent = report.battery_percent;
  state.seq_number = ++seq_;
  state.incarnation = incarnation_;
  state.coordinator = executing_coordinator_;
  state.stamp_ms = report.arrived_ms;
  transport.publish_state(state);
}

}  // namespace robot_agent
