#include "task_stream_scenario.hpp"

#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/wait.h>

#include <cstdio>
#include <fstream>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "child_process.hpp"
#include "run_logs.hpp"
#include "coordinator/fleet_config.hpp"
#include "ctsfleet/program.hpp"
#include "fleet_transport/transport.hpp"
#include "planner_core/instance_generator.hpp"

namespace coordinator {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

// Sends SIGINT (then SIGKILL after `grace_s`) and reaps the process.
void stop_child(pid_t pid, double grace_s) {
  if (pid <= 0) return;
  kill(pid, SIGINT);
  const Clock::time_point until = Clock::now() + std::chrono::milliseconds(static_cast<int>(1000 * grace_s));
  while (waitpid(pid, nullptr, WNOHANG) == 0) {
    if (Clock::now() > until) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

// What the fleet of processes did, seen from outside: its fleet status and the stream's answers.
struct Observer {
  std::mutex mutex;
  TaskStream& stream;
  fleet_transport::FleetStatus status;
  bool heard = false;
};

StreamFigures run_fleet_of_processes(const TaskStreamSettings& settings, const planner_core::Instance& mission,
                                     const fs::path& config_file, int domain, TaskStream& stream,
                                     nlohmann::json& coordinator_summary, std::string& collisions) {
  const std::string tag = std::to_string(mission.agent_count());
  const auto with_extra = [&settings](std::vector<std::string> args) {
    args.insert(args.end(), settings.extra_options.begin(), settings.extra_options.end());
    return args;
  };
  const std::vector<std::string> dds = {"--dds", settings.vendor, "--domain", std::to_string(domain),
                                        "--dds-config-dir", settings.dds_config_dir};
  std::vector<pid_t> agents;
  for (int r = 0; r < mission.agent_count(); ++r) {
    const planner_core::Cell start = mission.graph->cell_of(mission.starts[r]);
    std::vector<std::string> args{(settings.programs / "ctsfleet-agent").string(), "--id", "robot" + std::to_string(r),
                                  "--start", std::to_string(start.x) + "," + std::to_string(start.y), "--step",
                                  std::to_string(settings.step_s), "--jitter", std::to_string(settings.jitter),
                                  "--turn", std::to_string(settings.turn_s)};
    args.insert(args.end(), dds.begin(), dds.end());
    agents.push_back(start_child(with_extra(args), (settings.work / ("stream-robot" + std::to_string(r) + ".log")).string()));
  }
  std::vector<std::string> monitor_args{(settings.programs / "ctsfleet-monitor").string()};
  monitor_args.insert(monitor_args.end(), dds.begin(), dds.end());
  const fs::path monitor_log = settings.work / ("stream-monitor-" + tag + ".log");
  const pid_t monitor = start_child(with_extra(monitor_args), monitor_log.string());
  const fs::path summary_file = settings.work / ("stream-coordinator-" + tag + ".json");
  const pid_t coordinator = start_child(
      with_extra({(settings.programs / "ctsfleet-coordinator").string(), "--config", config_file.string(), "--json"}),
      (settings.work / ("stream-coordinator-" + tag + ".log")).string(), summary_file.string());

  Observer observer{.stream = stream};
  fleet_transport::TransportConfig transport_config;
  transport_config.vendor = fleet_transport::parse_vendor(settings.vendor);
  transport_config.domain_id = domain;
  transport_config.loopback_config_dir = settings.dds_config_dir;
  fleet_transport::Handlers handlers;
  handlers.on_fleet_status = [&observer](const fleet_transport::FleetStatus& status) {
    const std::lock_guard<std::mutex> lock(observer.mutex);
    observer.status = status;
    observer.heard = true;
  };
  handlers.on_task_reply = [&observer](const fleet_transport::TaskReply& reply) {
    const std::lock_guard<std::mutex> lock(observer.mutex);
    observer.stream.answered(reply);
  };
  StreamFigures figures;
  {
    auto transport = fleet_transport::make_transport(transport_config, handlers);
    const std::atomic<bool>& stop = ctsfleet::stop_requested();
    const Clock::time_point started = Clock::now();
    std::optional<Clock::time_point> first_plan, counting_from;
    int done_at_start = 0;
    const auto seconds = [](double s) { return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s)); };
    while (!stop.load()) {
      const Clock::time_point now = Clock::now();
      std::vector<fleet_transport::TaskRequest> requests;
      int done = 0;
      {
        const std::lock_guard<std::mutex> lock(observer.mutex);
        if (!first_plan && observer.heard && observer.status.plan_epoch >= 1) first_plan = now;
        done = observer.status.tasks_done;
        if (first_plan) requests = stream.due(observer.status.tasks_done, now);
      }
      for (const fleet_transport::TaskRequest& request : requests) transport->request_task(request);
      if (!first_plan && now - started > std::chrono::seconds(300)) break;  // never planned: see its log
      if (waitpid(coordinator, nullptr, WNOHANG) == coordinator) break;      // it ended: see its log
      if (first_plan && !counting_from && now >= *first_plan + seconds(settings.timeline.warmup_s)) {
        counting_from = now;
        done_at_start = done;
      }
      if (counting_from && now >= *counting_from + seconds(settings.timeline.measure_s)) {
        figures.tasks_done = done - done_at_start;
        figures.seconds = std::chrono::duration<double>(now - *counting_from).count();
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    figures.interrupted = stop.load();
  }
  stop_child(coordinator, 20);
  for (pid_t pid : agents) kill(pid, SIGTERM);
  for (pid_t pid : agents) waitpid(pid, nullptr, 0);
  stop_child(monitor, 10);
  collisions = monitor_overlaps(read_file(monitor_log.string()));
  coordinator_summary = read_summary(summary_file.string());
  figures.tasks_per_minute = figures.seconds > 0 ? 60 * figures.tasks_done / figures.seconds : 0;
  figures.accepted = stream.accepted();
  figures.refused = stream.refused();
  figures.windows = coordinator_summary.value("windows", int64_t{0});
  figures.window_ms_max = coordinator_summary.value("window_ms_max", 0.0);
  figures.tasks_reassigned = coordinator_summary.value("tasks_reassigned", int64_t{0});
  figures.replans = coordinator_summary.value("replans", 0);
  return figures;
}

}  // namespace

void print_task_stream_header(const TaskStreamSettings& settings) {
  if (settings.json) return;
  std::printf("| robots | step (s) | tasks/min, processes over DDS | tasks/min, in one process | ratio | windows | "
              "longest window (ms) | tasks moved by the pool | replans | coordinator peak memory (MB) | collisions |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|\n");
}

bool run_task_stream(const TaskStreamSettings& settings, int robots, int domain) {
  auto graph = std::make_shared<const planner_core::Graph>(planner_core::load_movingai_map(settings.map));
  const planner_core::Instance mission = planner_core::generate_instance(graph, {robots, 1, 1, static_cast<uint32_t>(robots)});  // the stream gives the work
  const fs::path mission_file = settings.work / ("stream-mission-" + std::to_string(robots) + ".yaml");
  std::ofstream(mission_file) << planner_core::instance_to_yaml(mission, fs::absolute(settings.map).string());
  const fs::path config_file = settings.work / ("stream-fleet-" + std::to_string(robots) + ".yaml");
  {
    std::ofstream config(config_file);
    config << "mission: " << mission_file.string() << "\nlifelong: true\n";
    if (!settings.lifelong_planner.empty()) config << "lifelong_planner: " << settings.lifelong_planner << "\n";
    config << "robots:\n  quorum: " << robots << "\n  wait_timeout_s: 120\nplanner:\n  solver: cts-pll-v2\n"
           << "  time_limit_s: 5\n  actions: " << settings.actions << "\n"
           << "  replan_solver: cts-pll-v2\n  replan_time_limit_s: 5\ndds:\n  vendor: " << settings.vendor
           << "\n  domain_id: " << domain << "\n  config_dir: " << settings.dds_config_dir
           << "\ntiming:\n  step_s: " << settings.step_s << "\n  silence_timeout_s: 3\n";
  }
  const uint32_t seed = static_cast<uint32_t>(robots);
  TaskStream processes_stream(*graph, robots, mission.task_count(), seed, "stream");
  nlohmann::json summary;
  std::string collisions;
  const StreamFigures processes =
      run_fleet_of_processes(settings, mission, config_file, domain, processes_stream, summary, collisions);
  if (processes.interrupted) return false;
  TaskStream in_process_stream(*graph, robots, mission.task_count(), seed, "stream");
  const StreamFigures in_process = run_in_process_fleet(load_fleet_config(config_file.string()), mission, settings.step_s,
                                                        settings.jitter, settings.turn_s, in_process_stream, settings.timeline,
                                                        ctsfleet::stop_requested());
  if (in_process.interrupted) return false;
  const double ratio = in_process.tasks_per_minute > 0 ? processes.tasks_per_minute / in_process.tasks_per_minute : 0;
  if (settings.json) {
    const auto figures = [](const StreamFigures& f) {
      return nlohmann::json{{"tasks_done", f.tasks_done}, {"seconds", f.seconds}, {"tasks_per_minute", f.tasks_per_minute},
                            {"accepted", f.accepted}, {"refused", f.refused}, {"windows", f.windows},
                            {"window_ms_max", f.window_ms_max}, {"tasks_reassigned", f.tasks_reassigned},
                            {"replans", f.replans}};
    };
    const nlohmann::json row = {{"robots", robots}, {"scenario", "task-stream"}, {"step_s", settings.step_s},
                                {"processes", figures(processes)}, {"in_process", figures(in_process)},
                                {"ratio", ratio}, {"collisions", collisions}, {"summary", summary},
                                {"logs", settings.work.string()}};
    std::printf("%s\n", row.dump().c_str());
  } else {
    std::printf("| %d | %.2f | %.1f | %.1f | %.3f | %lld | %.1f | %lld | %d | %.0f | %s |\n", robots, settings.step_s,
                processes.tasks_per_minute, in_process.tasks_per_minute, ratio, static_cast<long long>(processes.windows),
                processes.window_ms_max, static_cast<long long>(processes.tasks_reassigned), processes.replans,
                summary.value("peak_memory_mb", 0.0), collisions.c_str());
  }
  std::fflush(stdout);
  return true;
}

}  // namespace coordinator
