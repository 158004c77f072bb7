// ReplanRequests: why the plan in hand must be replaced (a robot lost or joined, a task added or
// cancelled, a duplicate in the way), counted so that a plan made meanwhile is known to be stale,
// and timed from the first unanswered request to the new plan's first command (the replan
// latency operators see).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>

namespace coordinator {

class ReplanRequests {
 public:
  using Clock = std::chrono::steady_clock;

  void ask(Clock::time_point now) {
    ++count_;
    if (!pending_) start_latency(now);
    pending_ = true;
  }
  // A plan that is not asked for, but whose latency counts (a takeover's first plan).
  void start_latency(Clock::time_point now) {
    asked_at_ = now;
    latency_open_ = true;
  }
  bool pending() const { return pending_; }
  void answered() { pending_ = false; }
  // Requests so far: a plan made from an older count is stale.
  int64_t count() const { return count_; }
  // Seconds from the first request to `now`, the first time a command goes out after it.
  std::optional<double> latency_until(Clock::time_point now) {
    if (!latency_open_) return std::nullopt;
    latency_open_ = false;
    return std::chrono::duration<double>(now - asked_at_).count();
  }

 private:
  bool pending_ = false;
  bool latency_open_ = false;
  Clock::time_point asked_at_{};
  int64_t count_ = 0;
};

}  // namespace coordinator
