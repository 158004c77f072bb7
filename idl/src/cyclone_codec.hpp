// The Cyclone DDS wire mapping: fleet_transport's messages to and from the idlc-generated C types,
// and nothing else (no DDS entity is touched), so that it is tested on its own
// (tests/idl/codec_round_trip_test.cpp). Strings longer than their IDL bound are cut to it, as the
// Fast DDS codec cuts them.
#pragma once

#include <functional>

#include "fleet.h"
#include "fleet_transport/messages.hpp"

namespace fleet_transport::cyclone_codec {

// Messages of fixed size: the wire sample is a value of its own.
fleet_Announcement to_wire(const Announcement& announcement);
fleet_RobotState to_wire(const RobotState& state);
fleet_StepCommand to_wire(const StepCommand& command);
fleet_CoordinatorStatus to_wire(const CoordinatorStatus& status);
fleet_FleetEvent to_wire(const FleetEvent& event);
fleet_TaskRequest to_wire(const TaskRequest& request);

// Messages with sequences or unbounded strings: the C sample points into storage that lives only
// while `use` runs (dds_write copies it).
template <typename Wire>
using UseWire = std::function<void(const Wire&)>;
void with_wire(const FleetStatus& status, const UseWire<fleet_FleetStatus>& use);
void with_wire(const MissionInfo& mission, const UseWire<fleet_MissionInfo>& use);
void with_wire(const FleetPlan& plan, const UseWire<fleet_FleetPlan>& use);
void with_wire(const TaskReply& reply, const UseWire<fleet_TaskReply>& use);

Announcement from_wire(const fleet_Announcement& wire);
RobotState from_wire(const fleet_RobotState& wire);
StepCommand from_wire(const fleet_StepCommand& wire);
CoordinatorStatus from_wire(const fleet_CoordinatorStatus& wire);
FleetStatus from_wire(const fleet_FleetStatus& wire);
MissionInfo from_wire(const fleet_MissionInfo& wire);
FleetPlan from_wire(const fleet_FleetPlan& wire);
FleetEvent from_wire(const fleet_FleetEvent& wire);
TaskRequest from_wire(const fleet_TaskRequest& wire);
TaskReply from_wire(const fleet_TaskReply& wire);

}  // namespace fleet_transport::cyclone_codec
