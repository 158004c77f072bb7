// ctsfleet-seqbench: measures task sequencing: Held-Karp time per task count (to choose the
// exact limit) and the time for K-best joint sequences on benchmark instances.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <random>

#include "planner_core/deadline.hpp"
#include "planner_core/joint_sequencer.hpp"

int main(int argc, char** argv) {
  using namespace planner_core;
  CLI::App app{"ctsfleet-seqbench: timing of Held-Karp ordering and K-best joint sequencing"};
  std::string map_path, instance_path;
  int sequences = 1000;
  app.add_option("--map", map_path, "map for the Held-Karp sweep")->required();
  app.add_option("--instance", instance_path, "instance for the K-best joint timing");
  app.add_option("-k,--sequences", sequences, "joint sequences to generate")->capture_default_str();
  CLI11_PARSE(app, argc, argv);

  auto graph = std::make_shared<const Graph>(load_movingai_map(map_path));
  std::mt19937 rng(1);
  std::printf("| tasks | Held-Karp best order (ms) | heuristic best order (ms) | heuristic / exact cost |\n|---|---|---|---|\n");
  for (int m = 8; m <= 20; ++m) {
    Instance instance;
    instance.graph = graph;
    std::vector<Vertex> cells(graph->vertex_count());
    for (Vertex v = 0; v < graph->vertex_count(); ++v) cells[v] = v;
    std::shuffle(cells.begin(), cells.end(), rng);
    instance.starts = {cells[0]};
    instance.goals = {cells[1]};
    for (int t = 0; t < m; ++t) instance.tasks.push_back({cells[2 + t], {0}});
    instance.index_tasks();
    DistTable dist(*graph);
    for (int t = 0; t < m + 2; ++t) {  // every distance the ordering needs, before the timing
      for (int s = 0; s < m + 2; ++s) dist.get(cells[t], cells[s]);
    }
    Clock::time_point start = Clock::now();
    KBestOrders exact(instance, 0, dist, TaskOrderConfig{24});
    const int exact_cost = exact.get(0)->cost;
    const double exact_ms = elapsed_ms(start);
    start = Clock::now();
    KBestOrders heuristic(instance, 0, dist, TaskOrderConfig{0});
    const int heuristic_cost = heuristic.get(0)->cost;
    const double heuristic_ms = elapsed_ms(start);
    std::printf("| %d | %.2f | %.3f | %.3f |\n", m, exact_ms, heuristic_ms,
                static_cast<double>(heuristic_cost) / exact_cost);
  }
  if (!instance_path.empty()) {
    const Instance instance = load_instance(instance_path);
    const Clock::time_point start = Clock::now();
    DistTable dist(*instance.graph);
    JointSequencer sequencer(instance, dist, TaskOrderConfig{});
    int produced = 0;
    int64_t last_cost = 0;
    while (produced < sequences) {
      const auto sequence = sequencer.next();
      if (!sequence) break;
      last_cost = sequence->cost;
      ++produced;
    }
    std::printf("\n%s: %d joint sequences in %.1f ms (including distance tables), costs %lld .. %lld\n",
                instance_path.c_str(), produced, elapsed_ms(start), static_cast<long long>(sequencer.lower_bound()),
                static_cast<long long>(last_cost));
  }
  return 0;
}
