#include "task_stream_scenario.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>

#include "fleet_of_processes.hpp"
#include "coordinator/fleet_config.hpp"
#include "ctsfleet/program.hpp"
#include "planner_core/instance_generator.hpp"

namespace coordinator {

namespace fs = std::filesystem;

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
  const uint32_t seed = static_cast<uint32_t>(robots);
  TaskStream processes_stream(*graph, robots, mission.task_count(), seed, "stream");
  ProcessFleetSettings fleet{.programs = settings.programs, .work = settings.work, .vendor = settings.vendor,
                             .dds_config_dir = settings.dds_config_dir, .extra_options = settings.extra_options,
                             .step_s = settings.step_s, .jitter = settings.jitter, .turn_s = settings.turn_s};
  const fs::path config_file =
      write_lifelong_fleet_config(fleet, mission_file, robots, settings.actions, settings.lifelong_planner, domain);
  const ProcessFleetRun run =
      run_fleet_of_processes(fleet, mission, config_file, domain, processes_stream, settings.timeline);
  const StreamFigures& processes = run.figures;
  const nlohmann::json& summary = run.coordinator_summary;
  const std::string& collisions = run.collisions;
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
                            {"window_ms_max", f.window_ms_max}, {"windows_late", f.windows_late},
                            {"robot_s_waiting_for_windows", f.robot_s_waiting_for_windows}, {"tasks_reassigned", f.tasks_reassigned},
                            {"replans", f.replans}};
    };
    const nlohmann::json row = {{"robots", robots}, {"scenario", "task-stream"}, {"step_s", settings.step_s},
                                {"processes", figures(processes)}, {"in_process", figures(in_process)},
                                {"restarted_robot", run.restarted_robot},
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
