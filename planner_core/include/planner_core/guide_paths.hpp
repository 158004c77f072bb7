// Guide paths (after Chen et al., "Traffic Flow Optimisation for Lifelong Multi-Agent Path
// Finding", AAAI 2024): each agent keeps a path to its goal that avoids the flows of the others,
// and PIBT tries the path's next cell first. Shortest paths send every agent with far-apart
// errands through the same middle of a map; there streams meet head on, and in the rotation model
// a jam that forms there grows for as long as the run lasts (CITY-02 of the 2024 main round: one
// blob of 719 agents after 600 steps, their rate of errands a third of the start's).
//
// A path's cost counts, for each move from u to v, 1 plus the agents whose remaining paths cross
// that edge the other way (contraflow) plus `vertex_weight` times the remaining paths through v
// (congestion) plus `crowd_weight` times how often an agent stood on v lately (a jam). Paths are
// searched by A* over cells with the distance tables the planner already holds as heuristic
// (turns and lanes included, so it may overestimate: a guide need not be optimal). An agent gets a new path when its goal changes or it stands off its path; each step
// also some others, oldest first, within the time given, so the paths follow the flows.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "planner_core/deadline.hpp"
#include "planner_core/graph.hpp"

namespace planner_core {

struct GuidePathSettings {
  bool on = false;
  double vertex_weight = 0.1;      // cost per other remaining path through a cell
  double crowd_weight = 4;         // cost of a cell taken at every recent step (crowd: 0..1)
  double crowd_memory = 0.95;      // per step, what the crowd figure keeps of its past
  int replans_per_step = 1 << 30;  // agents given a fresh path each step besides those that must, time allowing
  int lookahead = 24;              // how far along its path an agent is looked for
  double off_guide_moves = 1;      // with window LNS: a move off the guide costs this many moves more
};

class GuidePaths {
 public:
  // The heuristic: the planner's cost to `goal` from `cell` (any heading), in moves.
  using Heuristic = std::function<int(Vertex goal, Vertex cell)>;

  GuidePaths(const Graph& graph, GuidePathSettings settings);

  // After a step: agents that passed cells of their paths take those cells' flows off; agents with
  // a new goal or off their path get a new one; then others, oldest first, until the deadline.
  void update(const Config& positions, const Config& goals, const Heuristic& heuristic, const Deadline& deadline);

  // The cell after `here` on the agent's path (here looked for from its last known place on),
  // or kNoVertex when `here` is not on it or is its end.
  Vertex next(int agent, Vertex here) const;

  // The agent's path from its cell as last seen on (up to `most` cells; empty without a path).
  std::span<const Vertex> ahead(int agent, size_t most) const;

  int64_t paths_searched() const { return paths_searched_; }
  // The moves of the agents' remaining paths that go against another's path.
  int64_t contraflow_moves() const;

 private:
  struct Guide {
    std::vector<Vertex> cells;  // from where it was searched to the goal
    size_t at = 0;              // index of the agent's cell, as last seen
    Vertex goal = kNoVertex;
    int64_t searched_step = -1;
  };
  // Direction index (0..3) of the move from u to its neighbour v.
  int direction(Vertex u, Vertex v) const;
  void add_flows(const Guide& guide, int sign);
  // Takes the flows of cells passed off; false when `here` is not on the path ahead.
  bool follow(Guide& guide, Vertex here);
  void search(int agent, Vertex from, Vertex goal, const Heuristic& heuristic);

  const Graph& graph_;
  GuidePathSettings settings_;
  std::vector<Guide> guides_;
  std::vector<int32_t> flow_;   // vertex * 4 + direction: remaining paths leaving the vertex that way
  std::vector<int32_t> load_;   // vertex: remaining paths through it
  std::vector<float> crowd_;    // vertex: how often an agent stood there lately, 0..1
  int64_t step_ = 0;
  size_t next_refresh_ = 0;      // round-robin cursor of the refreshes
  int64_t paths_searched_ = 0;
  // A* scratch, reused
  std::vector<double> g_;
  std::vector<Vertex> parent_;
  std::vector<uint32_t> seen_;
  uint32_t search_id_ = 0;
};

}  // namespace planner_core
