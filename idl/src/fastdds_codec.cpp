#include "fastdds_codec.hpp"

#include <string>
#include <vector>

namespace fleet_transport::fastdds_codec {

namespace {

std::vector<GridCell> cells_of(const std::vector<fleet::GridCell>& wire) {
  std::vector<GridCell> cells;
  for (const fleet::GridCell& cell : wire) cells.push_back({cell.x(), cell.y()});
  return cells;
}

std::vector<fleet::GridCell> wire_cells(const std::vector<GridCell>& cells) {
  std::vector<fleet::GridCell> wire(cells.size());
  for (size_t i = 0; i < cells.size(); ++i) {
    wire[i].x(cells[i].x);
    wire[i].y(cells[i].y);
  }
  return wire;
}

fleet::RobotStatus wire_status(RobotStatus status) {
  switch (status) {
    case RobotStatus::kIdle: return fleet::ROBOT_IDLE;
    case RobotStatus::kMoving: return fleet::ROBOT_MOVING;
    case RobotStatus::kArrived: return fleet::ROBOT_ARRIVED;
    case RobotStatus::kFault: return fleet::ROBOT_FAULT;
  }
  return fleet::ROBOT_FAULT;
}

RobotStatus status_of(fleet::RobotStatus status) {
  switch (status) {
    case fleet::ROBOT_IDLE: return RobotStatus::kIdle;
    case fleet::ROBOT_MOVING: return RobotStatus::kMoving;
    case fleet::ROBOT_ARRIVED: return RobotStatus::kArrived;
    default: return RobotStatus::kFault;
  }
}

fleet::CoordinatorRole wire_role(CoordinatorRole role) {
  switch (role) {
    case CoordinatorRole::kActive: return fleet::COORDINATOR_ACTIVE;
    case CoordinatorRole::kStandby: return fleet::COORDINATOR_STANDBY;
    case CoordinatorRole::kStoodDown: return fleet::COORDINATOR_STOOD_DOWN;
    case CoordinatorRole::kEnded: return fleet::COORDINATOR_ENDED;
  }
  return fleet::COORDINATOR_ENDED;
}

CoordinatorRole role_of(fleet::CoordinatorRole role) {
  switch (role) {
    case fleet::COORDINATOR_ACTIVE: return CoordinatorRole::kActive;
    case fleet::COORDINATOR_STANDBY: return CoordinatorRole::kStandby;
    case fleet::COORDINATOR_STOOD_DOWN: return CoordinatorRole::kStoodDown;
    default: return CoordinatorRole::kEnded;
  }
}

}  // namespace

fleet::Announcement to_wire(const Announcement& announcement) {
  fleet::Announcement wire;
  wire.robot_id(announcement.robot_id);
  wire.backend(announcement.backend);
  wire.capabilities(announcement.capabilities);
  wire.version(announcement.version);
  wire.leaving(announcement.leaving);
  wire.incarnation(announcement.incarnation);
  return wire;
}

fleet::RobotState to_wire(const RobotState& state) {
  fleet::RobotState wire;
  wire.robot_id(state.robot_id);
  wire.cell_x(state.cell_x);
  wire.cell_y(state.cell_y);
  wire.pose_x(state.pose_x);
  wire.pose_y(state.pose_y);
  wire.pose_theta(state.pose_theta);
  wire.plan_epoch(state.plan_epoch);
  wire.action_index(state.action_index);
  wire.status(wire_status(state.status));
  wire.battery_percent(state.battery_percent);
  wire.seq_number(state.seq_number);
  wire.stamp_ms(state.stamp_ms);
  wire.incarnation(state.incarnation);
  wire.coordinator(state.coordinator);
  wire.heading(state.heading);
  return wire;
}

fleet::StepCommand to_wire(const StepCommand& command) {
  fleet::StepCommand wire;
  wire.robot_id(command.robot_id);
  wire.plan_epoch(command.plan_epoch);
  wire.action_index(command.action_index);
  wire.target_x(command.target_x);
  wire.target_y(command.target_y);
  wire.target_pose_x(command.target_pose_x);
  wire.target_pose_y(command.target_pose_y);
  wire.deadline_ms(command.deadline_ms);
  wire.coordinator(command.coordinator);
  wire.sent_ms(command.sent_ms);
  wire.robot_incarnation(command.robot_incarnation);
  wire.refused(command.refused);
  wire.target_heading(command.target_heading);
  return wire;
}

fleet::CoordinatorStatus to_wire(const CoordinatorStatus& status) {
  fleet::CoordinatorStatus wire;
  wire.coordinator(status.coordinator);
  wire.term(status.term);
  wire.claimed_ms(status.claimed_ms);
  wire.role(wire_role(status.role));
  wire.mission_id(status.mission_id);
  wire.plan_epoch(status.plan_epoch);
  return wire;
}

fleet::FleetStatus to_wire(const FleetStatus& status) {
  fleet::FleetStatus wire;
  wire.coordinator(status.coordinator);
  wire.plan_epoch(status.plan_epoch);
  wire.tasks_done(status.tasks_done);
  wire.tasks_total(status.tasks_total);
  wire.robots(status.robots);
  for (const Assignment& assignment : status.assignments) {
    fleet::Assignment row;
    row.robot_id(assignment.robot_id);
    row.role(assignment.role);
    row.tasks_done(assignment.tasks_done);
    row.tasks_total(assignment.tasks_total);
    wire.assignments().push_back(row);
  }
  for (const TaskVisit& done : status.done_visits) {
    fleet::TaskVisit visit;
    visit.task(done.task);
    visit.role(done.role);
    wire.done_visits().push_back(visit);
  }
  wire.round_trip_p50_ms(status.round_trip_p50_ms);
  wire.round_trip_p99_ms(status.round_trip_p99_ms);
  wire.last_planning_ms(status.last_planning_ms);
  wire.last_replan_latency_ms(status.last_replan_latency_ms);
  wire.steps_done(status.steps_done);
  wire.steps_planned(status.steps_planned);
  return wire;
}

fleet::MissionInfo to_wire(const MissionInfo& mission) {
  fleet::MissionInfo wire;
  wire.coordinator(mission.coordinator);
  wire.mission_id(mission.mission_id);
  wire.width(mission.width);
  wire.height(mission.height);
  wire.map_rows(mission.map_rows);
  wire.goals(wire_cells(mission.goals));
  for (const MissionTask& task : mission.tasks) {
    fleet::MissionTask row;
    row.x(task.x);
    row.y(task.y);
    row.roles(std::vector<int32_t>(task.roles.begin(), task.roles.end()));
    row.cancelled(task.cancelled);
    wire.tasks().push_back(row);
  }
  wire.lifelong(mission.lifelong);
  return wire;
}

fleet::FleetPlan to_wire(const FleetPlan& plan) {
  fleet::FleetPlan wire;
  wire.coordinator(plan.coordinator);
  wire.plan_epoch(plan.plan_epoch);
  wire.made_ms(plan.made_ms);
  wire.planning_ms(plan.planning_ms);
  wire.flowtime(plan.flowtime);
  for (const RobotPlan& robot : plan.robots) {
    fleet::RobotPlan row;
    row.robot_id(robot.robot_id);
    row.role(robot.role);
    row.path(wire_cells(robot.path));
    wire.robots().push_back(row);
  }
  return wire;
}

fleet::FleetEvent to_wire(const FleetEvent& event) {
  fleet::FleetEvent wire;
  wire.coordinator(event.coordinator);
  wire.stamp_ms(event.stamp_ms);
  wire.kind(event.kind);
  wire.robot_id(event.robot_id);
  wire.text(event.text);
  wire.value(event.value);
  return wire;
}

fleet::TaskRequest to_wire(const TaskRequest& request) {
  fleet::TaskRequest wire;
  wire.request_id(request.request_id);
  wire.action(static_cast<fleet::TaskAction>(request.action));
  wire.x(request.x);
  wire.y(request.y);
  wire.robot_id(request.robot_id);
  wire.task(request.task);
  return wire;
}

fleet::TaskReply to_wire(const TaskReply& reply) {
  fleet::TaskReply wire;
  wire.request_id(reply.request_id);
  wire.coordinator(reply.coordinator);
  wire.accepted(reply.accepted);
  wire.reason(reply.reason);
  wire.task(reply.task);
  wire.robot_id(reply.robot_id);
  wire.listing(reply.listing);
  return wire;
}

Announcement from_wire(const fleet::Announcement& wire) {
  return {wire.robot_id().to_string(), wire.backend().to_string(), wire.capabilities().to_string(),
          wire.version().to_string(), wire.leaving(), wire.incarnation()};
}

RobotState from_wire(const fleet::RobotState& wire) {
  RobotState state;
  state.robot_id = wire.robot_id().to_string();
  state.cell_x = wire.cell_x();
  state.cell_y = wire.cell_y();
  state.pose_x = wire.pose_x();
  state.pose_y = wire.pose_y();
  state.pose_theta = wire.pose_theta();
  state.plan_epoch = wire.plan_epoch();
  state.action_index = wire.action_index();
  state.status = status_of(wire.status());
  state.battery_percent = wire.battery_percent();
  state.seq_number = wire.seq_number();
  state.stamp_ms = wire.stamp_ms();
  state.incarnation = wire.incarnation();
  state.coordinator = wire.coordinator();
  state.heading = wire.heading();
  return state;
}

StepCommand from_wire(const fleet::StepCommand& wire) {
  return {wire.robot_id().to_string(), wire.plan_epoch(),    wire.action_index(),  wire.target_x(),
          wire.target_y(),             wire.target_pose_x(), wire.target_pose_y(), wire.deadline_ms(),
          wire.coordinator(),          wire.sent_ms(),       wire.robot_incarnation(), wire.refused(),
          wire.target_heading()};
}

CoordinatorStatus from_wire(const fleet::CoordinatorStatus& wire) {
  return {wire.coordinator(), wire.term(), wire.claimed_ms(), role_of(wire.role()), wire.mission_id().to_string(),
          wire.plan_epoch()};
}

FleetStatus from_wire(const fleet::FleetStatus& wire) {
  FleetStatus status;
  status.coordinator = wire.coordinator();
  status.plan_epoch = wire.plan_epoch();
  status.tasks_done = wire.tasks_done();
  status.tasks_total = wire.tasks_total();
  status.robots = wire.robots();
  for (const fleet::Assignment& row : wire.assignments()) {
    status.assignments.push_back({row.robot_id().to_string(), row.role(), row.tasks_done(), row.tasks_total()});
  }
  for (const fleet::TaskVisit& visit : wire.done_visits()) status.done_visits.push_back({visit.task(), visit.role()});
  status.round_trip_p50_ms = wire.round_trip_p50_ms();
  status.round_trip_p99_ms = wire.round_trip_p99_ms();
  status.last_planning_ms = wire.last_planning_ms();
  status.last_replan_latency_ms = wire.last_replan_latency_ms();
  status.steps_done = wire.steps_done();
  status.steps_planned = wire.steps_planned();
  return status;
}

MissionInfo from_wire(const fleet::MissionInfo& wire) {
  MissionInfo mission;
  mission.coordinator = wire.coordinator();
  mission.mission_id = wire.mission_id().to_string();
  mission.width = wire.width();
  mission.height = wire.height();
  mission.map_rows = wire.map_rows();
  mission.goals = cells_of(wire.goals());
  for (const fleet::MissionTask& task : wire.tasks()) {
    mission.tasks.push_back({task.x(), task.y(), std::vector<int>(task.roles().begin(), task.roles().end()),
                             task.cancelled()});
  }
  mission.lifelong = wire.lifelong();
  return mission;
}

FleetPlan from_wire(const fleet::FleetPlan& wire) {
  FleetPlan plan;
  plan.coordinator = wire.coordinator();
  plan.plan_epoch = wire.plan_epoch();
  plan.made_ms = wire.made_ms();
  plan.planning_ms = wire.planning_ms();
  plan.flowtime = wire.flowtime();
  for (const fleet::RobotPlan& robot : wire.robots()) {
    plan.robots.push_back({robot.robot_id().to_string(), robot.role(), cells_of(robot.path())});
  }
  return plan;
}

FleetEvent from_wire(const fleet::FleetEvent& wire) {
  return {wire.coordinator(), wire.stamp_ms(), wire.kind().to_string(), wire.robot_id().to_string(),
          wire.text().to_string(), wire.value()};
}

TaskRequest from_wire(const fleet::TaskRequest& wire) {
  return {wire.request_id().to_string(), static_cast<TaskAction>(wire.action()), wire.x(), wire.y(),
          wire.robot_id().to_string(), wire.task()};
}

TaskReply from_wire(const fleet::TaskReply& wire) {
  return {wire.request_id().to_string(), wire.coordinator(), wire.accepted(), wire.reason().to_string(),
          wire.task(), wire.robot_id().to_string(), wire.listing()};
}

}  // namespace fleet_transport::fastdds_codec
