#include "planner_core/guide_paths.hpp"

#include <algorithm>
#include <queue>

#include "planner_core/action_model.hpp"
#include "planner_core/dist_table.hpp"

namespace planner_core {

GuidePaths::GuidePaths(const Graph& graph, GuidePathSettings settings)
    : graph_(graph),
      settings_(settings),
      flow_(static_cast<size_t>(graph.vertex_count()) * kHeadings, 0),
      load_(static_cast<size_t>(graph.vertex_count()), 0),
      crowd_(static_cast<size_t>(graph.vertex_count()), 0),
      g_(static_cast<size_t>(graph.vertex_count()), 0),
      parent_(static_cast<size_t>(graph.vertex_count()), kNoVertex),
      seen_(static_cast<size_t>(graph.vertex_count()), 0) {}

int GuidePaths::direction(Vertex u, Vertex v) const { return heading_towards(graph_, u, v); }

void GuidePaths::add_flows(const Guide& guide, int sign) {
  for (size_t i = guide.at; i < guide.cells.size(); ++i) {
    load_[guide.cells[i]] += sign;
    if (i + 1 < guide.cells.size()) {
      flow_[static_cast<size_t>(guide.cells[i]) * kHeadings + direction(guide.cells[i], guide.cells[i + 1])] += sign;
    }
  }
}

bool GuidePaths::follow(Guide& guide, Vertex here) {
  const size_t end = std::min(guide.cells.size(), guide.at + static_cast<size_t>(settings_.lookahead));
  for (size_t i = guide.at; i < end; ++i) {
    if (guide.cells[i] != here) continue;
    for (size_t k = guide.at; k < i; ++k) {  // the cells passed no longer carry this agent's flow
      load_[guide.cells[k]] -= 1;
      flow_[static_cast<size_t>(guide.cells[k]) * kHeadings + direction(guide.cells[k], guide.cells[k + 1])] -= 1;
    }
    guide.at = i;
    return true;
  }
  return false;
}

void GuidePaths::update(const Config& positions, const Config& goals, const Heuristic& heuristic,
                        const Deadline& deadline) {
  const size_t n = positions.size();
  if (guides_.size() != n) {
    for (const Guide& guide : guides_) add_flows(guide, -1);
    guides_.assign(n, Guide{});
    next_refresh_ = 0;
  }
  ++step_;
  const float keep = static_cast<float>(settings_.crowd_memory);
  for (float& c : crowd_) c *= keep;
  for (Vertex v : positions) crowd_[v] += 1 - keep;
  std::vector<int> must;
  for (size_t a = 0; a < n; ++a) {
    Guide& guide = guides_[a];
    if (guide.goal != goals[a] || !follow(guide, positions[a])) must.push_back(static_cast<int>(a));
  }
  for (int a : must) {
    if (deadline.expired()) return;
    search(a, positions[a], goals[a], heuristic);
  }
  // Refreshes, oldest first: a path searched before the flows it meets settled.
  const size_t refreshes = std::min(n, static_cast<size_t>(settings_.replans_per_step));
  for (size_t k = 0; k < refreshes && !deadline.expired(); ++k) {
    const size_t a = next_refresh_++ % n;
    if (guides_[a].searched_step == step_) continue;
    search(static_cast<int>(a), positions[a], goals[a], heuristic);
  }
}

void GuidePaths::search(int agent, Vertex from, Vertex goal, const Heuristic& heuristic) {
  Guide& guide = guides_[agent];
  add_flows(guide, -1);
  guide.cells.clear();
  guide.at = 0;
  guide.goal = goal;
  guide.searched_step = step_;
  ++paths_searched_;
  if (++search_id_ == 0) {
    std::fill(seen_.begin(), seen_.end(), 0);
    search_id_ = 1;
  }
  using Entry = std::pair<double, Vertex>;  // f, vertex
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  g_[from] = 0;
  parent_[from] = kNoVertex;
  seen_[from] = search_id_;
  open.push({heuristic(goal, from), from});
  bool found = false;
  while (!open.empty()) {
    const auto [f, u] = open.top();
    open.pop();
    if (u == goal) {
      found = true;
      break;
    }
    if (f > g_[u] + heuristic(goal, u) + 1e-9) continue;  // a stale entry
    for (Vertex v : graph_.neighbours(u)) {
      const int back = direction(v, u);
      const double cost = 1.0 + flow_[static_cast<size_t>(v) * kHeadings + back] + settings_.vertex_weight * load_[v] +
                          settings_.crowd_weight * crowd_[v];
      const double g = g_[u] + cost;
      if (seen_[v] == search_id_ && g >= g_[v]) continue;
      const int h = heuristic(goal, v);
      if (h >= kUnreachable) continue;
      seen_[v] = search_id_;
      g_[v] = g;
      parent_[v] = u;
      open.push({g + h, v});
    }
  }
  if (!found) return;  // no path: the agent has no guide and PIBT goes by distances alone
  for (Vertex v = goal; v != kNoVertex; v = parent_[v]) guide.cells.push_back(v);
  std::reverse(guide.cells.begin(), guide.cells.end());
  add_flows(guide, +1);
}

Vertex GuidePaths::next(int agent, Vertex here) const {
  if (agent >= static_cast<int>(guides_.size())) return kNoVertex;
  const Guide& guide = guides_[agent];
  const size_t end = std::min(guide.cells.size(), guide.at + static_cast<size_t>(settings_.lookahead));
  for (size_t i = guide.at; i < end; ++i) {
    if (guide.cells[i] == here) return i + 1 < guide.cells.size() ? guide.cells[i + 1] : kNoVertex;
  }
  return kNoVertex;
}

std::span<const Vertex> GuidePaths::ahead(int agent, size_t most) const {
  if (agent >= static_cast<int>(guides_.size())) return {};
  const Guide& guide = guides_[agent];
  const size_t end = std::min(guide.cells.size(), guide.at + most);
  return {guide.cells.data() + guide.at, end - guide.at};
}

int64_t GuidePaths::contraflow_moves() const {
  int64_t total = 0;
  for (const Guide& guide : guides_) {
    for (size_t i = guide.at; i + 1 < guide.cells.size(); ++i) {
      const Vertex u = guide.cells[i];
      const Vertex v = guide.cells[i + 1];
      if (flow_[static_cast<size_t>(v) * kHeadings + direction(v, u)] > 0) ++total;
    }
  }
  return total;
}

}  // namespace planner_core
