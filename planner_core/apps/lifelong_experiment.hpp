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

namespace ctsfleet_bench {

struct LifelongExperimentSettings {
  std::vector<std::string> problems;  // LoRR problem JSON files; default: every one under benchmarks/lorr-2023
  std::string benchmarks;             // the benchmark folder (for the default)
  std::string out_dir = ".";
  int steps = 500;
  double step_time_s = 1.0;
  unsigned seed = 0;
  std::string guidance = "auto";      // none, lanes (planner_core/guided_distances.hpp) or auto (lifelong_guidance)
  int stay_cost = 0;                  // PibtLifelongSettings::stay_cost; 0: lifelong_stay_cost
  std::string actions = "move4";      // planner_core/action_model.hpp
  int rollouts = 128;                 // PibtLifelongSettings::rollouts
  int rollout_steps = 0;              // PibtLifelongSettings::rollout_steps; 0: lifelong_rollout_steps, or lifelong_window with lns
  bool lns = false;                   // PibtLifelongSettings::lns
  std::string keep_window = "auto";   // PibtLifelongSettings::keep_window (with lns): on, off or auto (lifelong_window)
  std::string keep_equal_cost = "auto";  // PibtLifelongSettings::lns_keeps_equal_cost (with lns): on, off or auto (lifelong_window)
  std::string neighbourhoods = "auto";  // PibtLifelongSettings::lns_neighbourhoods (with lns): nearest, adaptive or auto (lifelong_window)
  int64_t lns_rounds = 0;             // PibtLifelongSettings::lns_rounds; set, late steps are taken too
  std::string hold_plans = "auto";    // PibtLifelongSettings::hold_plans (rotation model); auto: lifelong_plan_holding
  bool keep_targets = true;           // PibtLifelongSettings::keep_targets (rotation model)
  std::string park_dead_ends = "auto";  // PibtLifelongSettings::park_dead_end_errands: on, off or auto (lifelong_parks_dead_ends)
  std::string traffic_costs = "auto";  // PibtLifelongSettings::traffic: on, off or auto (lifelong_traffic)
  bool league_output = false;         // also write <out-dir>/<problem>.lorr.json (planner_core/lorr_output.hpp)
  const std::atomic<bool>* interrupt = nullptr;  // Ctrl-C: the run under way ends, nothing more runs
};

// Returns the process exit code.
int run_lifelong_experiment(const LifelongExperimentSettings& settings);

}  // namespace ctsfleet_bench
