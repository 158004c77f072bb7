#include "planner_core/instance_generator.hpp"

#include <algorithm>
#include <random>
#include <set>

#include "planner_core/input_error.hpp"

namespace planner_core {

namespace {

std::vector<Vertex> largest_component(const Graph& graph) {
  std::vector<int> seen(graph.vertex_count(), 0);
  std::vector<Vertex> best;
  for (Vertex root = 0; root < graph.vertex_count(); ++root) {
    if (seen[root]) continue;
    std::vector<Vertex> piece{root};
    seen[root] = 1;
    for (size_t head = 0; head < piece.size(); ++head) {
      for (Vertex u : graph.neighbours(piece[head])) {
        if (!seen[u]) {
          seen[u] = 1;
          piece.push_back(u);
        }
      }
    }
    if (piece.size() > best.size()) best = std::move(piece);
  }
  std::sort(best.begin(), best.end());
  return best;
}

std::vector<Vertex> sample(const std::vector<Vertex>& from, int count, std::mt19937& rng) {
  std::vector<Vertex> picked;
  std::sample(from.begin(), from.end(), std::back_inserter(picked), count, rng);
  std::shuffle(picked.begin(), picked.end(), rng);
  return picked;
}

}  // namespace

Instance generate_instance(std::shared_ptr<const Graph> graph, const GeneratorSettings& settings) {
  if (settings.agents <= 0) throw InputError("generator: the number of agents must be positive");
  if (settings.tasks < 0) throw InputError("generator: the number of tasks must not be negative");
  if (settings.kmax <= 0) throw InputError("generator: kmax must be positive");
  const std::vector<Vertex> cells = largest_component(*graph);
  const int n = settings.agents, m = settings.tasks;
  if (static_cast<int>(cells.size()) < n + m || static_cast<int>(cells.size()) < 2 * n) {
    throw InputError("generator: map " + graph->name + " has " + std::to_string(cells.size()) +
                     " connected free cells, too few for " + std::to_string(n) + " agents and " + std::to_string(m) +
                     " tasks");
  }
  std::mt19937 rng(settings.seed);
  Instance instance;
  instance.graph = graph;
  instance.source = "generated";
  instance.starts = sample(cells, n, rng);
  instance.goals = sample(cells, n, rng);  // a goal may be another agent's start
  std::set<Vertex> used(instance.starts.begin(), instance.starts.end());
  used.insert(instance.goals.begin(), instance.goals.end());
  std::vector<Vertex> rest;
  for (Vertex v : cells) {
    if (!used.count(v)) rest.push_back(v);
  }
  if (static_cast<int>(rest.size()) < m) throw InputError("generator: not enough free cells left for the tasks");
  const std::vector<Vertex> task_cells = sample(rest, m, rng);
  std::vector<int> everyone(n);
  for (int a = 0; a < n; ++a) everyone[a] = a;
  std::vector<int> guaranteed = everyone;
  std::shuffle(guaranteed.begin(), guaranteed.end(), rng);
  std::uniform_int_distribution<int> how_many(1, std::min(settings.kmax, n));
  for (int t = 0; t < m; ++t) {
    std::vector<int> agents;
    std::sample(everyone.begin(), everyone.end(), std::back_inserter(agents), how_many(rng), rng);
    if (t < n && m >= n && std::find(agents.begin(), agents.end(), guaranteed[t]) == agents.end()) {
      agents.push_back(guaranteed[t]);
    }
    std::sort(agents.begin(), agents.end());
    instance.tasks.push_back({task_cells[t], agents});
  }
  instance.index_tasks();
  return instance;
}

}  // namespace planner_core
