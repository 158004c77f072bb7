// A Transport that sends nothing anywhere and remembers what it was given: commands, the last
// state and the last fleet status. For tests of the coordinator and the agent without DDS.
#pragma once

#include <chrono>
#include <vector>

#include "fleet_transport/transport.hpp"

namespace testing_support {

class FakeTransport : public fleet_transport::Transport {
 public:
  void announce(const fleet_transport::Announcement&) override {}
  void say_goodbye(const std::string&) override {}
  void publish_state(const fleet_transport::RobotState& state) override { last_state = state; }
  void send_command(const fleet_transport::StepCommand& command) override { commands.push_back(command); }
  void open_commands_for(const std::string&) override {}
  void publish_coordinator_status(const fleet_transport::CoordinatorStatus& status) override {
    last_coordinator_status = status;
    heartbeat_times.push_back(std::chrono::steady_clock::now());
  }
  void publish_fleet_status(const fleet_transport::FleetStatus& status) override {
    last_status = status;
    ++statuses;
  }
  void set_command_strength(int value) override { strength = value; }
  void publish_mission_info(const fleet_transport::MissionInfo& info) override { last_mission = info; }
  void publish_fleet_plan(const fleet_transport::FleetPlan& plan) override { last_plan = plan; }
  void publish_fleet_event(const fleet_transport::FleetEvent& event) override { events.push_back(event); }
  void request_task(const fleet_transport::TaskRequest&) override {}
  void reply_task(const fleet_transport::TaskReply& reply) override { replies.push_back(reply); }

  std::vector<fleet_transport::StepCommand> commands;
  fleet_transport::RobotState last_state;
  fleet_transport::FleetStatus last_status;
  fleet_transport::CoordinatorStatus last_coordinator_status;
  fleet_transport::MissionInfo last_mission;
  fleet_transport::FleetPlan last_plan;
  std::vector<fleet_transport::FleetEvent> events;
  std::vector<fleet_transport::TaskReply> replies;
  std::vector<std::chrono::steady_clock::time_point> heartbeat_times;  // of each CoordinatorStatus
  int statuses = 0;
  int strength = 0;
};

}  // namespace testing_support
