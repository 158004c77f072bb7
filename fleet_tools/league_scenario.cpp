#include "league_scenario.hpp"

#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "child_process.hpp"
#include "fleet_of_processes.hpp"
#include "ctsfleet/program.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/league_output.hpp"
#include "planner_core/lorr_problem.hpp"

namespace coordinator {

namespace fs = std::filesystem;

namespace {

using planner_core::InputError;

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ": not JSON: " + e.what());
  }
}

bool delays_wanted(const LeagueScenarioSettings& settings, const planner_core::LorrProblem& problem) {
  if (settings.delays == "auto") return !settings.delay_config.empty() || problem.delays.has_value();
  return settings.delays == "on";
}

// The problem as both runs read it: the same files (named by absolute paths), a team of `robots`,
// and the delayConfig of --delay-config when one is given, none when delays are off.
fs::path write_cut_problem(const LeagueScenarioSettings& settings, int robots, bool delays) {
  nlohmann::json problem = read_json(settings.problem);
  const fs::path folder = fs::absolute(settings.problem).parent_path();
  for (const char* key : {"mapFile", "agentFile", "taskFile"}) {
    problem[key] = (folder / problem[key].get<std::string>()).lexically_normal().string();
  }
  problem["teamSize"] = robots;
  if (!settings.delay_config.empty()) {
    const nlohmann::json given = read_json(settings.delay_config);
    problem["delayConfig"] = given.contains("delayConfig") ? given["delayConfig"] : given;
  }
  if (!delays) problem.erase("delayConfig");
  const fs::path cut = settings.work / ("league-problem-" + std::to_string(robots) + ".json");
  std::ofstream(cut) << problem.dump(4) << "\n";
  return cut;
}

// The map in the MovingAI symbols the fleet reads: '.' free, '@' not.
void write_fleet_map(const planner_core::Graph& graph, const fs::path& path) {
  std::ofstream out(path);
  out << "type octile\nheight " << graph.height() << "\nwidth " << graph.width() << "\nmap\n";
  for (int y = 0; y < graph.height(); ++y) {
    std::string row(graph.width(), '@');
    for (int x = 0; x < graph.width(); ++x) {
      if (graph.is_free({x, y})) row[x] = '.';
    }
    out << row << "\n";
  }
}

// The lockstep run's figures from its league.csv (one problem, one delay setting).
struct LockstepFigures {
  long long tasks = 0;
  double delayed_share = 0;
  int faults = 0;
  bool ran = false;
};

LockstepFigures read_lockstep_table(const fs::path& csv) {
  std::ifstream in(csv);
  std::string header, row;
  if (!std::getline(in, header) || !std::getline(in, row)) return {};
  std::vector<std::string> names, values;
  for (auto [text, into] : {std::pair{&header, &names}, std::pair{&row, &values}}) {
    std::istringstream fields(*text);
    for (std::string field; std::getline(fields, field, ',');) into->push_back(field);
  }
  LockstepFigures figures;
  for (size_t k = 0; k < names.size() && k < values.size(); ++k) {
    if (names[k] == "tasks") figures.tasks = std::stoll(values[k]);
    if (names[k] == "delayed_share") figures.delayed_share = std::stod(values[k]);
    if (names[k] == "faults") figures.faults = std::stoi(values[k]);
  }
  figures.ran = true;
  return figures;
}

