#include "planner_core/corridor_swap.hpp"

#include <utility>

namespace planner_core {

CorridorSwap::CorridorSwap(const Graph& graph, const std::vector<int>& occupied_now, Distance distance, Target target)
    : graph_(graph), occupied_now_(occupied_now), distance_(std::move(distance)), target_(std::move(target)) {}

int CorridorSwap::passable_neighbours(Vertex v, Vertex from, Vertex& other) const {
  int count = 0;
  for (Vertex u : graph_.neighbours(v)) {
    const int occupant = occupied_now_[u];
    const bool parked_in_dead_end = graph_.neighbours(u).size() == 1 && occupant != kNobody && target_(occupant) == u;
    if (u == from || parked_in_dead_end) continue;
    other = u;
    ++count;
  }
  return count;
}

bool CorridorSwap::required(int pusher, int puller, Vertex pusher_at, Vertex puller_at) const {
  // Walk the corridor ahead of the pusher while it leads the pusher closer to its target; a cell
  // with two ways on is room to pass, so no swap is needed.
  Vertex behind = pusher_at, ahead = puller_at;
  // Room to pass at once, the common case away from corridors: then the walk below would stop at
  // its first step, and what is left of the answer needs none of the pusher's distances (cache
  // misses at 10,000 agents), only whether the pusher stands on its target.
  Vertex beyond = kNoVertex;
  if (passable_neighbours(ahead, behind, beyond) >= 2) {
    return target_(pusher) == behind && distance_(puller, behind) < distance_(puller, ahead);
  }
  while (distance_(pusher, ahead) < distance_(pusher, behind)) {
    Vertex next = kNoVertex;
    const int ways = passable_neighbours(ahead, behind, next);
    if (ways >= 2) return false;
    if (ways == 0) break;
    behind = ahead;
    ahead = next;
  }
  return distance_(puller, behind) < distance_(puller, ahead) &&
         (distance_(pusher, behind) == 0 || distance_(pusher, ahead) < distance_(pusher, behind));
}

bool CorridorSwap::possible(Vertex pusher_at, Vertex puller_at) const {
  // Backing off along the corridor must reach a cell with room to let the other pass.
  Vertex behind = pusher_at, ahead = puller_at;
  while (ahead != pusher_at) {
    Vertex next = kNoVertex;
    const int ways = passable_neighbours(ahead, behind, next);
    if (ways >= 2) return true;
    if (ways == 0) return false;
    behind = ahead;
    ahead = next;
  }
  return false;
}

int CorridorSwap::partner(int agent, Vertex here, Vertex best, const Config& to) const {
  // The agent in the cell we want, not yet planned: swap when the corridor leaves no room.
  const int blocker = occupied_now_[best];
  if (blocker != kNobody && blocker != agent && to[blocker] == kNoVertex && required(agent, blocker, here, best) &&
      possible(best, here)) {
    return blocker;
  }
  // The clear operation (as in push-and-swap): a neighbour that must get past us to where we go.
  if (best != here) {
    for (Vertex u : graph_.neighbours(here)) {
      const int neighbour = occupied_now_[u];
      // (whether or not the neighbour has its move already: backing off still makes the room)
      if (u == best || neighbour == kNobody) continue;
      if (required(neighbour, agent, here, best) && possible(best, here)) return neighbour;
    }
  }
  return kNobody;
}

}  // namespace planner_core
