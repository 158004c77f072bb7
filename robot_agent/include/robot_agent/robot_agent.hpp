// RobotAgent: one robot's bridge between the fleet's DDS messages and its backend. Announces the
// robot, executes step commands addressed to it (checking each one), publishes its state.
#pragma once

#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "fleet_transport/transport.hpp"
#include "robot_agent/robot_backend.hpp"

namespace robot_agent {

struct AgentSettings {
  std::string robot_id;
  double state_rate_hz = 10;  // periodic state, besides one at every arrival
  std::string version = "0.1.0";
  uint64_t first_seq_number = 1;  // of the first state (a test starts high to play a long-running robot)
};

class RobotAgent {
 public:
  RobotAgent(const AgentSettings& settings, RobotBackend& backend);

  // Call from the transport's command handler (any thread).
  void on_command(const fleet_transport::StepCommand& command);
  // One iteration of the agent's loop: advance the backend, start commands, publish state when due.
  // Returns false when the agent must stop (crash fault).
  void step(fleet_transport::Transport& transport, bool reporting);
  fleet_transport::Announcement announcement() const;
  // This process's incarnation: random, never 0, in every announcement and state.
  uint64_t incarnation() const { return incarnation_; }
  // Sleeps until a command arrives or `timeout` passes (whichever is first).
  void wait_for_command(std::chrono::steady_clock::duration timeout);
  // How long the agent may sleep before step() has something to do (next state or arrival).
  std::chrono::steady_clock::duration idle_time() const;

 private:
  void reject(const fleet_transport::StepCommand& command, const std::string& why);

  AgentSettings settings_;
  RobotBackend& backend_;
  std::mutex mutex_;
  std::condition_variable command_arrived_;
  std::optional<fleet_transport::StepCommand> pending_;  // the newest accepted command not yet started
  GridCell next_start_{};  // where the robot will be when it starts its next command
  int epoch_ = -1;
  int accepted_index_ = -1;  // highest action index accepted in epoch_
  // The command executing or executed last.
  int executing_epoch_ = -1;
  int executing_index_ = -1;
  bool was_moving_ = false;
  bool in_fault_ = false;  // written by step() under mutex_: commands are refused meanwhile
  bool has_stood_on_a_cell_ = false;  // until then the robot has no cell to report
  int fault_epoch_ = -1;  // commands of this epoch or older were issued before a fault
  GridCell moving_to_{};
  uint64_t seq_ = 0;
  uint64_t incarnation_ = 0;
  std::chrono::steady_clock::time_point next_publish_{};
};

}  // namespace robot_agent
