#include "planner_core/lock_release.hpp"

#include <algorithm>

namespace planner_core {

LockSet detect_lock(const ExtendedPibt& pibt, DistTable& dist) {
  const Instance& instance = pibt.instance();
  const Config& now = pibt.plan().back();
  const Graph& graph = *instance.graph;
  LockSet lock;
  std::vector<int> unfinished, finished;
  for (int a = 0; a < instance.agent_count(); ++a) (pibt.finished(a) ? finished : unfinished).push_back(a);
  lock.agents = unfinished;
  // A finished agent is in the way when it stands next to an unfinished agent or on a shortest
  // path from one to its next target.
  for (int f : finished) {
    const Vertex cell = now[f];
    for (int u : unfinished) {
      const Vertex target = pibt.target_of(u);
      const int direct = dist.get(target, now[u]);
      if (graph.adjacent(cell, now[u]) || dist.get(cell, now[u]) + dist.get(target, cell) == direct) {
        lock.agents.push_back(f);
        break;
      }
    }
  }
  std::sort(lock.agents.begin(), lock.agents.end());
  lock.lock_time = static_cast<int>(pibt.plan().size()) - 1;
  for (int a : lock.agents) lock.lock_time = std::min(lock.lock_time, pibt.last_target_time(a));
  return lock;
}

LockSet widen_lock(const ExtendedPibt& pibt, const LockSet& lock, int radius) {
  const Instance& instance = pibt.instance();
  const Graph& graph = *instance.graph;
  const Config& at = pibt.plan()[lock.lock_time];
  std::vector<int> depth(graph.vertex_count(), -1);
  std::vector<Vertex> queue;
  for (int a : lock.agents) {
    depth[at[a]] = 0;
    queue.push_back(at[a]);
  }
  for (size_t head = 0; head < queue.size(); ++head) {
    const Vertex v = queue[head];
    if (depth[v] == radius) continue;
    for (Vertex u : graph.neighbours(v)) {
      if (depth[u] < 0) {
        depth[u] = depth[v] + 1;
        queue.push_back(u);
      }
    }
  }
  LockSet wider{{}, lock.lock_time};
  for (int a = 0; a < instance.agent_count(); ++a) {
    if (depth[at[a]] >= 0) wider.agents.push_back(a);
  }
  return wider;
}

namespace {

// A random permutation of the lock agents' cells, within each region of cells the frozen agents
// leave connected.
Config permuted_goals(const Graph& graph, const Config& starts, const std::vector<char>& blocked, std::mt19937& rng) {
  std::vector<int> region(graph.vertex_count(), -1);
  Config goals = starts;
  for (size_t k = 0; k < starts.size(); ++k) {
    if (region[starts[k]] >= 0) continue;
    std::vector<Vertex> queue{starts[k]};
    region[starts[k]] = static_cast<int>(k);
    for (size_t head = 0; head < queue.size(); ++head) {
      for (Vertex u : graph.neighbours(queue[head])) {
        if (region[u] < 0 && !blocked[u]) {
          region[u] = static_cast<int>(k);
          queue.push_back(u);
        }
      }
    }
    std::vector<size_t> members;
    for (size_t j = 0; j < starts.size(); ++j) {
      if (region[starts[j]] == static_cast<int>(k)) members.push_back(j);
    }
    std::vector<Vertex> cells;
    for (size_t j : members) cells.push_back(starts[j]);
    std::shuffle(cells.begin(), cells.end(), rng);
    for (size_t m = 0; m < members.size(); ++m) goals[members[m]] = cells[m];
  }
  return goals;
}

// Next target of each lock agent where it is free and unclaimed, else its own cell, else the
// nearest free unclaimed cell.
Config next_target_goals(const ExtendedPibt& pibt, const std::vector<int>& agents, const Config& starts,
                         const std::vector<char>& blocked) {
  const Graph& graph = *pibt.instance().graph;
  std::vector<char> claimed(graph.vertex_count(), 0);
  Config goals(agents.size(), kNoVertex);
  for (size_t k = 0; k < agents.size(); ++k) {
    const Vertex target = pibt.target_of(agents[k]);
    if (!blocked[target] && !claimed[target]) {
      goals[k] = target;
      claimed[target] = 1;
    }
  }
  for (size_t k = 0; k < agents.size(); ++k) {
    if (goals[k] != kNoVertex) continue;
    std::vector<Vertex> queue{starts[k]};
    std::vector<char> seen(graph.vertex_count(), 0);
    seen[starts[k]] = 1;
    for (size_t head = 0; head < queue.size(); ++head) {
      const Vertex v = queue[head];
      if (!claimed[v]) {
        goals[k] = v;
        claimed[v] = 1;
        break;
      }
      for (Vertex u : graph.neighbours(v)) {
        if (!seen[u] && !blocked[u]) {
          seen[u] = 1;
          queue.push_back(u);
        }
      }
    }
    if (goals[k] == kNoVertex) goals[k] = starts[k];
  }
  return goals;
}

// The agent's tasks (cells) not visited in the plan up to t^, in its order: what is left for it.
std::vector<Vertex> tasks_left(const Instance& instance, const Solution& plan, const JointSequence& sequence,
                               int agent, int t_hat) {
  std::vector<Vertex> left;
  for (int task : sequence.orders[agent]) {
    const Vertex cell = instance.tasks[task].at;
    bool visited = false;
    for (int t = 0; t <= t_hat && !visited; ++t) visited = plan[t][agent] == cell;
    if (!visited) left.push_back(cell);
  }
  return left;
}

}  // namespace

std::optional<Solution> release_lock(const ExtendedPibt& pibt, const LockSet& lock, Lacam& lacam,
                                     const LockReleaseConfig& config, bool next_target_goals_now, std::mt19937& rng,
                                     const Deadline& deadline) {
  const Instance& instance = pibt.instance();
  const Solution& plan = pibt.plan();
  const Config& frozen = plan[lock.lock_time];
  std::vector<char> blocked(instance.graph->vertex_count(), 0);
  std::vector<char> is_lock(instance.agent_count(), 0);
  for (int a : lock.agents) is_lock[a] = 1;
  for (int a = 0; a < instance.agent_count(); ++a) {
    if (!is_lock[a]) blocked[frozen[a]] = 1;
  }
  Config starts;
  for (int a : lock.agents) starts.push_back(frozen[a]);
  Config goals;
  if (config.next_target_goals || next_target_goals_now || lock.agents.size() == 1) {
    goals = next_target_goals(pibt, lock.agents, starts, blocked);
  } else {
    // The paper's practical choice: a random permutation of the lock agents' own cells.
    goals = starts;
    for (int attempt = 0; attempt < 8 && goals == starts; ++attempt) {
      goals = permuted_goals(*instance.graph, starts, blocked, rng);
    }
  }
  if (goals == starts) return std::nullopt;  // nothing would move: no release
  const LacamResult found = lacam.solve(starts, goals, blocked, deadline.within_work(Deadline::work_of(config.lacam_budget_s)));
  if (!found.solved) return std::nullopt;

  Solution spliced(plan.begin(), plan.begin() + lock.lock_time + 1);
  for (size_t step = 1; step < found.solution.size(); ++step) {
    Config config_at = frozen;
    for (size_t k = 0; k < lock.agents.size(); ++k) config_at[lock.agents[k]] = found.solution[step][k];
    spliced.push_back(std::move(config_at));
  }
  return spliced;
}

std::optional<Solution> complete_by_prioritized_planning(const ExtendedPibt& pibt, const JointSequence& sequence,
                                                         const LockSet& lock, DistTable& dist, std::mt19937& rng,
                                                         int attempts, bool forbid_rotations,
                                                         const Deadline& deadline) {
  const Instance& instance = pibt.instance();
  const Solution& plan = pibt.plan();
  const int n = instance.agent_count();
  const int t_hat = lock.lock_time;
  std::vector<char> is_lock(n, 0);
  for (int a : lock.agents) is_lock[a] = 1;
  for (int a = 0; a < n; ++a) {
    if (!is_lock[a] && !pibt.finished(a)) return std::nullopt;  // only unfinished agents can be replanned
  }
  const std::vector<int> arrival = arrival_times(plan, instance.goals);
  std::vector<Path> fixed(n);
  for (int a = 0; a < n; ++a) {
    const int until = is_lock[a] ? t_hat : arrival[a];
    for (int t = 0; t <= until; ++t) fixed[a].push_back(plan[t][a]);
  }
  // Targets still ahead of each lock agent at t^: its unvisited tasks in order, then its goal.
  std::vector<std::vector<Vertex>> targets(n);
  for (int a : lock.agents) {
    targets[a] = tasks_left(instance, plan, sequence, a, t_hat);
    targets[a].push_back(instance.goals[a]);
  }
  SpaceTimeLimits limits;
  limits.horizon = static_cast<int>(plan.size()) + 4 * instance.graph->vertex_count();
  limits.forbid_rotations = forbid_rotations;
  limits.deadline = deadline;

  std::vector<int> order = lock.agents;
  SafeIntervalPlanner planner(*instance.graph);
  for (int attempt = 0; attempt < attempts && !deadline.expired(); ++attempt) {
    std::shuffle(order.begin(), order.end(), rng);
    PathTable table(instance.graph->vertex_count());
    for (int a = 0; a < n; ++a) table.add(a, fixed[a], !is_lock[a]);
    std::vector<Path> full = fixed;
    bool complete = true;
    for (int a : order) {
      table.remove(a, fixed[a]);
      const Path rest = planner.plan(dist, table, plan[t_hat][a], targets[a], limits, t_hat);
      if (rest.empty()) {
        complete = false;
        break;
      }
      full[a].pop_back();  // rest[0] is the agent's cell at t^
      full[a].insert(full[a].end(), rest.begin(), rest.end());
      table.add(a, full[a]);
    }
    if (!complete) continue;
    size_t length = 0;
    for (const Path& path : full) length = std::max(length, path.size());
    Solution completed(length, Config(n));
    for (size_t t = 0; t < length; ++t) {
      for (int a = 0; a < n; ++a) completed[t][a] = full[a][std::min(t, full[a].size() - 1)];
    }
    return completed;
  }
  return std::nullopt;
}

std::optional<Solution> complete_by_search(const ExtendedPibt& pibt, const JointSequence& sequence,
                                           const LockSet& lock, DistTable& dist, std::mt19937& rng,
                                           bool forbid_rotations, const Deadline& deadline) {
  const Instance& instance = pibt.instance();
  const Solution& plan = pibt.plan();
  const int n = instance.agent_count();
  const int t_hat = lock.lock_time;
  Waypoints waypoints(n);
  for (int a = 0; a < n; ++a) waypoints[a] = tasks_left(instance, plan, sequence, a, t_hat);
  // The generator as CTS-LaCAM's (cts_lacam.cpp).
  Lacam lacam(*instance.graph, dist, LacamConfig{false, forbid_rotations, /*swap=*/true, /*prefer_free_cells=*/true}, rng);
  const LacamResult found = lacam.solve(plan[t_hat], instance.goals, {}, deadline, waypoints);
  if (!found.solved) return std::nullopt;
  Solution completed(plan.begin(), plan.begin() + t_hat);
  completed.insert(completed.end(), found.solution.begin(), found.solution.end());
  return completed;
}

}  // namespace planner_core
