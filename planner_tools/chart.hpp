// Charts drawn by ctsfleet-plot (scripts/ctsfleet-plot, matplotlib), installed beside the programs.
#pragma once

#include <string>
#include <vector>

namespace ctsfleet_bench {

// Runs ctsfleet-plot with `arguments` (chart, CSV, -o OUT, ...). A missing plotter or matplotlib
// only costs the picture (the tables and CSV are the results), so it is a warning on stderr.
void draw_chart(const std::vector<std::string>& arguments);

}  // namespace ctsfleet_bench
