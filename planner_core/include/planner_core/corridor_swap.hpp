// CorridorSwap: the swap operation of LaCAM3's PIBT (K. Okumura, "Engineering LaCAM*: Towards
// Real-Time, Large-Scale, and Near-Optimal Multi-Agent Pathfinding", AAMAS 2024). Two agents that
// meet head-on in a corridor cannot pass under plain PIBT; the swap rule makes the agent that
// wants the other's cell back off instead and pull the other along, until one of them reaches a
// cell with room to pass. Shared by Extended-PIBT and LaCAM's configuration generator.
#pragma once

#include <functional>
#include <vector>

#include "planner_core/graph.hpp"
#include "planner_core/solution.hpp"

namespace planner_core {

class CorridorSwap {
 public:
  static constexpr int kNobody = -1;
  using Distance = std::function<int(int agent, Vertex v)>;  // to the agent's current target
  using Target = std::function<Vertex(int agent)>;

  // `occupied_now[v]`: the agent at v in the current configuration, or kNobody.
  CorridorSwap(const Graph& graph, const std::vector<int>& occupied_now, Distance distance, Target target);

  // The agent to pull along when `agent`, at `here` and wanting `best`, must back off; kNobody
  // when no swap is needed or possible. to[a] == kNoVertex marks agents not yet given a move.
  int partner(int agent, Vertex here, Vertex best, const Config& to) const;

 private:
  bool required(int pusher, int puller, Vertex pusher_at, Vertex puller_at) const;
  bool possible(Vertex pusher_at, Vertex puller_at) const;
  // Free neighbours of v for a corridor walk: all but `from` and dead ends where an agent sits on
  // its target; returns their number and one of them in `other`.
  int passable_neighbours(Vertex v, Vertex from, Vertex& other) const;

  const Graph& graph_;
  const std::vector<int>& occupied_now_;
  Distance distance_;
  Target target_;
};

}  // namespace planner_core
