// Distances over a guidance graph: with no guidance they are the shortest paths; with one-way
// lanes (and with a ring road) they are the cheapest costs a plain Bellman-Ford finds over the
// same move costs, and the lanes' period follows the map's streets.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "planner_core/dist_table.hpp"
#include "planner_core/guided_distances.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/lorr_problem.hpp"

namespace planner_core {
namespace {

const std::string kRandom = std::string(CTSFLEET_BENCHMARKS_DIR) + "/lorr-2023/random.domain/";

TEST(GuidedDistances, WithoutGuidanceTheyAreShortestPaths) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_20.json");
  const Graph& graph = *problem.graph;
  GuidedDistances guided(graph, Guidance::kNone);
  DistTable shortest(graph);
  std::mt19937 rng(3);
  std::uniform_int_distribution<Vertex> any(0, graph.vertex_count() - 1);
  for (int k = 0; k < 20; ++k) {
    const Vertex target = any(rng);
    for (Vertex v = 0; v < graph.vertex_count(); ++v) {
      const int expected = shortest.get(target, v);
      ASSERT_EQ(guided.get(target, v), expected == kUnreachable ? GuidedDistances::kUnreachable : expected);
    }
  }
}

// Bellman-Ford over the move costs, as plainly as it can be written.
std::vector<int64_t> cheapest_to(const Graph& graph, const GuidedDistances& guided, Vertex target) {
  std::vector<int64_t> cost(graph.vertex_count(), GuidedDistances::kUnreachable);
  cost[target] = 0;
  for (bool changed = true; changed;) {
    changed = false;
    for (Vertex v = 0; v < graph.vertex_count(); ++v) {
      for (Vertex u : graph.neighbours(v)) {
        if (cost[u] + guided.move_cost(v, u) < cost[v]) {
          cost[v] = cost[u] + guided.move_cost(v, u);
          changed = true;
        }
      }
    }
  }
  return cost;
}

TEST(GuidedDistances, WithLanesTheyAreTheCheapestCosts) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_20.json");
  const Graph& graph = *problem.graph;
  GuidedDistances guided(graph, Guidance::kLanes);
  std::mt19937 rng(5);
  std::uniform_int_distribution<Vertex> any(0, graph.vertex_count() - 1);
  int dearer = 0;
  for (int k = 0; k < 10; ++k) {
    const Vertex target = any(rng);
    const std::vector<int64_t> expected = cheapest_to(graph, guided, target);
    for (Vertex v = 0; v < graph.vertex_count(); ++v) {
      ASSERT_EQ(guided.get(target, v), expected[v]) << "from " << to_string(graph.cell_of(v));
    }
  }
  // A move is dearer against its lane than with it, and every move is one or the other.
  for (Vertex v = 0; v < graph.vertex_count(); ++v) {
    for (Vertex u : graph.neighbours(v)) {
      const int there = guided.move_cost(v, u), back = guided.move_cost(u, v);
      EXPECT_TRUE((there == 1 && back == GuidedDistances::kAgainstLaneCost) ||
                  (there == GuidedDistances::kAgainstLaneCost && back == 1));
      dearer += there > 1 ? 1 : 0;
    }
  }
  EXPECT_GT(dearer, 0);
}

