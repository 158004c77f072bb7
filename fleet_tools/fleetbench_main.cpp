// ctsfleet-fleetbench: measures the fleet runtime on one host with N simulated agents (separate
// processes). Scenarios:
//   robot-loss  command -> state round trip (p50, p99), coordinator CPU, and the replanning latency
//               after one robot is killed (from the loss to the first command of the new plan);
//   failover    an active coordinator and a standby; the active one is SIGKILLed --kills times in
//               a row (each time a new standby is started): time from the kill to the standby's
//               first command, task visits planned twice, collisions seen by the safety monitor;
//   restart     the coordinator is SIGKILLed and started again with its journal: time from the
//               new process's start to its first command, task visits planned twice;
//   task-stream a lifelong fleet given a stream of tasks (about one waiting per robot): tasks done
//               per minute against the same fleet in one process at the same step, the lifelong
//               windows and their planning time, collisions (task_stream_scenario.hpp);
//   league      a League of Robot Runners problem (--problem) run by the fleet, beside the
//               benchmark's lockstep run of it for as many steps, delays included: tasks finished by
//               each and their ratio (league_scenario.hpp).
#include <nlohmann/json.hpp>
#include <spdlog/fmt/fmt.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <map>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "child_process.hpp"
#include "league_scenario.hpp"
#include "run_logs.hpp"
#include "task_stream_scenario.hpp"
#include "throwaway_fleet_ca.hpp"
#include "ctsfleet/data_dir.hpp"
#include "ctsfleet/program.hpp"
#include "fleet_transport/transport.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/instance_generator.hpp"
#include "planner_core/lifelong_config.hpp"

namespace fs = std::filesystem;
using coordinator::monitor_overlaps;
using coordinator::read_file;
using coordinator::read_summary;

namespace {

// The wall-clock ms of each "first command of term T" line in a coordinator log, by term.
std::map<int, int64_t> first_commands(const std::string& log) {
  std::map<int, int64_t> by_term;
  std::istringstream lines(read_file(log));
  for (std::string line; std::getline(lines, line);) {
    int term = 0;
    long long ms = 0;
    const size_t at = line.find("first command of term ");
    if (at != std::string::npos &&
        std::sscanf(line.c_str() + at, "first command of term %d sent at wall-clock ms %lld", &term, &ms) == 2) {
      by_term[term] = ms;
    }
  }
  return by_term;
}

// Task visits a coordinator planned again although they were done: for each "taking over ... V
// task visits" or "resuming ... V task visits" line, the next plan line must plan total - V.
int visits_planned_twice(const std::string& log, int total_visits) {
  std::istringstream lines(read_file(log));
  int done = -1, twice = 0;
  for (std::string line; std::getline(lines, line);) {
    int visits = 0;
    size_t at = line.find("; ");
    if (line.find("taking over as term") != std::string::npos && at != std::string::npos &&
        std::sscanf(line.c_str() + at, "; %d task visits", &visits) == 1) {
      done = visits;
    } else if (line.find("resuming run") != std::string::npos &&
               (at = line.find(": ", line.find("of mission"))) != std::string::npos &&
               std::sscanf(line.c_str() + at, ": %d task visits", &visits) == 1) {
      done = visits;
    } else if (done >= 0 && (at = line.find("robots, ")) != std::string::npos &&
               line.find("plan epoch") != std::string::npos && std::sscanf(line.c_str() + at, "robots, %d task visits", &visits) == 1) {
      twice += std::max(0, visits - (total_visits - done));
      done = -1;
    }
  }
  return twice;
}

int64_t wall_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Waits until `log` contains `text`, the process `pid` ended, `timeout_s` passed or Ctrl-C.
bool wait_for_line(const std::string& log, const std::string& text, pid_t pid, double timeout_s,
                   const std::atomic<bool>& stop) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < until && !stop.load()) {
    if (read_file(log).find(text) != std::string::npos) return true;
    if (pid > 0 && waitpid(pid, nullptr, WNOHANG) == pid) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return false;
}

std::string median_ms(std::vector<double> values) {
  if (values.empty()) return "-";
  std::sort(values.begin(), values.end());
  return std::to_string(static_cast<int>(values[values.size() / 2]));
}

std::string max_ms(const std::vector<double>& values) {
  return values.empty() ? "-" : std::to_string(static_cast<int>(*std::max_element(values.begin(), values.end())));
}

