// PathTable: a space-time reservation table of agents' paths for prioritized replanning. An agent
// whose path ends rests on its last cell forever after; nobody may be there from then on.
#pragma once

#include <vector>

#include "planner_core/graph.hpp"

namespace planner_core {

using Path = std::vector<Vertex>;  // path[t], t = 0 .. arrival time; the agent stays at path.back() afterwards

class PathTable {
 public:
  static constexpr int kFree = -1;

  explicit PathTable(int vertex_count);
  // `rests`: the agent stays on path.back() forever after (false for a path prefix).
  void add(int agent, const Path& path, bool rests = true);
  // Every agent's path at once (agent = index; each rests on its last cell) into an empty table:
  // O(entries log entries) where adding them one by one costs O(entries x visits per cell), which
  // at 10,000 agents waiting in crowds took seconds.
  void add_all(const std::vector<Path>& paths);
  void remove(int agent, const Path& path);
  // The agent at v at time t, counting agents resting on their final cell, or kFree.
  int occupant(Vertex v, int t) const;
  // The last time any stored path passes v (-1 if none); a resting agent's arrival counts.
  int last_visit(Vertex v) const { return visits_[v].empty() ? -1 : visits_[v].back().t; }
  // The maximal time intervals [first, last] in which v is free (last = kForever for the final one),
  // with the agents at v just before and just after (what occupant(v, first - 1) and
  // occupant(v, last + 1) return; kFree when there is none), for the swap test of a search.
  struct Interval {
    int first;
    int last;
    int occupant_before = kFree;
    int occupant_after = kFree;
  };
  static constexpr int kForever = 1 << 30;
  void safe_intervals(Vertex v, std::vector<Interval>& out) const;
  // Agents whose stored paths visit v at some time.
  void agents_at(Vertex v, std::vector<int>& out) const;
  // Agents other than `except` that visit v at time `from` or later, the latest visitor first, up
  // to `count` of them (appended to `out`).
  void visitors_from(Vertex v, int from, int except, int count, std::vector<int>& out) const;

 private:
  struct Visit {
    int t;
    int agent;
  };
  // Per vertex, the stored paths' visits sorted by time: a cell sees few agents, so safe
  // intervals and look-ups cost O(visits), not O(time horizon).
  std::vector<std::vector<Visit>> visits_;
  std::vector<int> resting_agent_;           // per vertex: who rests there forever, or kFree
  std::vector<int> resting_from_;
};

}  // namespace planner_core
