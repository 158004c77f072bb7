// The Fast DDS wire mapping: fleet_transport's messages to and from the fastddsgen-generated C++
// types, and nothing else (no DDS entity is touched), so that it is tested on its own
// (tests/idl/codec_round_trip_test.cpp). Strings longer than their IDL bound are cut to it, as the
// Cyclone DDS codec cuts them.
#pragma once

#include "fleet.h"
#include "fleet_transport/messages.hpp"

namespace fleet_transport::fastdds_codec {

fleet::Announcement to_wire(const Announcement& announcement);
fleet::RobotState to_wire(const RobotState& state);
fleet::StepCommand to_wire(const StepCommand& command);
fleet::CoordinatorStatus to_wire(const CoordinatorStatus& status);
fleet::FleetStatus to_wire(const FleetStatus& status);
fleet::MissionInfo to_wire(const MissionInfo& mission);
fleet::FleetPlan to_wire(const FleetPlan& plan);
fleet::FleetEvent to_wire(const FleetEvent& event);
fleet::TaskRequest to_wire(const TaskRequest& request);
fleet::TaskReply to_wire(const TaskReply& reply);

Announcement from_wire(const fleet::Announcement& wire);
RobotState from_wire(const fleet::RobotState& wire);
StepCommand from_wire(const fleet::StepCommand& wire);
CoordinatorStatus from_wire(const fleet::CoordinatorStatus& wire);
FleetStatus from_wire(const fleet::FleetStatus& wire);
MissionInfo from_wire(const fleet::MissionInfo& wire);
FleetPlan from_wire(const fleet::FleetPlan& wire);
FleetEvent from_wire(const fleet::FleetEvent& wire);
TaskRequest from_wire(const fleet::TaskRequest& wire);
TaskReply from_wire(const fleet::TaskReply& wire);

}  // namespace fleet_transport::fastdds_codec
