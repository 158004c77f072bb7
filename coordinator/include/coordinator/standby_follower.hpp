// StandbyFollower: what a standby coordinator keeps of the active one it follows (which robots it
// drives, in which roles) and the rule for taking over from it.
//
// The active coordinator is silent: dead, or cut off from this host. It may still drive robots
// this standby cannot hear (a network split with robots on both sides), and a plan that takes
// them for walls at their last cells would drive robots into them. So the standby takes over only
// once the active one has been silent for LeaseTimeouts::standby_takes_over_after_s() and, since
// it fell silent, every robot it drove has been heard here for two status periods: when a split
// heals, the robots' states may come back a little before the active one's status, which must not
// read as its death.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "coordinator/other_coordinators.hpp"
#include "coordinator/robot_registry.hpp"

namespace coordinator {

class StandbyFollower {
 public:
  using Clock = std::chrono::steady_clock;

  // `status_period_s`: how often coordinators send their heartbeat; `silence_timeout_s`: how long a
  // robot may be unheard (both from the fleet's config).
  StandbyFollower(double lease_s, double silence_timeout_s, double status_period_s);

  // Says once that no active coordinator of `mission_id` is heard.
  void no_active_coordinator(const std::string& mission_id);
  // Follows `active`: which robots it drives (and since when) and in which of `role_count` roles.
  void mirror(const OtherCoordinator& active, int role_count, Clock::time_point now);
  // Whether the followed coordinator's silence, and the robots heard here, call for a takeover now
  // (see above). Warns, once per episode, of robots it drives that this host does not hear.
  bool should_take_over(const OtherCoordinator& active, const RobotRegistry& robots, Clock::time_point now);

  uint64_t followed() const { return followed_; }
  // Robot id -> role, as the followed coordinator bound them.
  const std::map<std::string, int>& roles() const { return roles_; }

 private:
  // The robots the followed coordinator drives, or this one knows, that have not been heard since
  // `since`.
  std::vector<std::string> robots_unheard_since(const RobotRegistry& robots, Clock::time_point since) const;
  void warn_of_driven_robots_not_heard(const RobotRegistry& robots, Clock::time_point now);
  void warn_of_unheard_robots(const OtherCoordinator& active, const std::vector<std::string>& unheard,
                              double silent_s);

  double lease_s_;
  double silence_timeout_s_;
  double status_period_s_;
  uint64_t followed_ = 0;                             // the coordinator whose progress is mirrored
  std::map<std::string, int> roles_;                  // robot -> role, from that coordinator
  std::map<std::string, Clock::time_point> driven_since_;  // every robot it drives, and since when
  std::set<std::string> warned_not_heard_;            // driven robots it said it does not hear
  Clock::time_point next_not_heard_check_{};
  bool logged_unheard_robots_ = false;                // said why it does not take over yet
  bool logged_no_active_ = false;
  bool active_fell_silent_ = false;                   // for two status periods or more
  std::optional<Clock::time_point> every_robot_heard_since_;  // with the active one silent
};

}  // namespace coordinator
