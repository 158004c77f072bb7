// SimRobot: a simulated robot that moves cell to cell at a configured speed with random jitter,
// turning in place first when it does not face the way it goes (turn_s per quarter turn; 0, the
// default, turns in no time, a robot that moves any way as fast), plus fault injection (stall for a while, stop reporting, crash, be carried to another cell).
#pragma once

#include <chrono>
#include <optional>
#include <random>

#include "robot_agent/robot_backend.hpp"

namespace robot_agent {

struct SimSettings {
  double step_s = 0.2;          // nominal time of one move
  double jitter = 0.2;          // each move takes step_s * (1 + U[0, jitter])
  double turn_s = 0;            // time of a quarter turn in place (jittered the same way); 0: turns are free
  int start_heading = 0;        // 0 east, 1 south, 2 west, 3 north
  double delay_probability = 0;  // chance that a move is delayed by delay_s more
  double delay_s = 0;
  uint32_t seed = 0;
  // Faults, in seconds since the robot started (negative = never).
  double stall_at_s = -1;       // stop moving for stall_for_s
  double stall_for_s = 0;
  double silent_at_s = -1;      // stop reporting (the agent checks reporting_enabled)
  double crash_at_s = -1;       // the process aborts
  int teleport_after_moves = -1;  // after this many moves the robot is carried by hand to teleport_to
  Cell teleport_to{};
};

class SimRobot : public RobotBackend {
 public:
  SimRobot(Cell start, const SimSettings& settings);
  std::string kind() const override { return "sim"; }
  bool start_move(Cell target, int target_heading) override;
  BackendReport poll() override;
  std::optional<std::chrono::steady_clock::duration> time_to_arrival() const override;
  bool starts_moves_at_once() const override { return true; }
  bool reporting_enabled() const;
  bool should_crash() const;

 private:
  using Clock = std::chrono::steady_clock;
  double since_start_s() const;

  SimSettings settings_;
  std::mt19937 rng_;
  Clock::time_point started_;
  Cell cell_;
  int heading_;
  int64_t arrived_ms_;
  std::optional<Cell> target_;
  int target_heading_ = 0;
  Clock::time_point move_started_;
  Clock::time_point turn_ends_;  // the turn in place before the move (or the whole step, for a turn)
  Clock::time_point move_ends_;
  bool teleported_ = false;
  int moves_done_ = 0;
};

}  // namespace robot_agent
