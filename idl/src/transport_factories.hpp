// The two transport implementations, each in its own library with its own generated types.
#pragma once

#include <string>
#include <vector>

#include "fleet_transport/transport.hpp"

namespace fleet_transport {

std::unique_ptr<Transport> make_cyclone_transport(const TransportConfig& config, Handlers handlers);
std::unique_ptr<Transport> make_fastdds_transport(const TransportConfig& config, Handlers handlers);

// Step commands (and states and announcements) travel in one DDS partition per robot, so a command is sent to that robot's agent
// only: with one shared partition every agent received (and acknowledged) every robot's commands,
// which grows with the square of the fleet. Characters other than letters, digits, '_' and '-'
// become '_' (no partition wildcards from robot ids); agents still check the id in the command.
inline std::string command_partition(const std::string& robot_id) {
  std::string name = "robot/";
  for (const char c : robot_id) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
    name.push_back(plain ? c : '_');
  }
  return name;
}
inline constexpr const char* kEveryRobotPartition = "robot/*";  // a reader of every robot's messages

// True when a state or announcement about `robot_id` may come from a writer in `partitions`: the
// writer is in exactly that robot's partition.
inline bool written_in_own_partition(const std::string& robot_id, const std::vector<std::string>& partitions) {
  return partitions.size() == 1 && partitions[0] == command_partition(robot_id);
}

}  // namespace fleet_transport
