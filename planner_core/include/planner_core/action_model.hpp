// How an agent may act in one step. In the four-move model (the one every CTS-MAPF solver here
// plans in) it moves to any free neighbouring cell or waits. In the rotation model (the League of
// Robot Runners' 2023 model, and how a toio cube or a warehouse drive unit moves) it also has a
// heading and each step does one of: forward (to the cell ahead), turn clockwise, turn
// counter-clockwise (both in place), wait. Headings are numbered as the league numbers them:
// 0 east (next column), 1 south (next row), 2 west, 3 north; a clockwise turn adds one.
#pragma once

#include <string>
#include <vector>

#include "planner_core/graph.hpp"

namespace planner_core {

enum class ActionModel {
  kMove4,   // up, down, left, right or wait
  kRotate,  // forward, turn clockwise, turn counter-clockwise or wait
};

// "move4" or "rotate"; throws InputError naming `what` otherwise.
ActionModel parse_action_model(const std::string& text, const std::string& what);
std::string to_string(ActionModel model);

using Headings = std::vector<int>;  // one heading (0..3) per agent
constexpr int kHeadings = 4;

// Where the agents stand and, in the rotation model, which way each faces (no headings in the
// four-move model).
struct Poses {
  Config cells;
  Headings headings;
  bool operator==(const Poses&) const = default;
};

inline int turned_clockwise(int heading) { return (heading + 1) % kHeadings; }
inline int turned_counter_clockwise(int heading) { return (heading + kHeadings - 1) % kHeadings; }

// The cell a step forward from `v` facing `heading` leads to; kNoVertex at a wall or the edge.
Vertex ahead(const Graph& graph, Vertex v, int heading);

// The heading that faces neighbour `to` from `from` (they must be neighbours).
int heading_towards(const Graph& graph, Vertex from, Vertex to);

// The league's letter for a heading: E S W N; and back (-1 for any other character).
char heading_letter(int heading);
int heading_of_letter(char letter);

// The turns from one heading to another: 0, 1 (a quarter either way) or 2.
inline int turns_between(int from, int to) {
  const int difference = (to - from + kHeadings) % kHeadings;
  return difference == 3 ? 1 : difference;
}

}  // namespace planner_core
