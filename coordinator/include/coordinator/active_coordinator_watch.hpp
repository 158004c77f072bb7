// The safety monitor's watch on coordinators: two of them active at once, for longer than a
// coordinator needs to notice the other and stand down, is an alarm. A short overlap is normal: a
// coordinator that starts while another runs is active while it listens for a lease, and a
// takeover can race the old coordinator's last heartbeats. Header-only, on the wire types alone,
// so the monitor does not link the coordinator.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>

#include "fleet_transport/messages.hpp"

namespace coordinator {

class ActiveCoordinatorWatch {
 public:
  using Clock = std::chrono::steady_clock;

  explicit ActiveCoordinatorWatch(Clock::duration grace) : grace_(grace) {}

  // Takes one heartbeat heard at `now`; returns the alarm's text when it makes a pair of
  // coordinators active together for longer than the grace (each pair once).
  std::optional<std::string> on_status(const fleet_transport::CoordinatorStatus& status, Clock::time_point now) {
    if (status.role != fleet_transport::CoordinatorRole::kActive) {
      active_.erase(status.coordinator);  // stood down, ended, or a standby
      return std::nullopt;
    }
    auto [it, is_new] = active_.try_emplace(status.coordinator);
    Span& self = it->second;
    if (is_new) self.first = now;
    self.last = now;
    self.term = status.term;
    self.mission = status.mission_id;
    for (const auto& [other_id, other] : active_) {
      if (other_id == status.coordinator) continue;
      const Clock::duration together = std::min(self.last, other.last) - std::max(self.first, other.first);
      const auto pair = std::minmax(other_id, status.coordinator);
      if (together > grace_ && alarmed_.insert(pair).second) {
        return "two active coordinators for " + std::to_string(std::chrono::duration<double>(together).count()) +
               " s: " + describe(other_id, other) + " and " + describe(status.coordinator, self);
      }
    }
    return std::nullopt;
  }

  size_t alarms() const { return alarmed_.size(); }

 private:
  struct Span {
    Clock::time_point first, last;  // heard active from .. to
    uint64_t term = 0;
    std::string mission;
  };
  static std::string describe(uint64_t id, const Span& span) {
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(id));
    return std::string(hex) + " (term " + std::to_string(span.term) + ", mission " + span.mission + ")";
  }

  Clock::duration grace_;
  std::map<uint64_t, Span> active_;
  std::set<std::pair<uint64_t, uint64_t>> alarmed_;
};

}  // namespace coordinator
