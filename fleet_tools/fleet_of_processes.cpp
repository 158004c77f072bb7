#include "fleet_of_processes.hpp"

#include <signal.h>
#include <sys/wait.h>

#include <fstream>
#include <mutex>
#include <optional>
#include <thread>

#include "child_process.hpp"
#include "run_logs.hpp"
#include "ctsfleet/program.hpp"
#include "fleet_transport/transport.hpp"

namespace coordinator {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

// What the fleet of processes did, seen from outside: its fleet status and the stream's answers.
struct Observer {
  std::mutex mutex;
  TaskStream& stream;
  fleet_transport::FleetStatus status;
  bool heard = false;
  std::string watched_robot;               // the robot to restart, if any:
  std::optional<fleet_transport::RobotState> watched_at_rest;  // its last state standing still
};

constexpr double kRestartPauseS = 2;  // between a robot's kill and its new process

}  // namespace

fs::path write_lifelong_fleet_config(const ProcessFleetSettings& settings, const fs::path& mission_file, int robots,
                                     const std::string& actions, const std::string& lifelong_planner, int domain) {
  const fs::path path = settings.work / (settings.log_prefix + "-fleet-" + std::to_string(robots) + ".yaml");
  std::ofstream config(path);
  config << "mission: " << mission_file.string() << "\nlifelong: true\n";
  if (!lifelong_planner.empty()) config << "lifelong_planner: " << lifelong_planner << "\n";
  config << "robots:\n  quorum: " << robots << "\n  wait_timeout_s: 120\nplanner:\n  solver: cts-pll-v2\n"
         << "  time_limit_s: 5\n  actions: " << actions << "\n  replan_solver: cts-pll-v2\n  replan_time_limit_s: 5\n"
         << "dds:\n  vendor: " << settings.vendor << "\n  domain_id: " << domain << "\n  config_dir: "
         << settings.dds_config_dir << "\ntiming:\n  step_s: " << settings.step_s << "\n  silence_timeout_s: 3\n";
  return path;
}

