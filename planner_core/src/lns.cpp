#include "planner_core/lns.hpp"

#include <algorithm>
#include <numeric>

namespace planner_core {

namespace {
constexpr double kMinimumWeight = 1e-3;  // keeps every operator selectable
}

LnsRefiner::LnsRefiner(const Instance& instance, DistTable& dist, const LnsConfig& config, std::mt19937& rng)
    : instance_(instance),
      dist_(dist),
      config_(config),
      rng_(rng),
      table_(instance.graph->vertex_count()),
      planner_(*instance.graph) {
  weights_.fill(1.0);
}

DestroyOperator LnsRefiner::roulette() {
  const double total = std::accumulate(weights_.begin(), weights_.end(), 0.0);
  double pick = std::uniform_real_distribution<double>(0.0, total)(rng_);
  for (int op = 0; op < kDestroyOperatorCount; ++op) {
    pick -= weights_[op];
    if (pick <= 0) return static_cast<DestroyOperator>(op);
  }
  return static_cast<DestroyOperator>(kDestroyOperatorCount - 1);
}

std::vector<int> LnsRefiner::random_agents(std::vector<int> chosen) {
  const int n = instance_.agent_count();
  const int size = std::min(config_.neighbourhood_size, n);
  std::vector<char> taken(n, 0);
  for (int a : chosen) taken[a] = 1;
  std::uniform_int_distribution<int> any(0, n - 1);
  while (static_cast<int>(chosen.size()) < size) {
    const int a = any(rng_);
    if (!taken[a]) {
      taken[a] = 1;
      chosen.push_back(a);
    }
  }
  return chosen;
}

// Agents passing near a random intersection (a cell of degree >= 3 on some agent's path),
// gathered breadth-first outwards from it.
std::vector<int> LnsRefiner::intersection_agents() {
  const Graph& graph = *instance_.graph;
  const int n = instance_.agent_count();
  const int size = std::min(config_.neighbourhood_size, n);
  std::uniform_int_distribution<int> any(0, n - 1);
  Vertex centre = kNoVertex;
  for (int attempt = 0; attempt < 16 && centre == kNoVertex; ++attempt) {
    const Path& path = paths_[any(rng_)];
    const Vertex v = path[std::uniform_int_distribution<size_t>(0, path.size() - 1)(rng_)];
    if (graph.neighbours(v).size() >= 3) centre = v;
  }
  std::vector<int> chosen;
  if (centre == kNoVertex) return random_agents(chosen);
  std::vector<Vertex> queue{centre};
  std::vector<char> seen(graph.vertex_count(), 0);
  seen[centre] = 1;
  for (size_t head = 0; head < queue.size() && static_cast<int>(chosen.size()) < size && head < 256; ++head) {
    table_.agents_at(queue[head], chosen);
    for (Vertex u : graph.neighbours(queue[head])) {
      if (!seen[u]) {
        seen[u] = 1;
        queue.push_back(u);
      }
    }
  }
  if (static_cast<int>(chosen.size()) > size) {
    std::shuffle(chosen.begin() + 1, chosen.end(), rng_);
    chosen.resize(size);
  }
  return random_agents(chosen);
}

std::optional<int> LnsRefiner::delayed_agent() {
  const int n = instance_.agent_count();
  std::vector<double> delay(n);
  for (int a = 0; a < n; ++a) {
    delay[a] = std::max(0.0, static_cast<double>(static_cast<int>(paths_[a].size()) - 1 - tour_length_[a]));
  }
  if (std::all_of(delay.begin(), delay.end(), [](double d) { return d <= 0; })) return std::nullopt;
  return std::discrete_distribution<int>(delay.begin(), delay.end())(rng_);
}

// Starts from a delayed agent and follows the agents it meets along its path.
std::vector<int> LnsRefiner::random_walk_agents() {
  const Graph& graph = *instance_.graph;
  const int size = std::min(config_.neighbourhood_size, instance_.agent_count());
  const std::optional<int> late = delayed_agent();
  if (!late) return random_agents({});
  int walker = *late;
  std::vector<int> chosen{walker};
  std::vector<int> met;
  for (int step = 0; step < 4 * size && static_cast<int>(chosen.size()) < size; ++step) {
    const Path& path = paths_[walker];
    const int t = std::uniform_int_distribution<int>(0, static_cast<int>(path.size()) - 1)(rng_);
    met.clear();
    for (int dt = 0; dt <= 1; ++dt) {
      const auto look = [&](Vertex u) {
        const int other = table_.occupant(u, t + dt);
        if (other != PathTable::kFree && std::find(chosen.begin(), chosen.end(), other) == chosen.end()) {
          met.push_back(other);
        }
      };
      look(path[t]);
      for (Vertex u : graph.neighbours(path[t])) look(u);
    }
    if (met.empty()) continue;
    walker = met[std::uniform_int_distribution<size_t>(0, met.size() - 1)(rng_)];
    if (std::find(chosen.begin(), chosen.end(), walker) == chosen.end()) chosen.push_back(walker);
  }
  return random_agents(chosen);
}

// A delayed agent and the agents that pass its goal last, after it could have arrived: while they
// do, it cannot rest there. An agent parked on its goal in a corridor waits for everyone who still
// has to go through; replanned first, it arrives early and they pass it by another lane or earlier.
// The latest visitors go first, so a repeated pick peels them off from the end.
std::vector<int> LnsRefiner::goal_blocker_agents() {
  const std::optional<int> late = delayed_agent();
  if (!late) return random_agents({});
  const int size = std::min(config_.neighbourhood_size, instance_.agent_count());
  std::vector<int> chosen{*late};
  table_.visitors_from(instance_.goals[*late], tour_length_[*late], *late, size - 1, chosen);
  return random_agents(chosen);
}

std::vector<int> LnsRefiner::pick_neighbourhood(DestroyOperator op) {
  switch (op) {
    case DestroyOperator::kRandom: return random_agents({});
    case DestroyOperator::kIntersection: return intersection_agents();
    case DestroyOperator::kRandomWalk: return random_walk_agents();
    case DestroyOperator::kGoalBlockers: return goal_blocker_agents();
  }
  return random_agents({});
}

void LnsRefiner::load(const Solution& plan, const HeadingPlan* headings,
                      const std::vector<std::vector<int>>& orders) {
  const int n = instance_.agent_count();
  const std::vector<int> arrival = arrival_times(plan, instance_.goals);
  paths_.assign(n, {});
  path_headings_.assign(headings ? n : 0, {});
  targets_.assign(n, {});
  tour_length_.assign(n, 0);
  table_ = PathTable(instance_.graph->vertex_count());
  max_tour_ = 0;
  for (int a = 0; a < n; ++a) {
    for (int t = 0; t <= arrival[a]; ++t) {
      paths_[a].push_back(plan[t][a]);
      if (headings) path_headings_[a].push_back((*headings)[t][a]);
    }
    for (int task : orders[a]) targets_[a].push_back(instance_.tasks[task].at);
    targets_[a].push_back(instance_.goals[a]);
    Vertex at = instance_.starts[a];
    for (Vertex target : targets_[a]) {
      tour_length_[a] += dist_.get(target, at);
      at = target;
    }
    max_tour_ = std::max(max_tour_, tour_length_[a]);
  }
  table_.add_all(paths_);
  loaded_plan_ = plan;
  loaded_headings_ = headings ? *headings : HeadingPlan{};
  loaded_orders_ = orders;
}

Path LnsRefiner::repair(int a, const SpaceTimeLimits& limits, std::vector<int>& headings) {
  if (path_headings_.empty()) return planner_.plan(dist_, table_, instance_.starts[a], targets_[a], limits);
  return planner_.plan_with_turns(dist_, turning_, table_, instance_.starts[a], instance_.start_heading(a), targets_[a],
                                  limits, headings);
}

LnsStats LnsRefiner::run(Solution& plan, HeadingPlan* headings, const std::vector<std::vector<int>>& orders,
                         const Deadline& deadline, const std::function<void(int64_t)>& on_improvement) {
  const int n = instance_.agent_count();
  LnsStats stats;
  stats.weights = weights_;
  if (deadline.expired()) return stats;  // not even the (long) loading of a new plan
  // Going on from where the last call left this very plan keeps its paths and table (rebuilding
  // them costs O(agents x makespan), a good part of a short slice at 10,000 agents).
  const bool same_headings = headings ? *headings == loaded_headings_ : loaded_headings_.empty();
  if (plan != loaded_plan_ || orders != loaded_orders_ || !same_headings ||
      (headings != nullptr) != !path_headings_.empty()) {
    load(plan, headings, orders);
  }
  const int max_tour = max_tour_;
  int64_t flow = 0;
  int makespan = 0;
  for (const Path& path : paths_) {
    flow += static_cast<int64_t>(path.size()) - 1;
    makespan = std::max(makespan, static_cast<int>(path.size()) - 1);
  }

  std::vector<Path> old_paths, new_paths;
  std::vector<std::vector<int>> new_headings;
  std::vector<int> repaired_headings;
  int last_improvement = 0;
  while (!deadline.expired()) {
    if (config_.stall_iterations > 0 && stats.iterations - last_improvement >= config_.stall_iterations) break;
    ++stats.iterations;
    const DestroyOperator op = roulette();
    std::vector<int> group = pick_neighbourhood(op);
    // The repair's priority order: random, except that the late agent of a goal-blocker
    // neighbourhood goes first, to take its early arrival before the others are replanned.
    std::shuffle(group.begin() + (op == DestroyOperator::kGoalBlockers ? 1 : 0), group.end(), rng_);
    int64_t old_cost = 0;
    old_paths.clear();
    for (int a : group) {
      old_cost += static_cast<int64_t>(paths_[a].size()) - 1;
      old_paths.push_back(paths_[a]);
      table_.remove(a, paths_[a]);
    }
    SpaceTimeLimits limits = config_.search;
    limits.horizon = std::min(limits.horizon, makespan + max_tour);
    limits.deadline = deadline;
    // The repair is kept only if it costs no more than the paths it replaces, so each agent's
    // path may be at most what is left of the old cost after the others' shortest tours.
    int64_t others_shortest = 0;
    for (int a : group) others_shortest += tour_length_[a];
    new_paths.clear();
    new_headings.clear();
    int64_t new_cost = 0;
    for (int a : group) {
      others_shortest -= tour_length_[a];
      limits.max_length = static_cast<int>(std::min<int64_t>(old_cost - new_cost - others_shortest, 1 << 29));
      Path path = repair(a, limits, repaired_headings);
      if (path.empty()) break;
      new_cost += static_cast<int64_t>(path.size()) - 1;
      table_.add(a, path);
      new_paths.push_back(std::move(path));
      if (headings) new_headings.push_back(repaired_headings);
    }
    const bool repaired = new_paths.size() == group.size();
    if (!repaired) ++stats.repair_failures;
    double delta = 0;
    if (repaired && new_cost <= old_cost) {
      ++stats.accepted;
      delta = static_cast<double>(old_cost - new_cost);
      for (size_t k = 0; k < group.size(); ++k) paths_[group[k]] = std::move(new_paths[k]);
      if (headings) {
        for (size_t k = 0; k < group.size(); ++k) path_headings_[group[k]] = std::move(new_headings[k]);
      }
      if (new_cost < old_cost) {
        last_improvement = stats.iterations;
        flow -= old_cost - new_cost;
        if (on_improvement) on_improvement(flow);
      }
    } else {
      for (size_t k = 0; k < new_paths.size(); ++k) table_.remove(group[k], new_paths[k]);
      for (size_t k = 0; k < group.size(); ++k) table_.add(group[k], old_paths[k]);
    }
    double& weight = weights_[static_cast<int>(op)];
    weight = std::max(kMinimumWeight, (1 - config_.gamma) * weight + config_.gamma * std::max(delta, 0.0));
    makespan = 0;
    for (const Path& path : paths_) makespan = std::max(makespan, static_cast<int>(path.size()) - 1);
  }

  plan.assign(makespan + 1, Config(n));
  for (int t = 0; t <= makespan; ++t) {
    for (int a = 0; a < n; ++a) plan[t][a] = paths_[a][std::min<size_t>(t, paths_[a].size() - 1)];
  }
  loaded_plan_ = plan;
  if (headings) {
    headings->assign(makespan + 1, Headings(n));
    for (int t = 0; t <= makespan; ++t) {
      for (int a = 0; a < n; ++a) {
        (*headings)[t][a] = path_headings_[a][std::min<size_t>(t, path_headings_[a].size() - 1)];
      }
    }
    loaded_headings_ = *headings;
  }
  stats.weights = weights_;
  return stats;
}

}  // namespace planner_core