// "12.3" from a JSON number, "-" when absent.
std::string figure(const nlohmann::json& summary, const std::string& key, double scale = 1, const char* format = "%.2f") {
  if (!summary.contains(key) || !summary[key].is_number()) return "-";
  char text[32];
  std::snprintf(text, sizeof text, format, scale * summary[key].get<double>());
  return text;
}

}  // namespace

int main(int argc, char** argv) {
  ctsfleet::Program program("ctsfleet-fleetbench",
                            "latency, CPU and replanning time of the fleet runtime with N simulated agents");
  CLI::App& app = program.app();
  const fs::path here = ctsfleet::program_dir();
  std::vector<int> sizes{10, 50, 100};
  std::string map, vendor = "cyclone";
  double step = 0.2, kill_after = 8;
  int domain = 90;
  bool json = false;
  std::string scenario = "robot-loss";
  int kills = 1;
  app.add_option("--scenario", scenario, "robot-loss, failover, restart, task-stream or league (see the program's header)")
      ->check(CLI::IsMember({"robot-loss", "failover", "restart", "task-stream", "league"}))
      ->capture_default_str();
  app.add_option("--kills", kills, "failover: coordinators killed in a row in one mission (a soak)")
      ->check(ctsfleet::count_in(1, 1000))
      ->capture_default_str();
  app.add_option("-n,--robots", sizes, "fleet sizes to run")->check(ctsfleet::count_in(2, 1000))->capture_default_str();
  app.add_option("--map", map, "map of the generated missions (default: config/default/random-64-64-20.map)")
      ->check(CLI::ExistingFile);
  app.add_option("--step", step, "seconds per move (0.2 = 5 steps per second)")
      ->check(ctsfleet::positive_seconds(60))
      ->capture_default_str();
  app.add_option("--kill-after", kill_after, "seconds after the start when one robot is killed")
      ->check(ctsfleet::number_in(0, 3600))
      ->capture_default_str();
  app.add_option("--dds", vendor, "DDS implementation")->check(CLI::IsMember({"cyclone", "fastdds"}))->capture_default_str();
  app.add_option("--domain", domain, "DDS domain of the first fleet size (the next ones count up)")
      ->check(ctsfleet::count_in(0, 232))
      ->capture_default_str();
  app.add_flag("--json", json, "print one JSON object per fleet size instead of the table");
  std::string actions = "move4";
  app.add_option("--actions", actions, "task-stream: plans without turns (move4) or with (rotate)")
      ->check(CLI::IsMember({"move4", "rotate"}))
      ->capture_default_str();
  double turn_s = 0;
  app.add_option("--turn", turn_s, "task-stream: seconds per quarter turn of the sim robots (0: free)")
      ->check(ctsfleet::number_in(0, 60))
      ->capture_default_str();
  std::string lifelong_planner;
  app.add_option("--lifelong-planner", lifelong_planner,
                 "task-stream, league: the window planner's settings (a file as config/lifelong.yaml; the fleet config's "
                 "lifelong_planner); default: plain PIBT")
      ->check(CLI::ExistingFile);
  coordinator::StreamTimeline timeline;
  app.add_option("--warmup", timeline.warmup_s, "task-stream: seconds from the first plan before tasks are counted")
      ->check(ctsfleet::number_in(0, 3600))
      ->capture_default_str();
  app.add_option("--measure", timeline.measure_s, "task-stream: seconds over which tasks done are counted; league: seconds from the fleet's first plan")
      ->check(ctsfleet::positive_seconds(86400))
      ->capture_default_str();
  app.add_option("--restart-robot-at", timeline.restart_robot_at_s,
                 "task-stream, league: seconds into the counted time when robot N/2's process is SIGKILLed; it is "
                 "started again where it last stood 2 s later")
      ->check(ctsfleet::number_in(0, 86400));
  coordinator::LeagueScenarioSettings league;
  app.add_option("--problem", league.problem,
                 "league: a League of Robot Runners problem (JSON) of single-errand tasks, as the 2023 rounds' "
                 "(benchmarks/lorr-2023)")
      ->check(CLI::ExistingFile);
  app.add_option("--delays", league.delays,
                 "league: sim robots delayed as the problem's delayConfig draws (on), never (off), or on when there "
                 "is one (auto)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  app.add_option("--delay-config", league.delay_config,
                 "league: a delayConfig (the object itself, or a problem holding one) instead of the problem's")
      ->check(CLI::ExistingFile);
  bool secure = false;
  app.add_flag("--secure", secure, "DDS Security on every process, with a throw-away fleet CA made for the run");
  std::string discovery;
  app.add_option("--discovery", discovery,
                 "Fast DDS: 'simple' (the default: agents find coordinators and observers, a few find each other) "
                 "or 'server' (a ctsfleet-discovery process per fleet; open fleets only)")
      ->check(CLI::IsMember({"server", "simple"}));
  return program.main(argc, argv, [&] {
    if (domain + static_cast<int>(sizes.size()) - 1 > 232) {
      throw planner_core::InputError("--domain: " + std::to_string(domain) + " + " + std::to_string(sizes.size()) +
                                     " fleet sizes run past DDS domain 232");
    }
    if ((scenario == "task-stream" || scenario == "league") && (secure || discovery == "server")) {
      throw planner_core::InputError(std::string(secure ? "--secure" : "--discovery server") + ": the " + scenario +
                                     " scenario runs open fleets with simple discovery only");
    }
    if (timeline.restart_robot_at_s >= 0 && scenario != "league" && scenario != "task-stream") {
      throw planner_core::InputError("--restart-robot-at: only the task-stream and league scenarios restart a robot");
    }
    if (timeline.restart_robot_at_s >= 0 && timeline.restart_robot_at_s + 2 >= timeline.measure_s) {
      throw planner_core::InputError(fmt::format("--restart-robot-at {}: the robot must be back (2 s later) within "
                                                 "--measure {}", timeline.restart_robot_at_s, timeline.measure_s));
    }
    if ((scenario == "league") != !league.problem.empty()) {
      throw planner_core::InputError(scenario == "league" ? "--scenario league: give the problem (--problem F.json)"
                                                          : "--problem: only the league scenario runs a problem");
    }
    if (scenario != "league" && (league.delays != "auto" || !league.delay_config.empty())) {
      throw planner_core::InputError("--delays, --delay-config: only the league scenario delays its robots");
    }
    if (scenario == "league" && (actions != "move4" || turn_s != 0)) {
      throw planner_core::InputError("--actions, --turn: the league scenario plans turns, a quarter turn taking an action");
    }
    if (scenario == "league") {
      for (int n : sizes) coordinator::check_league_scenario(league, n);  // refused before any fleet starts
    }
    if (discovery.empty()) discovery = "simple";
    if (discovery == "server" && secure) {
      throw planner_core::InputError(std::string("--discovery server --secure: ") +
                                     fleet_transport::kSecureDiscoveryServerUnsupported);
    }
    if (discovery == "server" && vendor != "fastdds") {
      throw planner_core::InputError("--discovery server: discovery servers are a Fast DDS feature (--dds fastdds)");
    }
    if (map.empty()) map = ctsfleet::data_path("config/default/random-64-64-20.map").string();
    const std::string dds_config_dir = ctsfleet::data_path("config/dds").string();
    const std::atomic<bool>& stop = ctsfleet::stop_requested();
    const fs::path work = fs::temp_directory_path() / ("ctsfleet-fleetbench-" + std::to_string(getpid()));
    fs::create_directories(work);
    std::vector<std::string> security;  // the options every process gets
    if (secure) {
      std::vector<std::string> ids;
      for (int r = 0; r < *std::max_element(sizes.begin(), sizes.end()); ++r) ids.push_back("robot" + std::to_string(r));
      coordinator::make_throwaway_fleet_ca(here, work / "fleet-ca", ids);
      security = {"--security", (work / "fleet-ca").string()};
    }
    std::vector<std::string> discovery_options;  // set per fleet size (each has its own domain)
    const auto with_security = [&security, &discovery_options](std::vector<std::string> args) {
      args.insert(args.end(), security.begin(), security.end());
      args.insert(args.end(), discovery_options.begin(), discovery_options.end());
      return args;
    };
    if (scenario == "league") {
      league.programs = here;
      league.work = work;
      league.vendor = vendor;
      league.dds_config_dir = dds_config_dir;
      league.step_s = step;
      if (!lifelong_planner.empty()) {
        planner_core::load_lifelong_config(lifelong_planner);
        league.lifelong_planner = fs::absolute(lifelong_planner).string();
      }
      league.measure_s = timeline.measure_s;
      league.restart_robot_at_s = timeline.restart_robot_at_s;
      league.json = json;
      coordinator::print_league_header(league);
      for (int n : sizes) {
        league.extra_options = with_security({});
        if (!coordinator::run_league_scenario(league, n, domain++)) return ctsfleet::kExitInterrupted;
      }
      if (!json) std::printf("\nlogs: %s\n", work.c_str());
      return 0;
    }
    if (scenario == "task-stream") {
      coordinator::TaskStreamSettings settings;
      settings.programs = here;
      settings.work = work;
      settings.map = map;
      settings.vendor = vendor;
      settings.dds_config_dir = dds_config_dir;
      settings.step_s = step;
      settings.actions = actions;
      settings.turn_s = turn_s;
      if (!lifelong_planner.empty()) {
        planner_core::load_lifelong_config(lifelong_planner);  // refused here, before any fleet starts
        settings.lifelong_planner = fs::absolute(lifelong_planner).string();
      }
      settings.timeline = timeline;
      settings.json = json;
      coordinator::print_task_stream_header(settings);
      for (int n : sizes) {
        settings.extra_options = with_security({});
        if (!coordinator::run_task_stream(settings, n, domain++)) return ctsfleet::kExitInterrupted;
      }
      if (!json) std::printf("\nlogs: %s\n", work.c_str());
      return 0;
    }
    if (!json && scenario == "robot-loss") {
      std::printf("| robots | mission | all bound (s) | round trip p50 (ms) | p99 (ms) | max (ms) | coordinator CPU (%% of one core) | "
                  "replan latency after a loss (ms) |\n|---|---|---|---|---|---|---|---|\n");
    } else if (!json) {
      std::printf("| robots | mission | %s | median (ms) | max (ms) | visits planned twice | collisions |\n"
                  "|---|---|---|---|---|---|---|\n",
                  scenario == "failover" ? "kills" : "restarts");
    }
    for (int n : sizes) {
      auto graph = std::make_shared<const planner_core::Graph>(planner_core::load_movingai_map(map));
      // The coordinator scenarios need a mission long enough for their kills: more tasks per robot.
      const int tasks = scenario == "robot-loss" ? n : std::max(n, n * kills);
      const planner_core::Instance mission =
          planner_core::generate_instance(graph, {n, tasks, 2, static_cast<uint32_t>(n)});
      int total_visits = 0;
      for (const planner_core::Task& task : mission.tasks) total_visits += static_cast<int>(task.agents.size());
      const fs::path mission_file = work / ("mission-" + std::to_string(n) + ".yaml");
      std::ofstream(mission_file) << planner_core::instance_to_yaml(mission, fs::absolute(map).string());
      const fs::path config_file = work / ("fleet-" + std::to_string(n) + ".yaml");
      std::ofstream(config_file) << "mission: " << mission_file.string() << "\nrobots:\n  quorum: " << n
                                 << "\n  wait_timeout_s: 60\nplanner:\n  solver: cts-pll-v2\n  time_limit_s: 5\n"
                                 << "  replan_solver: cts-pll-v2\n  replan_time_limit_s: 5\ndds:\n  vendor: " << vendor
                                 << "\n  domain_id: " << domain << "\n  config_dir: " << dds_config_dir
                                 << "\ntiming:\n  step_s: " << step
                                 << "\n  silence_timeout_s: 3\n  mission_timeout_s: 300\n  replacement_timeout_s: 2\n";
      pid_t discovery_server = -1;
      if (discovery == "server") {
        const std::string listen = "127.0.0.1:" + std::to_string(fleet_transport::default_discovery_server_port(domain));
        std::vector<std::string> args{(here / "ctsfleet-discovery").string(), "--domain", std::to_string(domain),
                                      "--listen", listen, "--dds-config-dir", dds_config_dir, "--state-dir",
                                      (work / ("discovery-state-" + std::to_string(n))).string()};
        const std::string log = (work / ("discovery-" + std::to_string(n) + ".log")).string();
        discovery_server = coordinator::start_child(args, log);
        discovery_options = {"--discovery-server", listen};
        if (!wait_for_line(log, "listening on", discovery_server, 30, stop)) {
          throw std::runtime_error("the discovery server did not start (see " + log + ")");
        }
      }
      const auto stop_discovery_server = [&discovery_server] {
        if (discovery_server <= 0) return;
        kill(discovery_server, SIGTERM);
        waitpid(discovery_server, nullptr, 0);
        discovery_server = -1;
      };
      std::vector<pid_t> agents;
      const auto agents_started = std::chrono::steady_clock::now();
      for (int r = 0; r < n; ++r) {
        const planner_core::Cell start = graph->cell_of(mission.starts[r]);
        agents.push_back(coordinator::start_child(with_security({(here / "ctsfleet-agent").string(), "--id", "robot" + std::to_string(r), "--start",
                                std::to_string(start.x) + "," + std::to_string(start.y), "--dds", vendor, "--domain",
                                std::to_string(domain), "--step", std::to_string(step), "--jitter", "0.1",
                                "--dds-config-dir", dds_config_dir}),
                               (work / ("robot" + std::to_string(r) + ".log")).string()));
      }
      if (scenario != "robot-loss") {
        const std::string tag = std::to_string(n);
        const pid_t monitor = coordinator::start_child(
            with_security({(here / "ctsfleet-monitor").string(), "--dds", vendor, "--domain", std::to_string(domain),
             "--dds-config-dir", dds_config_dir}),
            (work / ("monitor-" + tag + ".log")).string());
        const std::string journal = (work / ("mission-" + tag + ".journal")).string();
        const auto coordinator_args = [&](const std::vector<std::string>& extra) {
          std::vector<std::string> args =
              with_security({(here / "ctsfleet-coordinator").string(), "--config", config_file.string(), "--json"});
          args.insert(args.end(), extra.begin(), extra.end());
          return args;
        };
        std::vector<double> latencies_ms;
        int twice = 0, generation = 0;
        const auto log_of = [&](int g) { return (work / ("coordinator-" + tag + "-" + std::to_string(g) + ".log")).string(); };
        const auto summary_of = [&](int g) { return (work / ("coordinator-" + tag + "-" + std::to_string(g) + ".json")).string(); };
        std::vector<std::string> extra;
        if (scenario == "restart") extra = {"--journal", journal};
        pid_t active = coordinator::start_child(coordinator_args(extra), log_of(0), summary_of(0));
        pid_t standby = -1;
        std::string active_log = log_of(0);
        bool mission_over = false;
        for (int kill_number = 0; kill_number < kills && !mission_over && !stop.load(); ++kill_number) {
          if (!wait_for_line(active_log, "first command of term", active, 180, stop)) {
            mission_over = true;
            break;
          }
          if (scenario == "failover") {
            ++generation;
            standby = coordinator::start_child(coordinator_args({"--standby"}), log_of(generation), summary_of(generation));
            if (!wait_for_line(log_of(generation), "standby: follows coordinator", standby, 60, stop)) {
              mission_over = true;
              break;
            }
          }
          std::this_thread::sleep_for(std::chrono::duration<double>(kill_after));
          if (waitpid(active, nullptr, WNOHANG) == active) {  // the mission ended first
            mission_over = true;
            break;
          }
          kill(active, SIGKILL);
          waitpid(active, nullptr, 0);
          const int64_t killed_ms = wall_ms();
          if (scenario == "restart") {
            ++generation;
            active = coordinator::start_child(coordinator_args(extra), log_of(generation), summary_of(generation));
          } else {
            active = standby;
          }
          active_log = log_of(generation);
          if (!wait_for_line(active_log, "first command of term", active, 60, stop)) {
            mission_over = true;
            break;
          }
          const auto firsts = first_commands(active_log);
          if (!firsts.empty()) latencies_ms.push_back(static_cast<double>(firsts.rbegin()->second - killed_ms));
          twice += visits_planned_twice(active_log, total_visits);
        }
        int status = 0;
        while (waitpid(active, &status, WNOHANG) == 0) {
          if (stop.load()) kill(active, SIGINT);
          std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        if (standby > 0 && standby != active) {
          kill(standby, SIGTERM);
          waitpid(standby, nullptr, 0);
        }
        for (pid_t pid : agents) kill(pid, SIGTERM);
        for (pid_t pid : agents) waitpid(pid, nullptr, 0);
        kill(monitor, SIGINT);
        waitpid(monitor, nullptr, 0);
        stop_discovery_server();
        const std::string collisions = monitor_overlaps(read_file((work / ("monitor-" + tag + ".log")).string()));
        const nlohmann::json summary = read_summary(summary_of(generation));
        if (json) {
          nlohmann::json row = {{"robots", n}, {"scenario", scenario}, {"latencies_ms", latencies_ms},
                                {"visits_planned_twice", twice}, {"collisions", collisions},
                                {"summary", summary}, {"logs", work.string()}};
          std::printf("%s\n", row.dump().c_str());
        } else {
          const std::string outcome = summary.empty() ? "no summary" : summary.value("completed", false) ? "completed" : "NOT completed";
          std::printf("| %d | %s | %zu | %s | %s | %d | %s |\n", n, outcome.c_str(), latencies_ms.size(),
                      median_ms(latencies_ms).c_str(), max_ms(latencies_ms).c_str(), twice, collisions.c_str());
        }
        std::fflush(stdout);
        ++domain;
        if (stop.load()) return ctsfleet::kExitInterrupted;
        continue;
      }
      const std::string coordinator_log = (work / ("coordinator-" + std::to_string(n) + ".log")).string();
      const std::string coordinator_summary = (work / ("coordinator-" + std::to_string(n) + ".json")).string();
      const pid_t coordinator_pid = coordinator::start_child(
          with_security({(here / "ctsfleet-coordinator").string(), "--config", config_file.string(), "--json"}),
          coordinator_log, coordinator_summary);
      // Kill one robot once the mission is under way. Meanwhile: when every robot is bound (from
      // the start of the first agent: discovery, with security the handshakes too).
      std::string bound_s = "-";
      const auto count_bound = [&coordinator_log] {
        const std::string text = read_file(coordinator_log);
        int bound = 0;
        for (size_t at = text.find(" takes role "); at != std::string::npos; at = text.find(" takes role ", at + 1)) ++bound;
        return bound;
      };
      const auto started = std::chrono::steady_clock::now();
      for (;;) {
        const bool planned = read_file(coordinator_log).find("plan epoch 1") != std::string::npos;
        if (bound_s == "-" && count_bound() >= n) {  // binding comes before the plan: checked first
          char text[32];
          std::snprintf(text, sizeof text, "%.2f",
                        std::chrono::duration<double>(std::chrono::steady_clock::now() - agents_started).count());
          bound_s = text;
        }
        if (planned || std::chrono::steady_clock::now() - started > std::chrono::seconds(120) || stop.load()) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      const auto kill_time = std::chrono::steady_clock::now() + std::chrono::duration<double>(kill_after);
      while (std::chrono::steady_clock::now() < kill_time && !stop.load()) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      kill(agents[0], SIGKILL);
      // Wait for the mission; Ctrl-C or SIGTERM is passed on to the coordinator.
      int status = 0;
      bool forwarded = false;
      while (waitpid(coordinator_pid, &status, WNOHANG) == 0) {
        if (stop.load() && !forwarded) {
          kill(coordinator_pid, SIGINT);
          forwarded = true;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      for (pid_t pid : agents) kill(pid, SIGTERM);
      for (pid_t pid : agents) waitpid(pid, nullptr, 0);
      stop_discovery_server();
      if (stop.load()) {
        std::fprintf(stderr, "interrupted: logs in %s\n", work.c_str());
        return ctsfleet::kExitInterrupted;
      }
      const nlohmann::json summary = read_summary(coordinator_summary);
      const double seconds = summary.value("seconds", 0.0);
      std::string cpu_share = "-";
      if (summary.contains("cpu_s") && seconds > 0) cpu_share = figure(summary, "cpu_s", 100 / seconds, "%.1f");
      const auto& latencies = summary.value("replan_latencies_s", std::vector<double>{});
      const std::string replan_ms = latencies.empty() ? "-" : std::to_string(static_cast<int>(1000 * latencies.front()));
      if (json) {
        nlohmann::json row = {{"robots", n}, {"all_bound_s", bound_s}, {"summary", summary}, {"logs", work.string()}};
        std::printf("%s\n", row.dump().c_str());
      } else {
        const std::string outcome = summary.empty() ? "no summary" : summary.value("completed", false) ? "completed" : "NOT completed";
        std::printf("| %d | %s, %s s | %s | %s | %s | %s | %s | %s |\n", n, outcome.c_str(), figure(summary, "seconds", 1, "%.1f").c_str(),
                    bound_s.c_str(),
                    figure(summary, "round_trip_p50_ms").c_str(), figure(summary, "round_trip_p99_ms").c_str(),
                    figure(summary, "round_trip_max_ms").c_str(), cpu_share.c_str(), replan_ms.c_str());
      }
      std::fflush(stdout);
      ++domain;
    }
    if (!json) std::printf("\nlogs: %s\n", work.c_str());
    return 0;
  });
}
