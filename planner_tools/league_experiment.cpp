#include "league_experiment.hpp"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "chart.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/league_output.hpp"
#include "planner_core/league_run.hpp"
#include "planner_core/lifelong_auto_rules.hpp"
#include "planner_core/lorr_problem.hpp"
#include "planner_core/pibt_lifelong.hpp"

namespace ctsfleet_bench {

namespace fs = std::filesystem;

namespace {

// The lifelong planner's settings for plans carried out by the Action Dependency Graph: no
// rotations (a cycle's moves would each wait for the next), no window LNS (its paths may close such
// cycles).
planner_core::PibtLifelongSettings executable_settings(const planner_core::LifelongConfig& asked,
                                                        const planner_core::LorrProblem& problem) {
  planner_core::PibtLifelongSettings pibt = planner_core::settle_lifelong_config(
      asked, *problem.graph, problem.starts.size(), planner_core::ActionModel::kRotate);
  pibt.forbid_rotations = true;
  pibt.lns = false;
  pibt.keep_window = false;
  return pibt;
}

// The planner holds a distance table per goal in use, one per robot at least: refuse a problem
// whose tables would not fit in this machine's memory rather than run it into swap.
void check_tables_fit(const planner_core::PibtLifelong& planner, const planner_core::LorrProblem& problem,
                      const std::string& path) {
  const double needed = static_cast<double>(planner.distances().bytes_per_target()) * problem.starts.size();
  const double memory = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * sysconf(_SC_PAGESIZE);
  if (needed > 0.75 * memory) {
    throw planner_core::InputError(
        path + ": " + std::to_string(problem.starts.size()) + " robots on " +
        std::to_string(problem.graph->vertex_count()) + " cells need about " +
        std::to_string(static_cast<long long>(needed / 1e9)) + " GB of distance tables (one per goal in use), more "
        "than this machine's memory allows (" + std::to_string(static_cast<long long>(memory / 1e9)) + " GB)");
  }
}

}  // namespace

int run_league_experiment(const LifelongExperimentSettings& common, const LeagueExperimentSettings& settings) {
  const std::vector<std::string> problems =
      common.problems.empty() ? problems_under(common.benchmarks, "lorr-2026") : common.problems;
  // Every problem read before anything is written: a bad one, or one too big for the planner's
  // tables, stops the run with nothing partial.
  for (const std::string& path : problems) {
    const planner_core::LorrProblem problem = planner_core::load_lorr_problem(path);
    const planner_core::PibtLifelong planner(*problem.graph, common.seed, executable_settings(common.planner, problem));
    check_tables_fit(planner, problem, path);
  }
  std::vector<bool> delay_settings;
  if (settings.delays != "off") delay_settings.push_back(true);
  if (settings.delays != "on") delay_settings.push_back(false);
  fs::create_directories(common.out_dir);
  const fs::path table_path = fs::path(common.out_dir) / "league.csv";
  const fs::path ticks_path = fs::path(common.out_dir) / "league_ticks.csv";
  std::ofstream table(table_path), per_tick(ticks_path);
  table << "problem,agents,ticks,tick_ms,plan_period_ms,delays,tasks,errands,delayed_share,plan_calls,plan_steps,"
           "plan_ms_p50,plan_ms_max,late_steps,invalid_steps,faults,peak_mb\n";
  per_tick << "problem,step,errands\n";
  std::printf("league (2026 rules, lockstep): %d ticks of %d ms, a planning call every %d ms, rotation model, "
              "planner pibt without rotations, guidance %s, %d rollouts, plans held %s, scheduler %s (seed %u)\n",
              settings.ticks, settings.tick_ms, settings.plan_period_ms, common.planner.guidance.c_str(),
              common.planner.rollouts, common.planner.hold_plans.c_str(), common.scheduler.c_str(), common.seed);
  std::printf("%-28s %6s %7s %7s %8s %9s %6s %9s %9s %5s %7s %6s %8s\n", "problem", "agents", "delays", "tasks",
              "errands", "delayed %", "calls", "p50 ms", "max ms", "late", "invalid", "faults", "peak MB");
  for (const std::string& path : problems) {
    const planner_core::LorrProblem problem = planner_core::load_lorr_problem(path);
    const std::string name = fs::path(path).stem().string();
    for (bool delays : delay_settings) {
      planner_core::PibtLifelong planner(*problem.graph, common.seed, executable_settings(common.planner, problem));
      planner_core::LeagueLog log;
      planner_core::LeagueRunSettings run;
      run.ticks = settings.ticks;
      run.tick_ms = settings.tick_ms;
      run.plan_period_ms = settings.plan_period_ms;
      run.preprocess_time_s = settings.preprocess_s;
      run.delays = delays;
      run.plan_round_delayed = settings.plan_round_delayed;
      run.lead_periods = settings.lead_periods;
      if (common.scheduler != "auto") run.scheduler = planner_core::parse_task_scheduler(common.scheduler, "--scheduler");
      run.interrupt = common.interrupt;
      run.log = common.league_output ? &log : nullptr;
      const planner_core::LeagueRunResult result = planner_core::run_league(problem, planner, run);
      if (result.interrupted) {
        std::printf("%s: interrupted after %zu ticks; nothing written for it\n", name.c_str(),
                    result.tasks_per_tick.size());
        return 130;  // ctsfleet::kExitInterrupted
      }
      const char* delay_name = !delays ? "off" : problem.delays ? "on" : "none";
      std::printf("%-28s %6zu %7s %7lld %8lld %9.1f %6zu %9.1f %9.1f %5d %7d %6d %8.0f\n", name.c_str(),
                  problem.starts.size(), delay_name, static_cast<long long>(result.tasks_finished),
                  static_cast<long long>(result.errands_finished), 100 * result.delayed_share(),
                  result.plan_ms.size(), quantile(result.plan_ms, 0.5), quantile(result.plan_ms, 1.0),
                  result.late_steps, result.invalid_steps, result.faults, peak_memory_mb());
      if (result.reassignments > 0) {
        std::printf("  %lld unopened tasks given to a nearer robot\n", static_cast<long long>(result.reassignments));
      }
      if (!result.first_invalid.empty()) std::printf("  first invalid step: %s\n", result.first_invalid.c_str());
      if (!result.first_fault.empty()) std::printf("  FIRST FAULT: %s\n", result.first_fault.c_str());
      if (common.league_output) {
        const fs::path output = fs::path(common.out_dir) / (name + (delays ? "" : ".no-delays") + ".lorr.json");
        planner_core::write_league_output(output.string(), problem, run, result, log);
        std::printf("  wrote %s\n", output.c_str());
      }
      table << name << "," << problem.starts.size() << "," << settings.ticks << "," << settings.tick_ms << ","
            << settings.plan_period_ms << "," << delay_name << "," << result.tasks_finished << ","
            << result.errands_finished << "," << result.delayed_share() << "," << result.plan_ms.size() << ","
            << result.plan_steps << "," << quantile(result.plan_ms, 0.5) << "," << quantile(result.plan_ms, 1.0)
            << "," << result.late_steps << "," << result.invalid_steps << "," << result.faults << ","
            << peak_memory_mb() << "\n";
      const std::string series = name + (delays ? "" : " (no delays)");
      for (size_t t = 0; t < result.tasks_per_tick.size(); ++t) {
        per_tick << series << "," << t << "," << result.tasks_per_tick[t] << "\n";
      }
    }
  }
  per_tick.close();
  std::printf("wrote %s and %s\n", table_path.c_str(), ticks_path.c_str());
  std::fflush(stdout);  // before the plotter writes its own line
  draw_chart({"lifelong", ticks_path.string(), "-o", (fs::path(common.out_dir) / "league.svg").string(), "--title",
              "Tasks finished per tick, 2026 rules", "--x-label", "tick", "--y-label",
              "tasks per tick (sliding mean)"});
  return 0;
}

}  // namespace ctsfleet_bench
