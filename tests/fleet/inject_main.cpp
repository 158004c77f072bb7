// ctsfleet-test-inject: publishes malformed or hostile messages for the fleet tests: commands for
// unknown robots, off-map and non-neighbour targets, stale epochs, states from unknown robots,
// duplicate robot ids, commands in the name of the active coordinator (a far-future epoch, a stale
// one) and of a coordinator the robot does not follow. Its command writer is the strongest, so the
// commands reach the agent past DDS ownership and the agent's own checks are what is tested.
//
// With --claim ID it plays an impostor instead: it announces itself as robot ID and reports ID's
// state for a few seconds, with the identity given by --security/--identity (loaded as it is, with
// none of the checks the fleet's programs make first, as a modified program would) and, with
// --in-partition-of, from another robot's partition. Exit 4 when the middleware refuses it.
#include <CLI/CLI.hpp>

#include <atomic>
#include <memory>
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
  std::string discovery_server;
  app.add_option("--discovery-server", discovery_server, fleet_transport::kDiscoveryServerHelp);
  app.add_option("--victim", victim, "a live robot id to aim at");
  std::string security_dir, identity, claim, partition_of;
  int claim_x = 0, claim_y = 0, claim_rounds = 30;
  app.add_option("--rounds", claim_rounds, "impostor: how many states it sends, one per 0.1 s");
  app.add_option("--security", security_dir, "fleet directory (DDS Security)");
  app.add_option("--identity", identity, "enrolled name whose files to present");
  app.add_option("--claim", claim, "impostor: announce and report state as this robot id");
  app.add_option("--at", claim_x, "impostor: the cell x it reports");
  app.add_option("--at-y", claim_y, "impostor: the cell y it reports");
  app.add_option("--in-partition-of", partition_of, "impostor: write in this robot's partition");
  CLI11_PARSE(app, argc, argv);
  fleet_transport::TransportConfig config;
  config.vendor = fleet_transport::parse_vendor(vendor);
  config.domain_id = domain;
  config.loopback_config_dir = dds_dir;
  config.discovery_servers = discovery_server;
  config.command_strength = 1000;
  config.test_partition_of = partition_of;
  if (!security_dir.empty()) {
    try {
      config.security = fleet_transport::fleet_security_files(security_dir, identity);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "refused: %s\n", e.what());
      return 4;
    }
  }
  std::atomic<uint64_t> coordinator{0};
  std::atomic<int> epoch{0};
  std::atomic<uint64_t> victim_incarnation{0};  // a hostile sender reads it off the victim's states
  fleet_transport::Handlers handlers;
  if (claim.empty()) {  // a claim plays one robot, whose identity may read no other robot's states
    handlers.on_state = [&](const fleet_transport::RobotState& state) {
      if (state.robot_id == victim && state.incarnation != 0) victim_incarnation = state.incarnation;
    };
  }
  handlers.on_coordinator_status = [&](const fleet_transport::CoordinatorStatus& status) {
    if (status.role != fleet_transport::CoordinatorRole::kActive) return;
    coordinator = status.coordinator;
    epoch = status.plan_epoch;
  };
  std::unique_ptr<fleet_transport::Transport> transport;
  try {
    transport = fleet_transport::make_transport(config, handlers);
    if (!claim.empty()) {
      for (int round = 0; round < claim_rounds; ++round) {
        fleet_transport::RobotState state;
        state.robot_id = claim;
        state.cell_x = claim_x;
        state.cell_y = claim_y;
        state.seq_number = static_cast<uint64_t>(round + 1);
        state.incarnation = 0x1d1d;
        state.stamp_ms = fleet_transport::wall_clock_ms();
        transport->announce({claim, "sim", "", "impostor", false, 0x1d1d});
        transport->publish_state(state);
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
      std::printf("claimed %s for %d rounds of 0.1 s\n", claim.c_str(), claim_rounds);
      return 0;
    }
  } catch (const std::exception& e) {  // e.g. access control refuses the participant or a writer
    std::fprintf(stderr, "refused: %s\n", e.what());
    return 4;
  }
  transport->open_commands_for("ghost");
  transport->open_commands_for(victim);
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
    const uint64_t body = victim_incarnation.load();
    transport->send_command({"ghost", 1, 0, 3, 3, 3, 3, later, real});                        // unknown robot
    transport->send_command({victim, 1000, 0, -5, -5, -5, -5, later, real, 0, body});         // far-future epoch
    transport->send_command({victim, now_epoch, 1, 30, 30, 30, 30, later, real, 0, body});    // not a neighbour
    transport->send_command({victim, 0, 99, 0, 0, 0, 0, later, real, 0, body});               // stale epoch
    transport->send_command({victim, now_epoch, 1, 0, 0, 0, 0, later, real ^ 1, 0, body});    // a coordinator not followed
    transport->send_command({victim, now_epoch, 1, 0, 0, 0, 0, later, real, 0, body ^ 1});    // another process of the id
    transport->send_command({victim, now_epoch, -1, 0, 0, 0, 0, later, real ^ 1, 0, body, true});  // a forged refusal
    fleet_transport::RobotState intruder;
    intruder.robot_id = "intruder";
    intruder.cell_x = -7;
    intruder.cell_y = 400;
    intruder.seq_number = static_cast<uint64_t>(round + 1);
    try {
      transport->publish_state(intruder);                                   // unknown robot, off the map
      transport->announce({victim, "toio", "grid-4", "9.9.9", false});     // duplicate id
    } catch (const std::exception& e) {  // an enrolled coordinator may not write robot states
      if (round == 0) std::fprintf(stderr, "refused: %s\n", e.what());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  }
  std::printf("injected\n");
  return 0;
}
