// SimRobot: a simulated robot that moves cell to cell at a configured speed with random jitter,
// turning in place first when it does not face the way it goes (turn_s per quarter turn; 0, the
// default, turns in no time, a robot that moves any way as fast), plus fault injection (stall for a while, stop reporting, crash, be carried to another cell).
#pragma once

#include <chrono>
#include <optional>
#include <random>

#include "planner_core/delay_draws.hpp"
#include "planner_core/lorr_problem.hpp"
#include "robot_agent/robot_backend.hpp"

namespace robot_agent {

struct SimSettings {
  double step_s = 0.2;          // nominal time of one move
  double jitter = 0.2;          // each move takes step_s * (1 + U[0, jitter])
  double turn_s = 0;            // time of a quarter turn in place (jittered the same way); 0: turns are free
  int start_heading = 0;        // 0 east, 1 south, 2 west, 3 north
  double delay_probability = 0;  // chance that a move is delayed by delay_s more
  double delay_s = 0;
  // Delays as the league's 2026 rules draw them (planner_core/delay_draws.hpp), in ticks of
  // delay_tick_s (0: step_s / 3, the agentCounter of every Start-Kit example): while the robot is
  // delayed it stands still, so a move takes as many more ticks as fall in a delay. The draws'
  // seed is the delayConfig's seed plus `seed`, so each robot has its own and a run repeats.
  std::optional<planner_core::LeagueDelays> league_delays;
  double delay_tick_s = 0;
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
  // League delays: ticks drawn so far, and those the robot spent delayed.
  int64_t delay_ticks_drawn() const { return ticks_drawn_; }
  int64_t delayed_ticks() const { return draws_ ? draws_->delayed_robot_ticks() : 0; }

 private:
  using Clock = std::chrono::steady_clock;
  double since_start_s() const;
  // A move of `seconds` stretched by the league delays that fall in it (and those drawn while the
  // robot stood since the last move).
  double with_league_delays(double seconds);
  double delay_tick_s() const { return settings_.delay_tick_s > 0 ? settings_.delay_tick_s : settings_.step_s / 3; }

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
  std::optional<planner_core::DelayDraws> draws_;
  int64_t ticks_drawn_ = 0;
};

}  // namespace robot_agent
