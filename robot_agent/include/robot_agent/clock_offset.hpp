// How far this host's wall clock is from a sender's, learnt from the sender's stamps: the
// smallest (our receive time - its send time) over its recent messages is our clock minus its,
// plus the shortest delivery delay seen. Hosts' clocks need not agree: a deadline the sender set
// on its clock is checked on ours as deadline + offset. Adapts within a window of samples when a
// clock is stepped.
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>
#include <optional>

namespace robot_agent {

class ClockOffset {
 public:
  static constexpr std::size_t kWindow = 64;  // samples; a command every step: a few seconds of them

  // A message stamped `sent_ms` on the sender's clock, received at `received_ms` on ours.
  void add(int64_t sent_ms, int64_t received_ms) {
    samples_.push_back(received_ms - sent_ms);
    if (samples_.size() > kWindow) samples_.pop_front();
  }

  // Our clock minus the sender's (plus the shortest delay); none before the first sample.
  std::optional<int64_t> offset_ms() const {
    if (samples_.empty()) return std::nullopt;
    return *std::min_element(samples_.begin(), samples_.end());
  }

 private:
  std::deque<int64_t> samples_;
};

}  // namespace robot_agent
