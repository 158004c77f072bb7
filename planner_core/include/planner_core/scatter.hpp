// Scatter: one path per agent, start to goal, chosen so that the agents' paths share cells and
// moments as little as possible (space-utilisation optimisation, SUO: S. D. Han and J. Yu,
// "Optimizing Space Utilization for More Effective Multi-Robot Path Planning", ICRA 2022; used as
// guidance for PIBT in lacam3, Okumura, AAMAS 2024).
//
// Each path is at most `cost_margin` steps longer than the agent's shortest one and never waits.
// Agents are planned one at a time against everyone else's current path, fewest collisions first,
// then shortest; rounds over all agents (in a new random order each) go on while the count of
// collisions falls. The paths are not a plan: they still collide. PIBT takes an agent's next cell
// on its path as the first choice (LacamConfig::guide), which spreads crowds over parallel
// corridors instead of sending everyone down the single shortest one.
//
// With waypoints (CTS-MAPF: an agent's task cells in its order, then its goal) a path goes through
// them leg by leg, each leg at most `cost_margin` longer than its shortest; Extended-PIBT then
// takes an agent's next cell on the leg it is on (PibtConfig::scatter).
#pragma once

#include <cstdint>
#include <random>
#include <tuple>
#include <utility>
#include <vector>

#include "planner_core/deadline.hpp"
#include "planner_core/dist_table.hpp"
#include "planner_core/graph.hpp"
#include "planner_core/path_table.hpp"
#include "planner_core/instance.hpp"

namespace planner_core {

struct ScatterStats {
  int rounds = 0;          // rounds over all agents begun
  int64_t collisions = 0;  // vertex, swap and goal collisions between the final paths
  int64_t sum_of_lengths = 0;
  bool complete = false;   // every agent has a path (false when the deadline came first)
};

// The margin the solvers use: each path (or leg) at most this many steps longer than its shortest,
// as lacam3.
constexpr int kScatterMargin = 10;
// The share of the time left that the solvers give Scatter to build its paths.
constexpr double kScatterTimeShare = 0.25;

class Scatter {
 public:
  // `waypoints[a]`: the cells agent a visits in this order before its goal (none: empty or no row).
  Scatter(const Graph& graph, DistTable& dist, const Config& starts, const Config& goals, int cost_margin,
          uint32_t seed, const std::vector<std::vector<Vertex>>& waypoints = {});

  // Plans the paths until the collisions stop falling or the deadline passes; an agent without a
  // path by then simply gets no guidance.
  ScatterStats build(const Deadline& deadline);

  // The cell after v on the agent's path (on its leg `leg`: 0 = towards its first waypoint), or
  // kNoVertex when v is not on that leg (or ends it).
  Vertex next(int agent, Vertex v) const { return next(agent, 0, v); }
  Vertex next(int agent, int leg, Vertex v) const;

 private:
  struct Visit {
    int t;
    int agent;
  };
  int collision_cost(Vertex from, Vertex to, int t_from) const;
  int64_t path_collisions(const Path& path) const;
  void enrol(int agent);
  void clear(int agent);
  bool plan(int agent, const Deadline& deadline);
  // Appends the best leg from path.back() to `target` (path non-empty); false if none was found.
  bool plan_leg(Path& path, Vertex target, const Deadline& deadline);

  const Graph& graph_;
  DistTable& dist_;
  const Config starts_;
  const Config goals_;
  std::vector<std::vector<Vertex>> targets_;  // per agent: waypoints, then the goal
  const int cost_margin_;
  std::mt19937 rng_;
  std::vector<Path> paths_;
  std::vector<std::vector<int>> leg_ends_;  // per agent: the time at which each leg of its path ends
  std::vector<std::vector<Visit>> visits_;   // per vertex, by time (several agents may share one)
  std::vector<std::vector<int>> arrivals_;   // per vertex: when paths ending there arrive
  int64_t collisions_ = 0;
  // Per agent (leg, v, next) along its path, sorted, for next().
  struct Step {
    int leg;
    Vertex v;
    Vertex next;
    bool operator<(const Step& other) const { return std::tie(leg, v) < std::tie(other.leg, other.v); }
  };
  std::vector<std::vector<Step>> steps_;
  // A*'s scratch: per vertex its parent in the current search (valid when stamp_ matches).
  std::vector<Vertex> parent_;
  std::vector<uint32_t> closed_stamp_;
  uint32_t stamp_ = 0;
};

}  // namespace planner_core
