#include "planner_core/safe_interval_planning.hpp"

#include <algorithm>
#include <cstdint>

#include "planner_core/action_model.hpp"

namespace planner_core {

SafeIntervalPlanner::SafeIntervalPlanner(const Graph& graph)
    : graph_(graph),
      interval_stamp_(graph.vertex_count(), 0),
      intervals_(graph.vertex_count()),
      best_stamp_(graph.vertex_count(), 0),
      best_arrival_(graph.vertex_count()) {}

namespace {

// Moving from -> to at time t, where `to` was occupied at t-1 by an agent leaving it at t: follows
// the chain of agents ahead (each leaving a cell for the next one's) and reports whether it ends
// back in `from`, which would make the move part of a rotation. A chain longer than kLongestChain
// is taken as closing (refusing a move is always safe).
bool closes_rotation(const Graph& graph, const PathTable& table, Vertex from, Vertex to, int t) {
  constexpr int kLongestChain = 64;
  Vertex cell = to;
  for (int hop = 0; hop < kLongestChain; ++hop) {
    const int leaver = table.occupant(cell, t - 1);
    if (leaver == PathTable::kFree) return false;  // the chain ends in a cell that was free
    Vertex next = kNoVertex;
    for (Vertex w : graph.neighbours(cell)) {
      if (table.occupant(w, t) == leaver) {
        next = w;
        break;
      }
    }
    if (next == kNoVertex) return false;  // the leaver's path ends here (a path prefix): no cycle
    if (next == from) return true;
    cell = next;
  }
  return true;
}

}  // namespace

Path SafeIntervalPlanner::search(DistTable& dist, GuidedDistances* turning, const PathTable& table, Vertex start,
                                 int start_heading,
                                 const std::vector<Vertex>& targets, const SpaceTimeLimits& limits, int start_time,
                                 std::vector<int>* headings) {
  const Graph& graph = graph_;
  const bool turning_model = start_heading >= 0;
  const int heading_slots = turning_model ? kHeadings : 1;
  const int target_count = static_cast<int>(targets.size());
  const Vertex goal = targets.back();
  std::vector<int> suffix(target_count, 0);  // suffix[k]: from targets[k] through the rest to the goal
  for (int k = target_count - 2; k >= 0; --k) suffix[k] = suffix[k + 1] + dist.get(targets[k + 1], targets[k]);
  const auto advance = [&](Vertex v, int done) {  // several targets in a row may share a cell
    while (done < target_count - 1 && targets[done] == v) ++done;
    return done;
  };

  // Safe intervals are read from the table once per call and vertex; the scratch is kept between
  // calls, and a new stamp makes every entry stale at once.
  if (++stamp_ == 0) {
    std::fill(interval_stamp_.begin(), interval_stamp_.end(), 0);
    std::fill(best_stamp_.begin(), best_stamp_.end(), 0);
    stamp_ = 1;
  }
  const auto intervals = [&](Vertex v) -> const std::vector<PathTable::Interval>& {
    if (interval_stamp_[v] != stamp_) {
      interval_stamp_[v] = stamp_;
      table.safe_intervals(v, intervals_[v]);
    }
    return intervals_[v];
  };
  const auto& goal_intervals = intervals(goal);
  if (goal_intervals.empty() || goal_intervals.back().last != PathTable::kForever) return {};
  const int earliest_rest = goal_intervals.back().first;
  // Admissible: no plan arrives before the goal's last safe interval opens. With turns, the way to
  // the next target counts the turns too (the legs after it, whose headings are not known yet, do not).
  const auto remaining = [&](Vertex v, int done, int heading) {
    const int next = turning ? std::min(turning->get(targets[done], v, heading), kUnreachable)
                             : dist.get(targets[done], v);
    return next + suffix[done];
  };
  const auto estimate = [&](Vertex v, int t, int done, int heading) {
    return std::max(t + remaining(v, done, heading), earliest_rest);
  };
  const int latest_arrival = limits.max_length >= (1 << 30) - start_time ? (1 << 30) : start_time + limits.max_length;
  const int heading_at_start = turning_model ? start_heading : 0;
  if (estimate(start, start_time, advance(start, 0), heading_at_start) > latest_arrival) return {};

  std::vector<State>& store = store_;
  store.clear();
  // A binary heap, best on top: lowest f, then lowest h, then latest t. Each entry carries its
  // keys, so the heap's comparisons read the heap alone (they were a third of the search's time
  // when they went through the store).
  const auto worse = [](const OpenEntry& a, const OpenEntry& b) {
    if (a.f != b.f) return a.f > b.f;
    if (a.h != b.h) return a.h > b.h;
    return a.t < b.t;
  };
  std::vector<OpenEntry>& open = open_;
  open.clear();
  const auto push = [&](int index) {
    const State& pushed = store[index];
    open.push_back({pushed.f, pushed.h, pushed.t, index});
    std::push_heap(open.begin(), open.end(), worse);
  };
  // The earliest arrival expanded per (vertex, interval, targets done, heading): per vertex an
  // array over its intervals, the targets and the headings, made stale at once by the call's stamp
  // (crowded cells have dozens of intervals; a list searched at each look-up cost LNS a tenth of
  // its iterations on a dense maze).
  const auto best_arrival = [&](Vertex v, int interval, int done, int heading) -> int& {
    std::vector<int>& at = best_arrival_[v];
    if (best_stamp_[v] != stamp_) {
      best_stamp_[v] = stamp_;
      at.assign(intervals(v).size() * static_cast<size_t>(target_count) * heading_slots, PathTable::kForever);
    }
    return at[(static_cast<size_t>(interval) * target_count + done) * heading_slots + heading];
  };

  const auto& start_intervals = intervals(start);
  int start_interval = -1;
  for (int k = 0; k < static_cast<int>(start_intervals.size()); ++k) {
    if (start_intervals[k].first <= start_time && start_time <= start_intervals[k].last) start_interval = k;
  }
  if (start_interval < 0) return {};
  const int start_done = advance(start, 0);
  store.push_back({start, start_interval, start_done, start_time,
                   estimate(start, start_time, start_done, heading_at_start),
                   remaining(start, start_done, heading_at_start), -1, heading_at_start});
  push(0);
  int expansions = 0;
  while (!open.empty()) {
    std::pop_heap(open.begin(), open.end(), worse);
    const int index = open.back().index;
    open.pop_back();
    const State state = store[index];
    int& best = best_arrival(state.v, state.interval, state.done, state.heading);
    if (best <= state.t) continue;
    best = state.t;
    const PathTable::Interval here = intervals(state.v)[state.interval];
    if (state.done == target_count - 1 && state.v == goal && here.last == PathTable::kForever) {
      // Rebuild the path, filling the waits between arrivals.
      std::vector<int> chain;
      for (int i = index; i >= 0; i = store[i].parent) chain.push_back(i);
      std::reverse(chain.begin(), chain.end());
      Path path;
      if (headings) headings->clear();
      for (size_t k = 0; k < chain.size(); ++k) {
        const State& s = store[chain[k]];
        if (k > 0) {
          while (static_cast<int>(path.size()) < s.t - start_time) {
            path.push_back(path.back());
            if (headings) headings->push_back(headings->back());
          }
        }
        path.push_back(s.v);
        if (headings) headings->push_back(s.heading);
      }
      return path;
    }
    if (++expansions > limits.max_expansions) break;
    limits.deadline.spend(1);
    if ((expansions & 1023) == 0 && limits.deadline.expired()) break;
    // The last moment we can leave this cell: the step after our interval closes.
    const int leave_by = here.last == PathTable::kForever ? PathTable::kForever : here.last + 1;
    if (turning_model && state.t + 1 <= here.last && state.t + 1 <= limits.horizon) {
      // A quarter turn either way, in place: the next step in the same safe interval.
      const int t = state.t + 1;
      for (const int heading : {turned_clockwise(state.heading), turned_counter_clockwise(state.heading)}) {
        const int to_go = remaining(state.v, state.done, heading);
        const int f = std::max(t + to_go, earliest_rest);
        if (f > latest_arrival || best_arrival(state.v, state.interval, state.done, heading) <= t) continue;
        store.push_back({state.v, state.interval, state.done, t, f, to_go, index, heading});
        push(static_cast<int>(store.size()) - 1);
      }
    }
    for (Vertex u : graph.neighbours(state.v)) {
      if (turning_model && u != ahead(graph, state.v, state.heading)) continue;  // forward only
      const auto& slots = intervals(u);
      const int done = advance(u, state.done);
      const int to_go = remaining(u, done, state.heading);
      // Intervals that close before the earliest move (t + 1) can take no move: start past them.
      const auto first_open = std::partition_point(
          slots.begin(), slots.end(), [&](const PathTable::Interval& slot) { return slot.last < state.t + 1; });
      // Later intervals are entered later: once one is too late (horizon, length bound), so are
      // all after it.
      for (int k = static_cast<int>(first_open - slots.begin()); k < static_cast<int>(slots.size()); ++k) {
        if (slots[k].first > leave_by) break;
        const int latest = std::min(slots[k].last, leave_by);
        int t = std::max(state.t + 1, slots[k].first);
        // Swap conflict: someone at u at t-1 moving onto our cell at t. Intervals are maximal, so
        // u can be occupied at t-1 only when its interval opens at t; one step later it is free.
        // Likewise our cell is taken at t only when our interval closes at t - 1: both agents are
        // those the intervals record next to them.
        if (t == slots[k].first) {
          const int other = slots[k].occupant_before;
          if (other != PathTable::kFree && t == here.last + 1 && here.occupant_after == other) {
            ++t;
          } else if (limits.forbid_rotations && closes_rotation(graph, table, state.v, u, t)) {
            ++t;  // one step later u has been free for a step: following nobody, closing nothing
          }
        }
        if (t > latest) continue;
        if (t > limits.horizon) break;
        const int f = std::max(t + to_go, earliest_rest);
        if (f > latest_arrival) break;
        if (best_arrival(u, k, done, state.heading) <= t) continue;
        store.push_back({u, k, done, t, f, to_go, index, state.heading});
        push(static_cast<int>(store.size()) - 1);
      }
    }
  }
  return {};
}

Path plan_through_targets(const Graph& graph, DistTable& dist, const PathTable& table, Vertex start,
                          const std::vector<Vertex>& targets, const SpaceTimeLimits& limits, int start_time) {
  SafeIntervalPlanner planner(graph);
  return planner.plan(dist, table, start, targets, limits, start_time);
}

}  // namespace planner_core
