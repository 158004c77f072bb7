#include "planner_core/step_faults.hpp"

#include <algorithm>
#include <unordered_map>

namespace planner_core {

StepFault find_step_fault(const Graph& graph, const Config& positions, const Config& next) {
  if (next.size() != positions.size()) {
    return {-1, -1, "a step for " + std::to_string(next.size()) + " agents, not " + std::to_string(positions.size())};
  }
  std::vector<int> entering(graph.vertex_count(), -1);
  for (size_t a = 0; a < next.size(); ++a) {
    const int agent = static_cast<int>(a);
    const Vertex v = next[a];
    if (v < 0 || v >= graph.vertex_count()) return {agent, -1, "agent " + std::to_string(a) + " to no cell"};
    if (v != positions[a] && !graph.adjacent(positions[a], v)) {
      return {agent, -1,
              "agent " + std::to_string(a) + " jumps from " + to_string(graph.cell_of(positions[a])) + " to " +
                  to_string(graph.cell_of(v))};
    }
    if (entering[v] != -1) {
      return {entering[v], agent,
              "agents " + std::to_string(entering[v]) + " and " + std::to_string(a) + " both on " +
                  to_string(graph.cell_of(v))};
    }
    entering[v] = agent;
  }
  std::vector<int> standing(graph.vertex_count(), -1);
  for (size_t a = 0; a < positions.size(); ++a) standing[positions[a]] = static_cast<int>(a);
  for (size_t a = 0; a < next.size(); ++a) {
    const int other = standing[next[a]];
    if (other != -1 && other != static_cast<int>(a) && next[other] == positions[a]) {
      return {static_cast<int>(a), other, "agents " + std::to_string(a) + " and " + std::to_string(other) + " swap"};
    }
  }
  return {};
}

std::string invalid_step(const Graph& graph, const Config& positions, const Config& next) {
  return find_step_fault(graph, positions, next).what;
}

StepFault find_pose_fault(const Graph& graph, ActionModel model, const Poses& now, const Poses& next) {
  if (model == ActionModel::kRotate) {
    if (next.headings.size() != next.cells.size() || now.headings.size() != now.cells.size()) {
      return {-1, -1, "a step without a heading for every agent"};
    }
    for (size_t a = 0; a < next.cells.size() && a < now.cells.size(); ++a) {
      const int agent = static_cast<int>(a);
      const int from = now.headings[a];
      const int to = next.headings[a];
      if (to < 0 || to >= kHeadings) return {agent, -1, "agent " + std::to_string(a) + " faces no heading"};
      if (next.cells[a] == now.cells[a]) {
        if (to == (from + 2) % kHeadings) return {agent, -1, "agent " + std::to_string(a) + " turns half round in one step"};
        continue;
      }
      if (to != from || next.cells[a] != ahead(graph, now.cells[a], from)) {
        return {agent, -1,
                "agent " + std::to_string(a) + " facing " + heading_letter(from) + " moves from " +
                    to_string(graph.cell_of(now.cells[a])) + " other than forward"};
      }
    }
  }
  return find_step_fault(graph, now.cells, next.cells);
}

StepFault find_rotation(const Config& positions, const Config& next) {
  std::unordered_map<Vertex, int> standing;  // cell -> agent there now
  for (size_t a = 0; a < positions.size(); ++a) standing[positions[a]] = static_cast<int>(a);
  // Follow each chain of agents moving into a cell another one leaves; a chain that comes back to
  // one of its own agents holds a cycle. Each agent is walked through once.
  std::vector<int> chain_of(positions.size(), -1);
  for (size_t first = 0; first < positions.size(); ++first) {
    std::vector<int> chain;
    int agent = static_cast<int>(first);
    while (agent != -1 && chain_of[agent] == -1 && next[agent] != positions[agent]) {
      chain_of[agent] = static_cast<int>(first);
      chain.push_back(agent);
      const auto there = standing.find(next[agent]);
      agent = there == standing.end() ? -1 : there->second;
    }
    if (agent != -1 && chain_of[agent] == static_cast<int>(first)) {
      const auto start = std::find(chain.begin(), chain.end(), agent);
      const size_t length = static_cast<size_t>(chain.end() - start);
      if (length < 2) continue;  // an agent into its own cell does not move
      return {*start, *(start + 1),
              "agents " + std::to_string(*start) + ", " + std::to_string(*(start + 1)) + (length > 2 ? ", ..." : "") +
                  " move in a cycle of " + std::to_string(length)};
    }
  }
  return {};
}

}  // namespace planner_core
