#include "planner_core/action_dependency_graph.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace planner_core {

ActionDependencyGraph::ActionDependencyGraph(const Solution& plan, const HeadingPlan& headings) {
  if (plan.empty()) return;
  moves_.assign(plan[0].size(), {});
  forgotten_.assign(plan[0].size(), 0);
  first_ = last_ = plan[0];
  if (!headings.empty()) first_headings_ = headings[0];
  extend(plan, headings);
}

void ActionDependencyGraph::extend(const Solution& more, const HeadingPlan& headings) {
  if (more.empty()) return;
  if (more[0] != last_) throw std::invalid_argument("the plan's extension does not start where the plan ends");
  if (!headings.empty() && headings.size() != more.size()) {
    throw std::invalid_argument("the plan has " + std::to_string(more.size()) + " steps but headings for " +
                                std::to_string(headings.size()));
  }
  if (!headings.empty() && !last_headings_.empty() && headings[0] != last_headings_) {
    throw std::invalid_argument("the plan's extension does not start facing the way the plan ends");
  }
  const int robots = robot_count();
  const auto heading = [&](size_t s, int r) { return headings.empty() ? -1 : headings[s][r]; };
  for (size_t s = 1; s < more.size(); ++s) {
    const int time = steps_ + static_cast<int>(s);
    // This step's departures first: a move may follow a robot leaving its target in the same step.
    std::vector<int> moving;
    for (int r = 0; r < robots; ++r) {
      if (more[s][r] == more[s - 1][r]) {
        // A turn in place is a move with no dependencies; a wait is no move.
        if (heading(s, r) != heading(s - 1, r)) moves_[r].push_back({more[s][r], more[s][r], time, heading(s, r), {}});
        continue;
      }
      moving.push_back(r);
      last_departures_[more[s - 1][r]] = {r, move_count(r)};
      moves_[r].push_back({more[s - 1][r], more[s][r], time, heading(s, r), {}});
    }
    // Each move waits for the latest departure from its target so far, by another robot.
    for (int r : moving) {
      Move& move = moves_[r].back();
      const auto departure = last_departures_.find(move.to);
      if (departure == last_departures_.end()) continue;
      const auto [other, index] = departure->second;
      if (other != r) move.after.emplace_back(other, index);
    }
  }
  steps_ += static_cast<int>(more.size()) - 1;
  last_ = more.back();
  if (!headings.empty()) last_headings_ = headings.back();
}

void ActionDependencyGraph::keep_moves(const std::vector<int>& keep) {
  last_departures_.clear();
  std::vector<std::pair<int, std::pair<int, int>>> departures;  // (plan time, (robot, move))
  for (int r = 0; r < robot_count(); ++r) {
    while (move_count(r) > std::max(keep[r], forgotten_[r])) moves_[r].pop_back();
    if (moves_[r].empty()) {  // never moved (a robot keeps the last move it finished)
      last_[r] = first_[r];
      if (!first_headings_.empty()) last_headings_[r] = first_headings_[r];
      continue;
    }
    last_[r] = moves_[r].back().to;
    if (!last_headings_.empty() && moves_[r].back().heading >= 0) last_headings_[r] = moves_[r].back().heading;
    for (int index = forgotten_[r]; index < move_count(r); ++index) {
      const Move& kept = move(r, index);
      if (kept.from != kept.to) departures.push_back({kept.plan_time, {r, index}});
    }
  }
  // Each cell's latest departure among the moves kept (a finished one forgotten holds nobody back).
  std::sort(departures.begin(), departures.end());
  for (const auto& [time, departure] : departures) last_departures_[move(departure.first, departure.second).from] = departure;
}

void ActionDependencyGraph::add_robot(Vertex at, int heading) {
  moves_.emplace_back();
  forgotten_.push_back(0);
  first_.push_back(at);
  last_.push_back(at);
  if (!first_headings_.empty()) first_headings_.push_back(heading);
  if (!last_headings_.empty()) last_headings_.push_back(heading);
}

void ActionDependencyGraph::forget_before(int robot, int index) {
  while (forgotten_[robot] < index && !moves_[robot].empty()) {
    moves_[robot].pop_front();
    ++forgotten_[robot];
  }
}

}  // namespace planner_core
