// The CTS-PLL paper's experiments reproduced on benchmarks/ (dense, sparse, scale) with the project's own
// solvers side by side: dense (success and flowtime), sparse (success, time, flowtime), scale
// (time to first solution), and the plots. Writes markdown, CSV and SVG into an output folder.
#pragma once

#include <cstdint>
#include <string>

namespace ctsfleet_bench {

struct ExperimentSettings {
  std::string benchmarks;  // default: the data folder's benchmarks/
  std::string out_dir = "docs/results";
  double seconds = 10;        // per instance and solver (scale: 30)
  int dense_per_setting = 10;
  int sparse_per_setting = 3;
  int scale_per_setting = 10;
  int threads = 2;
  unsigned seed = 0;
  int64_t iterations = 0;  // > 0: a work budget per run (ctsfleet-solve --iterations): tables reproduce exactly
};

// `which` is dense, sparse, scale or all; returns the process exit code.
int run_experiments(const std::string& which, const ExperimentSettings& settings);

}  // namespace ctsfleet_bench
