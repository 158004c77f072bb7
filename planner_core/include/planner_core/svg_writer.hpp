// SVG picture of an instance and its plan: map, starts (circles), goals (squares), tasks
// (diamonds, coloured by their agent when only one) and each agent's path in its own colour.
#pragma once

#include <string>

#include "planner_core/solution.hpp"

namespace planner_core {

std::string render_svg(const Instance& instance, const Solution& solution);
void write_svg(const std::string& path, const Instance& instance, const Solution& solution);

}  // namespace planner_core
