#include "planner_core/extended_pibt.hpp"

#include <algorithm>
#include <array>

#include "planner_core/scatter.hpp"

namespace planner_core {

namespace {
constexpr int kNobody = -1;
}

ExtendedPibt::ExtendedPibt(const Instance& instance, DistTable& dist, const PibtConfig& config, std::mt19937& rng)
    : instance_(instance),
      dist_(dist),
      config_(config),
      rng_(rng),
      occupied_now_(instance.graph->vertex_count(), kNobody),
      occupied_next_(instance.graph->vertex_count(), kNobody),
      planning_(instance.agent_count(), 0),
      swap_(*instance.graph, occupied_now_, [this](int agent, Vertex v) { return distance_to_target(agent, v); },
            [this](int agent) { return target_of(agent); }) {}

void ExtendedPibt::reset(const JointSequence& sequence, const Solution& prefix, const HeadingPlan& prefix_headings) {
  const int n = instance_.agent_count();
  agents_.assign(n, {});
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int64_t longest_tour = 0;
  for (int a = 0; a < n; ++a) {
    AgentState& agent = agents_[a];
    for (int task : sequence.orders[a]) agent.targets.push_back(instance_.tasks[task].at);
    agent.targets.push_back(instance_.goals[a]);
    agent.task_count = static_cast<int>(sequence.orders[a].size());
    agent.visited.assign(agent.task_count, 0);
    agent.suffix.assign(agent.targets.size(), 0);
    for (int k = static_cast<int>(agent.targets.size()) - 2; k >= 0; --k) {
      agent.suffix[k] = agent.suffix[k + 1] + dist_.get(agent.targets[k + 1], agent.targets[k]);
    }
    agent.tie_break = unit(rng_);
    longest_tour = std::max(longest_tour, agent.suffix[0] + dist_.get(agent.targets[0], instance_.starts[a]));
  }
  step_limit_ = static_cast<int>(config_.step_limit_factor * static_cast<double>(longest_tour)) + config_.step_limit_slack;

  plan_ = prefix.empty() ? Solution{instance_.starts} : prefix;
  headings_.clear();
  if (turning_) {
    Headings start(n);
    for (int a = 0; a < n; ++a) start[a] = instance_.start_heading(a);
    headings_ = prefix.empty() ? HeadingPlan{start} : prefix_headings;
  }
  for (int t = 0; t < static_cast<int>(plan_.size()); ++t) {
    for (int a = 0; a < n; ++a) mark_visits(a, plan_[t][a], t);
  }
  finished_count_ = 0;
  for (int a = 0; a < n; ++a) {
    finished_count_ += finished(a) ? 1 : 0;
    agents_[a].steps_since_target = static_cast<int>(plan_.size()) - 1 - agents_[a].last_target_time;
  }
}

bool ExtendedPibt::finished(int agent) const {
  return tasks_done(agent) && plan_.back()[agent] == instance_.goals[agent];
}

Vertex ExtendedPibt::target_of(int agent) const { return agents_[agent].targets[agents_[agent].next]; }

void ExtendedPibt::mark_visits(int agent, Vertex at, int time) {
  AgentState& state = agents_[agent];
  bool reached = false;
  // A task counts as visited whenever the agent stands on it, in or out of order.
  for (int k = state.next; k < state.task_count; ++k) {
    if (!state.visited[k] && state.targets[k] == at) {
      state.visited[k] = 1;
      reached = true;
    }
  }
  while (state.next < state.task_count && state.visited[state.next]) ++state.next;
  if (state.next == state.task_count && at == instance_.goals[agent]) reached = reached || time == 0 ||
                                                                                plan_[time - 1][agent] != at;
  if (reached) state.last_target_time = time;
}

int64_t ExtendedPibt::remaining_distance(int agent, Vertex at) {
  const AgentState& state = agents_[agent];
  return dist_.get(state.targets[state.next], at) + state.suffix[state.next];
}

bool ExtendedPibt::step() {
  const int n = instance_.agent_count();
  from_ = plan_.back();
  to_.assign(n, kNoVertex);
  for (int a = 0; a < n; ++a) occupied_now_[from_[a]] = a;

  // Task-aware priority: agents with targets left first; among them the longest without reaching
  // a target, then the largest remaining tour; a per-run random tie-break keeps the order strict.
  std::vector<PriorityKey>& keys = priority_;
  keys.resize(n);
  for (int a = 0; a < n; ++a) {
    const bool active = !finished(a);
    keys[a] = {active, active ? agents_[a].steps_since_target : 0, remaining_distance(a, from_[a]),
               agents_[a].tie_break};
  }
  order_.resize(n);
  for (int a = 0; a < n; ++a) order_[a] = a;
  std::sort(order_.begin(), order_.end(), [&](int x, int y) {
    const PriorityKey &a = keys[x], &b = keys[y];
    if (a.active != b.active) return a.active;
    if (a.waiting != b.waiting) return a.waiting > b.waiting;
    if (a.remaining != b.remaining) return a.remaining > b.remaining;
    return a.tie < b.tie;
  });
  for (int a : order_) {
    if (to_[a] == kNoVertex) plan_move(a);
  }
  planned_ = to_;
  if (turning_) take_rotation_actions();

  // Commit the step and clear the scratch entries this step touched.
  for (int a = 0; a < n; ++a) {
    occupied_now_[from_[a]] = kNobody;
    occupied_next_[planned_[a]] = kNobody;
  }
  plan_.push_back(to_);
  const int time = static_cast<int>(plan_.size()) - 1;
  finished_count_ = 0;
  int progress = 0;
  for (int a = 0; a < n; ++a) {
    const int before = agents_[a].last_target_time;
    mark_visits(a, to_[a], time);
    if (agents_[a].last_target_time != before) {
      agents_[a].steps_since_target = 0;
    } else {
      ++agents_[a].steps_since_target;
    }
    finished_count_ += finished(a) ? 1 : 0;
    progress += agents_[a].next + (finished(a) ? 1 : 0);
  }
  if (progress > best_progress_) {
    best_progress_ = progress;
    best_progress_step_ = time;
  }
  return finished_count_ == n;
}

bool ExtendedPibt::plan_move(int agent) {
  const Vertex here = from_[agent];
  const Vertex target = target_of(agent);
  std::array<Vertex, kMaxDegree + 1> candidates;
  int count = 0;
  for (Vertex u : instance_.graph->neighbours(here)) candidates[count++] = u;
  candidates[count++] = here;
  // Ties in distance are broken by a random order drawn for this call.
  std::shuffle(candidates.begin(), candidates.begin() + count, rng_);
  MoveKeys to_target{};
  if (turning_) {
    const int heading = headings_.back()[agent];
    for (int k = 0; k < count; ++k) to_target[k] = turning_cost(agent, here, heading, candidates[k]);
  } else {
    for (int k = 0; k < count; ++k) to_target[k] = dist_.get(target, candidates[k]);
  }
  sort_by_key(candidates, to_target, count);
  if (guide_) {
    const Vertex preferred = guide_->next(agent, agents_[agent].next, here);
    const auto at = std::find(candidates.begin(), candidates.begin() + count, preferred);
    if (preferred != kNoVertex && at != candidates.begin() + count) std::rotate(candidates.begin(), at, at + 1);
  }
  // A head-on meeting in a corridor: back off (worst candidate first) and pull the other along.
  const int partner = config_.swap ? swap_.partner(agent, here, candidates[0], to_) : kNobody;
  if (partner != kNobody) std::reverse(candidates.begin(), candidates.begin() + count);

  planning_[agent] = 1;
  for (int k = 0; k < count; ++k) {
    const Vertex v = candidates[k];
    if (occupied_next_[v] != kNobody) continue;                          // vertex conflict
    const int occupant = occupied_now_[v];
    if (occupant != kNobody && occupant != agent && to_[occupant] == here) continue;  // swap conflict
    if (config_.forbid_rotations && occupant != kNobody && occupant != agent && planning_[occupant]) continue;
    to_[agent] = v;
    occupied_next_[v] = agent;
    // Priority inheritance: the occupant of v must move first, or this candidate fails.
    if (occupant != kNobody && occupant != agent && to_[occupant] == kNoVertex && !plan_move(occupant)) continue;
    planning_[agent] = 0;
    if (k == 0 && partner != kNobody && v != here && to_[partner] == kNoVertex && occupied_next_[here] == kNobody) {
      to_[partner] = here;  // the partner follows into the cell we leave
      occupied_next_[here] = partner;
    }
    return true;
  }
  planning_[agent] = 0;
  to_[agent] = here;
  occupied_next_[here] = agent;
  return false;
}

int ExtendedPibt::turning_cost(int agent, Vertex here, int heading, Vertex v) {
  const Vertex target = target_of(agent);
  if (v == here) return 1 + turning_->get(target, here, heading);
  const int towards = heading_towards(*instance_.graph, here, v);
  return turns_between(heading, towards) + 1 + turning_->get(target, v, towards);
}

void ExtendedPibt::take_rotation_actions() {
  const Graph& graph = *instance_.graph;
  const int n = instance_.agent_count();
  Headings next = headings_.back();
  // Who stays on its cell: those PIBT kept there, and those that must turn before they move.
  std::vector<int> staying;
  for (int a = 0; a < n; ++a) {
    const Vertex here = from_[a];
    if (to_[a] == here) {
      staying.push_back(a);
      continue;
    }
    const int heading = next[a];
    if (to_[a] == ahead(graph, here, heading)) continue;
    int turned = heading_towards(graph, here, to_[a]);
    if (turns_between(heading, turned) == 2) {  // half round: the quarter nearer the target first
      const Vertex target = target_of(a);
      const int clockwise = turned_clockwise(heading);
      const int counter = turned_counter_clockwise(heading);
      turned = turning_->get(target, here, counter) < turning_->get(target, here, clockwise) ? counter : clockwise;
    }
    next[a] = turned;
    to_[a] = here;
    staying.push_back(a);
  }
  // Whoever meant to enter the cell of an agent that stays waits too, and so on back along the
  // chain. PIBT gave every cell one taker, so the step left is free of conflicts.
  for (size_t k = 0; k < staying.size(); ++k) {
    const int taker = occupied_next_[from_[staying[k]]];
    if (taker == kNobody || taker == staying[k] || to_[taker] == from_[taker]) continue;
    to_[taker] = from_[taker];
    staying.push_back(taker);
  }
  headings_.push_back(std::move(next));
}

ExtendedPibt::Outcome ExtendedPibt::run(const Deadline& deadline) {
  const int start_length = static_cast<int>(plan_.size());
  if (finished_count_ == instance_.agent_count()) return Outcome::kSolved;
  best_progress_ = -1;
  best_progress_step_ = start_length - 1;
  while (static_cast<int>(plan_.size()) - start_length < step_limit_) {
    deadline.spend(instance_.agent_count());
    if (step()) return Outcome::kSolved;
    const int time = static_cast<int>(plan_.size()) - 1;
    if (config_.stall_window > 0 && time - best_progress_step_ >= config_.stall_window) return Outcome::kStalled;
    // With many agents a step is long enough to look at the clock after every one.
    if ((instance_.agent_count() >= 256 || (plan_.size() & 15) == 0) && deadline.expired()) {
      return Outcome::kInterrupted;
    }
  }
  return Outcome::kStepLimit;
}

}  // namespace planner_core
