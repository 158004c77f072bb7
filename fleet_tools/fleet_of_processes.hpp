// A lifelong fleet of simulated robots, each its own process, run for the fleet benchmark's
// stream scenarios (task-stream, league): N ctsfleet-agent processes, the safety monitor and a
// lifelong coordinator over DDS on one domain, fed by a TaskStream from outside, as an operator's
// tool would feed it. Tasks done are counted from the fleet's status over a counted stretch.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "fleet_trace.hpp"
#include "in_process_fleet.hpp"
#include "planner_core/instance.hpp"
#include "task_stream.hpp"

namespace coordinator {

struct ProcessFleetSettings {
  std::filesystem::path programs;   // where ctsfleet-agent, -coordinator and -monitor are
  std::filesystem::path work;       // the processes' logs
  std::string vendor = "cyclone";
  std::string dds_config_dir;
  std::vector<std::string> extra_options;  // every process's (security, discovery)
  double step_s = 0.2;
  double jitter = 0.1;
  double turn_s = 0;                // the sim robots' quarter turn (0: free)
  // Robot r's options beyond its id, start, step, jitter and turn (e.g. its delays); may be empty.
  std::vector<std::vector<std::string>> robot_options;
  std::string log_prefix = "stream";  // the logs' names: <prefix>-robot<r>.log, <prefix>-coordinator-<N>.log
};

struct ProcessFleetRun {
  StreamFigures figures;
  nlohmann::json coordinator_summary;  // its --json summary
  std::string collisions;              // the safety monitor's overlaps ("-": it did not finish)
  int64_t counted_from_ms = 0;         // the counted stretch, wall clock (0: it never began)
  int64_t counted_until_ms = 0;
  std::string restarted_robot;         // timeline.restart_robot_at_s: the robot killed and started again
  planner_core::Cell restarted_at{};   // ... where it stood
};

// Writes the fleet config such a run starts its coordinator with: lifelong, `mission_file`, a
// quorum of `robots`, plans with `actions` (move4 or rotate), `lifelong_planner` when not empty,
// on `domain`; returns its path (work/<log_prefix>-fleet-<robots>.yaml).
std::filesystem::path write_lifelong_fleet_config(const ProcessFleetSettings& settings,
                                                  const std::filesystem::path& mission_file, int robots,
                                                  const std::string& actions, const std::string& lifelong_planner,
                                                  int domain);

// Runs `mission` (its starts are the robots') with the fleet config `config_file` (lifelong, on
// `domain`): tasks are counted from the first plan plus timeline.warmup_s, for timeline.measure_s.
// `trace` (optional) records the robots' states and the task events heard meanwhile. With
// timeline.restart_robot_at_s, robot N/2 is SIGKILLed then and started again where it was last
// heard standing, 2 s later (a supervisor's restart; the coordinator misses it by its lease or
// silence, and a process heard within a second of the last one would be refused as a duplicate).
ProcessFleetRun run_fleet_of_processes(const ProcessFleetSettings& settings, const planner_core::Instance& mission,
                                       const std::filesystem::path& config_file, int domain, TaskStream& stream,
                                       const StreamTimeline& timeline, FleetTrace* trace = nullptr);

}  // namespace coordinator
