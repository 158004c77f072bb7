// The cases every vendor's codec must pass: each message kind comes back whole from its wire
// type, and strings over their IDL bound come back cut to it, the same for both vendors (so a
// Cyclone DDS process and a Fast DDS one read each other's messages alike).
//
// A test file instantiates them with a Codec type that has, for each message M,
// `static M round_trip(const M&)`: encode to the wire type, (optionally) serialize and deserialize,
// decode. See cyclone_codec_test.cpp and fastdds_codec_test.cpp.
#pragma once

#include <gtest/gtest.h>

#include "fleet_transport/messages.hpp"
#include "sample_messages.hpp"

namespace fleet_transport {
namespace {

template <typename Codec>
class CodecRoundTrip : public testing::Test {};
TYPED_TEST_SUITE_P(CodecRoundTrip);

TYPED_TEST_P(CodecRoundTrip, EveryMessageKindComesBackWhole) {
  EXPECT_EQ(TypeParam::round_trip(samples::announcement()), samples::announcement());
  EXPECT_EQ(TypeParam::round_trip(samples::robot_state()), samples::robot_state());
  EXPECT_EQ(TypeParam::round_trip(samples::step_command()), samples::step_command());
  EXPECT_EQ(TypeParam::round_trip(samples::coordinator_status()), samples::coordinator_status());
  EXPECT_EQ(TypeParam::round_trip(samples::fleet_status()), samples::fleet_status());
  EXPECT_EQ(TypeParam::round_trip(samples::mission_info()), samples::mission_info());
  EXPECT_EQ(TypeParam::round_trip(samples::fleet_plan()), samples::fleet_plan());
  EXPECT_EQ(TypeParam::round_trip(samples::fleet_event()), samples::fleet_event());
  EXPECT_EQ(TypeParam::round_trip(samples::task_request()), samples::task_request());
  EXPECT_EQ(TypeParam::round_trip(samples::task_reply()), samples::task_reply());
}

TYPED_TEST_P(CodecRoundTrip, DefaultMessagesComeBackAsDefaults) {
  EXPECT_EQ(TypeParam::round_trip(Announcement{}), Announcement{});
  EXPECT_EQ(TypeParam::round_trip(RobotState{}), RobotState{});
  EXPECT_EQ(TypeParam::round_trip(StepCommand{}), StepCommand{});
  EXPECT_EQ(TypeParam::round_trip(CoordinatorStatus{}), CoordinatorStatus{});
  EXPECT_EQ(TypeParam::round_trip(FleetStatus{}), FleetStatus{});
  EXPECT_EQ(TypeParam::round_trip(MissionInfo{}), MissionInfo{});
  EXPECT_EQ(TypeParam::round_trip(FleetPlan{}), FleetPlan{});
  EXPECT_EQ(TypeParam::round_trip(FleetEvent{}), FleetEvent{});
  EXPECT_EQ(TypeParam::round_trip(TaskRequest{}), TaskRequest{});
  EXPECT_EQ(TypeParam::round_trip(TaskReply{}), TaskReply{});
}

TYPED_TEST_P(CodecRoundTrip, EveryEnumeratorSurvives) {
  for (RobotStatus status : {RobotStatus::kIdle, RobotStatus::kMoving, RobotStatus::kArrived, RobotStatus::kFault}) {
    RobotState state = samples::robot_state();
    state.status = status;
    EXPECT_EQ(TypeParam::round_trip(state).status, status) << to_string(status);
  }
  for (CoordinatorRole role : {CoordinatorRole::kActive, CoordinatorRole::kStandby, CoordinatorRole::kStoodDown,
                               CoordinatorRole::kEnded}) {
    CoordinatorStatus status = samples::coordinator_status();
    status.role = role;
    EXPECT_EQ(TypeParam::round_trip(status).role, role) << to_string(role);
  }
  for (TaskAction action : {TaskAction::kAdd, TaskAction::kCancel, TaskAction::kList}) {
    TaskRequest request = samples::task_request();
    request.action = action;
    EXPECT_EQ(TypeParam::round_trip(request).action, action) << to_string(action);
  }
}

TYPED_TEST_P(CodecRoundTrip, StringsOverTheirBoundComeBackCutToIt) {
  using samples::cut;
  using samples::too_long;
  Announcement announcement{too_long(32), too_long(16), too_long(64), too_long(16), false, 1};
  Announcement announcement_cut{cut(32), cut(16), cut(64), cut(16), false, 1};
  EXPECT_EQ(TypeParam::round_trip(announcement), announcement_cut);

  RobotState state = samples::robot_state();
  state.robot_id = too_long(32);
  EXPECT_EQ(TypeParam::round_trip(state).robot_id, cut(32));

  StepCommand command = samples::step_command();
  command.robot_id = too_long(32);
  EXPECT_EQ(TypeParam::round_trip(command).robot_id, cut(32));

  CoordinatorStatus status = samples::coordinator_status();
  status.mission_id = too_long(64);
  EXPECT_EQ(TypeParam::round_trip(status).mission_id, cut(64));

  FleetStatus progress = samples::fleet_status();
  progress.assignments[1].robot_id = too_long(32);
  EXPECT_EQ(TypeParam::round_trip(progress).assignments[1].robot_id, cut(32));

  MissionInfo mission = samples::mission_info();
  mission.mission_id = too_long(64);
  mission.map_rows = std::string(100000, '.');  // unbounded: comes back whole
  const MissionInfo mission_back = TypeParam::round_trip(mission);
  EXPECT_EQ(mission_back.mission_id, cut(64));
  EXPECT_EQ(mission_back.map_rows, mission.map_rows);

  FleetPlan plan = samples::fleet_plan();
  plan.robots[0].robot_id = too_long(32);
  EXPECT_EQ(TypeParam::round_trip(plan).robots[0].robot_id, cut(32));

  FleetEvent event{1, 2, too_long(16), too_long(32), too_long(256), 3};
  FleetEvent event_cut{1, 2, cut(16), cut(32), cut(256), 3};
  EXPECT_EQ(TypeParam::round_trip(event), event_cut);

  TaskRequest request{too_long(64), TaskAction::kAdd, 1, 2, too_long(32), 3};
  TaskRequest request_cut{cut(64), TaskAction::kAdd, 1, 2, cut(32), 3};
  EXPECT_EQ(TypeParam::round_trip(request), request_cut);

  TaskReply reply{too_long(64), 1, true, too_long(256), 2, too_long(32), std::string(70000, 'x')};
  TaskReply reply_cut{cut(64), 1, true, cut(256), 2, cut(32), std::string(70000, 'x')};
  EXPECT_EQ(TypeParam::round_trip(reply), reply_cut);
}

TYPED_TEST_P(CodecRoundTrip, AThousandRobotPlanComesBackWhole) {
  FleetPlan plan = samples::fleet_plan();
  plan.robots.clear();
  for (int r = 0; r < 1000; ++r) {
    RobotPlan robot{"robot" + std::to_string(r), r, {}};
    for (int t = 0; t < 50; ++t) robot.path.push_back({r % 97 + t, r / 97});
    plan.robots.push_back(robot);
  }
  EXPECT_EQ(TypeParam::round_trip(plan), plan);
}

REGISTER_TYPED_TEST_SUITE_P(CodecRoundTrip, EveryMessageKindComesBackWhole, DefaultMessagesComeBackAsDefaults,
                            EveryEnumeratorSurvives, StringsOverTheirBoundComeBackCutToIt,
                            AThousandRobotPlanComesBackWhole);

}  // namespace
}  // namespace fleet_transport
