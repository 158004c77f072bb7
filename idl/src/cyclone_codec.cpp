#include "cyclone_codec.hpp"

#include <cstring>
#include <string>
#include <vector>

namespace fleet_transport::cyclone_codec {

namespace {

template <size_t N>
void copy_string(char (&out)[N], const std::string& in) {
  std::strncpy(out, in.c_str(), N - 1);
  out[N - 1] = '\0';
}

// Points a C sequence at a vector's elements (no copy; the vector outlives the write).
template <typename Sequence, typename Element>
void borrow(Sequence& sequence, std::vector<Element>& elements) {
  sequence._length = sequence._maximum = static_cast<uint32_t>(elements.size());
  sequence._buffer = elements.data();
  sequence._release = false;
}

template <typename Sequence>
auto elements_of(const Sequence& sequence) {
  return std::vector(sequence._buffer, sequence._buffer + sequence._length);
}

std::vector<GridCell> cells_of(const dds_sequence_fleet_GridCell& sequence) {
  std::vector<GridCell> cells;
  for (const fleet_GridCell& cell : elements_of(sequence)) cells.push_back({cell.x, cell.y});
  return cells;
}

std::vector<fleet_GridCell> wire_cells(const std::vector<GridCell>& cells) {
  std::vector<fleet_GridCell> wire;
  for (const GridCell& cell : cells) wire.push_back({cell.x, cell.y});
  return wire;
}

fleet_RobotStatus wire_status(RobotStatus status) {
  switch (status) {
    case RobotStatus::kIdle: return fleet_ROBOT_IDLE;
    case RobotStatus::kMoving: return fleet_ROBOT_MOVING;
    case RobotStatus::kArrived: return fleet_ROBOT_ARRIVED;
    case RobotStatus::kFault: return fleet_ROBOT_FAULT;
  }
  return fleet_ROBOT_FAULT;
}

RobotStatus status_of(fleet_RobotStatus status) {
  switch (status) {
    case fleet_ROBOT_IDLE: return RobotStatus::kIdle;
    case fleet_ROBOT_MOVING: return RobotStatus::kMoving;
    case fleet_ROBOT_ARRIVED: return RobotStatus::kArrived;
    default: return RobotStatus::kFault;
  }
}

fleet_CoordinatorRole wire_role(CoordinatorRole role) {
  switch (role) {
    case CoordinatorRole::kActive: return fleet_COORDINATOR_ACTIVE;
    case CoordinatorRole::kStandby: return fleet_COORDINATOR_STANDBY;
    case CoordinatorRole::kStoodDown: return fleet_COORDINATOR_STOOD_DOWN;
    case CoordinatorRole::kEnded: return fleet_COORDINATOR_ENDED;
  }
  return fleet_COORDINATOR_ENDED;
}

CoordinatorRole role_of(fleet_CoordinatorRole role) {
  switch (role) {
    case fleet_COORDINATOR_ACTIVE: return CoordinatorRole::kActive;
    case fleet_COORDINATOR_STANDBY: return CoordinatorRole::kStandby;
    case fleet_COORDINATOR_STOOD_DOWN: return CoordinatorRole::kStoodDown;
    default: return CoordinatorRole::kEnded;
  }
}

}  // namespace

fleet_Announcement to_wire(const Announcement& announcement) {
  fleet_Announcement wire{};
  copy_string(wire.robot_id, announcement.robot_id);
  copy_string(wire.backend, announcement.backend);
  copy_string(wire.capabilities, announcement.capabilities);
  copy_string(wire.version, announcement.version);
  wire.leaving = announcement.leaving;
  wire.incarnation = announcement.incarnation;
  return wire;
}

fleet_RobotState to_wire(const RobotState& state) {
  fleet_RobotState wire{};
  copy_string(wire.robot_id, state.robot_id);
  wire.cell_x = state.cell_x;
  wire.cell_y = state.cell_y;
  wire.pose_x = state.pose_x;
  wire.pose_y = state.pose_y;
  wire.pose_theta = state.pose_theta;
  wire.plan_epoch = state.plan_epoch;
  wire.action_index = state.action_index;
  wire.status = wire_status(state.status);
  wire.battery_percent = state.battery_percent;
  wire.seq_number = state.seq_number;
  wire.stamp_ms = state.stamp_ms;
  wire.incarnation = state.incarnation;
  wire.coordinator = state.coordinator;
  wire.heading = state.heading;
  return wire;
}

fleet_StepCommand to_wire(const StepCommand& command) {
  fleet_StepCommand wire{};
  copy_string(wire.robot_id, command.robot_id);
  wire.plan_epoch = command.plan_epoch;
  wire.action_index = command.action_index;
  wire.target_x = command.target_x;
  wire.target_y = command.target_y;
  wire.target_pose_x = command.target_pose_x;
  wire.target_pose_y = command.target_pose_y;
  wire.deadline_ms = command.deadline_ms;
  wire.coordinator = command.coordinator;
  wire.sent_ms = command.sent_ms;
  wire.robot_incarnation = command.robot_incarnation;
  wire.refused = command.refused;
  wire.target_heading = command.target_heading;
  return wire;
}

fleet_CoordinatorStatus to_wire(const CoordinatorStatus& status) {
  fleet_CoordinatorStatus wire{};
  wire.coordinator = status.coordinator;
  wire.term = status.term;
  wire.claimed_ms = status.claimed_ms;
  wire.role = wire_role(status.role);
  copy_string(wire.mission_id, status.mission_id);
  wire.plan_epoch = status.plan_epoch;
  return wire;
}

fleet_FleetEvent to_wire(const FleetEvent& event) {
  fleet_FleetEvent wire{};
  wire.coordinator = event.coordinator;
  wire.stamp_ms = event.stamp_ms;
  copy_string(wire.kind, event.kind);
  copy_string(wire.robot_id, event.robot_id);
  copy_string(wire.text, event.text);
  wire.value = event.value;
  return wire;
}

fleet_TaskRequest to_wire(const TaskRequest& request) {
  fleet_TaskRequest wire{};
  copy_string(wire.request_id, request.request_id);
  wire.action = static_cast<fleet_TaskAction>(request.action);
  wire.x = request.x;
  wire.y = request.y;
  copy_string(wire.robot_id, request.robot_id);
  wire.task = request.task;
  return wire;
}

void with_wire(const FleetStatus& status, const UseWire<fleet_FleetStatus>& use) {
  std::vector<fleet_Assignment> rows(status.assignments.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    const Assignment& assignment = status.assignments[i];
    copy_string(rows[i].robot_id, assignment.robot_id);
    rows[i].role = assignment.role;
    rows[i].tasks_done = assignment.tasks_done;
    rows[i].tasks_total = assignment.tasks_total;
  }
  std::vector<fleet_TaskVisit> visits;
  for (const TaskVisit& visit : status.done_visits) visits.push_back({visit.task, visit.role});
  fleet_FleetStatus wire{};
  wire.coordinator = status.coordinator;
  wire.plan_epoch = status.plan_epoch;
  wire.tasks_done = status.tasks_done;
  wire.tasks_total = status.tasks_total;
  wire.robots = status.robots;
  borrow(wire.assignments, rows);
  borrow(wire.done_visits, visits);
  wire.round_trip_p50_ms = status.round_trip_p50_ms;
  wire.round_trip_p99_ms = status.round_trip_p99_ms;
  wire.last_planning_ms = status.last_planning_ms;
  wire.last_replan_latency_ms = status.last_replan_latency_ms;
  wire.steps_done = status.steps_done;
  wire.steps_planned = status.steps_planned;
  use(wire);
}

void with_wire(const MissionInfo& mission, const UseWire<fleet_MissionInfo>& use) {
  std::vector<fleet_GridCell> goals = wire_cells(mission.goals);
  std::vector<std::vector<int32_t>> roles;
  for (const MissionTask& task : mission.tasks) roles.emplace_back(task.roles.begin(), task.roles.end());
  std::vector<fleet_MissionTask> tasks(mission.tasks.size());
  for (size_t i = 0; i < tasks.size(); ++i) {
    tasks[i].x = mission.tasks[i].x;
    tasks[i].y = mission.tasks[i].y;
    tasks[i].cancelled = mission.tasks[i].cancelled;
    borrow(tasks[i].roles, roles[i]);
  }
  std::string rows = mission.map_rows;
  fleet_MissionInfo wire{};
  wire.coordinator = mission.coordinator;
  copy_string(wire.mission_id, mission.mission_id);
  wire.width = mission.width;
  wire.height = mission.height;
  wire.map_rows = rows.data();
  borrow(wire.goals, goals);
  borrow(wire.tasks, tasks);
  wire.lifelong = mission.lifelong;
  use(wire);
}

void with_wire(const FleetPlan& plan, const UseWire<fleet_FleetPlan>& use) {
  std::vector<std::vector<fleet_GridCell>> paths;
  for (const RobotPlan& robot : plan.robots) paths.push_back(wire_cells(robot.path));
  std::vector<fleet_RobotPlan> robots(plan.robots.size());
  for (size_t i = 0; i < robots.size(); ++i) {
    copy_string(robots[i].robot_id, plan.robots[i].robot_id);
    robots[i].role = plan.robots[i].role;
    borrow(robots[i].path, paths[i]);
  }
  fleet_FleetPlan wire{};
  wire.coordinator = plan.coordinator;
  wire.plan_epoch = plan.plan_epoch;
  wire.made_ms = plan.made_ms;
  wire.planning_ms = plan.planning_ms;
  wire.flowtime = plan.flowtime;
  borrow(wire.robots, robots);
  use(wire);
}

void with_wire(const TaskReply& reply, const UseWire<fleet_TaskReply>& use) {
  std::string listing = reply.listing;
  fleet_TaskReply wire{};
  copy_string(wire.request_id, reply.request_id);
  wire.coordinator = reply.coordinator;
  wire.accepted = reply.accepted;
  copy_string(wire.reason, reply.reason);
  wire.task = reply.task;
  copy_string(wire.robot_id, reply.robot_id);
  wire.listing = listing.data();
  use(wire);
}

Announcement from_wire(const fleet_Announcement& wire) {
  return {wire.robot_id, wire.backend, wire.capabilities, wire.version, wire.leaving, wire.incarnation};
}

RobotState from_wire(const fleet_RobotState& wire) {
  RobotState state;
  state.robot_id = wire.robot_id;
  state.cell_x = wire.cell_x;
  state.cell_y = wire.cell_y;
  state.pose_x = wire.pose_x;
  state.pose_y = wire.pose_y;
  state.pose_theta = wire.pose_theta;
  state.plan_epoch = wire.plan_epoch;
  state.action_index = wire.action_index;
  state.status = status_of(wire.status);
  state.battery_percent = wire.battery_percent;
  state.seq_number = wire.seq_number;
  state.stamp_ms = wire.stamp_ms;
  state.incarnation = wire.incarnation;
  state.coordinator = wire.coordinator;
  state.heading = wire.heading;
  return state;
}

StepCommand from_wire(const fleet_StepCommand& wire) {
  return {wire.robot_id,      wire.plan_epoch,    wire.action_index, wire.target_x,
          wire.target_y,      wire.target_pose_x, wire.target_pose_y, wire.deadline_ms,
          wire.coordinator,   wire.sent_ms,       wire.robot_incarnation, wire.refused,
          wire.target_heading};
}

CoordinatorStatus from_wire(const fleet_CoordinatorStatus& wire) {
  return {wire.coordinator, wire.term, wire.claimed_ms, role_of(wire.role), wire.mission_id, wire.plan_epoch};
}

FleetStatus from_wire(const fleet_FleetStatus& wire) {
  FleetStatus status;
  status.coordinator = wire.coordinator;
  status.plan_epoch = wire.plan_epoch;
  status.tasks_done = wire.tasks_done;
  status.tasks_total = wire.tasks_total;
  status.robots = wire.robots;
  for (const fleet_Assignment& row : elements_of(wire.assignments)) {
    status.assignments.push_back({row.robot_id, row.role, row.tasks_done, row.tasks_total});
  }
  for (const fleet_TaskVisit& visit : elements_of(wire.done_visits)) status.done_visits.push_back({visit.task, visit.role});
  status.round_trip_p50_ms = wire.round_trip_p50_ms;
  status.round_trip_p99_ms = wire.round_trip_p99_ms;
  status.last_planning_ms = wire.last_planning_ms;
  status.last_replan_latency_ms = wire.last_replan_latency_ms;
  status.steps_done = wire.steps_done;
  status.steps_planned = wire.steps_planned;
  return status;
}

MissionInfo from_wire(const fleet_MissionInfo& wire) {
  MissionInfo mission;
  mission.coordinator = wire.coordinator;
  mission.mission_id = wire.mission_id;
  mission.width = wire.width;
  mission.height = wire.height;
  mission.map_rows = wire.map_rows ? wire.map_rows : "";
  mission.goals = cells_of(wire.goals);
  for (const fleet_MissionTask& task : elements_of(wire.tasks)) {
    mission.tasks.push_back({task.x, task.y, elements_of(task.roles), task.cancelled});
  }
  mission.lifelong = wire.lifelong;
  return mission;
}

FleetPlan from_wire(const fleet_FleetPlan& wire) {
  FleetPlan plan;
  plan.coordinator = wire.coordinator;
  plan.plan_epoch = wire.plan_epoch;
  plan.made_ms = wire.made_ms;
  plan.planning_ms = wire.planning_ms;
  plan.flowtime = wire.flowtime;
  for (const fleet_RobotPlan& robot : elements_of(wire.robots)) {
    plan.robots.push_back({robot.robot_id, robot.role, cells_of(robot.path)});
  }
  return plan;
}

FleetEvent from_wire(const fleet_FleetEvent& wire) {
  return {wire.coordinator, wire.stamp_ms, wire.kind, wire.robot_id, wire.text, wire.value};
}

TaskRequest from_wire(const fleet_TaskRequest& wire) {
  return {wire.request_id, static_cast<TaskAction>(wire.action), wire.x, wire.y, wire.robot_id, wire.task};
}

TaskReply from_wire(const fleet_TaskReply& wire) {
  return {wire.request_id, wire.coordinator, wire.accepted, wire.reason,
          wire.task,       wire.robot_id,    wire.listing ? wire.listing : ""};
}

}  // namespace fleet_transport::cyclone_codec
