#include "planner_core/guided_distances.hpp"

#include <atomic>
#include <cstdlib>
#include <thread>

#include "planner_core/input_error.hpp"

namespace planner_core {

Guidance parse_guidance(const std::string& text, const std::string& what) {
  if (text == "none") return Guidance::kNone;
  if (text == "lanes") return Guidance::kLanes;
  throw InputError(what + ": \"" + text + "\" is no guidance (none or lanes)");
}

std::string to_string(Guidance guidance) { return guidance == Guidance::kLanes ? "lanes" : "none"; }

namespace {

// The smallest period p in 1..4 for which lines (rows when `rows`, else columns) changing
// direction every p lines hold about as many moves each way; the most even one if none does.
int balanced_period(const Graph& graph, bool rows) {
  int best = 1;
  double best_imbalance = 2;
  for (int period = 1; period <= 4; ++period) {
    int64_t forward = 0, backward = 0;
    for (Vertex v = 0; v < graph.vertex_count(); ++v) {
      const Cell cell = graph.cell_of(v);
      const Cell next = rows ? Cell{cell.x + 1, cell.y} : Cell{cell.x, cell.y + 1};
      if (!graph.is_free(next)) continue;
      const int line = rows ? cell.y : cell.x;
      (line / period % 2 == 0 ? forward : backward) += 1;
    }
    if (forward + backward == 0) return 1;
    const double imbalance =
        static_cast<double>(std::llabs(forward - backward)) / static_cast<double>(forward + backward);
    if (imbalance <= 0.25) return period;
    if (imbalance < best_imbalance) best_imbalance = imbalance, best = period;
  }
  return best;
}

}  // namespace

GuidedDistances::GuidedDistances(const Graph& graph, Guidance guidance)
    : graph_(graph),
      guidance_(guidance),
      row_period_(guidance == Guidance::kLanes ? balanced_period(graph, true) : 1),
      column_period_(guidance == Guidance::kLanes ? balanced_period(graph, false) : 1),
      // The dearest path costs at most kAgainstLaneCost per vertex.
      narrow_(static_cast<int64_t>(graph.vertex_count()) * kAgainstLaneCost < 0xFFFF),
      by_target_(graph.vertex_count()) {}

namespace {

// Dial's algorithm backwards from `target`: a bucket per cost (costs are small integers), so each
// vertex is settled once, in order of its cost to the target.
template <class Cost, class MoveCost>
void search_from(const Graph& graph, Vertex target, std::vector<Cost>& cost, Cost none, const MoveCost& move_cost,
                 int max_move_cost) {
  cost.assign(graph.vertex_count(), none);
  std::vector<std::vector<Vertex>> buckets(max_move_cost + 1);
  cost[target] = 0;
  buckets[0].push_back(target);
  size_t pending = 1;
  for (uint32_t d = 0; pending > 0; ++d) {
    std::vector<Vertex>& bucket = buckets[d % buckets.size()];
    for (size_t i = 0; i < bucket.size(); ++i) {
      const Vertex u = bucket[i];
      if (cost[u] != d) continue;  // settled cheaper already
      for (Vertex v : graph.neighbours(u)) {
        const uint32_t through = d + static_cast<uint32_t>(move_cost(v, u));  // v moves to u
        if (through < cost[v]) {
          cost[v] = static_cast<Cost>(through);
          buckets[through % buckets.size()].push_back(v);
          ++pending;
        }
      }
    }
    pending -= bucket.size();
    bucket.clear();
  }
}

}  // namespace

const GuidedDistances::Table& GuidedDistances::search(Vertex target) {
  auto table = std::make_unique<Table>();
  const auto cost = [this](Vertex from, Vertex to) { return move_cost(from, to); };
  const int dearest = guidance_ == Guidance::kNone ? 1 : kAgainstLaneCost;
  if (narrow_) {
    search_from<uint16_t>(graph_, target, table->narrow, 0xFFFF, cost, dearest);
  } else {
    search_from<uint32_t>(graph_, target, table->wide, 0xFFFFFFFFu, cost, dearest);
  }
  by_target_[target] = std::move(table);
  return *by_target_[target];
}

void GuidedDistances::prepare(const std::vector<Vertex>& targets, const Deadline& deadline, int threads) {
  std::vector<Vertex> missing;
  std::vector<char> listed(by_target_.size(), 0);
  for (Vertex t : targets) {
    if (!held(t) && !listed[t]) {
      listed[t] = 1;
      missing.push_back(t);
    }
  }
  std::atomic<size_t> next{0};
  const auto work = [&] {
    // Each target is searched by one thread only, into its own slot.
    for (size_t k = next++; k < missing.size() && !deadline.expired(); k = next++) search(missing[k]);
  };
  std::vector<std::thread> helpers;
  for (int t = 1; t < threads && static_cast<size_t>(t) < missing.size(); ++t) helpers.emplace_back(work);
  work();
  for (std::thread& helper : helpers) helper.join();
}

}  // namespace planner_core
