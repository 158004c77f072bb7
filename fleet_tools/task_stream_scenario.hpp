// The fleet benchmark's task-stream scenario (ctsfleet-fleetbench --scenario task-stream): a
// lifelong fleet of N simulated robots, each its own process, given a stream of tasks that keeps
// about one task per robot waiting; tasks done per minute over a counted stretch, against the
// same fleet in one process (in_process_fleet.hpp) at the same step; collisions seen by the
// safety monitor.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "in_process_fleet.hpp"

namespace coordinator {

struct TaskStreamSettings {
  std::filesystem::path programs;   // where ctsfleet-agent, -coordinator and -monitor are
  std::filesystem::path work;       // logs, mission and configuration files
  std::string map;
  std::string vendor = "cyclone";
  std::string dds_config_dir;
  std::vector<std::string> extra_options;  // every process's (security, discovery)
  double step_s = 0.2;
  double jitter = 0.1;
  std::string actions = "move4";  // planner.actions: rotate plans with turns
  double turn_s = 0;              // the sim robots' quarter turn (0: free)
  std::string lifelong_planner;   // the fleet config's lifelong_planner (empty: plain PIBT windows)
  StreamTimeline timeline;
  bool json = false;
};

// One fleet size on `domain`; prints a table row (or a JSON object). Returns false when interrupted.
bool run_task_stream(const TaskStreamSettings& settings, int robots, int domain);
void print_task_stream_header(const TaskStreamSettings& settings);

}  // namespace coordinator
