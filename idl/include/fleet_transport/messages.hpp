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
  bool operator==(const Announcement&) const = default;
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
  int heading = -1;          // 0 east, 1 south, 2 west, 3 north (the nearest quarter turn); -1 unknown
  bool operator==(const RobotState&) const = default;
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
  uint64_t robot_incarnation = 0;  // the robot process it is meant for; others with the same id ignore it
  bool refused = false;            // that process is refused: it stands still and obeys nothing (see fleet.idl)
  int target_heading = -1;         // the heading to end the step facing (plans with turns); -1 any
  bool operator==(const StepCommand&) const = default;
};

struct Assignment {
  std::string robot_id;
  int role = -1;
  int tasks_done = 0;
  int tasks_total = 0;
  bool operator==(const Assignment&) const = default;
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
  bool operator==(const CoordinatorStatus&) const = default;
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
  // Figures for operators (0 until measured).
  double round_trip_p50_ms = 0;
  double round_trip_p99_ms = 0;
  double last_planning_ms = 0;
  double last_replan_latency_ms = 0;
  int64_t steps_done = 0;     // moves confirmed, over every plan so far
  int64_t steps_planned = 0;  // moves in the plans so far (each plan counted from where it started)
  bool operator==(const FleetStatus&) const = default;
};

struct GridCell {
  int x = 0;
  int y = 0;
  bool operator==(const GridCell&) const = default;
};

// A task of the mission: its cell and the roles that must visit it. Tasks added at runtime are
// appended (a task's index is its id); a cancelled task stays in the list, marked.
struct MissionTask {
  int x = 0;
  int y = 0;
  std::vector<int> roles;
  bool cancelled = false;
  bool operator==(const MissionTask&) const = default;
};

// What a coordinator drives: the map ('.' free, '@' wall; row y = 0 first), goals and tasks.
struct MissionInfo {
  uint64_t coordinator = 0;
  std::string mission_id;
  int width = 0;
  int height = 0;
  std::string map_rows;  // height rows of width characters, joined by '\n'
  std::vector<GridCell> goals;  // per role
  std::vector<MissionTask> tasks;
  bool lifelong = false;
  bool operator==(const MissionInfo&) const = default;
};

// One robot's part of a plan: its start, then the target of each action.
struct RobotPlan {
  std::string robot_id;
  int role = -1;
  std::vector<GridCell> path;  // path[0] = start; path[i + 1] = target of action i
  bool operator==(const RobotPlan&) const = default;
};

struct FleetPlan {
  uint64_t coordinator = 0;
  int plan_epoch = 0;
  int64_t made_ms = 0;
  double planning_ms = 0;
  int64_t flowtime = 0;
  std::vector<RobotPlan> robots;
  bool operator==(const FleetPlan&) const = default;
};

// Something an operator wants to know happened (kinds: see idl/fleet.idl).
struct FleetEvent {
  uint64_t coordinator = 0;
  int64_t stamp_ms = 0;
  std::string kind;
  std::string robot_id;
  std::string text;
  double value = 0;
  bool operator==(const FleetEvent&) const = default;
};

enum class TaskAction { kAdd, kCancel, kList };
const char* to_string(TaskAction action);

struct TaskRequest {
  std::string request_id;
  TaskAction action = TaskAction::kAdd;
  int x = 0;
  int y = 0;
  std::string robot_id;  // "" = any robot
  int task = -1;
  bool operator==(const TaskRequest&) const = default;
};

struct TaskReply {
  std::string request_id;
  uint64_t coordinator = 0;
  bool accepted = false;
  std::string reason;
  int task = -1;
  std::string robot_id;
  std::string listing;
  bool operator==(const TaskReply&) const = default;
};

// Longest strings the wire types carry (longer ones are cut).
constexpr size_t kMaxEventTextLength = 256;
constexpr size_t kMaxRequestIdLength = 64;

// The order among active coordinators that every process applies alike: a higher term wins, then
// the earlier claim, then the lower incarnation. True when `a` outranks `b`.
bool outranks(const CoordinatorStatus& a, const CoordinatorStatus& b);

// Longest robot id the wire types carry.
constexpr size_t kMaxRobotIdLength = 32;
// A robot id is a name, not markup: 1 to 32 characters of A-Z, a-z, 0-9, '_', '-' (the fleet CA's
// rule for participant names, which are folder names too). Every program that takes an id (agent
// --id, fleet config, CA, task tool, dashboard) and the coordinator on every message apply it.
constexpr const char* kRobotIdRule = "1 to 32 characters of A-Z, a-z, 0-9, '_' and '-'";
bool is_valid_robot_id(const std::string& id);
// `text` safe to print in one log line: control and non-ASCII bytes as \xNN, cut to `at_most`
// characters with "..." (a hostile value neither breaks the line nor floods it).
std::string printable(const std::string& text, size_t at_most = 80);

// Milliseconds since the epoch on this host's clock (shifted by the test skew, if one is set).
int64_t wall_clock_ms();
// Tests only: this process's wall clock runs `skew_ms` ahead (behind when negative), as on a
// host whose clock is off.
void set_wall_clock_skew_for_tests(int64_t skew_ms);

}  // namespace fleet_transport
