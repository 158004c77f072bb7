#include "coordinator/other_coordinators.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>

namespace coordinator {

void OtherCoordinators::heard_status(const fleet_transport::CoordinatorStatus& status, Clock::time_point received) {
  OtherCoordinator& other = others_[status.coordinator];
  const bool first = other.status.coordinator == 0;
  other.status = status;
  other.heard = received;
  if (first) {
    spdlog::info("heard coordinator {:016x} ({}, term {}, mission {}, epoch {})", status.coordinator,
                 fleet_transport::to_string(status.role), status.term, status.mission_id, status.plan_epoch);
  }
}

void OtherCoordinators::heard_progress(const fleet_transport::FleetStatus& progress) {
  others_[progress.coordinator].progress = progress;
}

void OtherCoordinators::heard_mission(const fleet_transport::MissionInfo& mission) {
  others_[mission.coordinator].mission = mission;
}

const OtherCoordinator* OtherCoordinators::find(uint64_t coordinator) const {
  const auto found = others_.find(coordinator);
  return found == others_.end() ? nullptr : &found->second;
}

const OtherCoordinator* OtherCoordinators::stronger_active(const fleet_transport::CoordinatorStatus& mine,
                                                           Clock::time_point now, double gone_after_s) const {
  for (const auto& [id, other] : others_) {
    if (other.status.role != fleet_transport::CoordinatorRole::kActive) continue;
    if (std::chrono::duration<double>(now - other.heard).count() > gone_after_s) continue;  // gone
    if (fleet_transport::outranks(other.status, mine)) return &other;
  }
  return nullptr;
}

const OtherCoordinator* OtherCoordinators::highest_active(const std::string& mission_id) const {
  const OtherCoordinator* best = nullptr;
  for (const auto& [id, other] : others_) {
    if (other.status.role != fleet_transport::CoordinatorRole::kActive || other.status.mission_id != mission_id) continue;
    if (best == nullptr || fleet_transport::outranks(other.status, best->status)) best = &other;
  }
  return best;
}

uint32_t OtherCoordinators::highest_term(uint32_t floor) const {
  uint32_t highest = floor;
  for (const auto& [id, other] : others_) highest = std::max(highest, other.status.term);
  return highest;
}

}  // namespace coordinator
