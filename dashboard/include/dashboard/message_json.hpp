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
// RobotState and StepCommand: every field is required (a missing one is refused, naming it) but
// the heading, which recordings made before it existed do not have (-1 then: unknown, any).
inline void to_json(nlohmann::json& j, const RobotState& s) {
  j = {{"robot_id", s.robot_id},       {"cell_x", s.cell_x},
       {"cell_y", s.cell_y},           {"pose_x", s.pose_x},
       {"pose_y", s.pose_y},           {"pose_theta", s.pose_theta},
       {"plan_epoch", s.plan_epoch},   {"action_index", s.action_index},
       {"status", s.status},           {"battery_percent", s.battery_percent},
       {"seq_number", s.seq_number},   {"stamp_ms", s.stamp_ms},
       {"incarnation", s.incarnation}, {"coordinator", s.coordinator},
       {"heading", s.heading}};
}
inline void from_json(const nlohmann::json& j, RobotState& s) {
  j.at("robot_id").get_to(s.robot_id);
  j.at("cell_x").get_to(s.cell_x);
  j.at("cell_y").get_to(s.cell_y);
  j.at("pose_x").get_to(s.pose_x);
  j.at("pose_y").get_to(s.pose_y);
  j.at("pose_theta").get_to(s.pose_theta);
  j.at("plan_epoch").get_to(s.plan_epoch);
  j.at("action_index").get_to(s.action_index);
  j.at("status").get_to(s.status);
  j.at("battery_percent").get_to(s.battery_percent);
  j.at("seq_number").get_to(s.seq_number);
  j.at("stamp_ms").get_to(s.stamp_ms);
  j.at("incarnation").get_to(s.incarnation);
  j.at("coordinator").get_to(s.coordinator);
  s.heading = j.value("heading", -1);
}
inline void to_json(nlohmann::json& j, const StepCommand& c) {
  j = {{"robot_id", c.robot_id},       {"plan_epoch", c.plan_epoch},       {"action_index", c.action_index},
       {"target_x", c.target_x},       {"target_y", c.target_y},           {"target_pose_x", c.target_pose_x},
       {"target_pose_y", c.target_pose_y}, {"deadline_ms", c.deadline_ms}, {"coordinator", c.coordinator},
       {"sent_ms", c.sent_ms},         {"target_heading", c.target_heading}};
}
inline void from_json(const nlohmann::json& j, StepCommand& c) {
  j.at("robot_id").get_to(c.robot_id);
  j.at("plan_epoch").get_to(c.plan_epoch);
  j.at("action_index").get_to(c.action_index);
  j.at("target_x").get_to(c.target_x);
  j.at("target_y").get_to(c.target_y);
  j.at("target_pose_x").get_to(c.target_pose_x);
  j.at("target_pose_y").get_to(c.target_pose_y);
  j.at("deadline_ms").get_to(c.deadline_ms);
  j.at("coordinator").get_to(c.coordinator);
  j.at("sent_ms").get_to(c.sent_ms);
  c.target_heading = j.value("target_heading", -1);
}
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
