// ctsfleet-coordinator: plans the mission for the robots that announce themselves and drives
// them over DDS until every task is done.
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <thread>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>

#include "coordinator/fleet_config.hpp"
#include "coordinator/fleet_coordinator.hpp"
#include "planner_core/input_error.hpp"

namespace {
std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }
}  // namespace

int main(int argc, char** argv) {
  using namespace coordinator;
  CLI::App app{"ctsfleet-coordinator: plan the mission and drive the fleet over DDS"};
  std::string config_path, vendor;
  int domain = -1;
  app.add_option("-c,--config", config_path, "fleet configuration (YAML)")->required();
  app.add_option("--dds", vendor, "override dds.vendor")->check(CLI::IsMember({"cyclone", "fastdds"}));
  app.add_option("--domain", domain, "override dds.domain_id");
  CLI11_PARSE(app, argc, argv);
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  try {
    FleetConfig config = load_fleet_config(config_path);
    if (!vendor.empty()) config.dds_vendor = vendor;
    if (domain >= 0) config.domain_id = domain;
    planner_core::Instance mission = planner_core::load_instance(config.mission);
    spdlog::info("mission {}: {} roles, {} tasks; solver {}; {} domain {}", config.mission, mission.agent_count(),
                 mission.task_count(), config.solver, config.dds_vendor, config.domain_id);
    FleetCoordinator coordinator(config, std::move(mission));
    fleet_transport::TransportConfig transport_config;
    transport_config.vendor = fleet_transport::parse_vendor(config.dds_vendor);
    transport_config.domain_id = config.domain_id;
    transport_config.lease_s = config.lease_s;
    transport_config.loopback_config_dir = config.dds_config_dir;
    fleet_transport::Handlers handlers;
    handlers.on_announcement = [&](const fleet_transport::Announcement& a) { coordinator.on_announcement(a); };
    handlers.on_state = [&](const fleet_transport::RobotState& s) { coordinator.on_state(s); };
    handlers.on_robot_gone = [&](const std::string& id, fleet_transport::GoneReason r) { coordinator.on_robot_gone(id, r); };
    auto transport = fleet_transport::make_transport(transport_config, handlers);

    const bool tty = isatty(STDERR_FILENO);
    auto next_progress = std::chrono::steady_clock::now();
    while (!g_stop.load() && coordinator.step(*transport)) {
      const auto now = std::chrono::steady_clock::now();
      if (now >= next_progress) {
        if (tty) {
          std::fprintf(stderr, "\r%s   ", coordinator.progress_line().c_str());
        } else {
          spdlog::info("progress: {}", coordinator.progress_line());
        }
        next_progress = now + std::chrono::milliseconds(tty ? 250 : 2000);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    if (tty) std::fprintf(stderr, "\n");
    const MissionSummary& s = coordinator.summary();
    std::printf("mission %s: tasks %d/%d, %.1f s, first plan makespan %d steps flowtime %lld, sum of finish times "
                "%.1f s, replans %d, robots lost %d joined %d, commands %lld, states %lld\n",
                s.completed ? "completed" : "NOT completed", s.tasks_done, s.tasks_total, s.seconds,
                s.first_plan_makespan, static_cast<long long>(s.first_plan_flowtime), s.sum_of_finish_s, s.replans,
                s.robots_lost, s.robots_joined, static_cast<long long>(s.commands_sent),
                static_cast<long long>(s.states_received));
    for (double latency : s.replan_latencies_s) std::printf("replan latency %.3f s\n", latency);
    if (!s.round_trips_ms.empty()) {
      std::vector<double> sorted = s.round_trips_ms;
      std::sort(sorted.begin(), sorted.end());
      const auto at = [&](double q) { return sorted[std::min(sorted.size() - 1, static_cast<size_t>(q * sorted.size()))]; };
      std::printf("command round trip: n %zu p50 %.2f ms p99 %.2f ms max %.2f ms\n", sorted.size(), at(0.5), at(0.99),
                  sorted.back());
    }
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    const double cpu = usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e6;
    std::printf("coordinator cpu %.2f s\n", cpu);
    for (const std::string& line : s.pending) std::printf("pending: %s\n", line.c_str());
    std::fflush(stdout);
    if (g_stop.load()) return 130;
    return s.completed ? 0 : 3;
  } catch (const planner_core::InputError& e) {
    spdlog::error("{}", e.what());
    return 2;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
