// JSON of the fleet's wire messages (the dashboard's history files and its page use it): every
// field by its IDL name, enums as words ("moving", "active", "add"). Reading one back throws
// nlohmann::json::exception naming the missing or mistyped key.
#pragma once

#include <nlohmann/json.hpp>

#include "fleet_transport/messages.hpp"

namespace fleet_transport {

NLOHMANN_JSON_SERIALIZE_ENUM(RobotStatus, {{RobotStatus::kIdle, "idle"},
                                           {RobotStatus::kMoving, "moving"},
                                           {RobotStatus::kArrived, "arrived"},
                                           {RobotStatus::kFault, "fault"}})
NLOHMANN_JSON_SERIALIZE_ENUM(CoordinatorRole, {{CoordinatorRole::kActive, "active"},
                                               {CoordinatorRole::kStandby, "standby"},
                                               {CoordinatorRole::kStoodDown, "stood down"},
                                               {CoordinatorRole::kEnded, "ended"}})
NLOHMANN_JSON_SERIALIZE_ENUM(TaskAction, {{TaskAction::kAdd, "add"},
                                          {TaskAction::kCancel, "cancel"},
                                          {TaskAction::kList, "list"}})

NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Announcement, robot_id, backend, capabilities, version, leaving, incarnation)
// RobotState and StepCommand: a field missing from a recording keeps its default (recordings made
// before `heading` and `target_heading` existed still load).
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(RobotState, robot_id, cell_x, cell_y, pose_x, pose_y, pose_theta, plan_epoch,
                                   action_index, status, battery_percent, seq_number, stamp_ms, incarnation, coordinator,
                                   heading)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE_WITH_DEFAULT(StepCommand, robot_id, plan_epoch, action_index, target_x, target_y, target_pose_x,
                                   target_pose_y, deadline_ms, coordinator, sent_ms, target_heading)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Assignment, robot_id, role, tasks_done, tasks_total)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TaskVisit, task, role)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CoordinatorStatus, coordinator, term, claimed_ms, role, mission_id, plan_epoch)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(FleetStatus, coordinator, plan_epoch, tasks_done, tasks_total, robots, assignments,
                                   done_visits, round_trip_p50_ms, round_trip_p99_ms, last_planning_ms,
                                   last_replan_latency_ms, steps_done, steps_planned)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(GridCell, x, y)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(MissionTask, x, y, roles, cancelled)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(MissionInfo, coordinator, mission_id, width, height, map_rows, goals, tasks, lifelong)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(RobotPlan, robot_id, role, path)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(FleetPlan, coordinator, plan_epoch, made_ms, planning_ms, flowtime, robots)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(FleetEvent, coordinator, stamp_ms, kind, robot_id, text, value)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TaskRequest, request_id, action, x, y, robot_id, task)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(TaskReply, request_id, coordinator, accepted, reason, task, robot_id, listing)

}  // namespace fleet_transport
