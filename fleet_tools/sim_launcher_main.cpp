// ctsfleet-sim: runs a whole simulated fleet on this host: one ctsfleet-coordinator and N
// ctsfleet-agent processes (each its own process), waits for the mission, stops everything.
// With --backend toio-emulated the agents drive emulated toio cubes through their real BLE code
// path: a private dbus-daemon, ctsfleet-toio-emulator as BlueZ, agents with --backend toio.
// Exits 0 only when the mission completed; Ctrl-C stops everything cleanly.
#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <random>
#include <set>
#include <thread>

#include "child_process.hpp"
#include "throwaway_fleet_ca.hpp"
#include "coordinator/fleet_config.hpp"
#include "ctsfleet/data_dir.hpp"
#include "ctsfleet/program.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/instance.hpp"
#include "planner_core/lorr_problem.hpp"
#include "robot_agent/mat_calibration.hpp"

namespace {

namespace fs = std::filesystem;
const std::atomic<bool>& g_stop = ctsfleet::stop_requested();

// Waits until `done` holds, polling; false after `timeout`.
template <typename Condition>
bool wait_until(Condition done, std::chrono::seconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline || g_stop.load()) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

bool file_contains(const std::string& path, const std::string& text) {
  std::ifstream file(path);
  std::stringstream content;
  content << file.rdbuf();
  return content.str().find(text) != std::string::npos;
}

// A private D-Bus for the emulated BlueZ; returns its address. The socket lives in log_dir.
std::string start_private_bus(const fs::path& log_dir, std::vector<pid_t>& helpers) {
  const fs::path socket = fs::absolute(log_dir / "bluez-bus.socket");
  fs::remove(socket);
  const std::string address = "unix:path=" + socket.string();
  const std::string log = (log_dir / "dbus-daemon.log").string();
  helpers.push_back(coordinator::start_child(
      {"/usr/bin/dbus-daemon", "--session", "--nofork", "--nopidfile", "--print-address", "--address=" + address}, log));
  // It prints its address once it accepts connections; the socket file alone appears at bind(),
  // before listen(), and an emulator connecting then was refused (seen once in CI).
  if (!wait_until([&] { return file_contains(log, address); }, std::chrono::seconds(20))) {
    throw std::runtime_error("the private dbus-daemon did not start (see " + (log_dir / "dbus-daemon.log").string() + ")");
  }
  return address;
}

}  // namespace

