#include "planner_core/turning_execution.hpp"

#include <algorithm>

#include "planner_core/action_model.hpp"

namespace planner_core {

namespace {

// One agent's path without its waits, and which passage through each of its cells it is.
struct Route {
  std::vector<Vertex> cells;
  std::vector<int> passage;  // passage[k]: cells[k] is the passage-th agent to pass through it
  size_t at = 0;             // index in cells where the agent stands
};

}  // namespace

std::optional<TurningPlan> execute_with_turns(const Instance& instance, const Solution& plan, bool allow_cycles) {
  const Graph& graph = *instance.graph;
  const int n = instance.agent_count();
  std::vector<Route> routes(n);
  // Passages through each cell in the plan's order: by arrival time (none overlap in a valid plan).
  struct Arrival {
    int time;
    int agent;
    size_t index;
  };
  std::vector<std::vector<Arrival>> arrivals(graph.vertex_count());
  for (int a = 0; a < n; ++a) {
    for (size_t t = 0; t < plan.size(); ++t) {
      if (t > 0 && plan[t][a] == plan[t - 1][a]) continue;
      arrivals[plan[t][a]].push_back({static_cast<int>(t), a, routes[a].cells.size()});
      routes[a].cells.push_back(plan[t][a]);
    }
    routes[a].passage.assign(routes[a].cells.size(), 0);
  }
  for (auto& at_cell : arrivals) {
    std::sort(at_cell.begin(), at_cell.end(), [](const Arrival& x, const Arrival& y) { return x.time < y.time; });
    for (size_t k = 0; k < at_cell.size(); ++k) routes[at_cell[k].agent].passage[at_cell[k].index] = static_cast<int>(k);
  }
  std::vector<int> passed(graph.vertex_count(), 0);  // passages through the cell that have left it

  TurningPlan out;
  out.cells.push_back(plan.front());
  Headings headings(n);
  for (int a = 0; a < n; ++a) headings[a] = instance.start_heading(a);
  out.headings.push_back(headings);
  std::vector<char> acted(n);
  std::vector<int> occupant(graph.vertex_count(), -1);  // who stood on each cell before this step
  std::vector<int> chain;
  int moving = 0;
  for (const Route& route : routes) moving += route.cells.size() > 1 ? 1 : 0;
  const auto step_forward = [&](int a, Config& cells) {
    Route& route = routes[a];
    ++passed[route.cells[route.at]];
    ++route.at;
    cells[a] = route.cells[route.at];
    if (route.at + 1 == route.cells.size()) --moving;
    acted[a] = 1;
  };
  // The agent that `a`, facing its next cell, waits for: the one standing there, whose passage
  // comes just before a's and which has not acted yet; -1 when there is none such.
  const auto waits_for = [&](int a) {
    const Route& route = routes[a];
    if (acted[a] || route.at + 1 >= route.cells.size()) return -1;
    const Vertex next = route.cells[route.at + 1];
    if (headings[a] != heading_towards(graph, route.cells[route.at], next)) return -1;
    const int other = occupant[next];
    if (other < 0 || acted[other] || passed[next] + 1 != route.passage[route.at + 1]) return -1;
    return routes[other].passage[routes[other].at] == passed[next] ? other : -1;
  };
  while (moving > 0) {
    Config cells = out.cells.back();
    for (int a = 0; a < n; ++a) occupant[cells[a]] = a;
    std::fill(acted.begin(), acted.end(), 0);
    bool any = false;
    // Turns need nobody; a move waits until the passages before it have left the cell. An agent
    // leaving lets the one behind follow in the same step, so go round until nothing changes.
    for (bool changed = true; changed;) {
      changed = false;
      for (int a = 0; a < n; ++a) {
        Route& route = routes[a];
        if (acted[a] || route.at + 1 >= route.cells.size()) continue;
        const Vertex here = route.cells[route.at];
        const Vertex next = route.cells[route.at + 1];
        const int towards = heading_towards(graph, here, next);
        if (headings[a] != towards) {
          headings[a] = turns_between(headings[a], towards) == 2 || towards == turned_clockwise(headings[a])
                            ? turned_clockwise(headings[a])
                            : turned_counter_clockwise(headings[a]);
        } else if (passed[next] == route.passage[route.at + 1]) {
          step_forward(a, cells);
        } else {
          continue;
        }
        acted[a] = 1;
        changed = any = true;
      }
      // Agents that wait on each other round a cycle move together, each into the cell the next leaves.
      for (int a = 0; a < n && allow_cycles && !changed; ++a) {
        chain.assign(1, a);
        for (int next = waits_for(a); next >= 0 && next != a && chain.size() <= static_cast<size_t>(n);
             next = waits_for(next)) {
          chain.push_back(next);
        }
        if (chain.size() < 3 || waits_for(chain.back()) != a) continue;
        for (int member : chain) step_forward(member, cells);
        changed = any = true;
      }
    }
    for (const Config& before = out.cells.back(); Vertex v : before) occupant[v] = -1;
    if (!any) return std::nullopt;  // everyone waits on someone: the plan had a cycle
    out.cells.push_back(std::move(cells));
    out.headings.push_back(headings);
  }
  return out;
}

}  // namespace planner_core