ProcessFleetRun run_fleet_of_processes(const ProcessFleetSettings& settings, const planner_core::Instance& mission,
                                       const fs::path& config_file, int domain, TaskStream& stream,
                                       const StreamTimeline& timeline, FleetTrace* trace) {
  const std::string tag = std::to_string(mission.agent_count());
  const auto with_extra = [&settings](std::vector<std::string> args) {
    args.insert(args.end(), settings.extra_options.begin(), settings.extra_options.end());
    return args;
  };
  const auto log = [&settings](const std::string& name) {
    return (settings.work / (settings.log_prefix + "-" + name + ".log")).string();
  };
  const std::vector<std::string> dds = {"--dds", settings.vendor, "--domain", std::to_string(domain),
                                        "--dds-config-dir", settings.dds_config_dir};
  // Robot r's process, standing on `start` (facing `heading`, -1: the agent's default).
  const auto start_agent = [&](int r, planner_core::Cell start, int heading, const std::string& log_name) {
    std::vector<std::string> args{(settings.programs / "ctsfleet-agent").string(), "--id", "robot" + std::to_string(r),
                                  "--start", std::to_string(start.x) + "," + std::to_string(start.y), "--step",
                                  std::to_string(settings.step_s), "--jitter", std::to_string(settings.jitter),
                                  "--turn", std::to_string(settings.turn_s)};
    if (heading >= 0 && heading < 4) args.insert(args.end(), {"--heading", std::string(1, "ESWN"[heading])});
    args.insert(args.end(), dds.begin(), dds.end());
    if (static_cast<size_t>(r) < settings.robot_options.size()) {
      args.insert(args.end(), settings.robot_options[r].begin(), settings.robot_options[r].end());
    }
    return start_child(with_extra(args), log(log_name));
  };
  std::vector<pid_t> agents;
  for (int r = 0; r < mission.agent_count(); ++r) {
    agents.push_back(start_agent(r, mission.graph->cell_of(mission.starts[r]), -1, "robot" + std::to_string(r)));
  }
  std::vector<std::string> monitor_args{(settings.programs / "ctsfleet-monitor").string()};
  monitor_args.insert(monitor_args.end(), dds.begin(), dds.end());
  const std::string monitor_log = log("monitor-" + tag);
  const pid_t monitor = start_child(with_extra(monitor_args), monitor_log);
  const fs::path summary_file = settings.work / (settings.log_prefix + "-coordinator-" + tag + ".json");
  const pid_t coordinator = start_child(
      with_extra({(settings.programs / "ctsfleet-coordinator").string(), "--config", config_file.string(), "--json"}),
      log("coordinator-" + tag), summary_file.string());

  Observer observer{.stream = stream};
  const int restarted = timeline.restart_robot_at_s >= 0 ? mission.agent_count() / 2 : -1;
  if (restarted >= 0) observer.watched_robot = "robot" + std::to_string(restarted);
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
  if (trace != nullptr || restarted >= 0) {
    handlers.on_state = [&observer, trace](const fleet_transport::RobotState& state) {
      const std::lock_guard<std::mutex> lock(observer.mutex);
      if (trace != nullptr) trace->heard_state(state);
      if (state.robot_id == observer.watched_robot && state.status != fleet_transport::RobotStatus::kMoving) {
        observer.watched_at_rest = state;
      }
    };
  }
  if (trace != nullptr) {
    handlers.on_fleet_event = [&observer, trace](const fleet_transport::FleetEvent& event) {
      const std::lock_guard<std::mutex> lock(observer.mutex);
      trace->heard_event(event);
    };
  }
  ProcessFleetRun run;
  StreamFigures& figures = run.figures;
  {
    auto transport = fleet_transport::make_transport(transport_config, handlers);
    const std::atomic<bool>& stop = ctsfleet::stop_requested();
    const Clock::time_point started = Clock::now();
    std::optional<Clock::time_point> first_plan, counting_from;
    int done_at_start = 0;
    int64_t steps_at_start = 0;
    std::optional<Clock::time_point> killed_at;
    bool restart_done = false;
    const auto seconds = [](double s) { return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s)); };
    while (!stop.load()) {
      const Clock::time_point now = Clock::now();
      std::vector<fleet_transport::TaskRequest> requests;
      int done = 0;
      int64_t steps_done = 0;
      {
        const std::lock_guard<std::mutex> lock(observer.mutex);
        if (!first_plan && observer.heard && observer.status.plan_epoch >= 1) first_plan = now;
        done = observer.status.tasks_done;
        steps_done = observer.status.steps_done;
        if (first_plan) requests = stream.due(observer.status.tasks_done, now);
      }
      for (const fleet_transport::TaskRequest& request : requests) transport->request_task(request);
      if (!first_plan && now - started > std::chrono::seconds(300)) break;  // never planned: see its log
      if (waitpid(coordinator, nullptr, WNOHANG) == coordinator) break;      // it ended: see its log
      if (first_plan && !counting_from && now >= *first_plan + seconds(timeline.warmup_s)) {
        counting_from = now;
        run.counted_from_ms = fleet_transport::wall_clock_ms();
        done_at_start = done;
        steps_at_start = steps_done;
      }
      if (restarted >= 0 && counting_from && !killed_at && now >= *counting_from + seconds(timeline.restart_robot_at_s)) {
        kill(agents[restarted], SIGKILL);
        waitpid(agents[restarted], nullptr, 0);
        killed_at = now;
      }
      if (killed_at && !restart_done && now >= *killed_at + seconds(kRestartPauseS)) {
        // Where it last stood still: a robot killed mid-move is put back where that move began.
        fleet_transport::RobotState last;
        {
          const std::lock_guard<std::mutex> lock(observer.mutex);
          if (observer.watched_at_rest) last = *observer.watched_at_rest;
        }
        run.restarted_robot = observer.watched_robot;
        run.restarted_at = {last.cell_x, last.cell_y};
        agents[restarted] = start_agent(restarted, run.restarted_at, last.heading, "robot" + std::to_string(restarted) + "-restarted");
        restart_done = true;
      }
      if (counting_from && now >= *counting_from + seconds(timeline.measure_s)) {
        figures.tasks_done = done - done_at_start;
        figures.robot_steps = steps_done - steps_at_start;
        figures.seconds = std::chrono::duration<double>(now - *counting_from).count();
        run.counted_until_ms = fleet_transport::wall_clock_ms();
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
  run.collisions = monitor_overlaps(read_file(monitor_log));
  run.coordinator_summary = read_summary(summary_file.string());
  figures.tasks_per_minute = figures.seconds > 0 ? 60 * figures.tasks_done / figures.seconds : 0;
  figures.accepted = stream.accepted();
  figures.refused = stream.refused();
  figures.deferred = stream.deferred();
  figures.windows = run.coordinator_summary.value("windows", int64_t{0});
  figures.window_ms_max = run.coordinator_summary.value("window_ms_max", 0.0);
  figures.windows_late = run.coordinator_summary.value("windows_late", int64_t{0});
  figures.robot_s_waiting_for_windows = run.coordinator_summary.value("robot_s_waiting_for_windows", 0.0);
  figures.tasks_reassigned = run.coordinator_summary.value("tasks_reassigned", int64_t{0});
  figures.replans = run.coordinator_summary.value("replans", 0);
  return run;
}

}  // namespace coordinator
