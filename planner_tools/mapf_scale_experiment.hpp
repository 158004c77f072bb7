// The plain MAPF scale experiment (benchmarks/mapf-scale: 1,000 to 10,000 agents): each instance
// solved by `ctsfleet-solve` in a process of its own, one at a time, so that its peak memory and
// wall time are its own. Prints and writes a table of first-plan time (from the start of the
// process), preprocessing time, final sum of costs / lower bound, wall time against the limit and
// peak memory.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ctsfleet_bench {

struct MapfScaleSettings {
  std::string suite;  // default: the data folder's benchmarks/mapf-scale
  std::string out_dir = "docs/results";
  std::vector<std::string> solvers = {"lacam-star"};
  double seconds = 10;
  unsigned seed = 0;
  int64_t iterations = 0;  // ctsfleet-solve --iterations (0 = the time limit alone)
};

// Returns the process exit code (2 when the suite or ctsfleet-solve cannot be found).
int run_mapf_scale(const MapfScaleSettings& settings);

}  // namespace ctsfleet_bench
