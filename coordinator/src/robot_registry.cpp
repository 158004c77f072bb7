#include "coordinator/robot_registry.hpp"

#include <spdlog/fmt/fmt.h>

#include <utility>

namespace coordinator {

RobotRecord& RobotRegistry::operator[](const std::string& id) {
  RobotRecord& robot = robots_[id];
  robot.id = id;
  return robot;
}

RobotRecord* RobotRegistry::valid_record(const std::string& id,
                                         const std::function<void(const std::string& why)>& refused) {
  if (fleet_transport::is_valid_robot_id(id)) return &(*this)[id];
  if (bad_ids_reported_.size() < kBadIdsReported && bad_ids_reported_.insert(id).second) {
    refused(fmt::format("a message from robot id '{}' refused: robot ids are {}", fleet_transport::printable(id, 40),
                        fleet_transport::kRobotIdRule));
  }
  return nullptr;
}

const RobotRecord* RobotRegistry::find(const std::string& id) const {
  const auto it = robots_.find(id);
  return it == robots_.end() ? nullptr : &it->second;
}

RobotRegistry::Admission RobotRegistry::admit(const fleet_transport::Announcement& announcement,
                                              const FleetConfig& config) {
  RobotRecord& robot = (*this)[announcement.robot_id];
  if (robot.announced && robot.active) {
    return robot.backend == announcement.backend ? Admission::kRepeat : Admission::kDuplicate;
  }
  const bool expected = config.any_robots || std::find(config.expected_robots.begin(), config.expected_robots.end(),
                                                       robot.id) != config.expected_robots.end();
  if (!expected) {
    const Admission result = robot.refused ? Admission::kRefusedAgain : Admission::kRefused;
    robot.refused = true;
    return result;
  }
  robot.announced = true;
  robot.refused = false;
  robot.backend = announcement.backend;
  return Admission::kAdmitted;
}

int RobotRegistry::active_count() const {
  return static_cast<int>(std::count_if(robots_.begin(), robots_.end(), [](const auto& entry) { return entry.second.active; }));
}

std::vector<RobotRecord*> RobotRegistry::ready_robots() {
  std::vector<RobotRecord*> ready;
  for (const RobotRecord* robot : std::as_const(*this).ready_robots()) ready.push_back(const_cast<RobotRecord*>(robot));
  return ready;
}

std::vector<const RobotRecord*> RobotRegistry::ready_robots() const {
  std::vector<const RobotRecord*> ready;
  for (const auto& [id, robot] : robots_) {
    if (robot.active && robot.has_state) ready.push_back(&robot);
  }
  return ready;
}

std::vector<RobotRecord*> RobotRegistry::silent_robots(Clock::time_point now, double timeout_s) {
  std::vector<RobotRecord*> silent;
  for (auto& [id, robot] : robots_) {
    if (robot.active && std::chrono::duration<double>(now - robot.last_heard).count() > timeout_s) silent.push_back(&robot);
  }
  return silent;
}

void RobotRegistry::restart_silence_clocks(Clock::time_point now) {
  for (auto& [id, robot] : robots_) {
    if (robot.active) robot.last_heard = now;
  }
}

}  // namespace coordinator
