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
  uint64_t coordinator = 0;  // whose command it executes or executed last; 0 before any
};

struct StepCommand {
  std::string robot_id;
  int plan_epoch = 0;
  int action_index = 0;
  int target_x = 0;
  int target_y = 0;
  double target_pose_x = 0;
  double target_pose_y = 0;
  int64_t deadline_ms = 0;    // the sender's wall clock
  uint64_t coordinator = 0;  // the sender's incarnation
  int64_t sent_ms = 0;       // the sender's wall clock when sent (0: unknown)
};

struct Assignment {
  std::string robot_id;
  int role = -1;
  int tasks_done = 0;
  int tasks_total = 0;
};

enum class CoordinatorRole { kActive, kStandby, kStoodDown, kEnded };
const char* to_string(CoordinatorRole role);

struct TaskVisit {
  int task = 0;
  int role = 0;
  bool operator==(const TaskVisit&) const = default;
};

// A coordinator's heartbeat: who it is, how it ranks, the newest epoch it has announced.
struct CoordinatorStatus {
  uint64_t coordinator = 0;  // incarnation of the publishing coordinator
  uint32_t term = 0;
  int64_t claimed_ms = 0;
  CoordinatorRole role = CoordinatorRole::kActive;
  std::string mission_id;
  int plan_epoch = 0;
};

// A coordinator's mission progress: bindings and task visits done.
struct FleetStatus {
  uint64_t coordinator = 0;
  int plan_epoch = 0;
  int tasks_done = 0;
  int tasks_total = 0;
  int robots = 0;
  std::vector<Assignment> assignments;
  std::vector<TaskVisit> done_visits;
};

// The order among active coordinators that every process applies alike: a higher term wins, then
// the earlier claim, then the lower incarnation. True when `a` outranks `b`.
bool outranks(const CoordinatorStatus& a, const CoordinatorStatus& b);

// Longest robot id the wire types carry.
constexpr size_t kMaxRobotIdLength = 32;

// Milliseconds since the epoch on this host's clock (shifted by the test skew, if one is set).
int64_t wall_clock_ms();
// Tests only: this process's wall clock runs `skew_ms` ahead (behind when negative), as on a
// host whose clock is off.
void set_wall_clock_skew_for_tests(int64_t skew_ms);

}  // namespace fleet_transport
