// ctsfleet-bench: runs solvers over instance folders or lists, writes a CSV and prints a summary
// per (map, N, M) setting.
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "ctsfleet/data_dir.hpp"
#include "ctsfleet/program.hpp"
#include "league_experiment.hpp"
#include "lifelong_experiment.hpp"
#include "planner_core/lifelong_config.hpp"
#include "mapf_scale_experiment.hpp"
#include "paper_experiments.hpp"
#include "planner_core/benchmark_runner.hpp"
#include "planner_core/guided_distances.hpp"
#include "planner_core/input_error.hpp"
#include "solver_options.hpp"

namespace fs = std::filesystem;

namespace {

std::vector<std::string> collect_instances(const std::vector<std::string>& inputs) {
  std::vector<std::string> files;
  for (const std::string& input : inputs) {
    if (fs::is_directory(input)) {
      for (const auto& entry : fs::recursive_directory_iterator(input)) {
        const std::string ext = entry.path().extension().string();
        if (entry.is_regular_file() && (ext == ".yaml" || ext == ".yml")) files.push_back(entry.path().string());
      }
    } else if (fs::path(input).extension() == ".txt") {  // a list of instance paths, one per line
      std::ifstream list(input);
      for (std::string line; std::getline(list, line);) {
        if (!line.empty()) files.push_back(line);
      }
    } else {
      files.push_back(input);
    }
  }
  return files;
}

// A progress bar on stderr, only when stderr is a terminal.
void draw_progress(int done, int total) {
  if (!isatty(STDERR_FILENO)) return;
  const int width = 40;
  const int filled = total > 0 ? width * done / total : width;
  std::fprintf(stderr, "\r[%s%s] %d/%d", std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(),
               done, total);
  if (done == total) std::fprintf(stderr, "\n");
}

}  // namespace

