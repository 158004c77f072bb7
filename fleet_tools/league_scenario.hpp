// The fleet benchmark's league scenario (ctsfleet-fleetbench --scenario league --problem F.json):
// a League of Robot Runners problem run by the fleet, N simulated robots each its own process
// over DDS, beside the benchmark's lockstep run of the same problem (ctsfleet-bench --experiment
// league) for as many steps.
//
//   the problem F.json ──► a copy cut to N robots (work/league-problem-N.json), read by both runs
//     fleet:    map + the first N starts (goals: the starts) as the mission; the problem's tasks
//               fed in the file's order, numTasksReveal x N of them waiting; sim robots delayed
//               as its delayConfig draws (a tick is an action over agentCounter), each its seed;
//               rotation model (a quarter turn takes an action); counted from the first plan
//     lockstep: the same problem, robots and delays, for the steps the fleet ran x agentCounter
//               ticks, the pool scheduler the fleet follows (whole-task-reassign)
//
// Printed: tasks finished by each, per minute of the fleet's time and per step, their ratio, and
// what the fleet's run cost (windows, replans, collisions the safety monitor saw). The fleet's
// tasks are single cells: problems with multi-errand tasks (2024 on) are refused.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace coordinator {

struct LeagueScenarioSettings {
  std::filesystem::path programs;   // ctsfleet-agent, -coordinator, -monitor and ctsfleet-bench
  std::filesystem::path work;       // logs, the cut problem, mission and configuration files
  std::string problem;              // the league's problem (JSON)
  std::string delay_config;         // a delayConfig to use instead of the problem's ("": its own)
  std::string delays = "auto";      // on, off, or auto (on when there is a delayConfig)
  std::string vendor = "cyclone";
  std::string dds_config_dir;
  std::vector<std::string> extra_options;  // every process's (security, discovery)
  double step_s = 0.3;              // seconds per action of a sim robot
  double jitter = 0;                // sim robots' extra share of a step, U[0, jitter]
  std::string lifelong_planner;     // the fleet config's lifelong_planner (empty: plain PIBT windows)
  double measure_s = 60;            // from the fleet's first plan
  double restart_robot_at_s = -1;   // StreamTimeline::restart_robot_at_s
  bool json = false;
};

// Throws InputError naming the file and key when the problem cannot run in the fleet with `robots`
// robots: unreadable, a multi-errand task, a team smaller than `robots`, delays asked of a problem
// without a delayConfig. Nothing is started.
void check_league_scenario(const LeagueScenarioSettings& settings, int robots);

// One fleet size on `domain`; prints a table row (or a JSON object). Returns false when interrupted.
bool run_league_scenario(const LeagueScenarioSettings& settings, int robots, int domain);
void print_league_header(const LeagueScenarioSettings& settings);

}  // namespace coordinator
