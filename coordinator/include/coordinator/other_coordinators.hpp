// OtherCoordinators: every other coordinator this one has heard on the domain, with its last
// heartbeat (CoordinatorStatus), progress (FleetStatus) and mission info, and when it was heard.
// An active coordinator asks it whether one that outranks it is active; a standby, which one to
// follow.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>

#include "fleet_transport/messages.hpp"

namespace coordinator {

struct OtherCoordinator {
  using Clock = std::chrono::steady_clock;
  fleet_transport::CoordinatorStatus status;
  fleet_transport::FleetStatus progress;                // its last progress report
  std::optional<fleet_transport::MissionInfo> mission;  // its last mission info (tasks added at runtime)
  Clock::time_point heard;                              // its last heartbeat
};

class OtherCoordinators {
 public:
  using Clock = OtherCoordinator::Clock;

  void heard_status(const fleet_transport::CoordinatorStatus& status, Clock::time_point received);
  void heard_progress(const fleet_transport::FleetStatus& progress);
  void heard_mission(const fleet_transport::MissionInfo& mission);
  void forget(uint64_t coordinator) { others_.erase(coordinator); }

  const OtherCoordinator* find(uint64_t coordinator) const;
  // An active coordinator that outranks `mine` (fleet_transport::outranks) and was heard within
  // `gone_after_s` of `now`, or nullptr.
  const OtherCoordinator* stronger_active(const fleet_transport::CoordinatorStatus& mine, Clock::time_point now,
                                          double gone_after_s) const;
  // The highest-ranked active coordinator of `mission_id` (heard lately or not), or nullptr.
  const OtherCoordinator* highest_active(const std::string& mission_id) const;
  // The highest term heard, at least `floor`.
  uint32_t highest_term(uint32_t floor) const;

 private:
  std::map<uint64_t, OtherCoordinator> others_;  // by incarnation
};

}  // namespace coordinator
