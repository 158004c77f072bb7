#include "planner_core/joint_sequencer.hpp"

namespace planner_core {

JointSequencer::JointSequencer(const Instance& instance, DistTable& dist, const TaskOrderConfig& config,
                               const Deadline& deadline) {
  const int n = instance.agent_count();
  // Every distance the agents' tour matrices ask for (searches from their tasks and goal to all
  // their points, see TourMatrix), on all cores first; the orders below then only read them.
  std::vector<DistTable::Query> tour_legs;
  for (int a = 0; a < n; ++a) {
    std::vector<Vertex> points{instance.starts[a]};
    for (int t : instance.tasks_of_agent[a]) points.push_back(instance.tasks[t].at);
    points.push_back(instance.goals[a]);
    for (size_t to = 1; to < points.size(); ++to) {
      for (size_t from = 0; from < points.size(); ++from) {
        if (from != to) tour_legs.push_back({points[to], points[from]});
      }
    }
  }
  if (!dist.prepare(tour_legs, deadline)) return;
  int64_t cost = 0;
  for (int a = 0; a < n; ++a) {
    if (deadline.expired()) return;
    per_agent_.push_back(std::make_unique<KBestOrders>(instance, a, dist, config));
    cost += per_agent_.back()->get(0)->cost;
  }
  steps_.push_back({-1, -1});
  open_.push({cost, 0, 0});
  ready_ = true;
}

std::vector<int> JointSequencer::ranks_of(int step) const {
  std::vector<int> ranks(per_agent_.size(), 0);
  for (int s = step; steps_[s].parent >= 0; s = steps_[s].parent) ++ranks[steps_[s].changed_agent];
  return ranks;
}

std::optional<JointSequence> JointSequencer::next() {
  if (open_.empty()) return std::nullopt;
  const Node node = open_.top();
  open_.pop();
  const int n = agent_count();
  JointSequence sequence;
  sequence.cost = node.cost;
  sequence.index = produced_++;
  sequence.ranks = ranks_of(node.step);
  for (int a = 0; a < n; ++a) sequence.orders.push_back(per_agent_[a]->get(sequence.ranks[a])->task_ids);

  for (int a = node.last_changed; a < n; ++a) {
    const int rank = sequence.ranks[a];
    const TaskOrder* successor = per_agent_[a]->get(rank + 1);
    if (!successor) continue;
    const int64_t cost = node.cost + successor->cost - per_agent_[a]->get(rank)->cost;
    steps_.push_back({node.step, a});
    open_.push({cost, static_cast<int>(steps_.size()) - 1, a});
  }
  return sequence;
}

int64_t JointSequencer::lower_bound() const {
  if (!ready_) return 0;
  int64_t bound = 0;
  for (const auto& orders : per_agent_) bound += orders->lower_bound();
  return bound;
}

}  // namespace planner_core
