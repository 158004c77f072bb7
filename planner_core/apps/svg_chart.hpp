// SvgChart: a small line chart written as SVG (axes, ticks, one polyline per series, legend),
// enough for the benchmark report's plots.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace ctsfleet_bench {

struct Series {
  std::string name;
  std::string colour;
  std::vector<std::pair<double, double>> points;  // (x, y)
  bool steps = false;                             // draw as a step function (value holds until the next point)
};

std::string line_chart(const std::string& title, const std::string& x_label, const std::string& y_label,
                       const std::vector<Series>& series);

}  // namespace ctsfleet_bench
