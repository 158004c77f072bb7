// ctsfleet-seqbench: measures task sequencing: Held-Karp time per task count (to choose the
// exact limit) and the time for K-best joint sequences on benchmark instances.

#include <cstdio>
#include <random>

#include "ctsfleet/program.hpp"
#include "planner_core/deadline.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/joint_sequencer.hpp"

namespace {

// The free cells of the map's largest 4-connected piece.
std::vector<planner_core::Vertex> largest_connected_piece(const planner_core::Graph& graph) {
  using planner_core::Vertex;
  std::vector<int> piece_of(graph.vertex_count(), -1);
  std::vector<Vertex> best;
  for (Vertex root = 0; root < graph.vertex_count(); ++root) {
    if (piece_of[root] != -1) continue;
    std::vector<Vertex> piece{root};
    piece_of[root] = root;
    for (size_t i = 0; i < piece.size(); ++i) {
      for (Vertex next : graph.neighbours(piece[i])) {
        if (piece_of[next] == -1) {
          piece_of[next] = root;
          piece.push_back(next);
        }
      }
    }
    if (piece.size() > best.size()) best = std::move(piece);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace planner_core;
  ctsfleet::Program program("ctsfleet-seqbench", "timing of Held-Karp ordering and K-best joint sequencing");
  CLI::App& app = program.app();
  std::string map_path, instance_path;
  int sequences = 1000;
  constexpr int kMostTasks = 20;
  app.add_option("--map", map_path, "map for the Held-Karp sweep")->required()->check(CLI::ExistingFile);
  app.add_option("--instance", instance_path, "instance for the K-best joint timing")->check(CLI::ExistingFile);
  app.add_option("-k,--sequences", sequences, "joint sequences to generate")
      ->check(ctsfleet::count_in(1, 10'000'000))
      ->capture_default_str();
  return program.main(argc, argv, [&] {
    auto graph = std::make_shared<const Graph>(load_movingai_map(map_path));
    // The sweep draws a start, a goal and up to kMostTasks tasks from one connected piece of the map.
    std::vector<Vertex> piece = largest_connected_piece(*graph);
    if (static_cast<int>(piece.size()) < kMostTasks + 2) {
      throw InputError(map_path + ": the sweep needs " + std::to_string(kMostTasks + 2) +
                       " connected free cells, the largest connected piece has " + std::to_string(piece.size()));
    }
    std::mt19937 rng(1);
    std::printf("| tasks | Held-Karp best order (ms) | heuristic best order (ms) | heuristic / exact cost |\n|---|---|---|---|\n");
    for (int m = 8; m <= kMostTasks; ++m) {
      Instance instance;
      instance.graph = graph;
      std::vector<Vertex> cells = piece;
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
  });
}
