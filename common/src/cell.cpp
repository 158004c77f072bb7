#include "planner_core/cell.hpp"

namespace planner_core {

std::string to_string(Cell cell) {
  std::string text = "(";
  text.append(std::to_string(cell.x)).append(",").append(std::to_string(cell.y)).append(")");
  return text;
}

}  // namespace planner_core
