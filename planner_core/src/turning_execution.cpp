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
  // waiting[cell]: the agent facing `cell` whose passage there comes right after its occupant's.
  std::vector<int> waiting(graph.vertex_count(), -1);
  std::vector<int> ready;           // agents that may step forward now
  std::vector<char> colour(n);      // cycle search: 0 not seen, 1 on the path followed, 2 done
  std::vector<int> path;
  int moving = 0;
  std::vector<int> active;  // the agents with moves left, the only ones a step looks at
  for (int a = 0; a < n; ++a) {
    if (routes[a].cells.size() > 1) active.push_back(a);
  }
  moving = static_cast<int>(active.size());
  const auto next_passage = [&](int a) { return routes[a].passage[routes[a].at + 1]; };
  const auto next_cell = [&](int a) { return routes[a].cells[routes[a].at + 1]; };
  // Steps `a` forward; whoever waited for the cell it leaves may follow in the same step.
  const auto step_forward = [&](int a, Config& cells) {
    Route& route = routes[a];
    const Vertex left = route.cells[route.at];
    ++passed[left];
    ++route.at;
    cells[a] = route.cells[route.at];
    if (route.at + 1 == route.cells.size()) --moving;
    acted[a] = 1;
    const int follower = waiting[left];
    if (follower >= 0 && !acted[follower] && next_passage(follower) == passed[left]) ready.push_back(follower);
  };
  // The agent that `a` waits for: the one standing on a's next cell, which has not acted yet.
  const auto waits_for = [&](int a) {
    if (acted[a] || routes[a].at + 1 >= routes[a].cells.size()) return -1;
    const Vertex next = next_cell(a);
    return waiting[next] == a && occupant[next] >= 0 && !acted[occupant[next]] ? occupant[next] : -1;
  };
  while (moving > 0) {
    Config cells = out.cells.back();
    for (int a = 0; a < n; ++a) occupant[cells[a]] = a;
    std::fill(acted.begin(), acted.end(), 0);
    // Turns need nobody; a move waits until the passages before it have left the cell.
    for (int a : active) {
      Route& route = routes[a];
      const Vertex next = next_cell(a);
      const int towards = heading_towards(graph, route.cells[route.at], next);
      if (headings[a] != towards) {
        headings[a] = turns_between(headings[a], towards) == 2 || towards == turned_clockwise(headings[a])
                          ? turned_clockwise(headings[a])
                          : turned_counter_clockwise(headings[a]);
        acted[a] = 1;
      } else if (passed[next] == next_passage(a)) {
        ready.push_back(a);
      } else if (passed[next] + 1 == next_passage(a)) {
        waiting[next] = a;
      }
    }
    bool any = std::any_of(active.begin(), active.end(), [&](int a) { return acted[a] != 0; });
    for (bool cycle_moved = true; cycle_moved;) {
      while (!ready.empty()) {
        const int a = ready.back();
        ready.pop_back();
        step_forward(a, cells);
        any = true;
      }
      // Agents that wait on each other round a cycle move together, each into the cell the next
      // leaves. Each agent waits for one other at most: follow the links, each agent once.
      cycle_moved = false;
      for (int a : active) colour[a] = 0;
      for (int start : active) {
        if (!allow_cycles) break;
        path.clear();
        int a = start;
        while (a >= 0 && colour[a] == 0) {
          colour[a] = 1;
          path.push_back(a);
          a = waits_for(a);
        }
        if (a >= 0 && colour[a] == 1) {  // back on the path: a cycle from a on
          const auto first = std::find(path.begin(), path.end(), a);
          if (path.end() - first >= 3) {
            // All of them act now: none is released as another's follower and moved twice.
            for (auto member = first; member != path.end(); ++member) acted[*member] = 1;
            for (auto member = first; member != path.end(); ++member) step_forward(*member, cells);
            cycle_moved = any = true;
          }
        }
        for (int member : path) colour[member] = 2;
      }
    }
    for (const Config& before = out.cells.back(); Vertex v : before) occupant[v] = -1;
    for (int a : active) {
      if (routes[a].at + 1 < routes[a].cells.size()) waiting[next_cell(a)] = -1;
      waiting[routes[a].cells[routes[a].at]] = -1;
    }
    std::erase_if(active, [&](int a) { return routes[a].at + 1 >= routes[a].cells.size(); });
    if (!any) return std::nullopt;  // everyone waits on someone: the plan had a cycle
    out.cells.push_back(std::move(cells));
    out.headings.push_back(headings);
  }
  return out;
}

}  // namespace planner_core