// Runs ctsfleet-bench --experiment league on the cut problem; an empty result when it failed or
// was interrupted (its log says why).
LockstepFigures run_lockstep(const LeagueScenarioSettings& settings, const fs::path& cut_problem, int robots,
                             int ticks, int tick_ms, bool delays) {
  const fs::path out_dir = settings.work / ("league-lockstep-" + std::to_string(robots));
  const int plan_period_ms = tick_ms * std::max(1, static_cast<int>(std::lround(1000.0 / tick_ms)));
  const pid_t bench = start_child({(settings.programs / "ctsfleet-bench").string(), "--experiment", "league",
                                   "--problem", cut_problem.string(), "--ticks", std::to_string(ticks), "--tick-ms",
                                   std::to_string(tick_ms), "--plan-period-ms", std::to_string(plan_period_ms),
                                   "--delays", delays ? "on" : "off", "--scheduler", "whole-task-reassign",
                                   "--league-output", "--out-dir", out_dir.string()},
                                  (settings.work / ("league-lockstep-" + std::to_string(robots) + ".log")).string());
  int status = 0;
  while (waitpid(bench, &status, WNOHANG) == 0) {
    if (ctsfleet::stop_requested().load()) {
      stop_child(bench, 10);
      return {};
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return {};
  return read_lockstep_table(out_dir / "league.csv");
}

}  // namespace

void check_league_scenario(const LeagueScenarioSettings& settings, int robots) {
  const planner_core::LorrProblem problem = planner_core::load_lorr_problem(settings.problem);
  for (size_t t = 0; t < problem.tasks.size(); ++t) {
    if (problem.tasks[t].size() != 1) {
      throw InputError(settings.problem + ": task " + std::to_string(t) + " has " +
                       std::to_string(problem.tasks[t].size()) +
                       " errands; the fleet's tasks are single cells, so only problems of single-errand tasks "
                       "(the 2023 rounds') run in the fleet");
    }
  }
  if (robots > static_cast<int>(problem.starts.size())) {
    throw InputError("-n " + std::to_string(robots) + ": " + settings.problem + " has a team of " +
                     std::to_string(problem.starts.size()));
  }
  if (!settings.delay_config.empty()) planner_core::load_delay_config(settings.delay_config);
  if (settings.delays == "on" && settings.delay_config.empty() && !problem.delays) {
    throw InputError("--delays on: " + settings.problem + " has no delayConfig (give one with --delay-config)");
  }
}

void print_league_header(const LeagueScenarioSettings& settings) {
  if (settings.json) return;
  std::printf("| robots | delays | steps | fleet tasks | fleet tasks/min | lockstep tasks | ratio | lockstep "
              "delayed %% | fleet actions per robot | windows (late) | longest window (ms) | robot time waiting for windows %% | "
              "tasks moved by the pool | replans | collisions |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
}

bool run_league_scenario(const LeagueScenarioSettings& settings, int robots, int domain) {
  const planner_core::LorrProblem source = planner_core::load_lorr_problem(settings.problem);
  const bool delays = delays_wanted(settings, source);
  const fs::path cut_problem = write_cut_problem(settings, robots, delays);
  const planner_core::LorrProblem problem = planner_core::load_lorr_problem(cut_problem.string());
  const int ticks_per_action = problem.ticks_per_action;

  const fs::path map_file = settings.work / "league-map.map";
  write_fleet_map(*problem.graph, map_file);
  planner_core::Instance mission;
  mission.graph = problem.graph;
  mission.starts.assign(problem.starts.begin(), problem.starts.begin() + robots);
  mission.goals = mission.starts;
  mission.index_tasks();
  const fs::path mission_file = settings.work / ("league-mission-" + std::to_string(robots) + ".yaml");
  std::ofstream(mission_file) << planner_core::instance_to_yaml(mission, fs::absolute(map_file).string());
  ProcessFleetSettings fleet{.programs = settings.programs, .work = settings.work, .vendor = settings.vendor,
                             .dds_config_dir = settings.dds_config_dir, .extra_options = settings.extra_options,
                             .step_s = settings.step_s, .jitter = settings.jitter, .turn_s = settings.step_s,
                             .log_prefix = "league"};
  const fs::path config_file =
      write_lifelong_fleet_config(fleet, mission_file, robots, "rotate", settings.lifelong_planner, domain);
  if (delays) {
    for (int r = 0; r < robots; ++r) {
      fleet.robot_options.push_back({"--delay-config", cut_problem.string(), "--delay-tick",
                                     std::to_string(settings.step_s / ticks_per_action), "--seed", std::to_string(r)});
    }
  }
  std::vector<planner_core::Cell> task_cells;
  for (const std::vector<planner_core::Vertex>& task : problem.tasks) task_cells.push_back(problem.graph->cell_of(task[0]));
  const int waiting = std::max(1, static_cast<int>(std::ceil(problem.tasks_revealed_per_agent * robots)));
  TaskStream stream(task_cells, waiting, 0, "league");
  FleetTrace trace;
  const ProcessFleetRun run =
      run_fleet_of_processes(fleet, mission, config_file, domain, stream,
                             {0, settings.measure_s, settings.restart_robot_at_s}, &trace);
  if (run.figures.interrupted) return false;
  const StreamFigures& figures = run.figures;
  // The fleet's run as the league's output file, beside the lockstep run's (league-lockstep-N/).
  const fs::path fleet_output = settings.work / ("league-fleet-" + std::to_string(robots) + ".lorr.json");
  const int tick_ms = std::max(1, static_cast<int>(std::lround(1000 * settings.step_s / ticks_per_action)));
  const FleetLeagueRun fleet_run = league_log_of_fleet(trace, problem, robots, run.counted_from_ms,
                                                       run.counted_until_ms, tick_ms, stream.list_number_of_task());
  planner_core::LeagueRunSettings output_settings;
  output_settings.delays = delays;
  planner_core::write_league_output(fleet_output.string(), problem, output_settings, fleet_run.result, fleet_run.log);

  const int steps = static_cast<int>(std::lround(figures.seconds / settings.step_s));
  const LockstepFigures lockstep =
      steps > 0 ? run_lockstep(settings, cut_problem, robots, steps * ticks_per_action, tick_ms, delays) : LockstepFigures{};
  if (ctsfleet::stop_requested().load()) return false;
  const double ratio = lockstep.tasks > 0 ? figures.tasks_done / static_cast<double>(lockstep.tasks) : 0;
  const std::string delay_name = delays ? "on" : "off";
  if (settings.json) {
    const nlohmann::json row = {
        {"robots", robots}, {"scenario", "league"}, {"problem", settings.problem}, {"delays", delay_name},
        {"step_s", settings.step_s}, {"steps", steps},
        {"fleet", {{"tasks_done", figures.tasks_done}, {"seconds", figures.seconds},
                   {"tasks_per_minute", figures.tasks_per_minute}, {"accepted", figures.accepted},
                   {"refused", figures.refused}, {"deferred", figures.deferred}, {"robot_actions", figures.robot_steps}, {"windows", figures.windows}, {"window_ms_max", figures.window_ms_max},
                   {"windows_late", figures.windows_late}, {"robot_s_waiting_for_windows", figures.robot_s_waiting_for_windows},
                   {"tasks_reassigned", figures.tasks_reassigned}, {"replans", figures.replans}}},
        {"lockstep", {{"ran", lockstep.ran}, {"ticks", steps * ticks_per_action}, {"tasks", lockstep.tasks},
                      {"delayed_share", lockstep.delayed_share}, {"faults", lockstep.faults}}},
        {"fleet_output", {{"file", fleet_output.string()}, {"tasks", fleet_run.result.tasks_finished},
                          {"shifted", fleet_run.shifted}, {"jumps", fleet_run.jumps}}},
        {"restarted_robot", run.restarted_robot},
        {"ratio", ratio}, {"collisions", run.collisions}, {"summary", run.coordinator_summary},
        {"logs", settings.work.string()}};
    std::printf("%s\n", row.dump().c_str());
  } else {
    const std::string lockstep_tasks = lockstep.ran ? std::to_string(lockstep.tasks) : "failed (see its log)";
    const double waiting_share =
        figures.seconds > 0 ? figures.robot_s_waiting_for_windows / (robots * figures.seconds) : 0;
    std::printf("| %d | %s | %d | %d | %.1f | %s | %.3f | %.1f | %.1f | %lld (%lld) | %.1f | %.1f | %lld | %d | %s |\n",
                robots, delay_name.c_str(), steps, figures.tasks_done, figures.tasks_per_minute, lockstep_tasks.c_str(),
                ratio, 100 * lockstep.delayed_share, static_cast<double>(figures.robot_steps) / robots,
                static_cast<long long>(figures.windows), static_cast<long long>(figures.windows_late),
                figures.window_ms_max, 100 * waiting_share,
                static_cast<long long>(figures.tasks_reassigned), figures.replans, run.collisions.c_str());
  }
  std::fflush(stdout);
  return true;
}

}  // namespace coordinator
