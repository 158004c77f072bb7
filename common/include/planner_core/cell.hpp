// Cell: a grid cell (column x, row y). The one cell type of the planner, the coordinator and the
// robot agents; only the wire messages carry bare x, y integers.
#pragma once

#include <string>

namespace planner_core {

struct Cell {
  int x = 0;  // column
  int y = 0;  // row
  bool operator==(const Cell&) const = default;
};

std::string to_string(Cell cell);  // "(x,y)"

}  // namespace planner_core
