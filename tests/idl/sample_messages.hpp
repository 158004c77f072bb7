// One message of each kind with every field set to a value other than its default, and the same
// messages with every string longer than its IDL bound: what both vendors' codec tests encode and
// decode (tests/idl/{cyclone,fastdds}_codec_test.cpp), so both are held to one expectation.
#pragma once

#include <string>

#include "fleet_transport/messages.hpp"

namespace fleet_transport::samples {

inline Announcement announcement() { return {"robot-7", "toio", "move,light", "1.4.2", true, 0xfedcba9876543210ULL}; }

inline RobotState robot_state() {
  RobotState s;
  s.robot_id = "robot_12";
  s.cell_x = 31;
  s.cell_y = -2;
  s.pose_x = 123.25;
  s.pose_y = -7.5;
  s.pose_theta = 1.0 / 3.0;
  s.plan_epoch = 41;
  s.action_index = 17;
  s.status = RobotStatus::kArrived;
  s.battery_percent = 88;
  s.seq_number = 1ULL << 40;
  s.stamp_ms = 1796000000123;
  s.incarnation = 0x8000000000000001ULL;
  s.coordinator = 99;
  s.heading = 3;
  return s;
}

inline StepCommand step_command() {
  return {"robot_12", 41, 18, 32, -2, 130.5, -7.25, 1796000000999, 0xabcdef, 1796000000500, 0x8000000000000001ULL,
          true, 2};
}

inline CoordinatorStatus coordinator_status() {
  return {0x1234567890ULL, 7, 1796000000001, CoordinatorRole::kStoodDown, "mission-9f3a", 12};
}

inline FleetStatus fleet_status() {
  FleetStatus s;
  s.coordinator = 5;
  s.plan_epoch = 3;
  s.tasks_done = 4;
  s.tasks_total = 9;
  s.robots = 2;
  s.assignments = {{"robot1", 0, 3, 5}, {"robot2", 1, 1, 4}};
  s.done_visits = {{0, 1}, {4, 0}, {8, 1}};
  s.round_trip_p50_ms = 1.5;
  s.round_trip_p99_ms = 9.25;
  s.last_planning_ms = 120.75;
  s.last_replan_latency_ms = 310.5;
  s.steps_done = 1234567890123;
  s.steps_planned = 2234567890123;
  return s;
}

inline MissionInfo mission_info() {
  MissionInfo m;
  m.coordinator = 77;
  m.mission_id = "mission-9f3a";
  m.width = 4;
  m.height = 2;
  m.map_rows = "..@.\n....";
  m.goals = {{0, 0}, {3, 1}};
  m.tasks = {{1, 1, {0, 1}, false}, {2, 1, {1}, true}, {0, 1, {}, false}};
  m.lifelong = true;
  return m;
}

inline FleetPlan fleet_plan() {
  FleetPlan p;
  p.coordinator = 77;
  p.plan_epoch = 6;
  p.made_ms = 1796000000777;
  p.planning_ms = 42.5;
  p.flowtime = 31;
  p.robots = {{"robot1", 0, {{0, 0}, {1, 0}, {1, 1}}}, {"robot2", 1, {{3, 1}}}, {"robot3", 2, {}}};
  return p;
}

inline FleetEvent fleet_event() { return {77, 1796000000888, "off_plan", "robot2", "stood at (1, 1), planned (2, 1)", 2.5}; }

inline TaskRequest task_request() { return {"req-42", TaskAction::kCancel, 3, 4, "robot2", 7}; }

inline TaskReply task_reply() {
  return {"req-42", 77, true, "cancelled task 7", 7, "robot2", "0 (1, 1) roles 0 1 pending\n7 (3, 4) cancelled\n"};
}

// Every bounded string one character per bound too long (the IDL's bounds: messages.hpp and
// idl/fleet.idl), and what is left of it on the far side.
inline std::string too_long(size_t bound) { return std::string(bound, 'a') + "overflow"; }
inline std::string cut(size_t bound) { return std::string(bound, 'a'); }

}  // namespace fleet_transport::samples