// A ring road: the lanes' costs in tenths, less near the map's edge; the tables are still the
// cheapest costs, also in the rotation model where a turn costs the stay cost of its cell.
TEST(GuidedDistances, ARingRoadMakesTheEdgeCheaper) {
  const LorrProblem problem = load_lorr_problem(kRandom + "random_20.json");
  const Graph& graph = *problem.graph;
  GuidedDistances ring(graph, Guidance::kRing, ActionModel::kMove4, 2);
  const GuidedDistances lanes(graph, Guidance::kLanes, ActionModel::kMove4, 2);
  const int unit = GuidedDistances::kRingUnit;
  EXPECT_EQ(ring.cost_unit(), unit);
  EXPECT_EQ(lanes.cost_unit(), 1);
  EXPECT_EQ(ring.stay_cost(), 2 * unit);
  int on_the_ring = 0, inside = 0;
  for (Vertex v = 0; v < graph.vertex_count(); ++v) {
    const Cell c = graph.cell_of(v);
    const int depth = std::min({c.x, c.y, graph.width() - 1 - c.x, graph.height() - 1 - c.y});
    const int discount = GuidedDistances::ring_discount_at(depth);
    (discount > 0 ? on_the_ring : inside) += 1;
    EXPECT_EQ(ring.stay_cost(v), 2 * unit - discount);
    for (Vertex u : graph.neighbours(v)) {
      // The same lanes, in tenths, with the cell's discount.
      ASSERT_EQ(ring.move_cost(v, u), lanes.move_cost(v, u) * unit - discount) << to_string(c);
    }
  }
  // The discount: 6 tenths at the edge, half a tenth less a cell in (rounded up), none from 12 in.
  EXPECT_EQ(GuidedDistances::ring_discount_at(0), 6);
  EXPECT_EQ(GuidedDistances::ring_discount_at(1), 6);
  EXPECT_EQ(GuidedDistances::ring_discount_at(2), 5);
  EXPECT_EQ(GuidedDistances::ring_discount_at(11), 1);
  EXPECT_EQ(GuidedDistances::ring_discount_at(12), 0);
  EXPECT_EQ(GuidedDistances::ring_discount_at(40), 0);
  EXPECT_GT(on_the_ring, 0);
  EXPECT_GT(inside, 0);
  std::mt19937 rng(7);
  std::uniform_int_distribution<Vertex> any(0, graph.vertex_count() - 1);
  for (int k = 0; k < 5; ++k) {
    const Vertex target = any(rng);
    const std::vector<int64_t> expected = cheapest_to(graph, ring, target);
    for (Vertex v = 0; v < graph.vertex_count(); ++v) ASSERT_EQ(ring.get(target, v), expected[v]);
  }
  // Rotation model on a corridor along the top edge (depth 0 everywhere): a turn costs the
  // cell's stay cost, 2 units less its discount.
  constexpr int kEast = 0, kWest = 2;
  const Graph corridor(5, 1, {"....."});
  GuidedDistances turning(corridor, Guidance::kRing, ActionModel::kRotate, 2);
  const Vertex start = corridor.vertex_at({0, 0}), goal = corridor.vertex_at({4, 0});
  const int along = unit - GuidedDistances::ring_discount_at(0);  // row 0 runs east
  EXPECT_EQ(turning.get(goal, start, kEast), 4 * along);
  EXPECT_EQ(turning.get(goal, start, kWest), 2 * (2 * unit - GuidedDistances::ring_discount_at(0)) + 4 * along);
}

TEST(GuidedDistances, LanesFollowTheStreets) {
  // Streets only on even rows and odd columns, as on a sortation floor: lanes alternating row by
  // row would send every street the same way.
  std::vector<std::string> rows;
  for (int y = 0; y < 12; ++y) {
    std::string row;
    for (int x = 0; x < 16; ++x) row += (y % 2 == 1 && x % 2 == 0) ? '@' : '.';
    rows.push_back(row);
  }
  const Graph sortation(16, 12, rows);
  const GuidedDistances on_streets(sortation, Guidance::kLanes);
  EXPECT_EQ(on_streets.row_period(), 2);
  EXPECT_EQ(on_streets.column_period(), 2);
  const Vertex west_end = sortation.vertex_at({0, 0}), next = sortation.vertex_at({1, 0});
  const Vertex lower_street = sortation.vertex_at({0, 2}), its_next = sortation.vertex_at({1, 2});
  EXPECT_NE(on_streets.move_cost(west_end, next), on_streets.move_cost(lower_street, its_next));

  const Graph open(8, 8, std::vector<std::string>(8, "........"));
  const GuidedDistances on_open(open, Guidance::kLanes);
  EXPECT_EQ(on_open.row_period(), 1);
  EXPECT_EQ(on_open.column_period(), 1);
}

// A wait and a quarter turn cost stay_cost: an agent facing away from its goal pays two turns at
// that cost; one facing it pays none, and four-move tables do not change.
TEST(GuidedDistances, TurnsCostWhatAWaitCosts) {
  constexpr int kEast = 0, kWest = 2, kNorth = 3;  // headings (action_model.hpp)
  const Graph graph(5, 1, {"....."});
  const Vertex start = graph.vertex_at({0, 0}), goal = graph.vertex_at({4, 0});
  for (int stay_cost : {1, 3, GuidedDistances::kMaxStayCost}) {
    for (Guidance guidance : {Guidance::kNone, Guidance::kLanes}) {
      GuidedDistances turning(graph, guidance, ActionModel::kRotate, stay_cost);
      EXPECT_EQ(turning.stay_cost(), stay_cost);
      EXPECT_EQ(turning.get(goal, start, kEast), 4) << stay_cost;  // row 0 runs east
      EXPECT_EQ(turning.get(goal, start, kWest), 2 * stay_cost + 4) << stay_cost;
      EXPECT_EQ(turning.get(goal, start, kNorth), stay_cost + 4) << stay_cost;
      GuidedDistances four_moves(graph, guidance, ActionModel::kMove4, stay_cost);
      EXPECT_EQ(four_moves.get(goal, start), 4);
    }
  }
  for (int bad : {0, -1, GuidedDistances::kMaxStayCost + 1}) {
    EXPECT_THROW(GuidedDistances(graph, Guidance::kLanes, ActionModel::kRotate, bad), std::invalid_argument) << bad;
  }
}

