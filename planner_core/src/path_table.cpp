#include "planner_core/path_table.hpp"

#include <algorithm>

namespace planner_core {

PathTable::PathTable(int vertex_count)
    : by_vertex_(vertex_count), resting_agent_(vertex_count, kFree), resting_from_(vertex_count, 0) {}

void PathTable::add(int agent, const Path& path, bool rests) {
  for (int t = 0; t < static_cast<int>(path.size()); ++t) {
    std::vector<int>& slots = by_vertex_[path[t]];
    if (static_cast<int>(slots.size()) <= t) slots.resize(t + 1, kFree);
    slots[t] = agent;
  }
  if (!rests) return;
  resting_agent_[path.back()] = agent;
  resting_from_[path.back()] = static_cast<int>(path.size()) - 1;
}

void PathTable::remove(int agent, const Path& path) {
  for (int t = 0; t < static_cast<int>(path.size()); ++t) {
    std::vector<int>& slots = by_vertex_[path[t]];
    if (t < static_cast<int>(slots.size()) && slots[t] == agent) slots[t] = kFree;
    while (!slots.empty() && slots.back() == kFree) slots.pop_back();
  }
  if (resting_agent_[path.back()] == agent) resting_agent_[path.back()] = kFree;
}

int PathTable::occupant(Vertex v, int t) const {
  const std::vector<int>& slots = by_vertex_[v];
  if (t < static_cast<int>(slots.size()) && slots[t] != kFree) return slots[t];
  if (resting_agent_[v] != kFree && t >= resting_from_[v]) return resting_agent_[v];
  return kFree;
}

void PathTable::safe_intervals(Vertex v, std::vector<Interval>& out) const {
  out.clear();
  const std::vector<int>& slots = by_vertex_[v];
  const int end = resting_agent_[v] != kFree ? resting_from_[v] : kForever;  // free before a resting agent arrives
  int first = 0;
  for (int t = 0; t < static_cast<int>(slots.size()) && t < end; ++t) {
    if (slots[t] == kFree) continue;
    if (t > first) out.push_back({first, t - 1});
    first = t + 1;
  }
  if (first < end) out.push_back({first, end == kForever ? kForever : end - 1});
}

void PathTable::agents_at(Vertex v, std::vector<int>& out) const {
  for (int agent : by_vertex_[v]) {
    if (agent != kFree && std::find(out.begin(), out.end(), agent) == out.end()) out.push_back(agent);
  }
}

}  // namespace planner_core
