#include "planner_core/guided_distances.hpp"

#include <atomic>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>

#include "planner_core/input_error.hpp"

namespace planner_core {

Guidance parse_guidance(const std::string& text, const std::string& what) {
  if (text == "none") return Guidance::kNone;
  if (text == "lanes") return Guidance::kLanes;
  if (text == "ring") return Guidance::kRing;
  throw InputError(what + ": \"" + text + "\" is no guidance (none, lanes or ring)");
}

std::string to_string(Guidance guidance) {
  switch (guidance) {
    case Guidance::kNone:
      return "none";
    case Guidance::kLanes:
      return "lanes";
    case Guidance::kRing:
      return "ring";
  }
  return "?";
}

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

// Per vertex, what a move or wait from it costs less for being near the map's edge (kRing).
std::vector<uint8_t> ring_discounts(const Graph& graph) {
  std::vector<uint8_t> discount(graph.vertex_count(), 0);
  for (Vertex v = 0; v < graph.vertex_count(); ++v) {
    const Cell c = graph.cell_of(v);
    const int depth = std::min({c.x, c.y, graph.width() - 1 - c.x, graph.height() - 1 - c.y});
    discount[v] = static_cast<uint8_t>(GuidedDistances::ring_discount_at(depth));
  }
  return discount;
}

int checked_traffic_moves(int moves) {
  if (moves < 0 || moves > GuidedDistances::kMaxTrafficMoves) {
    throw std::invalid_argument("GuidedDistances: traffic costs of at most 0.." +
                                std::to_string(GuidedDistances::kMaxTrafficMoves) + " moves, not " + std::to_string(moves));
  }
  return moves;
}

int checked_stay_cost(int stay_cost) {
  if (stay_cost < 1 || stay_cost > GuidedDistances::kMaxStayCost) {
    throw std::invalid_argument("GuidedDistances: a wait's cost must be 1.." +
                                std::to_string(GuidedDistances::kMaxStayCost) + ", not " + std::to_string(stay_cost));
  }
  return stay_cost;
}

}  // namespace

GuidedDistances::GuidedDistances(const Graph& graph, Guidance guidance, ActionModel actions, int stay_cost,
                                 int max_traffic_moves)
    : graph_(graph),
      guidance_(guidance),
      actions_(actions),
      headings_(actions == ActionModel::kRotate ? kHeadings : 1),
      row_period_(guidance == Guidance::kNone ? 1 : balanced_period(graph, true)),
      column_period_(guidance == Guidance::kNone ? 1 : balanced_period(graph, false)),
      stay_cost_(checked_stay_cost(stay_cost)),
      unit_(guidance == Guidance::kRing ? kRingUnit : 1),
      discount_(guidance == Guidance::kRing ? ring_discounts(graph) : std::vector<uint8_t>{}),
      max_traffic_cost_(checked_traffic_moves(max_traffic_moves) * unit_),
      // The dearest path costs at most the dearest action per state.
      narrow_(static_cast<int64_t>(graph.vertex_count()) * static_cast<int64_t>(headings_) * dearest_action() < 0xFFFF),
      by_target_(graph.vertex_count()) {}

bool GuidedDistances::set_traffic_costs(std::vector<int> costs) {
  if (costs.size() != static_cast<size_t>(graph_.vertex_count())) {
    throw std::invalid_argument("GuidedDistances: " + std::to_string(costs.size()) + " traffic costs for " +
                                std::to_string(graph_.vertex_count()) + " cells");
  }
  for (int cost : costs) {
    if (cost < 0 || cost > max_traffic_cost_) {
      throw std::invalid_argument("GuidedDistances: a traffic cost of " + std::to_string(cost) + ", not within 0.." +
                                  std::to_string(max_traffic_cost_));
    }
  }
  const bool none_before = traffic_.empty() && std::all_of(costs.begin(), costs.end(), [](int c) { return c == 0; });
  if (none_before || costs == traffic_) return false;
  traffic_ = std::move(costs);
  for (auto& table : by_target_) table.reset();
  return true;
}

namespace {

// Dial's algorithm backwards from the `targets` states: a bucket per cost (costs are small
// integers), so each state is settled once, in order of its cost to the nearest target.
// `predecessors(state, visit)` calls visit(earlier, cost) for each state one step before `state`.
template <class Cost, class Predecessors>
void search_from(size_t states, const std::vector<size_t>& targets, std::vector<Cost>& cost, Cost none,
                 const Predecessors& predecessors, int max_step_cost) {
  cost.assign(states, none);
  std::vector<std::vector<size_t>> buckets(max_step_cost + 1);
  for (size_t target : targets) {
    cost[target] = 0;
    buckets[0].push_back(target);
  }
  size_t pending = targets.size();
  for (uint32_t d = 0; pending > 0; ++d) {
    std::vector<size_t>& bucket = buckets[d % buckets.size()];
    for (size_t i = 0; i < bucket.size(); ++i) {
      const size_t u = bucket[i];
      if (cost[u] != d) continue;  // settled cheaper already
      predecessors(u, [&](size_t v, int step_cost) {
        const uint32_t through = d + static_cast<uint32_t>(step_cost);  // v steps to u
        if (through < cost[v]) {
          cost[v] = static_cast<Cost>(through);
          buckets[through % buckets.size()].push_back(v);
          ++pending;
        }
      });
    }
    pending -= bucket.size();
    bucket.clear();
  }
}

}  // namespace

const GuidedDistances::Table& GuidedDistances::search(Vertex target) {
  auto table = std::make_unique<Table>();
  const int dearest = dearest_action();
  const size_t states = static_cast<size_t>(graph_.vertex_count()) * headings_;
  std::vector<size_t> targets;
  // Four moves: a cell's neighbours step to it.
  const auto move4 = [this](size_t u, const auto& visit) {
    for (Vertex v : graph_.neighbours(static_cast<Vertex>(u))) visit(static_cast<size_t>(v), move_cost(v, static_cast<Vertex>(u)));
  };
  // Rotation: (cell, h) is reached by turning in place from (cell, h - 1) and (cell, h + 1), or
  // by a step forward from the cell behind it, facing h.
  const auto rotate = [this](size_t u, const auto& visit) {
    const Vertex cell = static_cast<Vertex>(u / kHeadings);
    const int heading = static_cast<int>(u % kHeadings);
    const size_t base = static_cast<size_t>(cell) * kHeadings;
    visit(base + static_cast<size_t>(turned_clockwise(heading)), stay_cost(cell));
    visit(base + static_cast<size_t>(turned_counter_clockwise(heading)), stay_cost(cell));
    const Vertex behind = ahead(graph_, cell, (heading + 2) % kHeadings);
    if (behind != kNoVertex) visit(static_cast<size_t>(behind) * kHeadings + static_cast<size_t>(heading), move_cost(behind, cell));
  };
  for (size_t h = 0; h < headings_; ++h) targets.push_back(static_cast<size_t>(target) * headings_ + h);
  const auto run = [&](auto& cost, auto none) {
    if (actions_ == ActionModel::kRotate) {
      search_from(states, targets, cost, none, rotate, dearest);
    } else {
      search_from(states, targets, cost, none, move4, dearest);
    }
  };
  if (narrow_) {
    run(table->narrow, uint16_t{0xFFFF});
  } else {
    run(table->wide, uint32_t{0xFFFFFFFFu});
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
