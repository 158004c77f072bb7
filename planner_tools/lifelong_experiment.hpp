// The lifelong experiment: League of Robot Runners problems (benchmarks/lorr-2023) run for a
// horizon of steps with a time budget per step (planner_core/lifelong.hpp), one after another.
// Prints a table of errands finished, errands per step, the planner's time per step (p50, p99,
// max) against the budget, steps replaced by waiting, and peak memory; writes it as CSV beside the
// errands finished at each step.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "planner_core/lifelong_config.hpp"

namespace ctsfleet_bench {

struct LifelongExperimentSettings {
  std::vector<std::string> problems;  // LoRR problem JSON files; default: every one under benchmarks/lorr-2023
  std::string benchmarks;             // the benchmark folder (for the default)
  std::string out_dir = ".";
  int steps = 500;
  double step_time_s = 1.0;
  unsigned seed = 0;
  std::string actions = "move4";      // planner_core/action_model.hpp
  planner_core::LifelongConfig planner;  // the planner's settings, "auto" settled per problem
  bool league_output = false;         // also write <out-dir>/<problem>.lorr.json (planner_core/lorr_output.hpp)
  std::string scheduler = "auto";     // auto (the problem's rules), or a TaskScheduler's name
  const std::atomic<bool>* interrupt = nullptr;  // Ctrl-C: the run under way ends, nothing more runs
};

// The problem files (.json) under <benchmarks>/<suite>, sorted; throws InputError when there is no such folder.
std::vector<std::string> problems_under(const std::string& benchmarks, const std::string& suite);

// The q-quantile of `values` (0 when empty).
double quantile(std::vector<double> values, double q);

// Peak resident memory of this process so far, in MB.
double peak_memory_mb();

// Returns the process exit code.
int run_lifelong_experiment(const LifelongExperimentSettings& settings);

}  // namespace ctsfleet_bench
