// ctsfleet-agent: one robot's process. Bridges the fleet's step commands to a simulated robot or
// to a toio cube over BLE (BlueZ on the system D-Bus) and reports the robot's state.
#include <spdlog/spdlog.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <optional>
#include <thread>

#include "ctsfleet/data_dir.hpp"
#include "ctsfleet/program.hpp"
#include "fleet_transport/lease_timeouts.hpp"
#include "planner_core/input_error.hpp"
#include "robot_agent/robot_agent.hpp"
#include "robot_agent/sim_robot.hpp"
#include "robot_agent/toio_robot.hpp"

int main(int argc, char** argv) {
  using namespace robot_agent;
  ctsfleet::Program program("ctsfleet-agent", "one robot of the fleet (simulated robot or toio cube)");
  CLI::App& app = program.app();
  AgentSettings settings;
  SimSettings sim;
  ToioSettings toio;
  std::string mat_file;
  int max_speed = toio.max_speed, move_timeout_s = toio.move_timeout_s;
  std::string backend_name = "sim", start_text = "0,0", vendor = "cyclone", dds_dir;
  int domain = 0;
  double lease = 1.0;
  app.add_option("--id", settings.robot_id, "robot id (1 to 32 characters of A-Z, a-z, 0-9, '_' and '-')")->required();
  app.add_option("--backend", backend_name, "robot backend")->check(CLI::IsMember({"sim", "toio"}))->capture_default_str();
  app.add_option("--start", start_text, "starting cell x,y (sim)")->capture_default_str();
  app.add_option("--dds", vendor, "DDS implementation")->check(CLI::IsMember({"cyclone", "fastdds"}))->capture_default_str();
  app.add_option("--domain", domain, "DDS domain id")->check(ctsfleet::dds_domain())->capture_default_str();
  app.add_option("--lease", lease, "liveliness lease in seconds")->check(ctsfleet::positive_seconds(3600))->capture_default_str();
  app.add_option("--dds-config-dir", dds_dir,
                 "folder with the loopback DDS XML files (default: the shipped config/dds, as the coordinator's config)")
      ->check(CLI::ExistingDirectory);
  int64_t test_clock_skew_ms = 0;
  app.add_option("--test-clock-skew-ms", test_clock_skew_ms,
                 "tests only: this agent's wall clock runs this many ms ahead (behind when negative), as on a host "
                 "whose clock is off")
      ->check(CLI::Range(int64_t{-3600000}, int64_t{3600000}));
  int test_deaf_after = -1;
  double test_deaf_s = 0;
  CLI::Option* deaf_for = app.add_option("--test-deaf-s", test_deaf_s, "tests only: how long --test-deaf-after lasts")
                              ->check(ctsfleet::positive_seconds(3600));
  app.add_option("--test-deaf-after", test_deaf_after,
                 "tests only: after this many step commands, every command is lost before it reaches the robot "
                 "for --test-deaf-s, as when a command channel breaks while states still go out")
      ->check(CLI::Range(0, 1000000))
      ->needs(deaf_for);
  std::string network_interface, peers;
  app.add_option("--iface", network_interface, fleet_transport::kInterfaceHelp);
  app.add_option("--peers", peers, fleet_transport::kPeersHelp);
  std::string discovery_server;
  app.add_option("--discovery-server", discovery_server, fleet_transport::kDiscoveryServerHelp);
  std::string security_dir;
  bool insecure = false;
  app.add_option("--security", security_dir,
                 "fleet directory made by ctsfleet-ca (DDS Security; this robot's identity is the one enrolled as --id)");
  app.add_flag("--insecure", insecure, "toio: run without DDS Security (a real robot requires --security otherwise)");
  app.add_option("--state-rate", settings.state_rate_hz, "state messages per second")
      ->check(ctsfleet::number_in(0.1, 1000))
      ->capture_default_str();
  app.add_option("--first-seq", settings.first_seq_number,
                 "sequence number of the first state (tests: play a robot that ran long before a restart)")
      ->check(ctsfleet::count_in(1, 4'000'000'000'000'000'000))
      ->capture_default_str();
  app.add_option("--step", sim.step_s, "sim: seconds per move")->check(ctsfleet::positive_seconds(3600))->capture_default_str();
  app.add_option("--jitter", sim.jitter, "sim: each move takes step * (1 + U[0, jitter])")
      ->check(ctsfleet::number_in(0, 10))
      ->capture_default_str();
  app.add_option("--turn", sim.turn_s, "sim: seconds per quarter turn in place (0: turns take no time)")
      ->check(ctsfleet::number_in(0, 3600))
      ->capture_default_str();
  std::string heading = "E";
  app.add_option("--heading", heading, "sim: the way the robot faces at the start")
      ->check(CLI::IsMember({"E", "S", "W", "N"}))
      ->capture_default_str();
  app.add_option("--delay-probability", sim.delay_probability, "sim: chance of an extra delay per move")
      ->check(ctsfleet::number_in(0, 1));
  app.add_option("--delay", sim.delay_s, "sim: length of that delay in seconds")->check(ctsfleet::number_in(0, 3600));
  std::string delay_config;
  app.add_option("--delay-config", delay_config,
                 "sim: delays as the League of Robot Runners' 2026 rules draw them: a JSON file holding a "
                 "delayConfig (itself, or a problem with one); the draws' seed is its seed plus --seed")
      ->check(CLI::ExistingFile);
  app.add_option("--delay-tick", sim.delay_tick_s,
                 "sim, with --delay-config: seconds per tick of the delay model (0: --step / 3)")
      ->check(ctsfleet::number_in(0, 3600))
      ->capture_default_str();
  app.add_option("--stall-at", sim.stall_at_s, "sim fault: stall this many seconds after start")
      ->check(ctsfleet::number_in(0, 1e6));
  app.add_option("--stall-for", sim.stall_for_s, "sim fault: stall duration in seconds")->check(ctsfleet::number_in(0, 1e6));
  app.add_option("--silent-at", sim.silent_at_s, "sim fault: stop reporting state after this many seconds")
      ->check(ctsfleet::number_in(0, 1e6));
  app.add_option("--crash-at", sim.crash_at_s, "sim fault: abort the process after this many seconds")
      ->check(ctsfleet::number_in(0, 1e6));
  std::string teleport_to;
  app.add_option("--teleport-after", sim.teleport_after_moves, "sim fault: carried by hand to --to after this many moves")
      ->check(ctsfleet::count_in(0, 1'000'000));
  app.add_option("--to", teleport_to, "sim fault: the cell x,y --teleport-after puts the robot on");
  app.add_option("--seed", sim.seed, "sim: random seed");
  app.add_option("--cube", toio.cube, "toio: the cube's advertised name (toio-XXX) or Bluetooth address");
  app.add_option("--mat", mat_file, "toio: mat file (config/mats/*.yaml) placing the grid on the mat")
      ->check(CLI::ExistingFile);
  app.add_option("--adapter", toio.adapter, "toio: Bluetooth adapter")->capture_default_str();
  app.add_option("--max-speed", max_speed, "toio: speed of a move, 10-255")->capture_default_str()
      ->check(CLI::Range(10, 255));
  app.add_option("--move-timeout", move_timeout_s, "toio: seconds before a move counts as failed")
      ->capture_default_str()->check(CLI::Range(1, 30));
  return program.main(argc, argv, [&] {
    const std::atomic<bool>& g_stop = ctsfleet::stop_requested();
    using planner_core::InputError;
    if (!fleet_transport::is_valid_robot_id(settings.robot_id)) {
      throw InputError("--id: '" + fleet_transport::printable(settings.robot_id, 40) + "' is not a robot id (" +
                       fleet_transport::kRobotIdRule + ")");
    }
    Cell start;
    char trailing = 0;
    if (std::sscanf(start_text.c_str(), "%d,%d%c", &start.x, &start.y, &trailing) != 2 || start.x < 0 || start.y < 0 ||
        start.x > 100000 || start.y > 100000) {
      throw InputError("--start: must be x,y with x and y in [0, 100000], not '" + start_text + "'");
    }
    sim.start_heading = std::string("ESWN").find(heading.at(0));
    if (sim.teleport_after_moves >= 0) {
      if (std::sscanf(teleport_to.c_str(), "%d,%d%c", &sim.teleport_to.x, &sim.teleport_to.y, &trailing) != 2 ||
          sim.teleport_to.x < 0 || sim.teleport_to.y < 0 || sim.teleport_to.x > 100000 || sim.teleport_to.y > 100000) {
        throw InputError("--to: --teleport-after needs a cell x,y with x and y in [0, 100000], not '" + teleport_to + "'");
      }
    }
    if (!delay_config.empty()) sim.league_delays = planner_core::load_delay_config(delay_config);
    if (dds_dir.empty()) dds_dir = ctsfleet::data_path("config/dds").string();
    if (test_clock_skew_ms != 0) {
      fleet_transport::set_wall_clock_skew_for_tests(test_clock_skew_ms);
      spdlog::warn("{}: clock skewed by {} ms for a test", settings.robot_id, test_clock_skew_ms);
    }
    if (backend_name == "toio" && security_dir.empty() && !insecure) {
      throw InputError(std::string("--backend toio drives a real robot and requires --security FLEET_DIR (") +
                       fleet_transport::kFleetCaHint + "); --insecure runs it without, on a network you trust");
    }
    const fleet_transport::SecurityFiles security = fleet_transport::load_fleet_security(security_dir, settings.robot_id);
    fleet_transport::check_discovery_servers(fleet_transport::parse_vendor(vendor), discovery_server, security.enabled());
    fleet_transport::check_network(network_interface, peers);
    if (!security.enabled()) spdlog::warn("{}: DDS Security is off: any process on the domain can command this robot", settings.robot_id);
    std::unique_ptr<RobotBackend> backend;
    SimRobot* sim_robot = nullptr;
    if (backend_name == "toio") {
      toio.max_speed = static_cast<uint8_t>(max_speed);
      toio.move_timeout_s = static_cast<uint8_t>(move_timeout_s);
      if (toio.cube.empty() || mat_file.empty()) throw InputError("--backend toio needs --cube and --mat");
      backend = std::make_unique<ToioRobot>(toio, MatCalibration::load(mat_file));
    } else {
      auto robot = std::make_unique<SimRobot>(start, sim);
      sim_robot = robot.get();
      backend = std::move(robot);
    }
    auto reporting = [sim_robot] { return sim_robot == nullptr || sim_robot->reporting_enabled(); };
    try {
      RobotBackend& robot = *backend;
      settings.coordinator_silence_s = fleet_transport::LeaseTimeouts{lease}.coordinator_gone_s();
      RobotAgent agent(settings, robot);
      fleet_transport::TransportConfig config;
      config.vendor = fleet_transport::parse_vendor(vendor);
      config.domain_id = domain;
      config.lease_s = lease;
      config.commands_for = settings.robot_id;
      config.loopback_config_dir = dds_dir;
      config.discovery_servers = discovery_server;
      config.network_interface = network_interface;
      config.peers = peers;
      config.security = security;
      fleet_transport::Handlers handlers;
      handlers.on_command = [&agent](const fleet_transport::StepCommand& c) { agent.on_command(c); };
      if (test_deaf_after >= 0) {
        handlers.on_command = [&agent, &settings, test_deaf_after, test_deaf_s, heard = 0,
                               deaf_until = std::optional<std::chrono::steady_clock::time_point>()](
                                  const fleet_transport::StepCommand& c) mutable {
          const auto now = std::chrono::steady_clock::now();
          if (++heard > test_deaf_after && !deaf_until) {
            deaf_until = now + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                   std::chrono::duration<double>(test_deaf_s));
            spdlog::warn("{}: deaf to commands for {} s (a test)", settings.robot_id, test_deaf_s);
          }
          if (deaf_until && now < *deaf_until) return;
          agent.on_command(c);
        };
      }
      handlers.on_coordinator_status = [&agent](const fleet_transport::CoordinatorStatus& s) {
        agent.on_coordinator_status(s);
      };
      auto transport = fleet_transport::make_transport(config, handlers);
      agent.start_commands_where_they_arrive(*transport, reporting);
      transport->announce(agent.announcement());
      spdlog::info("{}: {} robot on {} domain {}, incarnation {:016x}", settings.robot_id, robot.kind(), vendor, domain,
                   agent.incarnation());
      // Announce again every second: a coordinator that starts later or restarts learns of us even
      // when the middleware's late-joiner delivery is slow (seen with Fast DDS).
      auto next_announcement = std::chrono::steady_clock::now() + std::chrono::seconds(1);
      // An agent that never hears a coordinator says where it listens, once: a wrong domain, a
      // network without multicast or a firewall otherwise looks like a fleet that has not started.
      const auto hint_at = std::chrono::steady_clock::now() + std::chrono::seconds(10);
      bool hinted = false;
      while (!g_stop.load()) {
        if (!hinted && agent.followed_coordinator() == 0 && std::chrono::steady_clock::now() >= hint_at) {
          hinted = true;
          spdlog::warn("{}: no coordinator heard after 10 s on {}: a coordinator must run with {}", settings.robot_id,
                       fleet_transport::describe_network(config), fleet_transport::options_to_join(config));
        }
        if (std::chrono::steady_clock::now() >= next_announcement && reporting()) {
          transport->announce(agent.announcement());
          next_announcement += std::chrono::seconds(1);
        }
        if (sim_robot && sim_robot->should_crash()) {
          spdlog::error("{}: injected crash", settings.robot_id);
          std::abort();
        }
        agent.step(*transport, reporting());
        // Sleep until a command arrives, the robot arrives, or the next state is due (at most 50 ms).
        agent.wait_for_command(std::min<std::chrono::steady_clock::duration>(agent.idle_time(),
                                                                             std::chrono::milliseconds(50)));
      }
      fleet_transport::exit_if_shutdown_hangs(1.5, 0);
      transport->say_goodbye(settings.robot_id);
      spdlog::info("{}: goodbye", settings.robot_id);
      std::this_thread::sleep_for(std::chrono::milliseconds(200));  // let the goodbye go out
      return 0;
    } catch (const std::exception& e) {
      spdlog::error("{}: {}", settings.robot_id, e.what());
      return 1;
    }
  });
}
