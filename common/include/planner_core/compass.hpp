// Headings on the grid, shared by the planner, the coordinator and the robot agents: 0 east (next
// column, +x), 1 south (next row, +y), 2 west, 3 north, as the League of Robot Runners numbers
// them; a clockwise turn adds one (rows grow downwards, so clockwise on screen and on a toio mat).
#pragma once

#include <cmath>
#include <numbers>

#include "planner_core/cell.hpp"

namespace planner_core {

// The heading that faces neighbour `to` from `from`; -1 when they are not neighbours.
inline int heading_between(Cell from, Cell to) {
  const int dx = to.x - from.x, dy = to.y - from.y;
  if (dx == 1 && dy == 0) return 0;
  if (dx == 0 && dy == 1) return 1;
  if (dx == -1 && dy == 0) return 2;
  if (dx == 0 && dy == -1) return 3;
  return -1;
}

// The heading nearest to `theta` (radians, clockwise from the grid's +x axis, any turn count).
inline int nearest_heading(double theta) {
  const long quarters = std::lround(theta / (std::numbers::pi / 2));
  return static_cast<int>(((quarters % 4) + 4) % 4);
}

// The quarter turns from one heading to another: 0, 1 (either way) or 2.
inline int quarter_turns(int from, int to) {
  const int difference = ((to - from) % 4 + 4) % 4;
  return difference == 3 ? 1 : difference;
}

// The angle of a heading, radians clockwise from the grid's +x axis.
inline double heading_angle(int heading) { return heading * (std::numbers::pi / 2); }

}  // namespace planner_core
