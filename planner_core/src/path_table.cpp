#include "planner_core/path_table.hpp"

#include <algorithm>

namespace planner_core {

PathTable::PathTable(int vertex_count)
    : visits_(vertex_count), resting_agent_(vertex_count, kFree), resting_from_(vertex_count, 0) {}

namespace {
template <class Visits>
auto first_at_or_after(Visits& visits, int t) {
  return std::lower_bound(visits.begin(), visits.end(), t, [](const auto& visit, int time) { return visit.t < time; });
}
}  // namespace

void PathTable::add(int agent, const Path& path, bool rests) {
  for (int t = 0; t < static_cast<int>(path.size()); ++t) {
    std::vector<Visit>& visits = visits_[path[t]];
    const auto at = first_at_or_after(visits, t);
    if (at != visits.end() && at->t == t) {
      at->agent = agent;  // as a table indexed by time would: the later entry wins
    } else {
      visits.insert(at, Visit{t, agent});
    }
  }
  if (!rests) return;
  resting_agent_[path.back()] = agent;
  resting_from_[path.back()] = static_cast<int>(path.size()) - 1;
}

void PathTable::add_all(const std::vector<Path>& paths) {
  for (int agent = 0; agent < static_cast<int>(paths.size()); ++agent) {
    const Path& path = paths[agent];
    for (int t = 0; t < static_cast<int>(path.size()); ++t) visits_[path[t]].push_back(Visit{t, agent});
    resting_agent_[path.back()] = agent;
    resting_from_[path.back()] = static_cast<int>(path.size()) - 1;
  }
  for (std::vector<Visit>& visits : visits_) {
    // By time; of several visits at one time the last added wins, as in add().
    std::stable_sort(visits.begin(), visits.end(), [](const Visit& a, const Visit& b) { return a.t < b.t; });
    const auto last_of_each_time = std::unique(visits.rbegin(), visits.rend(),
                                               [](const Visit& a, const Visit& b) { return a.t == b.t; });
    visits.erase(visits.begin(), last_of_each_time.base());
  }
}

void PathTable::remove(int agent, const Path& path) {
  for (int t = 0; t < static_cast<int>(path.size()); ++t) {
    std::vector<Visit>& visits = visits_[path[t]];
    const auto at = first_at_or_after(visits, t);
    if (at != visits.end() && at->t == t && at->agent == agent) visits.erase(at);
  }
  if (resting_agent_[path.back()] == agent) resting_agent_[path.back()] = kFree;
}

int PathTable::occupant(Vertex v, int t) const {
  const std::vector<Visit>& visits = visits_[v];
  const auto at = first_at_or_after(visits, t);
  if (at != visits.end() && at->t == t) return at->agent;
  if (resting_agent_[v] != kFree && t >= resting_from_[v]) return resting_agent_[v];
  return kFree;
}

void PathTable::safe_intervals(Vertex v, std::vector<Interval>& out) const {
  out.clear();
  const int end = resting_agent_[v] != kFree ? resting_from_[v] : kForever;  // free before a resting agent arrives
  int first = 0;
  int before = kFree;  // the agent at v at first - 1
  int after_end = resting_agent_[v];  // the agent at v at `end`: a visit then wins over the resting one
  for (const Visit& visit : visits_[v]) {
    if (visit.t >= end) {
      if (visit.t == end) after_end = visit.agent;
      break;
    }
    if (visit.t > first) out.push_back({first, visit.t - 1, before, visit.agent});
    first = visit.t + 1;
    before = visit.agent;
  }
  if (first < end) out.push_back({first, end == kForever ? kForever : end - 1, before, end == kForever ? kFree : after_end});
}

void PathTable::agents_at(Vertex v, std::vector<int>& out) const {
  for (const Visit& visit : visits_[v]) {
    if (std::find(out.begin(), out.end(), visit.agent) == out.end()) out.push_back(visit.agent);
  }
}

void PathTable::visitors_from(Vertex v, int from, int except, int count, std::vector<int>& out) const {
  const size_t wanted = out.size() + static_cast<size_t>(std::max(count, 0));
  for (auto visit = visits_[v].rbegin(); visit != visits_[v].rend() && visit->t >= from; ++visit) {
    if (out.size() >= wanted) return;
    if (visit->agent != except && std::find(out.begin(), out.end(), visit->agent) == out.end()) {
      out.push_back(visit->agent);
    }
  }
}

}  // namespace planner_core
