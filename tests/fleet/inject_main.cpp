// ctsfleet-test-inject: publishes malformed or hostile messages for the fleet tests: commands for
// unknown robots, off-map and non-neighbour targets, stale epochs, states from unknown robots,
// duplicate robot ids, commands in the name of the active coordinator (a far-future epoch, a stale
// one) and of a coordinator the robot does not follow. Its command writer is the strongest, so the
// commands reach the agent past DDS ownership and the agent's own checks are what is tested.
#include <CLI/CLI.hpp>

#include <atomic>
#include <cstdio>
#include <thread>

#include "fleet_transport/transport.hpp"

int main(int argc, char** argv) {
  CLI::App app{"ctsfleet-test-inject: send hostile fleet messages (tests only)"};
  std::string vendor = "cyclone", dds_dir, victim = "robot0";
  int domain = 0;
  app.add_option("--dds", vendor);
  app.add_option("--domain", domain);
  app.add_option("--dds-config-dir", dds_dir);
  app.add_option("--victim", victim, "a live robot id to aim at");
  CLI11_PARSE(app, argc, argv);
  fleet_transport::TransportConfig config;
  config.vendor = fleet_transport::parse_vendor(vendor);
  config.domain_id = domain;
  config.loopback_config_dir = dds_dir;
  config.command_strength = 1000;
  std::atomic<uint64_t> coordinator{0};
  std::atomic<int> epoch{0};
  fleet_transport::Handlers handlers;
  handlers.on_coordinator_status = [&](const fleet_transport::CoordinatorStatus& status) {
    if (status.role != fleet_transport::CoordinatorRole::kActive) return;
    coordinator = status.coordinator;
    epoch = status.plan_epoch;
  };
  auto transport = fleet_transport::make_transport(config, handlers);
  transport->prepare_commands_for("ghost");
  transport->prepare_commands_for(victim);
  for (int i = 0; i < 100 && coordinator.load() == 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  if (coordinator.load() == 0) {
    std::fprintf(stderr, "no active coordinator heard in 10 s\n");
    return 3;
  }
  std::this_thread::sleep_for(std::chrono::seconds(2));  // discovery
  const int64_t later = fleet_transport::wall_clock_ms() + 5000;
  const uint64_t real = coordinator.load();
  const int now_epoch = epoch.load();
  // A second "coordinator" of term 0: ranks below the real one, so the robot does not follow it.
  fleet_transport::CoordinatorStatus rival;
  rival.coordinator = real ^ 1;
  rival.term = 0;
  rival.claimed_ms = fleet_transport::wall_clock_ms();
  rival.mission_id = "rival";
  rival.plan_epoch = now_epoch;
  for (int round = 0; round < 3; ++round) {
    transport->publish_coordinator_status(rival);
    transport->send_command({"ghost", 1, 0, 3, 3, 3, 3, later, real});               // unknown robot
    transport->send_command({victim, 1000, 0, -5, -5, -5, -5, later, real});         // far-future epoch
    transport->send_command({victim, now_epoch, 1, 30, 30, 30, 30, later, real});    // not a neighbour
    transport->send_command({victim, 0, 99, 0, 0, 0, 0, later, real});               // stale epoch
    transport->send_command({victim, now_epoch, 1, 0, 0, 0, 0, later, real ^ 1});    // a coordinator not followed
    fleet_transport::RobotState intruder;
    intruder.robot_id = "intruder";
    intruder.cell_x = -7;
    intruder.cell_y = 400;
    intruder.seq_number = static_cast<uint64_t>(round + 1);
    transport->publish_state(intruder);                                     // unknown robot, off the map
    transport->announce({victim, "toio", "grid-4", "9.9.9", false});       // duplicate id
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }
  std::printf("injected\n");
  return 0;
}
