#include "robot_agent/sim_robot.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "planner_core/compass.hpp"

namespace robot_agent {

namespace {

using Clock = std::chrono::steady_clock;

Clock::duration seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

}  // namespace

SimRobot::SimRobot(Cell start, const SimSettings& settings)
    : settings_(settings),
      rng_(settings.seed),
      started_(Clock::now()),
      cell_(start),
      heading_(((settings.start_heading % 4) + 4) % 4),
      arrived_ms_(wall_clock_ms()) {
  if (settings.league_delays) {
    planner_core::LeagueDelays delays = *settings.league_delays;
    delays.seed += settings.seed;
    draws_.emplace(delays, 1);
  }
}

double SimRobot::with_league_delays(double move_s) {
  // At most 100,000 ticks drawn at once (hours): a robot delayed for ever (pDelay 1) never arrives.
  constexpr int64_t kMostTicks = 100'000;
  const double tick_s = delay_tick_s();
  const auto standing = static_cast<int64_t>(since_start_s() / tick_s) - ticks_drawn_;
  for (int64_t k = 0; k < std::min(standing, kMostTicks); ++k) draws_->tick();
  ticks_drawn_ += std::max<int64_t>(0, standing);
  const int64_t nominal = std::max<int64_t>(1, static_cast<int64_t>(std::ceil(move_s / tick_s - 1e-9)));
  int64_t needed = nominal;
  int64_t spent = 0;
  while (needed > 0 && spent < kMostTicks) {
    draws_->tick();
    ++spent;
    if (!draws_->delayed(0)) --needed;
  }
  ticks_drawn_ += spent;
  if (spent > nominal) spdlog::info("sim: this move delayed {} ticks of {} s", spent - nominal, tick_s);
  return move_s + static_cast<double>(spent - nominal) * tick_s;  // the ticks spent delayed on top
}

double SimRobot::since_start_s() const { return std::chrono::duration<double>(Clock::now() - started_).count(); }

bool SimRobot::reporting_enabled() const { return settings_.silent_at_s < 0 || since_start_s() < settings_.silent_at_s; }

bool SimRobot::should_crash() const { return settings_.crash_at_s >= 0 && since_start_s() >= settings_.crash_at_s; }

bool SimRobot::start_move(Cell target, int target_heading) {
  if (target_) return false;
  const int travel = planner_core::heading_between(cell_, target);
  const int end_heading = travel >= 0 ? travel : target_heading >= 0 ? target_heading % 4 : heading_;
  const int turns = planner_core::quarter_turns(heading_, end_heading);
  const double stretch = 1.0 + std::uniform_real_distribution<double>(0.0, settings_.jitter)(rng_);
  // A turn in place is a step of its own (no move after it); a wait or a move takes step_s.
  const bool turn_only = travel < 0 && turns > 0;
  double turn_seconds = turns * settings_.turn_s * stretch;
  double seconds_total = turn_only ? turn_seconds : turn_seconds + settings_.step_s * stretch;
  if (settings_.delay_probability > 0 && std::bernoulli_distribution(settings_.delay_probability)(rng_)) {
    seconds_total += settings_.delay_s;
  }
  if (draws_) seconds_total = with_league_delays(seconds_total);
  const double now = since_start_s();
  if (settings_.stall_at_s >= 0 && now + seconds_total > settings_.stall_at_s &&
      now < settings_.stall_at_s + settings_.stall_for_s) {
    seconds_total += settings_.stall_at_s + settings_.stall_for_s - now;  // stuck until the stall ends
  }
  target_ = target;
  target_heading_ = end_heading;
  move_started_ = Clock::now();
  turn_ends_ = move_started_ + seconds(turn_only ? seconds_total : turn_seconds);
  move_ends_ = move_started_ + seconds(seconds_total);
  return true;
}

std::optional<std::chrono::steady_clock::duration> SimRobot::time_to_arrival() const {
  if (!target_) return std::nullopt;
  return std::max(move_ends_ - Clock::now(), Clock::duration::zero());
}

BackendReport SimRobot::poll() {
  const Clock::time_point now = Clock::now();
  if (target_ && now >= move_ends_) {
    cell_ = *target_;
    heading_ = target_heading_;
    target_.reset();
    arrived_ms_ = wall_clock_ms();
    ++moves_done_;
  }
  if (settings_.teleport_after_moves >= 0 && !teleported_ && moves_done_ >= settings_.teleport_after_moves) {
    teleported_ = true;  // picked up and put down elsewhere
    cell_ = settings_.teleport_to;
    target_.reset();
    arrived_ms_ = wall_clock_ms();
  }
  BackendReport report;
  report.cell = cell_;
  report.arrived_ms = arrived_ms_;
  report.moving = target_.has_value();
  report.pose_x = cell_.x;
  report.pose_y = cell_.y;
  report.pose_theta = planner_core::heading_angle(heading_);
  if (target_) {
    const auto fraction = [](Clock::time_point from, Clock::time_point to, Clock::time_point at) {
      if (to <= from) return at >= to ? 1.0 : 0.0;
      return std::clamp(std::chrono::duration<double>(at - from) / (to - from), 0.0, 1.0);
    };
    // Turning first (the shorter way round), then driving.
    const int turn = ((target_heading_ - heading_) % 4 + 4) % 4;
    const double signed_quarters = turn == 3 ? -1 : turn;
    report.pose_theta += signed_quarters * (std::numbers::pi / 2) * fraction(move_started_, turn_ends_, now);
    const double driven = fraction(turn_ends_, move_ends_, now);
    report.pose_x += (target_->x - cell_.x) * driven;
    report.pose_y += (target_->y - cell_.y) * driven;
  }
  report.heading = planner_core::nearest_heading(report.pose_theta);
  report.battery_percent = 100;
  return report;
}

}  // namespace robot_agent
