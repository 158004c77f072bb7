// ctsfleet-sim: runs a whole simulated fleet on this host: one ctsfleet-coordinator and N
// ctsfleet-agent processes (each its own process), waits for the mission, stops everything.
// Exits 0 only when the mission completed; Ctrl-C stops everything cleanly.
#include <CLI/CLI.hpp>
#include <signal.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <random>
#include <set>
#include <thread>

#include "coordinator/child_process.hpp"
#include "coordinator/fleet_config.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/instance.hpp"


namespace {

namespace fs = std::filesystem;
std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ctsfleet-sim: a coordinator and N simulated robot agents as separate processes"};
  const fs::path here = fs::canonical("/proc/self/exe").parent_path();
  std::string config_path = (here / "../../config/fleet.yaml").lexically_normal().string();
  std::string vendor, agent_vendor, backend = "sim", log_dir = "out/sim-logs";
  int robots = 8, domain = -1;
  double step = 0.1, jitter = 0.2;
  unsigned seed = 1;
  app.add_option("--robots", robots, "number of robot agents")->capture_default_str();
  app.add_option("-c,--config", config_path, "fleet configuration")->capture_default_str();
  app.add_option("--dds", vendor, "DDS for every process (default: the config's)")
      ->check(CLI::IsMember({"cyclone", "fastdds"}));
  app.add_option("--agent-dds", agent_vendor, "DDS for the agents only (cross-vendor runs)")
      ->check(CLI::IsMember({"cyclone", "fastdds"}));
  app.add_option("--backend", backend, "robot backend")->check(CLI::IsMember({"sim"}))->capture_default_str();
  app.add_option("--domain", domain, "DDS domain id (default: the config's)");
  app.add_option("--step", step, "sim: seconds per move")->capture_default_str();
  app.add_option("--jitter", jitter, "sim: each move takes step * (1 + U[0, jitter])")->capture_default_str();
  app.add_option("--seed", seed, "sim: random seed of the first agent")->capture_default_str();
  app.add_option("--log-dir", log_dir, "where the agents' logs go")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);

  try {
    const coordinator::FleetConfig config = coordinator::load_fleet_config(config_path);
    const planner_core::Instance mission = planner_core::load_instance(config.mission);
    if (vendor.empty()) vendor = config.dds_vendor;
    if (agent_vendor.empty()) agent_vendor = vendor;
    if (domain < 0) domain = config.domain_id;
    fs::create_directories(log_dir);

    // Robots start on the roles' starts, then on random free cells nobody needs.
    std::vector<planner_core::Cell> starts;
    std::set<planner_core::Vertex> used(mission.starts.begin(), mission.starts.end());
    used.insert(mission.goals.begin(), mission.goals.end());
    for (int r = 0; r < robots && r < mission.agent_count(); ++r) starts.push_back(mission.graph->cell_of(mission.starts[r]));
    std::mt19937 rng(seed);
    while (static_cast<int>(starts.size()) < robots) {
      const planner_core::Vertex v = std::uniform_int_distribution<int>(0, mission.graph->vertex_count() - 1)(rng);
      if (used.insert(v).second) starts.push_back(mission.graph->cell_of(v));
    }

    std::vector<pid_t> agents;
    for (int r = 0; r < robots; ++r) {
      std::vector<std::string> args = {(here / "ctsfleet-agent").string(),
                                       "--id", "robot" + std::to_string(r),
                                       "--backend", backend,
                                       "--start", std::to_string(starts[r].x) + "," + std::to_string(starts[r].y),
                                       "--dds", agent_vendor,
                                       "--domain", std::to_string(domain),
                                       "--lease", std::to_string(config.lease_s),
                                       "--step", std::to_string(step),
                                       "--jitter", std::to_string(jitter),
                                       "--seed", std::to_string(seed + r)};
      if (!config.dds_config_dir.empty()) args.insert(args.end(), {"--dds-config-dir", config.dds_config_dir});
      agents.push_back(coordinator::start_child(args, log_dir + "/robot" + std::to_string(r) + ".log"));
    }
    const pid_t coordinator_pid = coordinator::start_child({(here / "ctsfleet-coordinator").string(), "--config", config_path, "--dds",
                                     vendor, "--domain", std::to_string(domain)},
                                    "");
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
    if (g_stop.load()) return 130;
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 1;
    spdlog::info("coordinator exited with {}", code);
    return code;
  } catch (const planner_core::InputError& e) {
    spdlog::error("{}", e.what());
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
