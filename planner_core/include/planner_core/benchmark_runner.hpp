// Benchmark runner: one solver over many instance files in parallel threads, one row per
// instance, and a summary per setting (map, N, M).
#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "planner_core/solver.hpp"

namespace planner_core {

struct BenchmarkRow {
  std::string file;
  std::string map;
  int agents = 0;
  int tasks = 0;
  bool solved = false;
  double comp_time_ms = 0;
  double first_solution_ms = -1;
  int64_t flowtime = 0;
  int makespan = 0;
  int64_t lower_bound = 0;
  double ratio = 0;  // flowtime / lower bound, 0 when not solved
  int sequences = 0;
  std::string error;  // input problem or validation failure
};

struct BenchmarkSummary {
  std::string map;
  int agents = 0;
  int tasks = 0;
  int instances = 0;
  int solved = 0;
  double median_first_ms = -1;
  double mean_ratio = 0;
  double mean_flowtime = 0;
};

// Keeps at most `per_setting` files of each (map, N, M) setting, in name order (0 = all).
std::vector<std::string> sample_per_setting(std::vector<std::string> files, int per_setting);

// Runs `config` with `seconds` per instance (and `iterations`, as ctsfleet-solve --iterations,
// when > 0) on `threads` threads. `on_row` is called (from the worker threads, serialised) after
// each instance.
std::vector<BenchmarkRow> run_benchmark(const std::vector<std::string>& files, const SolverConfig& config,
                                        double seconds, int64_t iterations, int threads,
                                        const std::function<void(const BenchmarkRow&, int done)>& on_row = {},
                                        ActionModel actions = ActionModel::kMove4,
                                        const std::atomic<bool>* interrupt = nullptr);

std::vector<BenchmarkSummary> summarise(const std::vector<BenchmarkRow>& rows);
std::string csv_header();
std::string to_csv(const BenchmarkRow& row, const std::string& solver);

// One CSV field per RFC 4180: quoted (with quotes doubled) when it holds a comma, quote or line break.
std::string csv_field(const std::string& text);

}  // namespace planner_core
