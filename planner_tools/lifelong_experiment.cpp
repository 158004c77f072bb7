#include "lifelong_experiment.hpp"

#include "chart.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "planner_core/input_error.hpp"
#include "planner_core/lifelong.hpp"
#include "planner_core/lifelong_auto_rules.hpp"
#include "planner_core/pibt_lifelong.hpp"
#include "planner_core/lorr_output.hpp"
#include "planner_core/lorr_problem.hpp"

namespace ctsfleet_bench {

namespace fs = std::filesystem;

std::vector<std::string> problems_under(const std::string& benchmarks, const std::string& suite) {
  std::vector<std::string> found;
  const fs::path root = fs::path(benchmarks) / suite;
  if (!fs::is_directory(root)) throw planner_core::InputError(root.string() + ": no such folder (give --problem)");
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    if (entry.is_regular_file() && entry.path().extension() == ".json") found.push_back(entry.path().string());
  }
  std::sort(found.begin(), found.end());
  return found;
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<size_t>(q * values.size()))];
}

double peak_memory_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

int run_lifelong_experiment(const LifelongExperimentSettings& settings) {
  const std::vector<std::string> problems =
      settings.problems.empty() ? problems_under(settings.benchmarks, "lorr-2023") : settings.problems;
  // Every problem read before anything is written: a bad one stops the run with nothing partial.
  for (const std::string& path : problems) planner_core::load_lorr_problem(path);
  fs::create_directories(settings.out_dir);
  const fs::path table_path = fs::path(settings.out_dir) / "lifelong.csv";
  const fs::path steps_path = fs::path(settings.out_dir) / "lifelong_steps.csv";
  std::ofstream table(table_path), per_step(steps_path);
  table << "problem,agents,steps,step_time_s,planner,errands,tasks,errands_per_step,step_ms_p50,step_ms_p99,"
           "step_ms_max,over_budget,invalid,peak_mb,preprocess_ms\n";
  per_step << "problem,step,errands\n";
  const planner_core::ActionModel actions = planner_core::parse_action_model(settings.actions, "--actions");
  const planner_core::LifelongConfig& asked = settings.planner;
  const std::string turning =
      actions == planner_core::ActionModel::kRotate
          ? ", plans held " + asked.hold_plans + (asked.keep_targets ? ", targets kept" : ", targets not kept")
          : "";
  const std::string rollout_steps = asked.rollout_steps > 0 ? std::to_string(asked.rollout_steps) : "auto";
  std::printf(
      "lifelong: %d steps, %.3f s per step, actions %s%s, planner pibt, lns %s, guidance %s, %d rollouts of %s steps, "
      "scheduler %s (seed %u)\n",
      settings.steps, settings.step_time_s, settings.actions.c_str(), turning.c_str(), asked.lns.c_str(),
      asked.guidance.c_str(), asked.rollouts, rollout_steps.c_str(), settings.scheduler.c_str(), settings.seed);
  if (asked.lns_rounds > 0) {
    std::printf("work counted, not timed: every step %d rollouts and, with LNS, %lld LNS rounds, and taken however long it took\n",
                asked.rollouts, static_cast<long long>(asked.lns_rounds));
  }
  std::printf("%-28s %6s %9s %8s %9s %9s %9s %6s %7s %8s %9s\n", "problem", "agents", "errands", "per step",
              "p50 ms", "p99 ms", "max ms", "over", "invalid", "peak MB", "prep ms");
  for (const std::string& path : problems) {
    const planner_core::LorrProblem problem = planner_core::load_lorr_problem(path);
    const planner_core::PibtLifelongSettings pibt =
        planner_core::settle_lifelong_config(asked, *problem.graph, problem.starts.size(), actions);
    const bool adaptive = pibt.lns_neighbourhoods == planner_core::WindowLns::Neighbourhoods::kAdaptive;
    const std::string turning_name = actions == planner_core::ActionModel::kRotate
                                         ? "-hold-" + planner_core::to_string(pibt.hold_plans) + (pibt.keep_targets ? "-keep" : "")
                                         : "";
    planner_core::PibtLifelong planner(*problem.graph, settings.seed, pibt);
    planner_core::LifelongLog log;
    planner_core::LifelongSettings lifelong;
    lifelong.actions = actions;
    lifelong.steps = settings.steps;
    lifelong.step_time_s = settings.step_time_s;
    lifelong.interrupt = settings.interrupt;
    lifelong.late_steps_taken = asked.lns_rounds > 0;
    if (settings.scheduler != "auto") lifelong.scheduler = planner_core::parse_task_scheduler(settings.scheduler, "--scheduler");
    lifelong.log = settings.league_output ? &log : nullptr;
    const planner_core::LifelongResult result = planner_core::run_lifelong(problem, planner, lifelong);
    if (result.interrupted) {
      std::printf("%s: interrupted after %zu steps; nothing written for it\n", fs::path(path).stem().c_str(),
                  result.step_ms.size());
      return 130;  // ctsfleet::kExitInterrupted
    }
    const std::string name = fs::path(path).stem().string();
    const double per = static_cast<double>(result.errands_finished) / settings.steps;
    std::printf("%-28s %6zu %9lld %8.2f %9.3f %9.3f %9.3f %6d %7d %8.0f %9.0f\n", name.c_str(), problem.starts.size(),
                static_cast<long long>(result.errands_finished), per, quantile(result.step_ms, 0.5),
                quantile(result.step_ms, 0.99), quantile(result.step_ms, 1.0), result.steps_over_budget,
                result.invalid_steps, peak_memory_mb(), result.preprocess_ms);
    if (!result.first_invalid.empty()) std::printf("  first invalid step: %s\n", result.first_invalid.c_str());
    if (problem.delays || problem.ticks_per_action != 1) {
      std::printf("  %s: agentCounter %d%s read; not simulated here (--experiment league does): every action "
                  "takes one step, no robot is delayed\n",
                  problem.version.empty() ? "execution settings" : problem.version.c_str(), problem.ticks_per_action,
                  problem.delays ? ", delayConfig" : "");
    }
    if (pibt.lns) {
      const planner_core::WindowLnsStats& lns = planner.lns_totals();
      std::printf("  window LNS: %lld iterations, %lld improvements, window cost %lld -> %lld\n",
                  static_cast<long long>(lns.iterations), static_cast<long long>(lns.improvements),
                  static_cast<long long>(lns.cost_before), static_cast<long long>(lns.cost_after));
      std::printf("  windows of %d steps%s, %s%s\n", pibt.rollout_steps, asked.rollout_steps > 0 ? "" : " (auto)",
                  pibt.keep_window ? "kept from step to step" : "planned afresh each step",
                  asked.keep_window == "auto" ? " (auto)" : "");
      std::printf("  paths of equal cost %s%s\n", pibt.lns_keeps_equal_cost ? "kept" : "not kept",
                  asked.keep_equal_cost == "auto" ? " (auto)" : "");
      std::printf("  neighbourhoods %s%s\n", adaptive ? "adaptive (nearest, crossing, random)" : "nearest",
                  asked.neighbourhoods == "auto" ? " (auto)" : "");
      if (adaptive) {
        std::printf("  rounds by neighbourhood: nearest %lld (%lld improved), crossing %lld (%lld), random %lld (%lld)\n",
                    static_cast<long long>(lns.rounds_by_kind[0]), static_cast<long long>(lns.improvements_by_kind[0]),
                    static_cast<long long>(lns.rounds_by_kind[1]), static_cast<long long>(lns.improvements_by_kind[1]),
                    static_cast<long long>(lns.rounds_by_kind[2]), static_cast<long long>(lns.improvements_by_kind[2]));
      }
      if (pibt.keep_window) {
        std::printf("  last window carried on at %lld of %lld steps, and taken at %lld\n",
                    static_cast<long long>(planner.windows_carried_on()), static_cast<long long>(settings.steps),
                    static_cast<long long>(planner.windows_kept()));
      }
    } else if (pibt.rollouts > 1) {
      std::printf("  rollouts of %d steps%s\n", pibt.rollout_steps, asked.rollout_steps > 0 ? "" : " (auto)");
    }
    const char* chosen = asked.guidance == "auto" ? " (auto)" : "";
    if (pibt.guidance == planner_core::Guidance::kLanes) {
      std::printf("  guidance lanes%s: they turn every %d rows and every %d columns; a wait or turn costs %d\n", chosen,
                  planner.distances().row_period(), planner.distances().column_period(), pibt.stay_cost);
    } else if (pibt.guidance == planner_core::Guidance::kRing) {
      std::printf(
          "  guidance ring%s: lanes turning every %d rows and every %d columns, and cheaper within %d cells of the "
          "edge; a wait or turn costs %d (costs in tenths of a move)\n",
          chosen, planner.distances().row_period(), planner.distances().column_period(),
          planner_core::GuidedDistances::kRingDepth, pibt.stay_cost);
    } else {
      std::printf("  guidance none%s: shortest paths; a wait or turn costs %d\n", chosen, pibt.stay_cost);
    }
    if (asked.hold_plans == "auto" && actions == planner_core::ActionModel::kRotate) {
      std::printf("  plans held %s (auto)\n", planner_core::to_string(pibt.hold_plans).c_str());
    }
    if (pibt.park_dead_end_errands) {
      std::printf("  parked%s: %d agents at the last step, whose errand is a dead end (given up)\n",
                  asked.park_dead_ends == "auto" ? " (auto)" : "", planner.parked_agents());
    }
    if (pibt.traffic.on) {
      std::printf("  traffic costs%s: cells taken more than %.0f%% of the time cost up to %d moves more\n",
                  asked.traffic_costs == "auto" ? " (auto)" : "", 100 * pibt.traffic.threshold,
                  pibt.traffic.max_moves);
    }
    if (pibt.guide_paths.on) {
      std::printf("  guide paths%s: %lld searched, %lld moves of them against another's at the end\n",
                  asked.guide_paths == "auto" ? " (auto)" : "", static_cast<long long>(planner.guides().paths_searched()),
                  static_cast<long long>(planner.guides().contraflow_moves()));
    }
    if (settings.league_output) {
      const fs::path output = fs::path(settings.out_dir) / (name + ".lorr.json");
      planner_core::write_lorr_output(output.string(), problem, result, log);
      std::printf("  wrote %s\n", output.c_str());
    }
    table << name << "," << problem.starts.size() << "," << settings.steps << "," << settings.step_time_s << ",pibt-" << (actions == planner_core::ActionModel::kRotate ? "rotate-" : "") << planner_core::to_string(pibt.guidance) << (pibt.stay_cost != 1 ? "-stay" + std::to_string(pibt.stay_cost) : "") << "-r" << pibt.rollouts << (pibt.lns ? "-lns" : "") << (pibt.keep_window ? "-window-kept" : "") << (pibt.lns_keeps_equal_cost ? "-equal-kept" : "") << (adaptive ? "-adaptive" : "") << turning_name << (pibt.park_dead_end_errands ? "-park" : "") << (pibt.traffic.on ? "-traffic" : "") << (pibt.guide_paths.on ? "-guided" : "") << ","
          << result.errands_finished << "," << result.tasks_finished << "," << per << ","
          << quantile(result.step_ms, 0.5) << "," << quantile(result.step_ms, 0.99) << ","
          << quantile(result.step_ms, 1.0) << "," << result.steps_over_budget << "," << result.invalid_steps << ","
          << peak_memory_mb() << "," << result.preprocess_ms << "\n";
    for (size_t s = 0; s < result.errands_per_step.size(); ++s) {
      per_step << name << "," << s << "," << result.errands_per_step[s] << "\n";
    }
  }
  per_step.close();
  std::printf("wrote %s and %s\n", table_path.c_str(), steps_path.c_str());
  std::fflush(stdout);  // before the plotter writes its own line
  draw_chart({"lifelong", steps_path.string(), "-o", (fs::path(settings.out_dir) / "lifelong.svg").string()});
  return 0;
}

}  // namespace ctsfleet_bench
