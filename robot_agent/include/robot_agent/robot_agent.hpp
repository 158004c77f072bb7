// RobotAgent: one robot's bridge between the fleet's DDS messages and its backend. Announces the
// robot, executes step commands addressed to it (checking each one), publishes its state.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>

#include "fleet_transport/transport.hpp"
#include "robot_agent/clock_offset.hpp"
#include "robot_agent/robot_backend.hpp"

namespace robot_agent {

struct AgentSettings {
  std::string robot_id;
  double state_rate_hz = 10;  // periodic state, besides one at every arrival
  std::string version = "0.1.0";
  uint64_t first_seq_number = 1;  // of the first state (a test starts high to play a long-running robot)
  // A coordinator not heard for this long is no longer followed once another one is active.
  double coordinator_silence_s = 2.0;
  uint64_t incarnation = 0;  // this process's; 0: a random one (tests fix it)
};

class RobotAgent {
 public:
  RobotAgent(const AgentSettings& settings, RobotBackend& backend);

  // Call from the transport's handlers (any thread). Commands are obeyed only from the coordinator
  // the robot follows (the highest-ranked active one heard), and only for epochs it has announced
  // in its status; a command that cannot be judged yet (its coordinator or epoch not yet heard) is
  // held, the newest one, until the next status.
  void on_command(const fleet_transport::StepCommand& command);
  void on_coordinator_status(const fleet_transport::CoordinatorStatus& status);
  // The coordinator followed now (0: none yet).
  uint64_t followed_coordinator() const;
  // One iteration of the agent's loop: advance the backend, start commands, publish state when due.
  void step(fleet_transport::Transport& transport, bool reporting);
  // With a backend that starts moves at once (the sim): from now on, an accepted command is
  // started, and the state that acknowledges it published, on the thread that received it (DDS's)
  // rather than after the agent's loop wakes up. `transport` must outlive the agent's handlers.
  void start_commands_where_they_arrive(fleet_transport::Transport& transport, std::function<bool()> reporting);
  fleet_transport::Announcement announcement() const;
  // This process's incarnation: random, never 0, in every announcement and state.
  uint64_t incarnation() const { return incarnation_; }
  // Sleeps until a command arrives (or was started on a receiving thread) or `timeout` passes.
  void wait_for_command(std::chrono::steady_clock::duration timeout);
  // How long the agent may sleep before step() has something to do (next state or arrival).
  std::chrono::steady_clock::duration idle_time() const;
  // Moves of a plan with turns that the robot started not facing their way (it turned first, so
  // the plan's timing and the robot's disagree): 0 when the coordinator's headings are right. A
  // move whose index skips the previous one's (the coordinator folded turns into it) is meant to
  // turn first and is not counted.
  int moves_started_off_heading() const;

 private:
  struct KnownCoordinator {
    fleet_transport::CoordinatorStatus status;
    std::chrono::steady_clock::time_point heard;
  };
  void reject(const fleet_transport::StepCommand& command, const std::string& why);
  // Under step_mutex_.
  void step_locked(fleet_transport::Transport& transport, bool reporting);
  // After a command was accepted (not under mutex_): starts it on this thread if
  // start_commands_where_they_arrive allows it and no other thread is stepping; otherwise wakes
  // the loop to start it.
  void start_accepted_command();
  // Both under mutex_. consider() leaves an accepted command in pending_ and wakes nobody.
  void consider(const fleet_transport::StepCommand& command);
  void choose_coordinator();

  AgentSettings settings_;
  RobotBackend& backend_;
  // step() may run on the agent's loop and on a receiving thread: one at a time. Taken before
  // mutex_, never after it. It guards the backend and what only step() writes.
  mutable std::mutex step_mutex_;
  std::atomic<fleet_transport::Transport*> start_here_transport_{nullptr};
  std::function<bool()> start_here_reporting_;  // set once, before start_here_transport_
  mutable std::mutex mutex_;
  std::condition_variable command_arrived_;
  std::optional<fleet_transport::StepCommand> pending_;  // the newest accepted command not yet started
  std::optional<fleet_transport::StepCommand> held_;     // the newest command not judged yet
  bool loop_must_look_again_ = false;  // a command was started on a receiving thread
  std::chrono::steady_clock::time_point loop_wakes_at_{};  // the end of the loop's last sleep
  std::map<uint64_t, KnownCoordinator> coordinators_;
  std::map<uint64_t, ClockOffset> clock_offsets_;  // per sending coordinator (hosts' clocks differ)
  uint64_t followed_ = 0;
  Cell next_start_{};  // where the robot will be when it starts its next command
  int epoch_ = -1;
  int accepted_index_ = -1;  // highest action index accepted in epoch_
  // The command executing or executed last.
  int executing_epoch_ = -1;
  int executing_index_ = -1;
  uint64_t executing_coordinator_ = 0;
  bool was_moving_ = false;
  // Refused by the coordinator followed: another process drives this robot id. Stands still and
  // obeys nothing until a plan made after the refusal drives it.
  bool refused_ = false;
  int refused_epoch_ = -1;  // the epoch of the latest refusal: only a later plan drives it again
  std::set<uint64_t> foreign_incarnations_;  // other processes with this id whose commands were seen (logged once)
  bool in_fault_ = false;  // written by step() under mutex_: commands are refused meanwhile
  bool has_stood_on_a_cell_ = false;  // until then the robot has no cell to report
  int fault_epoch_ = -1;  // commands of this epoch or older were issued before a fault
  Cell moving_to_{};
  int moves_started_off_heading_ = 0;  // under step_mutex_
  uint64_t seq_ = 0;
  uint64_t incarnation_ = 0;
  std::chrono::steady_clock::time_point next_publish_{};
};

}  // namespace robot_agent
