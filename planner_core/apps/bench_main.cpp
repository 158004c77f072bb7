// ctsfleet-bench: runs solvers over instance folders or lists, writes a CSV and prints a summary
// per (map, N, M) setting.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "mapf_scale_experiment.hpp"
#include "paper_experiments.hpp"
#include "planner_core/benchmark_runner.hpp"

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

void draw_progress(int done, int total) {
  const int width = 40;
  const int filled = total > 0 ? width * done / total : width;
  std::fprintf(stderr, "\r[%s%s] %d/%d", std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(),
               done, total);
  if (done == total) std::fprintf(stderr, "\n");
}

}  // namespace

int main(int argc, char** argv) {
  using namespace planner_core;
  CLI::App app{"ctsfleet-bench: run solvers over benchmark instances and summarise per (map, N, M)"};
  std::vector<std::string> inputs, solvers{"cts-pibt"};
  std::string csv_path = "bench.csv";
  double seconds = 10;
  int sample = 0;
  int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  SolverConfig config;
  std::string experiment;
  bool full = false;
  ctsfleet_bench::ExperimentSettings experiment_settings;
  app.add_option("inputs", inputs, "instance files, folders (searched for .yaml) or .txt lists");
  app.add_option("--experiment", experiment,
                 "reproduce the CTS-PLL paper's experiments side by side: dense, sparse, scale or all")
      ->check(CLI::IsMember({"dense", "sparse", "scale", "all", "mapf-scale"}));
  ctsfleet_bench::MapfScaleSettings mapf_scale;
  app.add_option("--scale-suite", mapf_scale.suite, "experiment mapf-scale: the plain MAPF scale suite folder")
      ->capture_default_str();
  app.add_option("--benchmarks", experiment_settings.benchmarks, "experiment: benchmark suites folder")
      ->capture_default_str();
  app.add_option("--out-dir", experiment_settings.out_dir, "experiment: where tables, CSV and plots go")
      ->capture_default_str();
  app.add_flag("--full", full, "experiment: every instance of the suites and 60 s per run");
  app.add_option("--solver", solvers, "solver variants to compare (repeatable)")
      ->check(CLI::IsMember(solver_names()))
      ->capture_default_str();
  app.add_option("-t,--time", seconds, "time limit per instance in seconds")->capture_default_str();
  app.add_option("--sample", sample, "at most K instances per (map, N, M) setting (0 = all)")->capture_default_str();
  app.add_option("-j,--threads", threads, "instances run in parallel")->capture_default_str();
  app.add_option("--csv", csv_path, "CSV file to write, one row per (instance, solver)")->capture_default_str();
  app.add_option("--seed", config.seed, "random seed")->capture_default_str();
  app.add_flag("--swap", config.pibt.swap, "Extended-PIBT with LaCAM3's swap operation (head-on meetings in corridors)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;  // --help is 0; every command-line error is an input error, 2
  }

  if (!is_valid_time_limit(seconds)) {
    std::cerr << "error: -t/--time: the time limit must be a number of seconds in (0, 1e6], not " << seconds << "\n";
    return 2;
  }
  if (!experiment.empty()) {
    experiment_settings.seconds = app.count("--time") ? seconds : (full ? 60 : 10);
    experiment_settings.threads = threads;
    experiment_settings.seed = config.seed;
    if (full) {
      experiment_settings.dense_per_setting = experiment_settings.sparse_per_setting = 0;
      experiment_settings.scale_per_setting = 0;
    } else if (sample > 0) {
      experiment_settings.dense_per_setting = experiment_settings.sparse_per_setting = sample;
      experiment_settings.scale_per_setting = sample;
    }
    if (experiment == "mapf-scale") {
      mapf_scale.out_dir = experiment_settings.out_dir;
      mapf_scale.seconds = experiment_settings.seconds;
      mapf_scale.seed = config.seed;
      if (app.count("--solver")) mapf_scale.solvers = solvers;
      return ctsfleet_bench::run_mapf_scale(mapf_scale);
    }
    return ctsfleet_bench::run_experiments(experiment, experiment_settings);
  }
  if (inputs.empty()) {
    std::cerr << "error: give instance files or folders, or --experiment\n";
    return 2;
  }

  const std::vector<std::string> files = sample_per_setting(collect_instances(inputs), sample);
  if (files.empty()) {
    std::cerr << "error: no instances found in the inputs\n";
    return 2;
  }
  std::ofstream csv(csv_path);
  if (!csv) {
    std::cerr << "error: " << csv_path << ": cannot write\n";
    return 2;
  }
  csv << csv_header() << "\n";
  int errors = 0;
  for (const std::string& solver : solvers) {
    config.solver = solver;
    std::fprintf(stderr, "%s: %zu instances, %.1f s each, %d threads\n", solver.c_str(), files.size(), seconds,
                 threads);
    const auto rows = run_benchmark(files, config, seconds, threads, [&](const BenchmarkRow&, int done) {
      draw_progress(done, static_cast<int>(files.size()));
    });
    for (const BenchmarkRow& row : rows) {
      csv << to_csv(row, solver) << "\n";
      if (!row.error.empty()) {
        ++errors;
        std::fprintf(stderr, "%s: %s\n", row.file.c_str(), row.error.c_str());
      }
    }
    std::printf("\n%s (time limit %.1f s)\n", solver.c_str(), seconds);
    std::printf("| map | N | M | instances | success | median first (ms) | mean flowtime | mean flowtime/LB |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    for (const BenchmarkSummary& s : summarise(rows)) {
      std::printf("| %s | %d | %d | %d | %.0f%% | %.1f | %.1f | %.3f |\n", s.map.c_str(), s.agents, s.tasks,
                  s.instances, 100.0 * s.solved / s.instances, s.median_first_ms, s.mean_flowtime, s.mean_ratio);
    }
  }
  std::printf("\nrows written to %s\n", csv_path.c_str());
  return errors > 0 ? 1 : 0;
}
