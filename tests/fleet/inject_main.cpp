// ctsfleet-test-inject: publishes malformed or hostile messages for the fleet tests: commands for
// unknown robots, off-map and non-neighbour targets, stale epochs, states from unknown robots,
// duplicate robot ids.
#include <CLI/CLI.hpp>

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
  auto transport = fleet_transport::make_transport(config, {});
  transport->prepare_commands_for("ghost");
  transport->prepare_commands_for(victim);
  std::this_thread::sleep_for(std::chrono::seconds(2));  // discovery
  const int64_t later = fleet_transport::wall_clock_ms() + 5000;
  for (int round = 0; round < 3; ++round) {
    transport->send_command({"ghost", 1, 0, 3, 3, 3, 3, later});            // unknown robot
    transport->send_command({victim, 1000, 0, -5, -5, -5, -5, later});      // off the map, far future epoch
    transport->send_command({victim, 1000, 1, 30, 30, 30, 30, later});      // not a neighbour
    transport->send_command({victim, 0, 99, 0, 0, 0, 0, later});            // stale epoch
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
