// ctsfleet-coordinator: plans the mission for the robots that announce themselves and drives
// them over DDS until every task is done.
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include <atomic>
#include <cstdio>
#include <thread>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>

#include "coordinator/fleet_config.hpp"
#include "ctsfleet/program.hpp"
#include "coordinator/fleet_coordinator.hpp"
#include "planner_core/input_error.hpp"

namespace {

using namespace coordinator;

// What the command line may say over the fleet configuration.
struct Overrides {
  std::string vendor;
  int domain = -1;
  std::string network_interface, peers, discovery_server, security_dir, identity, actions;

  void add_to(CLI::App& app) {
    app.add_option("--dds", vendor, "override dds.vendor")->check(CLI::IsMember({"cyclone", "fastdds"}));
    app.add_option("--domain", domain, "override dds.domain_id")->check(ctsfleet::dds_domain());
    app.add_option("--iface", network_interface, std::string("override dds.interface: ") + fleet_transport::kInterfaceHelp);
    app.add_option("--peers", peers, std::string("override dds.peers: ") + fleet_transport::kPeersHelp);
    app.add_option("--discovery-server", discovery_server,
                   std::string("override dds.discovery_server. ") + fleet_transport::kDiscoveryServerHelp);
    app.add_option("--security", security_dir, "override security.fleet_dir: the fleet directory made by ctsfleet-ca");
    app.add_option("--identity", identity, "override security.identity: the name this coordinator is enrolled as");
    app.add_option("--actions", actions, "override planner.actions: rotate plans with turns, move4 without")
        ->check(CLI::IsMember({"move4", "rotate"}));
  }
  void apply(FleetConfig& config) const {
    if (!vendor.empty()) config.dds_vendor = vendor;
    if (domain >= 0) config.domain_id = domain;
    if (!discovery_server.empty()) config.discovery_server = discovery_server;
    if (!network_interface.empty()) config.network_interface = network_interface;
    if (!peers.empty()) config.peers = peers;
    if (!security_dir.empty()) config.security_dir = security_dir;
    if (!identity.empty()) config.security_identity = identity;
    if (!actions.empty()) {
      config.actions = planner_core::parse_action_model(actions, "--actions");
    }
  }
};

// The transport's handlers: each hands what it heard to the coordinator's queue.
fleet_transport::Handlers handlers_for(FleetCoordinator& coordinator, std::atomic<int>& announcements, bool standby) {
  fleet_transport::Handlers handlers;
  handlers.on_announcement = [&](const fleet_transport::Announcement& a) {
    ++announcements;
    coordinator.on_announcement(a);
  };
  handlers.on_state = [&](const fleet_transport::RobotState& s) { coordinator.on_state(s); };
  handlers.on_refused = [&](const std::string& what) {
    spdlog::warn("refused: {}", what);
    coordinator.on_refused(what);
  };
  handlers.on_robot_gone = [&](const std::string& id, fleet_transport::GoneReason r) { coordinator.on_robot_gone(id, r); };
  handlers.on_coordinator_status = [&](const fleet_transport::CoordinatorStatus& s) {
    coordinator.on_coordinator_status(s);
  };
  handlers.on_task_request = [&](const fleet_transport::TaskRequest& r) { coordinator.on_task_request(r); };
  if (standby) {  // only a standby mirrors another coordinator's progress
    handlers.on_fleet_status = [&](const fleet_transport::FleetStatus& s) { coordinator.on_fleet_status(s); };
    handlers.on_mission_info = [&](const fleet_transport::MissionInfo& m) { coordinator.on_mission_info(m); };
  }
  return handlers;
}

// Steps the coordinator until the mission ends or Ctrl-C, with a progress line on the terminal
// (or in the log) and a hint when no robot is heard.
void drive(FleetCoordinator& coordinator, fleet_transport::Transport& transport,
           const fleet_transport::TransportConfig& transport_config, const std::atomic<int>& announcements) {
  const std::atomic<bool>& stop = ctsfleet::stop_requested();
  const bool tty = isatty(STDERR_FILENO);
  const auto started = std::chrono::steady_clock::now();
  auto next_progress = started;
  bool hinted = false;
  while (!stop.load() && coordinator.step(transport)) {
    const auto now = std::chrono::steady_clock::now();
    if (!hinted && announcements.load() == 0 && now - started > std::chrono::seconds(5)) {
      hinted = true;
      spdlog::warn("no robot heard after 5 s on {}: an agent must run with {}",
                   fleet_transport::describe_network(transport_config),
                   fleet_transport::options_to_join(transport_config));
    }
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
}

// The summary's figures that are worked out at the end.
struct EndFigures {
  std::vector<double> round_trips;  // sorted
  double cpu_s = 0;
  double peak_memory_mb = 0;  // the process's peak resident set
  double quantile(double q) const {
    return round_trips.empty() ? 0.0
                               : round_trips[std::min(round_trips.size() - 1, static_cast<size_t>(q * round_trips.size()))];
  }
};

EndFigures end_figures(const MissionSummary& s) {
  EndFigures figures;
  figures.round_trips = s.round_trips_ms;
  std::sort(figures.round_trips.begin(), figures.round_trips.end());
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  figures.cpu_s =
      usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e6;
  figures.peak_memory_mb = usage.ru_maxrss / 1024.0;  // Linux: kilobytes
  return figures;
}

void print_json(const FleetCoordinator& coordinator, const EndFigures& f, int exit_code) {
  const MissionSummary& s = coordinator.summary();
  const nlohmann::json summary = {
      {"completed", s.completed}, {"tasks_done", s.tasks_done}, {"tasks_total", s.tasks_total},
      {"seconds", s.seconds}, {"first_plan_makespan", s.first_plan_makespan},
      {"first_plan_flowtime", s.first_plan_flowtime}, {"sum_of_finish_s", s.sum_of_finish_s},
      {"replans", s.replans}, {"robots_lost", s.robots_lost}, {"robots_joined", s.robots_joined},
      {"off_plan", s.off_plan}, {"plans_discarded", s.plans_discarded}, {"journal_failed", s.journal_failed},
      {"commands", s.commands_sent}, {"states", s.states_received},
      {"replan_latencies_s", s.replan_latencies_s}, {"round_trips", f.round_trips.size()},
      {"round_trip_p50_ms", f.quantile(0.5)}, {"round_trip_p99_ms", f.quantile(0.99)},
      {"round_trip_max_ms", f.round_trips.empty() ? 0.0 : f.round_trips.back()}, {"cpu_s", f.cpu_s}, {"peak_memory_mb", f.peak_memory_mb},
      {"pending", s.pending}, {"coordinator", fmt::format("{:016x}", coordinator.incarnation())},
      {"mission_id", coordinator.mission_id()}, {"term", s.term}, {"stood_down", s.stood_down},
      {"stood_down_because", s.stood_down_because}, {"took_over", s.took_over},
      {"tasks_done_before", s.tasks_done_before}, {"windows", s.windows}, {"window_ms_max", s.window_ms_max}, {"windows_late", s.windows_late},
      {"robot_s_waiting_for_windows", s.robot_s_waiting_for_windows}, {"wait_for_window_ms_max", s.wait_for_window_ms_max}, {"tasks_reassigned", s.tasks_reassigned}, {"robots_planned_around", s.robots_planned_around},
      {"moves_cut", s.moves_cut}, {"robots_taken_back", s.robots_taken_back},
      {"robots_joined_mid_plan", s.robots_joined_mid_plan}, {"first_command_wall_ms", s.first_command_wall_ms},
      {"exit_code", exit_code}};
  std::printf("%s\n", summary.dump().c_str());
}

void print_text(const MissionSummary& s, const EndFigures& f) {
  if (s.stood_down) std::printf("stood down: %s\n", s.stood_down_because.c_str());
  if (s.tasks_done_before > 0) std::printf("%d tasks were done before this coordinator drove\n", s.tasks_done_before);
  std::printf("mission %s: tasks %d/%d, %.1f s, first plan makespan %d steps flowtime %lld, sum of finish times "
              "%.1f s, replans %d, robots lost %d joined %d, commands %lld, states %lld\n",
              s.completed ? "completed" : "NOT completed", s.tasks_done, s.tasks_total, s.seconds,
              s.first_plan_makespan, static_cast<long long>(s.first_plan_flowtime), s.sum_of_finish_s, s.replans,
              s.robots_lost, s.robots_joined, static_cast<long long>(s.commands_sent),
              static_cast<long long>(s.states_received));
  for (double latency : s.replan_latencies_s) std::printf("replan latency %.3f s\n", latency);
  if (!f.round_trips.empty()) {
    std::printf("command round trip: n %zu p50 %.2f ms p99 %.2f ms max %.2f ms\n", f.round_trips.size(),
                f.quantile(0.5), f.quantile(0.99), f.round_trips.back());
  }
  std::printf("coordinator cpu %.2f s\n", f.cpu_s);
  for (const std::string& line : s.pending) std::printf("pending: %s\n", line.c_str());
}

std::unique_ptr<MissionJournal> open_journal(const std::string& path, const FleetConfig& config,
                                             const planner_core::Instance& mission) {
  if (path.empty()) return nullptr;
  return std::make_unique<MissionJournal>(path, mission_fingerprint(mission),
                                          config.mission + " (" + std::to_string(mission.agent_count()) + " roles, " +
                                              std::to_string(mission.task_count()) + " tasks)");
}

}  // namespace

int main(int argc, char** argv) {
  ctsfleet::Program program("ctsfleet-coordinator", "plan the mission and drive the fleet over DDS");
  CLI::App& app = program.app();
  std::string config_path, journal_path;
  bool json = false, standby = false;
  Overrides overrides;
  app.add_option("-c,--config", config_path, "fleet configuration (YAML)")->required()->check(CLI::ExistingFile);
  app.add_flag("--json", json, "print the mission summary as one JSON object");
  app.add_option("--journal", journal_path,
                 "SQLite journal of the mission: every task visit is committed there; an unfinished run found in "
                 "it is resumed (done tasks are not redone)")
      ->check(ctsfleet::writable_file());
  overrides.add_to(app);
  app.add_flag("--standby", standby,
               "follow the active coordinator of this mission and take over when it falls silent");
  return program.main(argc, argv, [&] {
    FleetConfig config = load_fleet_config(config_path);
    overrides.apply(config);
    fleet_transport::TransportConfig transport_config = config.transport_config();  // checks the security files
    if (!transport_config.security.enabled()) {
      spdlog::warn("DDS Security is off: any process on domain {} can join the fleet (see ctsfleet-ca)", config.domain_id);
    }
    planner_core::Instance mission = planner_core::load_instance(config.mission);
    spdlog::info("mission {}: {} roles, {} tasks; solver {}; {} domain {}", config.mission, mission.agent_count(),
                 mission.task_count(), config.solver, config.dds_vendor, config.domain_id);
    const std::unique_ptr<MissionJournal> journal = open_journal(journal_path, config, mission);
    FleetCoordinator coordinator(config, std::move(mission), {standby, journal.get()});
    coordinator.set_interrupt(&ctsfleet::stop_requested());  // Ctrl-C cuts a running solve short
    // Of several live coordinators' commands, a robot hears the highest term's (a standby has none yet).
    transport_config.command_strength = standby ? 0 : static_cast<int>(coordinator.summary().term);
    std::atomic<int> announcements{0};
    auto transport = fleet_transport::make_transport(transport_config, handlers_for(coordinator, announcements, standby));
    drive(coordinator, *transport, transport_config, announcements);
    coordinator.finish(*transport);
    const MissionSummary& s = coordinator.summary();
    const EndFigures figures = end_figures(s);
    const int exit_code = ctsfleet::stop_requested().load() ? ctsfleet::kExitInterrupted
                          : s.stood_down                    ? ctsfleet::kExitStoodDown
                          : s.completed                     ? ctsfleet::kExitSuccess
                                                            : ctsfleet::kExitUnfinished;
    if (json) {
      print_json(coordinator, figures, exit_code);
    } else {
      print_text(s, figures);
    }
    std::fflush(stdout);
    fleet_transport::exit_if_shutdown_hangs(1.5, exit_code);
    return exit_code;
  });
}
