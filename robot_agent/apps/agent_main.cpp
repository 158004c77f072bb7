// ctsfleet-agent: one robot's process. Bridges the fleet's step commands to a simulated robot
// (or, later, a toio cube) and reports the robot's state.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <thread>

#include "robot_agent/robot_agent.hpp"
#include "robot_agent/sim_robot.hpp"

namespace {
std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }
}  // namespace

int main(int argc, char** argv) {
  using namespace robot_agent;
  CLI::App app{"ctsfleet-agent: one robot of the fleet (simulated backend)"};
  AgentSettings settings;
  SimSettings sim;
  std::string backend = "sim", start_text = "0,0", vendor = "cyclone", dds_dir;
  int domain = 0;
  double lease = 1.0;
  app.add_option("--id", settings.robot_id, "robot id (at most 32 characters)")->required();
  app.add_option("--backend", backend, "robot backend")->check(CLI::IsMember({"sim"}))->capture_default_str();
  app.add_option("--start", start_text, "starting cell x,y (sim)")->capture_default_str();
  app.add_option("--dds", vendor, "DDS implementation")->check(CLI::IsMember({"cyclone", "fastdds"}))->capture_default_str();
  app.add_option("--domain", domain, "DDS domain id")->capture_default_str();
  app.add_option("--lease", lease, "liveliness lease in seconds")->capture_default_str();
  app.add_option("--dds-config-dir", dds_dir, "folder with the loopback DDS XML files");
  app.add_option("--state-rate", settings.state_rate_hz, "state messages per second")->capture_default_str();
  app.add_option("--step", sim.step_s, "sim: seconds per move")->capture_default_str();
  app.add_option("--jitter", sim.jitter, "sim: each move takes step * (1 + U[0, jitter])")->capture_default_str();
  app.add_option("--delay-probability", sim.delay_probability, "sim: chance of an extra delay per move");
  app.add_option("--delay", sim.delay_s, "sim: length of that delay in seconds");
  app.add_option("--stall-at", sim.stall_at_s, "sim fault: stall this many seconds after start");
  app.add_option("--stall-for", sim.stall_for_s, "sim fault: stall duration in seconds");
  app.add_option("--silent-at", sim.silent_at_s, "sim fault: stop reporting state after this many seconds");
  app.add_option("--crash-at", sim.crash_at_s, "sim fault: abort the process after this many seconds");
  app.add_option("--seed", sim.seed, "sim: random seed");
  CLI11_PARSE(app, argc, argv);

  if (settings.robot_id.empty() || settings.robot_id.size() > fleet_transport::kMaxRobotIdLength) {
    spdlog::error("--id must have 1 to {} characters", fleet_transport::kMaxRobotIdLength);
    return 2;
  }
  GridCell start;
  if (std::sscanf(start_text.c_str(), "%d,%d", &start.x, &start.y) != 2) {
    spdlog::error("--start must be x,y, got '{}'", start_text);
    return 2;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  try {
    SimRobot robot(start, sim);
    RobotAgent agent(settings, robot);
    fleet_transport::TransportConfig config;
    config.vendor = fleet_transport::parse_vendor(vendor);
    config.domain_id = domain;
    config.lease_s = lease;
    config.commands_for = settings.robot_id;
    config.loopback_config_dir = dds_dir;
    fleet_transport::Handlers handlers;
    handlers.on_command = [&agent](const fleet_transport::StepCommand& c) { agent.on_command(c); };
    auto transport = fleet_transport::make_transport(config, handlers);
    transport->announce(agent.announcement());
    spdlog::info("{}: {} robot at ({},{}) on {} domain {}", settings.robot_id, robot.kind(), start.x, start.y, vendor,
                 domain);
    // Announce again every second: a coordinator that starts later or restarts learns of us even
    // when the middleware's late-joiner delivery is slow (seen with Fast DDS).
    auto next_announcement = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    while (!g_stop.load()) {
      if (std::chrono::steady_clock::now() >= next_announcement && robot.reporting_enabled()) {
        transport->announce(agent.announcement());
        next_announcement += std::chrono::seconds(1);
      }
      if (robot.should_crash()) {
        spdlog::error("{}: injected crash", settings.robot_id);
        std::abort();
      }
      agent.step(*transport, robot.reporting_enabled());
      // Sleep until a command arrives, the robot arrives, or the next state is due (at most 50 ms).
      agent.wait_for_command(std::min<std::chrono::steady_clock::duration>(agent.idle_time(),
                                                                           std::chrono::milliseconds(50)));
    }
    transport->say_goodbye(settings.robot_id);
    spdlog::info("{}: goodbye", settings.robot_id);
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // let the goodbye go out
    return 0;
  } catch (const std::exception& e) {
    spdlog::error("{}: {}", settings.robot_id, e.what());
    return 1;
  }
}
