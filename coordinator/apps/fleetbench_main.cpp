// ctsfleet-fleetbench: measures the fleet runtime on one host with N simulated agents (separate
// processes): command -> state round trip (p50, p99), coordinator CPU, and the replanning latency
// after one robot is killed (from the loss to the first command of the new plan).
#include <CLI/CLI.hpp>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "coordinator/child_process.hpp"
#include "planner_core/instance_generator.hpp"

namespace fs = std::filesystem;

namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string find(const std::string& text, const std::string& pattern) {
  std::smatch match;
  return std::regex_search(text, match, std::regex(pattern)) ? match[1].str() : "-";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ctsfleet-fleetbench: latency, CPU and replanning time of the fleet runtime with N simulated agents"};
  const fs::path here = fs::canonical("/proc/self/exe").parent_path();
  const fs::path root = (here / "../..").lexically_normal();
  std::vector<int> sizes{10, 50, 100};
  std::string map = (root / "config/default/random-64-64-20.map").string(), vendor = "cyclone";
  double step = 0.2, kill_after = 8;
  int domain = 90;
  app.add_option("-n,--robots", sizes, "fleet sizes to run")->capture_default_str();
  app.add_option("--map", map, "map of the generated missions")->capture_default_str();
  app.add_option("--step", step, "seconds per move (0.2 = 5 steps per second)")->capture_default_str();
  app.add_option("--kill-after", kill_after, "seconds after the start when one robot is killed")->capture_default_str();
  app.add_option("--dds", vendor)->check(CLI::IsMember({"cyclone", "fastdds"}))->capture_default_str();
  app.add_option("--domain", domain)->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  const fs::path work = fs::temp_directory_path() / ("ctsfleet-fleetbench-" + std::to_string(getpid()));
  fs::create_directories(work);
  std::printf("| robots | mission | round trip p50 (ms) | p99 (ms) | max (ms) | coordinator CPU (%% of one core) | "
              "replan latency after a loss (ms) |\n|---|---|---|---|---|---|---|\n");
  for (int n : sizes) {
    auto graph = std::make_shared<const planner_core::Graph>(planner_core::load_movingai_map(map));
    const planner_core::Instance mission = planner_core::generate_instance(graph, {n, n, 2, static_cast<uint32_t>(n)});
    const fs::path mission_file = work / ("mission-" + std::to_string(n) + ".yaml");
    std::ofstream(mission_file) << planner_core::instance_to_yaml(mission, fs::absolute(map).string());
    const fs::path config_file = work / ("fleet-" + std::to_string(n) + ".yaml");
    std::ofstream(config_file) << "mission: " << mission_file.string() << "\nrobots:\n  quorum: " << n
                               << "\n  wait_timeout_s: 60\nplanner:\n  solver: cts-pll-v2\n  time_limit_s: 5\n"
                               << "  replan_solver: cts-pll-v2\n  replan_time_limit_s: 5\ndds:\n  vendor: " << vendor
                               << "\n  domain_id: " << domain << "\n  config_dir: " << (root / "config/dds").string()
                               << "\ntiming:\n  step_s: " << step
                               << "\n  silence_timeout_s: 3\n  mission_timeout_s: 300\n  replacement_timeout_s: 2\n";
    std::vector<pid_t> agents;
    for (int r = 0; r < n; ++r) {
      const planner_core::Cell start = graph->cell_of(mission.starts[r]);
      agents.push_back(coordinator::start_child({(here / "ctsfleet-agent").string(), "--id", "robot" + std::to_string(r), "--start",
                              std::to_string(start.x) + "," + std::to_string(start.y), "--dds", vendor, "--domain",
                              std::to_string(domain), "--step", std::to_string(step), "--jitter", "0.1",
                              "--dds-config-dir", (root / "config/dds").string()},
                             (work / ("robot" + std::to_string(r) + ".log")).string()));
    }
    const std::string coordinator_log = (work / ("coordinator-" + std::to_string(n) + ".log")).string();
    const pid_t coordinator_pid = coordinator::start_child({(here / "ctsfleet-coordinator").string(), "--config", config_file.string()},
                                    coordinator_log);
    // Kill one robot once the mission is under way.
    const auto started = std::chrono::steady_clock::now();
    while (read_file(coordinator_log).find("plan epoch 1") == std::string::npos &&
           std::chrono::steady_clock::now() - started < std::chrono::seconds(120)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    std::this_thread::sleep_for(std::chrono::duration<double>(kill_after));
    kill(agents[0], SIGKILL);
    int status = 0;
    waitpid(coordinator_pid, &status, 0);
    for (pid_t pid : agents) kill(pid, SIGTERM);
    for (pid_t pid : agents) waitpid(pid, nullptr, 0);
    const std::string text = read_file(coordinator_log);
    const std::string seconds = find(text, R"(tasks \d+/\d+, ([0-9.]+) s)");
    const std::string cpu = find(text, R"(coordinator cpu ([0-9.]+) s)");
    char cpu_share[32] = "-";
    if (cpu != "-" && seconds != "-" && std::stod(seconds) > 0) {
      std::snprintf(cpu_share, sizeof cpu_share, "%.1f", 100 * std::stod(cpu) / std::stod(seconds));
    }
    const std::string replan = find(text, R"(replan latency ([0-9.]+) s)");
    std::printf("| %d | %s, %s s | %s | %s | %s | %s | %s |\n", n,
                find(text, R"(mission (completed|NOT completed))").c_str(), seconds.c_str(),
                find(text, R"(p50 ([0-9.]+) ms)").c_str(), find(text, R"(p99 ([0-9.]+) ms)").c_str(),
                find(text, R"(max ([0-9.]+) ms)").c_str(), cpu_share,
                replan == "-" ? "-" : std::to_string(static_cast<int>(1000 * std::stod(replan))).c_str());
    std::fflush(stdout);
    ++domain;
  }
  std::printf("\nlogs: %s\n", work.c_str());
  return 0;
}
