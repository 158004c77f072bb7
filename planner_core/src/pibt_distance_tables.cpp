// PibtLifelong's distance tables: searched when a goal is first seen, freed when nobody needs them
// and the budget is spent, searched again when traffic costs change.
#include "planner_core/pibt_lifelong.hpp"

#include <algorithm>

#include "planner_core/dist_table.hpp"

namespace planner_core {

void PibtLifelong::follow_goals(const Config& goals, const Deadline& deadline) {
  std::vector<Vertex> new_goals;
  for (size_t a = 0; a < goals.size(); ++a) {
    const bool changed = !following_ || last_goals_[a] != goals[a];
    if (!changed) continue;
    if (following_ && --bound_for_[last_goals_[a]] == 0) unneeded_.push_back(last_goals_[a]);
    if (bound_for_[goals[a]]++ == 0 && !table_held_[goals[a]]) {
      table_held_[goals[a]] = 1;
      ++tables_held_;
    }
    new_goals.push_back(goals[a]);
  }
  following_ = true;
  last_goals_ = goals;
  // Free the oldest unneeded tables while over the budget (a goal needed again meanwhile stays).
  const size_t budget = std::max(goals.size(), settings_.distance_bytes / distances_.bytes_per_target());
  while (static_cast<size_t>(tables_held_) > budget && !unneeded_.empty()) {
    const Vertex v = unneeded_.front();
    unneeded_.pop_front();
    if (bound_for_[v] == 0 && table_held_[v]) {
      distances_.forget(v);
      table_held_[v] = 0;
      --tables_held_;
    }
  }
  distances_.prepare(new_goals, deadline, DistTable::default_threads());
}

void PibtLifelong::follow_traffic(const Config& positions, const Deadline& deadline) {
  if (!settings_.traffic.on || !traffic_.observe(positions)) return;
  if (!distances_.set_traffic_costs(traffic_.costs())) return;  // the same costs: tables stand
  std::vector<Vertex> needed;
  for (Vertex v = 0; v < graph_.vertex_count(); ++v) {
    if (bound_for_[v] > 0) {
      needed.push_back(v);
    } else if (table_held_[v]) {
      table_held_[v] = 0;
      --tables_held_;
    }
  }
  unneeded_.clear();
  distances_.prepare(needed, deadline, DistTable::default_threads());
}

GuidePaths::Heuristic PibtLifelong::guide_heuristic() {
  return [this](Vertex goal, Vertex cell) {
    int best = distances_.get(goal, cell);
    for (int heading = 1; settings_.actions == ActionModel::kRotate && heading < kHeadings; ++heading) {
      best = std::min(best, distances_.get(goal, cell, heading));
    }
    return best >= GuidedDistances::kUnreachable ? best : best / distances_.cost_unit();
  };
}

void PibtLifelong::follow_guides(const Poses& now, const Config& goals, const Deadline& deadline) {
  if (!settings_.guide_paths.on) return;
  Deadline share = Deadline::in_seconds(kGuideShare * deadline.seconds_left());
  share.interrupt = deadline.interrupt;
  guides_.update(now.cells, goals, guide_heuristic(), share);
}

int PibtLifelong::distance(Vertex goal, const Poses& poses, int agent) {
  if (settings_.actions == ActionModel::kRotate) return distances_.get(goal, poses.cells[agent], poses.headings[agent]);
  return distances_.get(goal, poses.cells[agent]);
}

}  // namespace planner_core