int main(int argc, char** argv) {
  ctsfleet::Program program("ctsfleet-sim", "a coordinator and N simulated robot agents as separate processes");
  CLI::App& app = program.app();
  const fs::path here = ctsfleet::program_dir();
  std::string config_path, mat_path;
  bool json = false;
  std::string vendor, agent_vendor, backend = "sim", log_dir = "out/sim-logs";
  int robots = 8, domain = -1;
  double step = 0.1, jitter = 0.2, turn = 0;
  std::string actions;
  unsigned seed = 1;
  app.add_option("--robots", robots, "number of robot agents (at most the mission map's free cells)")
      ->check(ctsfleet::count_in(1, 10'000))
      ->capture_default_str();
  app.add_option("-c,--config", config_path,
                 "fleet configuration (default: config/fleet.yaml, or config/toio/fleet.yaml for toio-emulated)")
      ->check(CLI::ExistingFile);
  app.add_option("--mat", mat_path, "toio-emulated: mat file placing the grid on the mat (default: "
                                    "config/mats/toio-collection-ring.yaml)")
      ->check(CLI::ExistingFile);
  app.add_option("--dds", vendor, "DDS for every process (default: the config's)")
      ->check(CLI::IsMember({"cyclone", "fastdds"}));
  app.add_option("--agent-dds", agent_vendor, "DDS for the agents only (cross-vendor runs)")
      ->check(CLI::IsMember({"cyclone", "fastdds"}));
  app.add_option("--backend", backend, "robot backend")->check(CLI::IsMember({"sim", "toio-emulated"}))->capture_default_str();
  app.add_option("--domain", domain, "DDS domain id (default: the config's)")->check(ctsfleet::dds_domain());
  app.add_option("--step", step, "sim: seconds per move (default: the config's timing.step_s, what the coordinator plans with)")
      ->check(ctsfleet::positive_seconds(3600));
  app.add_option("--jitter", jitter, "sim: each move takes step * (1 + U[0, jitter])")
      ->check(ctsfleet::number_in(0, 10))
      ->capture_default_str();
  app.add_option("--turn", turn, "sim: seconds per quarter turn in place (0: turns take no time)")
      ->check(ctsfleet::number_in(0, 3600))
      ->capture_default_str();
  app.add_option("--actions", actions, "plans with turns (rotate) or without (move4); default: the config's")
      ->check(CLI::IsMember({"move4", "rotate"}));
  app.add_option("--seed", seed, "sim: random seed of the first agent")->capture_default_str();
  std::string delay_config;
  app.add_option("--delay-config", delay_config,
                 "robots delayed as the League of Robot Runners' 2026 rules draw delays: a JSON file holding a "
                 "delayConfig (itself, or a problem with one); each simulated robot draws with its own seed "
                 "(--seed + its number), emulated cubes with --seed")
      ->check(CLI::ExistingFile);
  app.add_option("--log-dir", log_dir, "where the agents' logs go")->check(ctsfleet::writable_folder())->capture_default_str();
  app.add_flag("--json", json, "the coordinator prints its mission summary as one JSON object");
  bool secure = false;
  app.add_flag("--secure", secure,
               "DDS Security with a throw-away fleet CA made for this run in LOG_DIR/fleet-ca (always on for "
               "toio-emulated, whose config requires it)");
  std::string discovery;
  app.add_option("--discovery", discovery,
                 "Fast DDS: 'simple' (the default) or 'server' (a ctsfleet-discovery process; open, all-Fast DDS "
                 "fleets only)")
      ->check(CLI::IsMember({"server", "simple"}));
  int dashboard_port = -1;
  app.add_option("--dashboard", dashboard_port,
                 "also run ctsfleet-dashboard on this port (0: any free one) for the whole run, recording the run in "
                 "LOG_DIR/history.jsonl; its address is printed")
      ->check(CLI::Range(0, 65535));
  std::string security_dir;
  app.add_option("--security", security_dir,
                 "DDS Security with this fleet directory (made by ctsfleet-ca, with robot0..robotN-1 and a coordinator "
                 "enrolled) instead of a throw-away one")
      ->check(CLI::ExistingDirectory);
  return program.main(argc, argv, [&]() -> int {
    const bool toio = backend == "toio-emulated";
    if (config_path.empty()) config_path = ctsfleet::data_path(toio ? "config/toio/fleet.yaml" : "config/fleet.yaml").string();
    if (mat_path.empty()) mat_path = ctsfleet::data_path("config/mats/toio-collection-ring.yaml").string();
    std::vector<pid_t> helpers;  // dbus-daemon and emulator, stopped last
    auto stop_helpers = [&helpers] {
      for (auto it = helpers.rbegin(); it != helpers.rend(); ++it) kill(*it, SIGTERM);
      for (pid_t pid : helpers) waitpid(pid, nullptr, 0);
      helpers.clear();
    };

    try {
      const coordinator::FleetConfig config = coordinator::load_fleet_config(config_path);
      const planner_core::Instance mission = planner_core::load_instance(config.mission);
      if (vendor.empty()) vendor = config.dds_vendor;
      if (agent_vendor.empty()) agent_vendor = vendor;
      if (domain < 0) domain = config.domain_id;
      // One source for the simulated robots' speed: the config the coordinator times its commands by.
      if (app.count("--step") == 0) step = config.step_s;
      if (!delay_config.empty()) {
        planner_core::load_delay_config(delay_config);  // refused here, once, before anything starts
        delay_config = fs::absolute(delay_config).string();
      }
      fs::create_directories(log_dir);
      if (!security_dir.empty()) secure = true;
      const fs::path fleet_ca = security_dir.empty() ? fs::absolute(fs::path(log_dir) / "fleet-ca") : fs::absolute(security_dir);
      if ((secure || config.security_required) && agent_vendor != vendor) {
        throw planner_core::InputError(
            "--secure with --agent-dds " + agent_vendor + " and a " + vendor + " coordinator: DDS Security does not work "
            "across the two vendors in Debian 12 (Cyclone DDS 0.10.2 and Fast DDS 2.9.1 fail each other's handshake: "
            "Fast DDS encodes its Diffie-Hellman key in a form Cyclone cannot read; see docs/SECURITY.md); run a secure "
            "fleet on one vendor");
      }
      // Robots start on the roles' starts, then on random free cells nobody needs.
      std::vector<planner_core::Cell> starts;
      std::set<planner_core::Vertex> used(mission.starts.begin(), mission.starts.end());
      used.insert(mission.goals.begin(), mission.goals.end());
      for (int r = 0; r < robots && r < mission.agent_count(); ++r) starts.push_back(mission.graph->cell_of(mission.starts[r]));
      const int free_cells = mission.graph->vertex_count() - static_cast<int>(used.size());
      if (robots > mission.agent_count() + free_cells) {
        throw planner_core::InputError("--robots: " + std::to_string(robots) + " robots do not fit on " + config.mission +
                                       ": " + std::to_string(mission.agent_count()) + " role starts and " +
                                       std::to_string(free_cells) + " other free cells");
      }
      std::mt19937 rng(seed);
      while (static_cast<int>(starts.size()) < robots) {
        const planner_core::Vertex v = std::uniform_int_distribution<int>(0, mission.graph->vertex_count() - 1)(rng);
        if (used.insert(v).second) starts.push_back(mission.graph->cell_of(v));
      }

      std::optional<robot_agent::MatCalibration> mat;
      if (toio) {
        mat = robot_agent::MatCalibration::load(mat_path);
        if (mission.graph->width() > mat->grid_width() || mission.graph->height() > mat->grid_height()) {
          throw planner_core::InputError(config.mission + ": the " + std::to_string(mission.graph->width()) + "x" +
                                         std::to_string(mission.graph->height()) + " map does not fit the " +
                                         std::to_string(mat->grid_width()) + "x" + std::to_string(mat->grid_height()) +
                                         " grid of " + mat_path);
        }
        const std::string bus = start_private_bus(log_dir, helpers);
        setenv("DBUS_SYSTEM_BUS_ADDRESS", bus.c_str(), 1);  // the agents' "system bus" is the private one
        std::vector<std::string> emulator = {(here / "ctsfleet-toio-emulator").string(), "--bus", bus, "--mat", mat_path};
        for (int r = 0; r < robots; ++r) {
          emulator.push_back("--cube");
          emulator.push_back("toio-" + std::to_string(r) + "@cell:" + std::to_string(starts[r].x) + "," +
                             std::to_string(starts[r].y));
        }
        if (!delay_config.empty()) emulator.insert(emulator.end(), {"--delay-config", delay_config, "--seed", std::to_string(seed)});
        const std::string emulator_log = (fs::path(log_dir) / "toio-emulator.log").string();
        helpers.push_back(coordinator::start_child(emulator, emulator_log));
        if (!wait_until([&] { return file_contains(emulator_log, "toio-emulator ready"); }, std::chrono::seconds(20))) {
          throw std::runtime_error("the toio emulator did not start (see " + emulator_log + ")");
        }
        spdlog::info("emulated BlueZ with {} toio cubes on {}", robots, bus);
      }

      // The fleet CA last, when everything else is known to be right (it takes a moment per robot).
      if (!security_dir.empty()) {
        // What the children would refuse one by one, said once here: the coordinator's and each robot's files.
        fleet_transport::load_fleet_security(fleet_ca.string(), config.security_identity);
        for (int r = 0; r < robots; ++r) fleet_transport::load_fleet_security(fleet_ca.string(), "robot" + std::to_string(r));
        spdlog::info("DDS Security on: fleet directory {}", fleet_ca.string());
      } else if (secure || config.security_required) {
        std::vector<std::string> ids;
        for (int r = 0; r < robots; ++r) ids.push_back("robot" + std::to_string(r));
        coordinator::make_throwaway_fleet_ca(here, fleet_ca, ids);
        secure = true;
        spdlog::info("DDS Security on: throw-away fleet CA in {}", fleet_ca.string());
      } else {
        spdlog::warn("DDS Security is off (loopback simulation; --secure turns it on)");
      }
      const bool all_fastdds = vendor == "fastdds" && agent_vendor == "fastdds";
      if (discovery.empty()) discovery = "simple";
      if (discovery == "server" && !all_fastdds) {
        throw planner_core::InputError("--discovery server: discovery servers are a Fast DDS feature; every process "
                                       "must run Fast DDS (--dds fastdds, no --agent-dds cyclone)");
      }
      if (discovery == "server" && secure) {
        throw planner_core::InputError(std::string("--discovery server with security: ") +
                                       fleet_transport::kSecureDiscoveryServerUnsupported);
      }
      std::vector<std::string> discovery_options;
      if (discovery == "server") {
        const std::string listen = "127.0.0.1:" + std::to_string(fleet_transport::default_discovery_server_port(domain));
        const std::string log = log_dir + "/discovery.log";
        std::vector<std::string> args{(here / "ctsfleet-discovery").string(), "--domain", std::to_string(domain),
                                      "--listen", listen, "--state-dir", log_dir + "/discovery-state"};
        if (!config.dds_config_dir.empty()) args.insert(args.end(), {"--dds-config-dir", config.dds_config_dir});
        helpers.push_back(coordinator::start_child(args, log));
        if (!wait_until([&] { return file_contains(log, "listening on"); }, std::chrono::seconds(30))) {
          throw std::runtime_error("the discovery server did not start (see " + log + ")");
        }
        discovery_options = {"--discovery-server", listen};
        spdlog::info("Fast DDS discovery server on {}", listen);
      }

      if (dashboard_port >= 0) {
        if (!security_dir.empty()) fleet_transport::load_fleet_security(fleet_ca.string(), "dashboard");
        const std::string log = log_dir + "/dashboard.log";
        std::vector<std::string> args{(here / "ctsfleet-dashboard").string(), "--dds", vendor, "--domain",
                                      std::to_string(domain), "--port", std::to_string(dashboard_port), "--record",
                                      log_dir + "/history.jsonl"};
        if (!config.dds_config_dir.empty()) args.insert(args.end(), {"--dds-config-dir", config.dds_config_dir});
        if (secure) args.insert(args.end(), {"--security", fleet_ca.string(), "--identity", "dashboard"});
        args.insert(args.end(), discovery_options.begin(), discovery_options.end());
        helpers.push_back(coordinator::start_child(args, log));
        if (!wait_until([&] { return file_contains(log, "dashboard: http://"); }, std::chrono::seconds(30))) {
          throw std::runtime_error("the dashboard did not start (see " + log + ")");
        }
        std::ifstream in(log);
        std::string line;
        while (std::getline(in, line)) {
          if (line.rfind("dashboard: http://", 0) == 0) std::cout << line << std::endl;
        }
        spdlog::info("the run is recorded in {}/history.jsonl (replay: ctsfleet-dashboard --replay FILE)", log_dir);
      }

      std::vector<pid_t> agents;
      for (int r = 0; r < robots; ++r) {
        std::vector<std::string> args = {(here / "ctsfleet-agent").string(),
                                         "--id", "robot" + std::to_string(r),
                                         "--backend", toio ? "toio" : "sim",
                                         "--start", std::to_string(starts[r].x) + "," + std::to_string(starts[r].y),
                                         "--dds", agent_vendor,
                                         "--domain", std::to_string(domain),
                                         "--lease", std::to_string(config.lease_s),
                                         "--step", std::to_string(step),
                                         "--jitter", std::to_string(jitter),
                                         "--turn", std::to_string(turn),
                                         "--seed", std::to_string(seed + r)};
        if (!config.dds_config_dir.empty()) args.insert(args.end(), {"--dds-config-dir", config.dds_config_dir});
        if (toio) args.insert(args.end(), {"--cube", "toio-" + std::to_string(r), "--mat", mat_path});
        if (!toio && !delay_config.empty()) args.insert(args.end(), {"--delay-config", delay_config});
        if (secure) args.insert(args.end(), {"--security", fleet_ca.string()});
        args.insert(args.end(), discovery_options.begin(), discovery_options.end());
        agents.push_back(coordinator::start_child(args, log_dir + "/robot" + std::to_string(r) + ".log"));
      }
      std::vector<std::string> coordinator_args = {(here / "ctsfleet-coordinator").string(), "--config", config_path,
                                                   "--dds", vendor, "--domain", std::to_string(domain)};
      if (json) coordinator_args.push_back("--json");
      if (!actions.empty()) coordinator_args.insert(coordinator_args.end(), {"--actions", actions});
      if (secure) coordinator_args.insert(coordinator_args.end(), {"--security", fleet_ca.string()});
      coordinator_args.insert(coordinator_args.end(), discovery_options.begin(), discovery_options.end());
      const pid_t coordinator_pid = coordinator::start_child(coordinator_args, "");
      spdlog::info("started {} agents ({}) and the coordinator ({}) on domain {}; agent logs in {}", robots,
                   agent_vendor, vendor, domain, log_dir);
      int status = 0;
      bool coordinator_done = false;
      while (!coordinator_done) {
        const pid_t done = waitpid(coordinator_pid, &status, WNOHANG);
        if (done == coordinator_pid) {
          coordinator_done = true;
          break;
        }
        if (g_stop.load()) {
          kill(coordinator_pid, SIGINT);
          waitpid(coordinator_pid, &status, 0);
          coordinator_done = true;
          break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      for (pid_t pid : agents) kill(pid, SIGTERM);
      for (pid_t pid : agents) waitpid(pid, nullptr, 0);
      stop_helpers();
      if (g_stop.load()) return ctsfleet::kExitInterrupted;
      const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 1;
      spdlog::info("coordinator exited with {}", code);
      return code;
    } catch (...) {
      stop_helpers();
      throw;
    }
  });
}
