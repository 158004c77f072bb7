#include "planner_core/window_lns.hpp"

#include <algorithm>
#include <queue>

namespace planner_core {

WindowLns::WindowLns(const Graph& graph, GuidedDistances& distances, ActionModel actions)
    : graph_(graph), distances_(distances), actions_(actions), cells_(static_cast<size_t>(graph.vertex_count())) {
  for (Vertex v = 0; v < graph.vertex_count(); ++v) {
    if (graph.neighbours(v).size() > 2) crossings_.push_back(v);
  }
}

int WindowLns::heuristic(Vertex goal, Vertex cell, int heading) {
  return actions_ == ActionModel::kRotate ? distances_.get(goal, cell, heading) : distances_.get(goal, cell);
}

void WindowLns::mark_guide(int agent) {
  guide_marked_ = false;
  if (guides_ == nullptr) return;
  if (guide_mark_.size() != cells_) guide_mark_.assign(cells_, 0);
  if (++guide_stamp_ == 0) {
    std::fill(guide_mark_.begin(), guide_mark_.end(), 0);
    guide_stamp_ = 1;
  }
  // A window of `steps_` moves reaches no further along the guide than that.
  for (Vertex cell : guides_->ahead(agent, static_cast<size_t>(steps_) + 1)) {
    guide_mark_[cell] = guide_stamp_;
    guide_marked_ = true;
  }
}

int64_t WindowLns::path_cost(const std::vector<Poses>& window, int agent, Vertex goal) {
  if (window[0].cells[agent] == goal) return 0;
  mark_guide(agent);
  int64_t cost = 0;
  for (int t = 1; t <= steps_; ++t) {
    const Vertex from = window[t - 1].cells[agent];
    const Vertex to = window[t].cells[agent];
    cost += to == from ? distances_.stay_cost(from) : distances_.move_cost(from, to) + off_guide(from, to);
    if (to == goal) return cost;
  }
  const int heading = actions_ == ActionModel::kRotate ? window[steps_].headings[agent] : 0;
  return cost + heuristic(goal, window[steps_].cells[agent], heading);
}

void WindowLns::reserve(const std::vector<Poses>& window, int agent, Vertex goal, int who) {
  for (int t = 0; t <= steps_; ++t) {
    occupied_[static_cast<size_t>(t) * cells_ + window[t].cells[agent]] = who;
    if (t > 0 && window[t].cells[agent] == goal) return;  // arrived: its next errand takes it on
  }
}

bool WindowLns::plan_agent(std::vector<Poses>& window, int agent, Vertex goal) {
  const bool rotate = actions_ == ActionModel::kRotate;
  const int headings = rotate ? kHeadings : 1;
  mark_guide(agent);
  ++stamp_;
  nodes_.clear();
  using Entry = std::pair<std::pair<int64_t, int64_t>, int>;  // (f, -g), node
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  const Vertex start = window[0].cells[agent];
  const int start_heading = rotate ? window[0].headings[agent] : 0;
  nodes_.push_back({heuristic(goal, start, start_heading), 0, 0, start, start_heading, -1});
  open.push({{nodes_[0].f, 0}, 0});
  while (!open.empty()) {
    const int index = open.top().second;
    open.pop();
    const Node node = nodes_[index];
    if (node.t == steps_ || (node.t > 0 && node.cell == goal)) {
      // Write the path back, standing on the goal after it is reached (holding no cell there).
      for (int t = steps_; t > node.t; --t) {
        window[t].cells[agent] = node.cell;
        if (rotate) window[t].headings[agent] = node.heading;
      }
      for (int k = index; k != -1 && nodes_[k].t > 0; k = nodes_[k].parent) {
        window[nodes_[k].t].cells[agent] = nodes_[k].cell;
        if (rotate) window[nodes_[k].t].headings[agent] = nodes_[k].heading;
      }
      return true;
    }
    const int t = node.t + 1;
    const auto visit = [&](Vertex cell, int heading, int cost) {
      if (!free_at(t, cell)) return;
      if (cell != node.cell) {
        const int there = occupant(node.t, cell);  // no swap with the agent standing there
        if (there != -1 && occupant(t, node.cell) == there) return;
      }
      const size_t state = (static_cast<size_t>(t) * cells_ + static_cast<size_t>(cell)) * headings + heading;
      const int64_t g = node.g + cost;
      if (seen_[state] == stamp_ && best_g_[state] <= g) return;
      seen_[state] = stamp_;
      best_g_[state] = g;
      const int h = heuristic(goal, cell, heading);
      if (h >= GuidedDistances::kUnreachable) return;
      nodes_.push_back({g + h, g, t, cell, heading, index});
      open.push({{g + h, -g}, static_cast<int>(nodes_.size()) - 1});
    };
    if (rotate) {
      const Vertex forward = ahead(graph_, node.cell, node.heading);
      if (forward != kNoVertex) {
        visit(forward, node.heading, distances_.move_cost(node.cell, forward) + off_guide(node.cell, forward));
      }
      visit(node.cell, turned_clockwise(node.heading), distances_.stay_cost(node.cell));
      visit(node.cell, turned_counter_clockwise(node.heading), distances_.stay_cost(node.cell));
    } else {
      for (Vertex next : graph_.neighbours(node.cell)) {
        visit(next, 0, distances_.move_cost(node.cell, next) + off_guide(node.cell, next));
      }
    }
    visit(node.cell, node.heading, distances_.stay_cost(node.cell));
  }
  return false;
}

template <typename Visit>
void WindowLns::walk_until_full(Vertex start, const std::vector<int>& group, std::mt19937* order, Visit visit) {
  std::vector<Vertex> frontier{start};
  std::vector<Vertex> reached = frontier;
  for (size_t k = 0; k < frontier.size() && group.size() < static_cast<size_t>(kNeighbourhood); ++k) {
    std::vector<Vertex> next(graph_.neighbours(frontier[k]).begin(), graph_.neighbours(frontier[k]).end());
    if (order != nullptr) std::shuffle(next.begin(), next.end(), *order);
    for (Vertex v : next) {
      if (std::find(reached.begin(), reached.end(), v) != reached.end()) continue;
      reached.push_back(v);
      frontier.push_back(v);
      visit(v);
    }
    if (reached.size() > kMostCellsWalked) break;
  }
}

std::vector<int> WindowLns::nearest(const std::vector<Poses>& window, int late, std::mt19937& rng) {
  // The late agent and those standing nearest it now.
  std::vector<int> group{late};
  walk_until_full(window[0].cells[late], group, &rng, [&](Vertex cell) {
    const int there = occupant(0, cell);
    if (there != -1 && group.size() < static_cast<size_t>(kNeighbourhood)) group.push_back(there);
  });
  return group;
}

void WindowLns::add_agents_through(Vertex cell, std::vector<int>& group) {
  for (int t = 0; t <= steps_ && group.size() < static_cast<size_t>(kNeighbourhood); ++t) {
    const int there = occupant(t, cell);
    if (there != -1 && std::find(group.begin(), group.end(), there) == group.end()) group.push_back(there);
  }
}

std::vector<int> WindowLns::through_crossing(std::mt19937& rng) {
  // The agents passing a crossing in the window, then those passing the crossings nearest it.
  std::vector<int> group;
  if (crossings_.empty()) return group;
  const Vertex start = crossings_[std::uniform_int_distribution<size_t>(0, crossings_.size() - 1)(rng)];
  add_agents_through(start, group);
  walk_until_full(start, group, nullptr, [&](Vertex cell) {
    if (graph_.neighbours(cell).size() > 2) add_agents_through(cell, group);
  });
  return group;
}

std::vector<int> WindowLns::random_agents(int agents, std::mt19937& rng) {
  std::vector<int> group;
  const size_t size = std::min(static_cast<size_t>(kNeighbourhood), static_cast<size_t>(agents));
  std::uniform_int_distribution<int> any(0, agents - 1);
  while (group.size() < size) {
    const int a = any(rng);
    if (std::find(group.begin(), group.end(), a) == group.end()) group.push_back(a);
  }
  return group;
}

WindowLns::Kind WindowLns::pick_kind(std::mt19937& rng) {
  if (neighbourhoods_ == Neighbourhoods::kNearest) return kNearestKind;
  double sum = 0;
  for (double w : kind_weights_) sum += w;
  double r = std::uniform_real_distribution<double>(0, sum)(rng);
  for (int k = 0; k < kKinds - 1; ++k) {
    if (r < kind_weights_[k]) return static_cast<Kind>(k);
    r -= kind_weights_[k];
  }
  return static_cast<Kind>(kKinds - 1);
}

void WindowLns::weigh(Kind kind, int64_t gain, size_t agents) {
  double& weight = kind_weights_[kind];
  if (gain > 0) {
    weight = kKindReaction * std::max(static_cast<double>(gain) / static_cast<double>(agents), 1.0) +
             (1 - kKindReaction) * weight;
  } else {
    weight = std::max(weight * (1 - kKindDecay), kLeastKindWeight);
  }
}

void WindowLns::clear_reservations(const std::vector<Poses>& window) {
  steps_ = static_cast<int>(window.size()) - 1;
  const size_t states = static_cast<size_t>(steps_ + 1) * cells_ * (actions_ == ActionModel::kRotate ? kHeadings : 1);
  occupied_.assign(static_cast<size_t>(steps_ + 1) * cells_, -1);
  if (seen_.size() != states) {
    seen_.assign(states, 0);
    best_g_.assign(states, 0);
    stamp_ = 0;
  }
}

int64_t WindowLns::cost(const std::vector<Poses>& window, const Config& goals) {
  steps_ = static_cast<int>(window.size()) - 1;
  int64_t total = 0;
  for (size_t a = 0; a < goals.size(); ++a) total += path_cost(window, static_cast<int>(a), goals[a]);
  return total;
}

bool WindowLns::replan(std::vector<Poses>& window, const Config& goals, const std::vector<int>& agents, int* blocked) {
  if (window.size() < 2) return agents.empty();
  clear_reservations(window);
  // The agents to plan again may stand in the others' way (their old paths lead elsewhere), so
  // only the others' cells are marked.
  std::vector<char> again(goals.size(), 0);
  for (int a : agents) again[a] = 1;
  for (size_t a = 0; a < goals.size(); ++a) {
    if (!again[a]) reserve(window, static_cast<int>(a), goals[a], static_cast<int>(a));
  }
  for (int a : agents) {
    if (!plan_agent(window, a, goals[a])) {
      if (blocked != nullptr) *blocked = a;
      return false;
    }
    reserve(window, a, goals[a], a);
  }
  return true;
}

WindowLnsStats WindowLns::improve(std::vector<Poses>& window, const Config& goals, const Deadline& deadline,
                                  std::mt19937& rng, int64_t rounds) {
  WindowLnsStats stats;
  if (window.size() < 2) return stats;
  const int n = static_cast<int>(goals.size());
  const bool rotate = actions_ == ActionModel::kRotate;
  clear_reservations(window);
  for (int a = 0; a < n; ++a) reserve(window, a, goals[a], a);
  kind_weights_.fill(1.0);
  std::vector<int64_t> cost(n);
  std::vector<int> late;
  for (int a = 0; a < n; ++a) {
    cost[a] = path_cost(window, a, goals[a]);
    stats.cost_before += cost[a];
    const int heading = rotate ? window[0].headings[a] : 0;
    if (cost[a] > heuristic(goals[a], window[0].cells[a], heading)) late.push_back(a);
  }
  while (!late.empty() && stats.iterations < rounds && !deadline.expired()) {
    ++stats.iterations;
    const Kind kind = pick_kind(rng);
    std::vector<int> group;
    if (kind == kCrossingKind) {
      group = through_crossing(rng);
    } else if (kind == kRandomKind) {
      group = random_agents(n, rng);
    } else {
      group = nearest(window, late[std::uniform_int_distribution<size_t>(0, late.size() - 1)(rng)], rng);
    }
    ++stats.rounds_by_kind[kind];
    if (group.empty()) {  // no agent passes the crossing in the window
      weigh(kind, 0, 1);
      continue;
    }
    int64_t old_cost = 0;
    std::vector<Poses> old_paths(window.size(), Poses{Config(group.size()), Headings(rotate ? group.size() : 0)});
    for (size_t k = 0; k < group.size(); ++k) {
      old_cost += cost[group[k]];
      for (int t = 0; t <= steps_; ++t) {
        old_paths[t].cells[k] = window[t].cells[group[k]];
        if (rotate) old_paths[t].headings[k] = window[t].headings[group[k]];
      }
      reserve(window, group[k], goals[group[k]], -1);
    }
    std::vector<size_t> order(group.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), rng);
    bool planned = true;
    size_t done = 0;
    for (; done < order.size(); ++done) {
      const int a = group[order[done]];
      if (!plan_agent(window, a, goals[a])) {
        planned = false;
        break;
      }
      reserve(window, a, goals[a], a);
    }
    int64_t new_cost = 0;
    if (planned) {
      for (int a : group) new_cost += path_cost(window, a, goals[a]);
    }
    weigh(kind, planned ? old_cost - new_cost : 0, group.size());
    if (planned && (new_cost < old_cost || (keep_equal_cost_ && new_cost == old_cost))) {
      if (new_cost < old_cost) {
        ++stats.improvements;
        ++stats.improvements_by_kind[kind];
      }
      for (int a : group) cost[a] = path_cost(window, a, goals[a]);
      continue;
    }
    for (size_t k = 0; k < done; ++k) reserve(window, group[order[k]], goals[group[order[k]]], -1);
    for (size_t k = 0; k < group.size(); ++k) {
      for (int t = 0; t <= steps_; ++t) {
        window[t].cells[group[k]] = old_paths[t].cells[k];
        if (rotate) window[t].headings[group[k]] = old_paths[t].headings[k];
      }
      reserve(window, group[k], goals[group[k]], group[k]);
    }
  }
  for (int a = 0; a < n; ++a) stats.cost_after += cost[a];
  return stats;
}

}  // namespace planner_core
