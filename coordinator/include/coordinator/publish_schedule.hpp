// PublishSchedule: when a coordinator's heartbeat (CoordinatorStatus) and progress (FleetStatus)
// go out. The heartbeat every kStatusPeriodS, and at once when something must be announced before
// it is used (a new epoch, a new term); the progress every kProgressPeriodS, and on a change, at
// most every kProgressGapS.
#pragma once

#include <chrono>

namespace coordinator {

class PublishSchedule {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr double kStatusPeriodS = 0.25;
  static constexpr double kProgressPeriodS = 0.5;
  static constexpr double kProgressGapS = 0.05;

  bool status_due(Clock::time_point now) const { return now >= next_status_; }
  void status_sent(Clock::time_point now) { next_status_ = now + period(kStatusPeriodS); }

  void progress_changed() { progress_changed_ = true; }
  bool progress_due(Clock::time_point now) const {
    return now >= next_progress_ || (progress_changed_ && now - last_progress_ >= period(kProgressGapS));
  }
  void progress_sent(Clock::time_point now) {
    progress_changed_ = false;
    last_progress_ = now;
    next_progress_ = now + period(kProgressPeriodS);
  }

 private:
  static Clock::duration period(double s) {
    return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
  }

  Clock::time_point next_status_{};
  Clock::time_point next_progress_{};
  Clock::time_point last_progress_{};
  bool progress_changed_ = false;
};

}  // namespace coordinator
