// The league experiment: League of Robot Runners problems run under the 2026 rules
// (planner_core/league_run.hpp): ticks, agentCounter, delays drawn from each problem's
// delayConfig, a planning call every plan period, the Action Dependency Graph carrying plans out.
// Prints, per problem and delay setting, tasks finished, the share of robot time delayed, the
// planning calls' times against their budget and the tick check's faults; writes it as CSV beside
// the tasks finished at each tick, and a chart of them.
#pragma once

#include <string>

#include "lifelong_experiment.hpp"

namespace ctsfleet_bench {

struct LeagueExperimentSettings {
  int ticks = 5000;             // simulationTime
  int tick_ms = 100;            // actionMoveTimeLimit
  int plan_period_ms = 1000;    // planCommTimeLimit
  double preprocess_s = 30;     // preprocessTimeLimit
  std::string delays = "on";    // on, off, or both (each problem run twice)
  bool plan_round_delayed = false;  // LeagueRunSettings::plan_round_delayed
  double lead_periods = 1.5;       // LeagueRunSettings::lead_periods
};

// `common` gives the problems (default: every one under benchmarks/lorr-2026), the planner's
// settings, seed, output folder and --league-output. Returns the process exit code.
int run_league_experiment(const LifelongExperimentSettings& common, const LeagueExperimentSettings& settings);

}  // namespace ctsfleet_bench
