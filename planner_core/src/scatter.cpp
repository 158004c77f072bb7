#include "planner_core/scatter.hpp"

#include <algorithm>
#include <numeric>
#include <queue>
#include <tuple>

namespace planner_core {

namespace {

template <class Visits>
auto first_at_or_after(Visits& visits, int t) {
  return std::lower_bound(visits.begin(), visits.end(), t, [](const auto& visit, int time) { return visit.t < time; });
}

}  // namespace

Scatter::Scatter(const Graph& graph, DistTable& dist, const Config& starts, const Config& goals, int cost_margin,
                 uint32_t seed, const std::vector<std::vector<Vertex>>& waypoints)
    : graph_(graph),
      dist_(dist),
      starts_(starts),
      goals_(goals),
      targets_(starts.size()),
      cost_margin_(cost_margin),
      rng_(seed),
      paths_(starts.size()),
      leg_ends_(starts.size()),
      visits_(graph.vertex_count()),
      arrivals_(graph.vertex_count()),
      steps_(starts.size()),
      parent_(graph.vertex_count(), kNoVertex),
      closed_stamp_(graph.vertex_count(), 0) {
  for (size_t a = 0; a < starts.size(); ++a) {
    if (a < waypoints.size()) targets_[a] = waypoints[a];
    targets_[a].push_back(goals[a]);
  }
}

// Moving from -> to between t_from and t_from + 1: agents at `to` then (vertex), agents coming
// the other way (swap), agents whose paths ended at `to` before (they rest there).
int Scatter::collision_cost(Vertex from, Vertex to, int t_from) const {
  const int t_to = t_from + 1;
  int cost = 0;
  const std::vector<Visit>& at_to = visits_[to];
  const std::vector<Visit>& at_from = visits_[from];
  for (auto it = first_at_or_after(at_to, t_to); it != at_to.end() && it->t == t_to; ++it) ++cost;
  for (auto it = first_at_or_after(at_from, t_to); it != at_from.end() && it->t == t_to; ++it) {
    for (auto back = first_at_or_after(at_to, t_from); back != at_to.end() && back->t == t_from; ++back) {
      if (back->agent == it->agent) ++cost;
    }
  }
  for (int arrival : arrivals_[to]) {
    if (t_to > arrival) ++cost;
  }
  return cost;
}

// The collisions of `path` with every path in the tables (its own must not be in them).
int64_t Scatter::path_collisions(const Path& path) const {
  int64_t count = 0;
  for (int t = 1; t < static_cast<int>(path.size()); ++t) count += collision_cost(path[t - 1], path[t], t - 1);
  const std::vector<Visit>& at_goal = visits_[path.back()];
  count += at_goal.end() - first_at_or_after(at_goal, static_cast<int>(path.size()));
  return count;
}

void Scatter::enrol(int agent) {
  const Path& path = paths_[agent];
  if (path.empty()) return;
  collisions_ += path_collisions(path);
  for (int t = 0; t < static_cast<int>(path.size()); ++t) {
    std::vector<Visit>& visits = visits_[path[t]];
    visits.insert(first_at_or_after(visits, t + 1), Visit{t, agent});
  }
  arrivals_[path.back()].push_back(static_cast<int>(path.size()) - 1);
}

void Scatter::clear(int agent) {
  const Path& path = paths_[agent];
  if (path.empty()) return;
  for (int t = 0; t < static_cast<int>(path.size()); ++t) {
    std::vector<Visit>& visits = visits_[path[t]];
    for (auto it = first_at_or_after(visits, t); it != visits.end() && it->t == t; ++it) {
      if (it->agent == agent) {
        visits.erase(it);
        break;
      }
    }
  }
  std::vector<int>& arrivals = arrivals_[path.back()];
  arrivals.erase(std::find(arrivals.begin(), arrivals.end(), static_cast<int>(path.size()) - 1));
  collisions_ -= path_collisions(path);
}

// Leg by leg, each leg best-first over cells (each cell once, no waiting): fewest collisions, then
// shortest; no leg longer than its shortest plus the margin. Keeps the old path when none is found.
bool Scatter::plan(int agent, const Deadline& deadline) {
  Path path{starts_[agent]};
  std::vector<int> leg_ends;
  for (Vertex target : targets_[agent]) {
    if (!plan_leg(path, target, deadline)) return false;
    leg_ends.push_back(static_cast<int>(path.size()) - 1);
  }
  paths_[agent] = std::move(path);
  leg_ends_[agent] = std::move(leg_ends);
  return true;
}

bool Scatter::plan_leg(Path& path, Vertex target, const Deadline& deadline) {
  const Vertex start = path.back();
  const int begin = static_cast<int>(path.size()) - 1;  // the time the leg starts
  const DistTable::Row to_target = dist_.row(target);
  const int shortest = to_target.get(start);
  if (shortest >= kUnreachable) return false;
  if (start == target) return true;
  const int longest = shortest + cost_margin_;
  if (++stamp_ == 0) {
    std::fill(closed_stamp_.begin(), closed_stamp_.end(), 0);
    stamp_ = 1;
  }
  struct Node {
    int collisions;
    int f;
    int g;
    Vertex v;
    Vertex parent;
    bool operator>(const Node& other) const {
      return std::tie(collisions, f, v) > std::tie(other.collisions, other.f, other.v);
    }
  };
  std::priority_queue<Node, std::vector<Node>, std::greater<Node>> open;
  open.push({0, shortest, 0, start, kNoVertex});
  int popped = 0;
  while (!open.empty()) {
    const Node node = open.top();
    open.pop();
    if (closed_stamp_[node.v] == stamp_) continue;
    closed_stamp_[node.v] = stamp_;
    parent_[node.v] = node.parent;
    if (node.v == target) {
      const size_t leg_begin = path.size();
      for (Vertex v = target; v != start; v = parent_[v]) path.push_back(v);
      std::reverse(path.begin() + static_cast<std::ptrdiff_t>(leg_begin), path.end());
      return true;
    }
    deadline.spend(1);
    if ((++popped & 255) == 0 && deadline.expired()) return false;
    for (Vertex u : graph_.neighbours(node.v)) {
      if (closed_stamp_[u] == stamp_ || u == start) continue;
      const int h = to_target.get(u);
      if (node.g + 1 + h > longest) continue;
      open.push({node.collisions + collision_cost(node.v, u, begin + node.g), node.g + 1 + h, node.g + 1, u, node.v});
    }
  }
  return false;
}

ScatterStats Scatter::build(const Deadline& deadline) {
  ScatterStats stats;
  const int n = static_cast<int>(starts_.size());
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  int64_t before = -1;
  while (!deadline.expired() && (stats.rounds < 2 || collisions_ < before)) {
    before = collisions_;
    ++stats.rounds;
    std::shuffle(order.begin(), order.end(), rng_);
    for (int agent : order) {
      if (deadline.expired()) break;
      clear(agent);
      plan(agent, deadline);
      enrol(agent);
    }
    if (collisions_ == 0) break;
  }
  stats.collisions = collisions_;
  stats.complete = true;
  for (int agent = 0; agent < n; ++agent) {
    const Path& path = paths_[agent];
    std::vector<Step>& steps = steps_[agent];
    steps.clear();
    if (path.empty()) {
      stats.complete = false;
      continue;
    }
    stats.sum_of_lengths += static_cast<int64_t>(path.size()) - 1;
    int leg = 0;
    const std::vector<int>& leg_ends = leg_ends_[agent];
    for (int t = 0; t + 1 < static_cast<int>(path.size()); ++t) {
      while (t >= leg_ends[leg]) ++leg;  // legs of length 0 (a waypoint where the last one ended)
      steps.push_back({leg, path[t], path[t + 1]});
    }
    std::sort(steps.begin(), steps.end());
  }
  return stats;
}

Vertex Scatter::next(int agent, int leg, Vertex v) const {
  const std::vector<Step>& steps = steps_[agent];
  const auto it = std::lower_bound(steps.begin(), steps.end(), Step{leg, v, kNoVertex});
  return it != steps.end() && it->leg == leg && it->v == v ? it->next : kNoVertex;
}

}  // namespace planner_core
