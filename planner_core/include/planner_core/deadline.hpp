// Deadline: a wall-clock limit plus an atomic interrupt flag that another thread may raise.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>

namespace planner_core {

using Clock = std::chrono::steady_clock;

struct Deadline {
  Clock::time_point at = Clock::time_point::max();
  const std::atomic<bool>* interrupt = nullptr;

  static Deadline in_seconds(double seconds, const std::atomic<bool>* interrupt = nullptr) {
    // Beyond this the clock's range would overflow: no limit (programs refuse such limits first).
    constexpr double kNoLimitBeyondS = 1e9;
    if (!(seconds < kNoLimitBeyondS)) return {Clock::time_point::max(), interrupt};
    return {Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds)),
            interrupt};
  }
  // The earlier of this deadline and `seconds` from now, with the same interrupt flag.
  Deadline within(double seconds) const {
    Deadline slice = in_seconds(seconds, interrupt);
    if (at < slice.at) slice.at = at;
    return slice;
  }
  // Seconds until the deadline (0 once it has passed or the interrupt is raised).
  double seconds_left() const {
    if (interrupt && interrupt->load(std::memory_order_relaxed)) return 0;
    if (at == Clock::time_point::max()) return 1e18;
    return std::max(0.0, std::chrono::duration<double>(at - Clock::now()).count());
  }
  bool expired() const {
    return (interrupt && interrupt->load(std::memory_order_relaxed)) || Clock::now() >= at;
  }
};

// A time limit a program accepts from its user: a finite number of seconds in (0, 1e6].
constexpr double kMaxTimeLimitS = 1e6;

inline double elapsed_ms(Clock::time_point since) {
  return std::chrono::duration<double, std::milli>(Clock::now() - since).count();
}

}  // namespace planner_core
