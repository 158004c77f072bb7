#include "robot_agent/sim_robot.hpp"


namespace robot_agent {

SimRobot::SimRobot(Cell start, const SimSettings& settings)
    : settings_(settings),
      rng_(settings.seed),
      started_(Clock::now()),
      cell_(start),
      arrived_ms_(wall_clock_ms()) {}

double SimRobot::since_start_s() const { return std::chrono::duration<double>(Clock::now() - started_).count(); }

bool SimRobot::reporting_enabled() const { return settings_.silent_at_s < 0 || since_start_s() < settings_.silent_at_s; }

bool SimRobot::should_crash() const { return settings_.crash_at_s >= 0 && since_start_s() >= settings_.crash_at_s; }

bool SimRobot::start_move(Cell target) {
  if (target_) return false;
  double seconds = settings_.step_s * (1.0 + std::uniform_real_distribution<double>(0.0, settings_.jitter)(rng_));
  if (settings_.delay_probability > 0 && std::bernoulli_distribution(settings_.delay_probability)(rng_)) {
    seconds += settings_.delay_s;
  }
  const double now = since_start_s();
  if (settings_.stall_at_s >= 0 && now + seconds > settings_.stall_at_s && now < settings_.stall_at_s + settings_.stall_for_s) {
    seconds += settings_.stall_at_s + settings_.stall_for_s - now;  // stuck until the stall ends
  }
  target_ = target;
  move_started_ = Clock::now();
  move_ends_ = move_started_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
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
  if (target_) {
    const double f = std::chrono::duration<double>(now - move_started_).count() /
                     std::max(1e-9, std::chrono::duration<double>(move_ends_ - move_started_).count());
    report.pose_x += (target_->x - cell_.x) * f;
    report.pose_y += (target_->y - cell_.y) * f;
  }
  report.battery_percent = 100;
  return report;
}

}  // namespace robot_agent
