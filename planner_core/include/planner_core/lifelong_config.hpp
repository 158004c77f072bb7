// The lifelong planner's settings as a person writes them: config/lifelong.yaml (read by
// ctsfleet-bench --lifelong-config and by the coordinator's lifelong mode, fleet key
// lifelong_planner), each key a value or "auto". settle_lifelong_config turns them into the
// planner's settings for one map and fleet, "auto" decided by the rules of lifelong_auto_rules.hpp.
// The defaults below are config/lifelong.yaml's (a test holds the two together).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "planner_core/action_model.hpp"
#include "planner_core/graph.hpp"
#include "planner_core/pibt_lifelong.hpp"

namespace planner_core {

struct LifelongConfig {
  std::string lns = "auto";              // window LNS: on, off or auto (lifelong_lns)
  std::string guidance = "auto";         // none, lanes, ring or auto (lifelong_guidance)
  int stay_cost = 0;                     // a wait's or quarter turn's cost, 1-6; 0: auto (lifelong_stay_cost)
  int rollouts = 128;                    // PIBT runs tried each step, 1-1,000,000 (1: plain PIBT)
  int rollout_steps = 0;                 // 1-1,000; 0: auto (lifelong_rollout_steps, or lifelong_window with LNS)
  int64_t lns_rounds = 0;                // 0: timed; N: every rollout and N LNS rounds a step, the same everywhere
  std::string keep_window = "auto";      // with LNS: on, off or auto (lifelong_window)
  std::string keep_equal_cost = "auto";  // with LNS: on, off or auto (lifelong_window)
  std::string neighbourhoods = "auto";   // with LNS: nearest, adaptive or auto (lifelong_window)
  std::string hold_plans = "auto";       // rotation model: never, half, always or auto (lifelong_plan_holding)
  bool keep_targets = true;              // rotation model: an agent short of its target tries it first
  std::string park_dead_ends = "auto";   // on, off or auto (lifelong_parks_dead_ends)
  std::string traffic_costs = "auto";    // on, off or auto (lifelong_traffic)
  std::string guide_paths = "auto";      // on, off or auto (off: settle_lifelong_config says why)

  bool operator==(const LifelongConfig&) const = default;
};

// Reads a lifelong settings file (a map of the keys above; any may be left out). An unknown key,
// a value of the wrong type or out of range: InputError "file:line: key: problem".
LifelongConfig load_lifelong_config(const std::string& path);

// Checks every key's value (for settings that came from the command line): InputError naming
// `what` and the key.
void check_lifelong_config(const LifelongConfig& config, const std::string& what);

// The planner's settings for `agents` agents on `graph` in `actions`, "auto" settled by the rules.
PibtLifelongSettings settle_lifelong_config(const LifelongConfig& config, const Graph& graph, size_t agents,
                                            ActionModel actions);

}  // namespace planner_core