int main(int argc, char** argv) {
  using namespace planner_core;
  ctsfleet::Program program("ctsfleet-bench", "run solvers over benchmark instances and summarise per (map, N, M)");
  CLI::App& app = program.app();
  std::vector<std::string> inputs, solvers{"cts-pibt"};
  std::string csv_path = "bench.csv";
  double seconds = 10;
  int sample = 0;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  SolverConfig config;
  std::string experiment;
  bool full = false, json = false;
  ctsfleet_bench::ExperimentSettings experiment_settings;
  app.add_option("inputs", inputs, "instance files, folders (searched for .yaml) or .txt lists")->check(CLI::ExistingPath);
  app.add_option("--experiment", experiment,
                 "reproduce the CTS-PLL paper's experiments side by side: dense, sparse, scale or all; "
                 "mapf-scale; lifelong (League of Robot Runners problems, a time budget per step); league (the "
                 "league's 2026 rules: ticks, agentCounter, delays, a planning call every period, plans carried out "
                 "by the Action Dependency Graph)")
      ->check(CLI::IsMember({"dense", "sparse", "scale", "all", "mapf-scale", "lifelong", "league"}));
  ctsfleet_bench::LifelongExperimentSettings lifelong;
  app.add_option("--problem", lifelong.problems,
                 "experiment lifelong or league: a League of Robot Runners problem (JSON; repeatable; default: every "
                 "one under benchmarks/lorr-2023, for league benchmarks/lorr-2026)")
      ->check(CLI::ExistingFile);
  ctsfleet_bench::LeagueExperimentSettings league;
  app.add_option("--ticks", league.ticks, "experiment league: the horizon in ticks (the league's simulationTime)")
      ->check(ctsfleet::count_in(1, 1'000'000))
      ->capture_default_str();
  app.add_option("--tick-ms", league.tick_ms, "experiment league: milliseconds per tick (actionMoveTimeLimit)")
      ->check(ctsfleet::count_in(1, 60'000))
      ->capture_default_str();
  app.add_option("--plan-period-ms", league.plan_period_ms,
                 "experiment league: a planning call every this many milliseconds, with that budget "
                 "(planCommTimeLimit); a whole number of ticks")
      ->check(ctsfleet::count_in(1, 3'600'000))
      ->capture_default_str();
  app.add_option("--preprocess-s", league.preprocess_s, "experiment league: seconds to prepare (preprocessTimeLimit)")
      ->check(ctsfleet::positive_seconds(3600))
      ->capture_default_str();
  app.add_option("--delays", league.delays,
                 "experiment league: robots delayed as each problem's delayConfig draws (on), never (off), or each "
                 "problem run both ways (both)")
      ->check(CLI::IsMember({"on", "off", "both"}))
      ->capture_default_str();
  app.add_flag("--plan-round-delayed,!--no-plan-round-delayed", league.plan_round_delayed,
               "experiment league: robots delayed for longer than an action when the planner is called are "
               "planned to stay where their staged moves end, the others round them (off by default: measured "
               "no better)")
      ->capture_default_str();
  app.add_option("--lead-periods", league.lead_periods,
                 "experiment league: how far ahead of the median robot the staged plan is kept, in plan periods' "
                 "worth of actions")
      ->check(ctsfleet::number_in(0.1, 100))
      ->capture_default_str();
  app.add_option("--scheduler", lifelong.scheduler,
                 "experiment lifelong or league: who gets which task: round-robin, nearest-errand (nearest first errand), "
                 "whole-task (the task finished soonest, as the Start-Kit's default), whole-task-reassign (that, "
                 "and unopened tasks go to a nearer robot), or auto (the problem's rules: whole-task-reassign for "
                 "a pool)")
      ->check(CLI::IsMember({"auto", "round-robin", "nearest-errand", "whole-task", "whole-task-reassign"}))
      ->capture_default_str();
  app.add_option("--steps", lifelong.steps, "experiment lifelong: the horizon in steps")
      ->check(ctsfleet::count_in(1, 1'000'000))
      ->capture_default_str();
  app.add_option("--step-time", lifelong.step_time_s, "experiment lifelong: seconds to decide each step")
      ->check(ctsfleet::positive_seconds(3600))
      ->capture_default_str();
  app.add_option("--guidance", lifelong.planner.guidance,
                 "experiment lifelong: none (shortest paths), lanes (one-way lanes: rows alternate east and west, "
                 "columns south and north; a move against its lane costs 3), ring (lanes, and within 12 cells of the "
                 "map's edge moves and waits cost up to 0.6 of a move less, the more the nearer) or auto (lanes, but none with LNS "
                 "while agents number at most a quarter of the free cells and at most 2,000, and ring with LNS in the "
                 "rotation model on maps at most 36 cells across)")
      ->check(CLI::IsMember({"auto", "none", "lanes", "ring"}))
      ->capture_default_str();
  app.add_option("--stay-cost", lifelong.planner.stay_cost,
                 "experiment lifelong: what a wait or a quarter turn costs in the guidance, 1-6 (0: 3 with --lns "
                 "on lanes in the rotation model, else 1)")
      ->check(CLI::Range(0, planner_core::GuidedDistances::kMaxStayCost))
      ->capture_default_str();
  app.add_option("--actions", lifelong.actions,
                 "move4 (up, down, left, right, wait) or rotate (the league's 2023 model: forward, turn clockwise, "
                 "turn counter-clockwise, wait); for instance files as ctsfleet-solve --actions (headings from "
                 "the instances, east when absent; the CSV's solver gets '+rotate'), and for experiment lifelong "
                 "(agents start facing east)")
      ->check(CLI::IsMember({"move4", "rotate"}))
      ->capture_default_str();
  std::string turns = "both";
  app.add_option("--turns", turns, "with --actions rotate, as ctsfleet-solve --turns: planned, added or both")
      ->check(CLI::IsMember({"both", "planned", "added"}))
      ->capture_default_str();
  app.add_option("--rollouts", lifelong.planner.rollouts,
                 "experiment lifelong: PIBT runs tried --rollout-steps ahead each step, the best first step taken "
                 "(1: plain PIBT); they stop at half the step's budget")
      ->check(ctsfleet::count_in(1, 1'000'000))
      ->capture_default_str();
  app.add_option("--rollout-steps", lifelong.planner.rollout_steps,
                 "experiment lifelong: how far ahead each rollout runs, in steps, and with --lns the window LNS "
                 "improves; 0: without --lns 3, or 8 in the rotation model where agents fill more than 90% of the free "
                 "cells; with it 8, or 16 in the rotation model while agents are at most a quarter of the free cells "
                 "and at most 4,000")
      ->check(ctsfleet::count_in(0, 1000))
      ->capture_default_str();
  bool lns = false;
  app.add_flag("--lns,!--no-lns", lns,
               "experiment lifelong: improve the best rollout's steps by Large Neighbourhood Search (space-time "
               "A* for 8 agents around a late one at a time) with half of the rollouts' time; --no-lns: rollouts "
               "only, the cheaper planner (default: the lifelong settings' lns, auto: on in the rotation model "
               "unless agents fill more than 90% of the free cells)");
  std::string lifelong_config;
  app.add_option("--lifelong-config", lifelong_config,
                 "experiment lifelong: the planner's settings (YAML, config/lifelong.yaml documents every key); "
                 "each option below given on the command line overrides its key")
      ->check(CLI::ExistingFile);
  app.add_option("--lns-rounds", lifelong.planner.lns_rounds,
                 "experiment lifelong: count the work instead of timing it: every step all --rollouts "
                 "rollouts and, with LNS, exactly N LNS rounds, whatever the clock, and steps taken however long they took: "
                 "the same run on every run and machine (timed steps of 1 s do about 24,000 rounds here at 400 agents)")
      ->check(ctsfleet::count_in(1, 1'000'000'000));
  app.add_option("--keep-window", lifelong.planner.keep_window,
                 "experiment lifelong, with --lns: start each step's LNS from the last step's improved window, one "
                 "step on (agents with a new errand planned again), when it costs less than the best rollout; on, "
                 "off or auto (on in the rotation model, unless agents are at most a quarter of the free cells but "
                 "more than 4,000)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  app.add_option("--keep-equal-cost", lifelong.planner.keep_equal_cost,
                 "experiment lifelong, with --lns: an LNS round whose new paths cost the same as the old keeps them "
                 "(the search wanders over plateaus); on, off or auto (on in the rotation model while agents are at "
                 "most a quarter of the free cells and at most 4,000, where the window is 16 steps by default)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  app.add_option("--neighbourhoods", lifelong.planner.neighbourhoods,
                 "experiment lifelong, with --lns: how an LNS round picks the 8 agents it plans again: nearest (a "
                 "late agent and those standing nearest it), adaptive (each round one of nearest, those passing a "
                 "crossing in the window, or any at random, weighted by their recent gains), or auto (adaptive in "
                 "the rotation model wherever --keep-window auto keeps the window)")
      ->check(CLI::IsMember({"auto", "nearest", "adaptive"}))
      ->capture_default_str();
  app.add_option("--hold-plans", lifelong.planner.hold_plans,
                 "experiment lifelong, rotation model: when the cells PIBT chose are carried out as a plan, turning "
                 "and moving agents while the others wait, until every agent stands on its own: never, half (in "
                 "every second rollout; the look-ahead picks), always, or auto (always when agents fill more than "
                 "90% of the free cells, else half)")
      ->check(CLI::IsMember({"auto", "never", "half", "always"}))
      ->capture_default_str();
  app.add_flag("--keep-targets,!--no-keep-targets", lifelong.planner.keep_targets,
               "experiment lifelong, rotation model: an agent short of the cell PIBT chose for it (turned towards "
               "it, or queued behind one that turned) decides first and tries that cell first")
      ->capture_default_str();
  app.add_option("--park-dead-ends", lifelong.planner.park_dead_ends,
                 "experiment lifelong: park agents whose errand is a dead end (a cell with one neighbour): they "
                 "only move to make way, and give that errand up; on, off or auto (on when agents fill more than "
                 "90% of the free cells)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  app.add_option("--traffic-costs", lifelong.planner.traffic_costs,
                 "experiment lifelong: cells crowded lately cost more in the guidance (taken more than 60% of the "
                 "last 50 steps or so: 0.6 of a move more per 10% above, at most 2 moves; counted every 10 steps); "
                 "on, off or auto (on with the ring road)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  app.add_option("--guide-paths", lifelong.planner.guide_paths,
                 "experiment lifelong or league: each agent follows a path round the others' flows (1 a move, "
                 "plus 1 for each agent whose path takes the move the other way, 0.1 for each whose path crosses "
                 "the cell, 4 times how often the cell was taken lately); PIBT tries its next cell first and "
                 "window LNS counts a move off it as a move more; on, off or auto (off)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  app.add_flag("--league-output", lifelong.league_output,
               "experiment lifelong or league: also write each run as the league's output file, "
               "<out-dir>/<problem>.lorr.json (league: the 2026 format) "
               "(for PlanViz; about 4 bytes per agent and step)");
  ctsfleet_bench::MapfScaleSettings mapf_scale;
  app.add_option("--scale-suite", mapf_scale.suite,
                 "experiment mapf-scale: the plain MAPF scale suite folder (default: the installed benchmarks/mapf-scale)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--benchmarks", experiment_settings.benchmarks,
                 "experiment: benchmark suites folder (default: the installed benchmarks/)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--out-dir", experiment_settings.out_dir, "experiment: where tables, CSV and plots go")
      ->check(ctsfleet::writable_folder())
      ->capture_default_str();
  app.add_flag("--full", full, "experiment: every instance of the suites and 60 s per run");
  app.add_option("--solver", solvers, "solver variants to compare (repeatable)")
      ->check(CLI::IsMember(solver_names()))
      ->capture_default_str();
  app.add_option("-t,--time", seconds, "time limit per instance in seconds")
      ->check(ctsfleet::positive_seconds(kMaxTimeLimitS))
      ->capture_default_str();
  app.add_option("--sample", sample, "at most K instances per (map, N, M) setting (0 = all)")
      ->check(ctsfleet::count_in(0, 1'000'000))
      ->capture_default_str();
  app.add_option("-j,--threads", threads, "instances run in parallel")->check(ctsfleet::count_in(1, 256))->capture_default_str();
  app.add_option("--csv", csv_path, "CSV file to write, one row per (instance, solver)")
      ->check(ctsfleet::writable_file())
      ->capture_default_str();
  app.add_flag("--json", json, "print the summary tables as one JSON object");
  app.add_option("--seed", config.seed, "random seed")->capture_default_str();
  app.add_flag("--no-fallback{false}", config.complete_fallback,
               "CTS solvers: no complete search when their own method runs out (the --experiment runs never use it)");
  add_solver_part_options(app, config);
  int64_t iterations = 0;
  add_iterations_option(app, iterations);
  return program.main(argc, argv, [&] {
    if (!experiment.empty()) {
      if (std::string unwritable = ctsfleet::writable_folder()(experiment_settings.out_dir); !unwritable.empty()) {
        throw InputError("--out-dir: " + unwritable);
      }
      if (experiment_settings.benchmarks.empty()) experiment_settings.benchmarks = ctsfleet::data_path("benchmarks").string();
      if (mapf_scale.suite.empty()) mapf_scale.suite = ctsfleet::data_path("benchmarks/mapf-scale").string();
      experiment_settings.seconds = app.count("--time") ? seconds : (full ? 60 : 10);
      experiment_settings.threads = threads;
      experiment_settings.seed = config.seed;
      experiment_settings.iterations = iterations;
      if (full) {
        experiment_settings.dense_per_setting = experiment_settings.sparse_per_setting = 0;
        experiment_settings.scale_per_setting = 0;
      } else if (sample > 0) {
        experiment_settings.dense_per_setting = experiment_settings.sparse_per_setting = sample;
        experiment_settings.scale_per_setting = sample;
      }
      if (experiment == "lifelong" || experiment == "league") {
        // The settings file, then each option given on the command line over its key.
        planner_core::LifelongConfig& planner = lifelong.planner;
        const planner_core::LifelongConfig given = planner;
        if (!lifelong_config.empty()) planner = planner_core::load_lifelong_config(lifelong_config);
        const auto over = [&](const char* option, auto member) {
          if (app.count(option) > 0) planner.*member = given.*member;
        };
        using Config = planner_core::LifelongConfig;
        over("--guidance", &Config::guidance);
        over("--stay-cost", &Config::stay_cost);
        over("--rollouts", &Config::rollouts);
        over("--rollout-steps", &Config::rollout_steps);
        over("--lns-rounds", &Config::lns_rounds);
        over("--keep-window", &Config::keep_window);
        over("--keep-equal-cost", &Config::keep_equal_cost);
        over("--neighbourhoods", &Config::neighbourhoods);
        over("--hold-plans", &Config::hold_plans);
        over("--keep-targets", &Config::keep_targets);
        over("--park-dead-ends", &Config::park_dead_ends);
        over("--traffic-costs", &Config::traffic_costs);
        over("--guide-paths", &Config::guide_paths);
        if (app.count("--lns") + app.count("--no-lns") > 0) planner.lns = lns ? "on" : "off";
        planner_core::check_lifelong_config(planner, "the lifelong settings");
        lifelong.benchmarks = experiment_settings.benchmarks;
        lifelong.out_dir = experiment_settings.out_dir;
        lifelong.seed = config.seed;
        lifelong.interrupt = &ctsfleet::stop_requested();
        if (experiment == "league") {
          if (league.plan_period_ms % league.tick_ms != 0) {
            throw InputError("--plan-period-ms: " + std::to_string(league.plan_period_ms) +
                             " is not a whole number of ticks of --tick-ms " + std::to_string(league.tick_ms));
          }
          return ctsfleet_bench::run_league_experiment(lifelong, league);
        }
        return ctsfleet_bench::run_lifelong_experiment(lifelong);
      }
      if (experiment == "mapf-scale") {
        mapf_scale.out_dir = experiment_settings.out_dir;
        mapf_scale.seconds = experiment_settings.seconds;
        mapf_scale.seed = config.seed;
        mapf_scale.iterations = iterations;
        if (app.count("--solver")) mapf_scale.solvers = solvers;
        return ctsfleet_bench::run_mapf_scale(mapf_scale);
      }
      return ctsfleet_bench::run_experiments(experiment, experiment_settings);
    }
    if (inputs.empty()) throw InputError("give instance files or folders, or --experiment");
    const std::vector<std::string> files = sample_per_setting(collect_instances(inputs), sample);
    if (files.empty()) throw InputError("no instances (.yaml) found in the inputs");
    std::ofstream csv(csv_path);
    if (!csv) throw InputError("--csv: " + csv_path + ": cannot write");
    nlohmann::json summary_json = nlohmann::json::object();
    csv << csv_header() << "\n";
    int errors = 0;
    const ActionModel actions = parse_action_model(lifelong.actions, "--actions");
    config.plan_with_turns = turns != "added";
    config.add_turns = turns != "planned";
    for (const std::string& solver : solvers) {
      if (ctsfleet::stop_requested().load()) break;
      config.solver = solver;
      const std::string name = solver + (actions == ActionModel::kRotate ? "+rotate" : "") +
                               (actions == ActionModel::kRotate && turns != "both" ? "-" + turns : "");
      std::fprintf(stderr, "%s: %zu instances, %.1f s each, %d threads\n", name.c_str(), files.size(), seconds,
                   threads);
      const auto rows = run_benchmark(
          files, config, seconds, iterations, threads,
          [&](const BenchmarkRow&, int done) { draw_progress(done, static_cast<int>(files.size())); }, actions,
          &ctsfleet::stop_requested());
      for (const BenchmarkRow& row : rows) {
        csv << to_csv(row, name) << "\n";
        if (!row.error.empty()) {
          ++errors;
          std::fprintf(stderr, "%s: %s\n", row.file.c_str(), row.error.c_str());
        }
      }
      if (json) {
        nlohmann::json& settings = summary_json[name] = nlohmann::json::array();
        for (const BenchmarkSummary& s : summarise(rows)) {
          settings.push_back({{"map", s.map}, {"agents", s.agents}, {"tasks", s.tasks}, {"instances", s.instances},
                              {"solved", s.solved}, {"median_first_ms", s.median_first_ms},
                              {"mean_flowtime", s.mean_flowtime}, {"mean_ratio", s.mean_ratio}});
        }
        continue;
      }
      std::printf("\n%s (time limit %.1f s)\n", name.c_str(), seconds);
      std::printf("| map | N | M | instances | success | median first (ms) | mean flowtime | mean flowtime/LB |\n");
      std::printf("|---|---|---|---|---|---|---|---|\n");
      for (const BenchmarkSummary& s : summarise(rows)) {
        std::printf("| %s | %d | %d | %d | %.0f%% | %.1f | %.1f | %.3f |\n", s.map.c_str(), s.agents, s.tasks,
                    s.instances, 100.0 * s.solved / s.instances, s.median_first_ms, s.mean_flowtime, s.mean_ratio);
      }
    }
    if (json) {
      std::printf("%s\n", nlohmann::json{{"time_limit_s", seconds}, {"csv", csv_path}, {"solvers", summary_json}}.dump().c_str());
    } else {
      std::printf("\nrows written to %s\n", csv_path.c_str());
    }
    // Ctrl-C or SIGTERM: the solve in hand stopped, the instances left were not run (rows so marked).
    if (ctsfleet::stop_requested().load()) return ctsfleet::kExitInterrupted;
    return errors > 0 ? 1 : 0;
  });
}
