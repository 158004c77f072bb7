// Domain types of the fleet runtime's messages: plain C++, no DDS types. The transport
// implementations convert them to and from the IDL-generated wire types.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fleet_transport {

enum class RobotStatus { kIdle, kMoving, kArrived, kFault };
const char* to_string(RobotStatus status);

struct Announcement {
  std::string robot_id;
  std::string backend;       // "sim", "toio"
  std::string capabilities;
  std::string version;
  bool leaving = false;
  uint64_t incarnation = 0;  // random per process start; 0 from senders that do not set it
};

struct RobotState {
  std::string robot_id;
  int cell_x = 0;
  int cell_y = 0;
  double pose_x = 0;
  double pose_y = 0;
  double pose_theta = 0;
  int plan_epoch = -1;
  int action_index = -1;
  RobotStatus status = RobotStatus::kIdle;
  int battery_percent = -1;
  uint64_t seq_number = 0;
  int64_t stamp_ms = 0;  // wall clock of the arrival at (cell_x, cell_y)
  uint64_t incarnation = 0;  // of the publishing process; seq_number counts within one incarnation
};

struct StepCommand {
  std::string robot_id;
  int plan_epoch = 0;
  int action_index = 0;
  int target_x = 0;
  int target_y = 0;
  double target_pose_x = 0;
  double target_pose_y = 0;
  int64_t deadline_ms = 0;
};

struct Assignment {
  std::string robot_id;
  int role = -1;
  int tasks_done = 0;
  int tasks_total = 0;
};

struct FleetStatus {
  int plan_epoch = 0;
  int tasks_done = 0;
  int tasks_total = 0;
  int robots = 0;
  std::vector<Assignment> assignments;
};

// Longest robot id the wire types carry.
constexpr size_t kMaxRobotIdLength = 32;

int64_t wall_clock_ms();

}  // namespace fleet_transport
