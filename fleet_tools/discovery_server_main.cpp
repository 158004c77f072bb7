// ctsfleet-discovery: a Fast DDS discovery server for a fleet. Start it first (or two, with
// different --server-id, for redundancy), then give every Fast DDS program of the fleet
// --discovery-server with the servers' addresses: each robot then discovers its coordinators and
// observers through the server, never the other robots. Open fleets only: Fast DDS 2.9.1 cannot
// combine a discovery server with DDS Security. Runs until SIGINT/SIGTERM; the server itself runs
// in a child process that is started again when it crashes.
#include <spdlog/spdlog.h>

#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <thread>

#include "ctsfleet/data_dir.hpp"
#include "ctsfleet/program.hpp"
#include "fleet_transport/discovery_server.hpp"
#include "fleet_transport/transport.hpp"
#include "discovery_state_keeper.hpp"
#include "restart_on_crash.hpp"

namespace {

// Runs the server until SIGINT/SIGTERM.
int serve(const fleet_transport::DiscoveryServerConfig& config) {
  auto server = std::make_unique<fleet_transport::DiscoveryServer>(config);
  spdlog::info("discovery server {} listening on {} (Fast DDS, domain {}); programs take --discovery-server {}",
               config.server_id, config.listen, config.domain_id, config.listen);
  const auto& stop = ctsfleet::stop_requested();
  auto next_report = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!stop.load()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (std::chrono::steady_clock::now() >= next_report) {
      spdlog::info("participants known: {}", server->participants());
      next_report += std::chrono::seconds(30);
    }
  }
  fleet_transport::exit_if_shutdown_hangs(1.5, 0);
  server.reset();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  ctsfleet::Program program("ctsfleet-discovery", "a Fast DDS discovery server for the fleet");
  CLI::App& app = program.app();
  fleet_transport::DiscoveryServerConfig config;
  app.add_option("--domain", config.domain_id, "DDS domain id")->check(ctsfleet::dds_domain())->capture_default_str();
  app.add_option("--listen", config.listen, "IPv4 HOST:PORT the fleet's programs reach this server at")
      ->capture_default_str();
  app.add_option("--server-id", config.server_id,
                 "this server's place in the programs' --discovery-server list (0 = first)")
      ->check(CLI::Range(0, 255))
      ->capture_default_str();
  std::string state_dir;
  app.add_option("--state-dir", state_dir,
                 "where the server keeps what it knows, so that it restarts where it stopped (default: "
                 "ctsfleet-discovery-state/domain-D-server-I in the current directory)");
  coordinator::RestartPolicy restarts;
  app.add_option("--max-crashes", restarts.max_crashes_a_minute,
                 "crashes within a minute after which the server is not started again (0: a crash ends it)")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  app.add_option("--dds-config-dir", config.loopback_config_dir,
                 "folder with the loopback DDS XML files (default: the shipped config/dds)")
      ->check(CLI::ExistingDirectory);
  return program.main(argc, argv, [&] {
    fleet_transport::check_listen_address(config.listen);  // before anything is written
    if (config.loopback_config_dir.empty()) config.loopback_config_dir = ctsfleet::data_path("config/dds").string();
    config.loopback_config_dir = std::filesystem::absolute(config.loopback_config_dir).string();
    if (state_dir.empty()) {
      state_dir = "ctsfleet-discovery-state/domain-" + std::to_string(config.domain_id) + "-server-" +
                  std::to_string(config.server_id);
    }
    // Fast DDS writes the backup file in the working directory.
    std::error_code error;
    std::filesystem::create_directories(state_dir, error);
    if (error || chdir(state_dir.c_str()) != 0) {
      throw std::invalid_argument("--state-dir: cannot use '" + state_dir + "' (" +
                                     (error ? error.message() : std::strerror(errno)) + ")");
    }
    coordinator::DiscoveryStateKeeper state(std::filesystem::current_path());  // one server per state
    spdlog::info("state kept in {}", std::filesystem::current_path().string());
    // A previous ctsfleet-discovery may have died with its server.
    const auto prepare_state = [&] {
      state.restore_cut_short_files();
      state.forget_what_the_server_received();
    };
    prepare_state();
    spdlog::warn("a discovery server is open (Fast DDS 2.9.1 cannot secure one): use it for open fleets only");
    config.on_event = [](const std::string& event) { spdlog::info("{}", event); };
    // Fast DDS 2.9.1's server can abort on an assertion of its own when many programs join at
    // once; it then starts again from its state file (its last complete copy, if the crash cut
    // the file short), and the programs find it again.
    coordinator::SupervisorHooks hooks;
    hooks.every_second = [&] { state.keep_complete_copies(); };
    hooks.before_restart = prepare_state;
    return coordinator::run_restarting_on_crash("the discovery server", [&] { return serve(config); }, restarts,
                                                hooks);
  });
}
