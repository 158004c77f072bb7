#include "coordinator/standby_follower.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "fleet_transport/lease_timeouts.hpp"

namespace coordinator {

namespace {

StandbyFollower::Clock::duration seconds(double s) {
  return std::chrono::duration_cast<StandbyFollower::Clock::duration>(std::chrono::duration<double>(s));
}

}  // namespace

StandbyFollower::StandbyFollower(double lease_s, double silence_timeout_s, double status_period_s)
    : lease_s_(lease_s), silence_timeout_s_(silence_timeout_s), status_period_s_(status_period_s) {}

void StandbyFollower::no_active_coordinator(const std::string& mission_id) {
  if (logged_no_active_) return;
  logged_no_active_ = true;
  spdlog::info("standby: waiting for an active coordinator of mission {}", mission_id);
}

void StandbyFollower::mirror(const OtherCoordinator& active, int role_count, Clock::time_point now) {
  if (active.status.coordinator != followed_) {
    followed_ = active.status.coordinator;
    spdlog::info("standby: follows coordinator {:016x} (term {})", followed_, active.status.term);
  }
  roles_.clear();
  std::set<std::string> driven;
  for (const fleet_transport::Assignment& row : active.progress.assignments) {
    driven.insert(row.robot_id);
    if (row.role >= 0 && row.role < role_count) roles_[row.robot_id] = row.role;
  }
  std::erase_if(driven_since_, [&](const auto& entry) { return driven.count(entry.first) == 0; });
  for (const std::string& id : driven) driven_since_.emplace(id, now);
}

bool StandbyFollower::should_take_over(const OtherCoordinator& active, const RobotRegistry& robots,
                                       Clock::time_point now) {
  const Clock::duration status_gap = seconds(2 * status_period_s_);
  if (now - active.heard <= status_gap) {
    if (active_fell_silent_) {  // heard again after a silence; so are the robots, a moment apart
      for (auto& [id, since] : driven_since_) since = now;
    }
    active_fell_silent_ = false;
    logged_unheard_robots_ = false;
    every_robot_heard_since_.reset();
    warn_of_driven_robots_not_heard(robots, now);
    return false;
  }
  active_fell_silent_ = true;
  // "Since" leaves the same gap: a robot's last state from before a split may arrive after the
  // active one's last status (sent up to a period before the split).
  const std::vector<std::string> unheard = robots_unheard_since(robots, active.heard + status_gap);
  if (!unheard.empty()) every_robot_heard_since_.reset();
  if (unheard.empty() && !every_robot_heard_since_) every_robot_heard_since_ = now;
  const double silent_s = std::chrono::duration<double>(now - active.heard).count();
  if (silent_s <= fleet_transport::LeaseTimeouts{lease_s_}.standby_takes_over_after_s()) return false;
  if (every_robot_heard_since_ && now - *every_robot_heard_since_ >= status_gap) return true;
  if (!unheard.empty()) warn_of_unheard_robots(active, unheard, silent_s);
  return false;
}

void StandbyFollower::warn_of_unheard_robots(const OtherCoordinator& active, const std::vector<std::string>& unheard,
                                             double silent_s) {
  if (logged_unheard_robots_) return;
  logged_unheard_robots_ = true;
  constexpr size_t kNamed = 8;
  std::string names;
  for (size_t i = 0; i < std::min(unheard.size(), kNamed); ++i) names += (i == 0 ? "" : ", ") + unheard[i];
  if (unheard.size() > kNamed) names += fmt::format(" and {} more", unheard.size() - kNamed);
  spdlog::warn("standby: coordinator {:016x} (term {}) silent for {:.2f} s, but so {} {}: this host may be cut off "
               "from part of the fleet, which that coordinator may still drive; taking over once every robot "
               "is heard",
               active.status.coordinator, active.status.term, silent_s, unheard.size() == 1 ? "is" : "are", names);
}

void StandbyFollower::warn_of_driven_robots_not_heard(const RobotRegistry& robots, Clock::time_point now) {
  if (now < next_not_heard_check_) return;  // a standby steps every few ms; robots report ten times a second
  next_not_heard_check_ = now + seconds(status_period_s_);
  const Clock::duration silence = seconds(silence_timeout_s_);
  for (const auto& [id, since] : driven_since_) {
    const RobotRecord* robot = robots.find(id);
    const bool heard = robot != nullptr && robot->has_state && now - robot->last_state_received <= silence;
    if (heard) {
      warned_not_heard_.erase(id);
    } else if (now - since > silence && warned_not_heard_.insert(id).second) {
      spdlog::warn("standby: robot {}, which coordinator {:016x} drives, is not heard here: this standby could not "
                   "take over while it is not (check this host's network)",
                   id, followed_);
    }
  }
}

std::vector<std::string> StandbyFollower::robots_unheard_since(const RobotRegistry& robots,
                                                               Clock::time_point since) const {
  std::set<std::string> drivable;
  for (const auto& [id, first_driven] : driven_since_) drivable.insert(id);
  for (const auto& [id, robot] : robots) {
    if (robot.active && robot.has_state) drivable.insert(id);  // joined after the last progress heard
  }
  std::vector<std::string> unheard;
  for (const std::string& id : drivable) {
    const RobotRecord* robot = robots.find(id);
    if (robot != nullptr && robot->said_goodbye) continue;  // it left: nobody drives it any more
    if (robot == nullptr || !robot->has_state || robot->last_state_received <= since) unheard.push_back(id);
  }
  return unheard;
}

}  // namespace coordinator