// A crowded cell (traffic_costs.hpp) costs more to enter and to wait or turn on: distances are
// searched again over the new costs, and a way round it is taken once that is cheaper.
TEST(GuidedDistances, TrafficCostsMakeACrowdedCellDearerAndWaysGoRoundIt) {
  const Graph graph(3, 3, {"...", "...", "..."});
  const Vertex west = graph.vertex_at({0, 1}), middle = graph.vertex_at({1, 1}), east = graph.vertex_at({2, 1});
  GuidedDistances guided(graph, Guidance::kNone, ActionModel::kMove4, 1, GuidedDistances::kMaxTrafficMoves);
  EXPECT_EQ(guided.get(east, west), 2);  // through the middle
  std::vector<int> costs(graph.vertex_count(), 0);
  costs[middle] = 1;
  guided.set_traffic_costs(costs);
  EXPECT_EQ(guided.move_cost(west, middle), 2);
  EXPECT_EQ(guided.stay_cost(middle), 2);
  EXPECT_EQ(guided.stay_cost(west), 1);
  EXPECT_EQ(guided.get(east, west), 3) << "still through the middle, 1 dearer";
  costs[middle] = GuidedDistances::kMaxTrafficMoves;
  guided.set_traffic_costs(costs);
  EXPECT_EQ(guided.get(east, west), 4) << "round the middle: four moves";
  EXPECT_EQ(guided.get(middle, west), 1 + GuidedDistances::kMaxTrafficMoves);
  // In the rotation model turning on a crowded cell costs as much more as waiting there.
  GuidedDistances turning(graph, Guidance::kNone, ActionModel::kRotate, 1, 2);
  std::vector<int> crowded_west(graph.vertex_count(), 0);
  crowded_west[west] = 2;
  constexpr int kEast = 0, kWest = 2;
  EXPECT_EQ(turning.get(east, west, kWest), 4);  // two turns and two moves
  turning.set_traffic_costs(crowded_west);
  EXPECT_EQ(turning.get(east, west, kWest), 8) << "each turn 2 dearer";
  EXPECT_EQ(turning.get(east, west, kEast), 2) << "leaving costs nothing more";
}

TEST(GuidedDistances, TrafficCostsOutOfRangeAreRefused) {
  const Graph graph(3, 1, {"..."});
  GuidedDistances lanes(graph, Guidance::kLanes, ActionModel::kMove4, 1, 2);
  EXPECT_EQ(lanes.max_traffic_cost(), 2);
  EXPECT_THROW(lanes.set_traffic_costs({0, 0}), std::invalid_argument) << "one per cell";
  EXPECT_THROW(lanes.set_traffic_costs({0, 3, 0}), std::invalid_argument) << "above the largest";
  EXPECT_THROW(lanes.set_traffic_costs({0, -1, 0}), std::invalid_argument);
  GuidedDistances ring(graph, Guidance::kRing, ActionModel::kMove4, 1, 2);
  EXPECT_EQ(ring.max_traffic_cost(), 2 * GuidedDistances::kRingUnit) << "in tenths of a move";
  GuidedDistances none(graph, Guidance::kLanes);
  EXPECT_EQ(none.max_traffic_cost(), 0);
  EXPECT_THROW(none.set_traffic_costs({0, 1, 0}), std::invalid_argument) << "none allowed";
  for (int bad : {-1, GuidedDistances::kMaxTrafficMoves + 1}) {
    EXPECT_THROW(GuidedDistances(graph, Guidance::kLanes, ActionModel::kMove4, 1, bad), std::invalid_argument) << bad;
  }
}

TEST(GuidedDistances, AnUnknownGuidanceIsNamed) {
  EXPECT_EQ(parse_guidance("lanes", "--guidance"), Guidance::kLanes);
  EXPECT_EQ(parse_guidance("none", "--guidance"), Guidance::kNone);
  EXPECT_EQ(parse_guidance("ring", "--guidance"), Guidance::kRing);
  EXPECT_EQ(to_string(Guidance::kRing), "ring");
  try {
    parse_guidance("highway", "guidance (config.yaml line 4)");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("config.yaml line 4"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("highway"), std::string::npos);
  }
}

}  // namespace
}  // namespace planner_core
