// LaCAM's high-level search: nodes, their order and constraints, LaCAM*'s costs (lacam.hpp).
#include "lacam_search_state.hpp"

namespace planner_core {

LacamSearch::State::State(const Graph& graph, DistTable& dist, const LacamConfig& config, std::mt19937& rng, const Config& starts,
      const Config& goals, const std::vector<char>& blocked, const Waypoints& waypoints,
      const Headings& start_headings)
    : graph_(graph),
      config_(config),
      rng_(rng),
      goals_(goals),
      blocked_(blocked),
      n_(static_cast<int>(starts.size())),
      turning_(config.turning),
      occupied_now_(graph.vertex_count(), kNobody),
      occupied_next_(graph.vertex_count(), kNobody),
      constrained_(starts.size(), 0),
      swap_(graph, occupied_now_, [this](int agent, Vertex v) { return distance_to_target(agent, current(*from_, agent), v); },
            [this](int agent) { return targets_[slot(agent, current(*from_, agent))]; }) {
  for (const std::vector<Vertex>& row : waypoints) augmented_ = augmented_ || !row.empty();
  if (turning_) {
    if (!blocked.empty()) throw std::invalid_argument("LaCAM in the rotation model takes no blocked cells");
    if (start_headings.size() != starts.size()) {
      throw std::invalid_argument("LaCAM in the rotation model needs one start heading per agent");
    }
    for (int heading : start_headings) {
      if (heading < 0 || heading >= kHeadings) {
        throw std::invalid_argument("LaCAM in the rotation model: start heading " + std::to_string(heading) +
                                    " is not 0..3");
      }
    }
    config_.swap = false;  // CorridorSwap's moves are four-way
    config_.guide = nullptr;
  }
  progress_at_ = turning_ ? 2 * n_ : n_;
  config_size_ = progress_at_ + (augmented_ ? n_ : 0);
  // Every agent's targets in a row: its waypoints, then its goal; slot(agent, k) indexes them.
  for (int i = 0; i < n_; ++i) {
    first_target_.push_back(static_cast<int>(targets_.size()));
    if (augmented_) targets_.insert(targets_.end(), waypoints[i].begin(), waypoints[i].end());
    last_.push_back(static_cast<int>(targets_.size()) - first_target_.back());
    targets_.push_back(goals[i]);
  }
  if (!blocked.empty()) {
    config_.swap = false;  // CorridorSwap's corridor walks do not know blocked cells
    std::map<Vertex, int> searched;
    for (Vertex target : targets_) {
      const auto [it, is_new] = searched.try_emplace(target, static_cast<int>(own_distances_.size()));
      if (is_new) own_distances_.push_back(bfs_around_blocked(target));
      own_index_.push_back(it->second);
    }
  } else {
    for (Vertex target : targets_) target_rows_.push_back(dist.row(target));
  }
  // What is left of each agent's tour from each of its targets, along its order.
  remaining_.assign(targets_.size(), 0);
  for (int i = 0; i < n_; ++i) {
    for (int k = last_[i] - 1; k >= 0; --k) {
      const int leg = distance_to_target(i, k + 1, targets_[slot(i, k)]);
      remaining_[slot(i, k)] = std::min(kUnreachable, remaining_[slot(i, k + 1)] + leg);
    }
  }
  Config start = starts;
  start.resize(config_size_, 0);
  if (turning_) std::copy(start_headings.begin(), start_headings.end(), start.begin() + n_);
  if (augmented_) {
    for (int i = 0; i < n_; ++i) start[progress_at_ + i] = advance(i, 0, starts[i]);
  }
  open_.push_back(make_node(start, nullptr));
}

LacamResult LacamSearch::State::run(const Deadline& deadline) {
  LacamResult result;
  Config next(config_size_);
  // With many agents an iteration is long enough to look at the clock every time.
  const int64_t clock_mask = n_ >= 256 ? 0 : 63;
  while (!open_.empty()) {
    deadline.spend(n_ + kWorkPerNode);
    if ((++iterations_ & clock_mask) == 0 && deadline.expired()) break;
    if (goal_node_ && goal_node_->g < reported_cost_) break;
    HighLevelNode* node = open_.back();
    if (all_home(node->config) && (!goal_node_ || node->g < goal_node_->g)) {
      goal_node_ = node;
      if (!config_.refine) break;
      settle_costs();  // the links recorded before the first solution can make it cheaper
      continue;
    }
    if (goal_node_ && node->g + heuristic(*node) >= goal_node_->g) {  // LaCAM*: cannot beat the best found
      open_.pop_back();
      continue;
    }
    if (node->constraints.empty()) {
      open_.pop_back();
      continue;
    }
    Constraint constraint = std::move(node->constraints.front());
    node->constraints.pop_front();
    grow_constraints(*node, constraint);
    if (!generate(*node, constraint, next)) continue;
    if (augmented_) {
      for (int i = 0; i < n_; ++i) next[progress_at_ + i] = advance(i, current(node->config, i), next[i]);
    }
    const auto found = explored_.find(next);
    if (found != explored_.end()) {
      HighLevelNode* known = *found;
      if (config_.refine) {
        // Before the first solution costs matter to nobody: only record the link, and
        // settle_costs propagates them all once when a goal is found, instead of a propagation
        // at every revisit (a search stuck near the goal revisits thousands of times).
        if (goal_node_) {
          rewire(node, known);
        } else {
          node->neighbours.push_back(known);
        }
      }
      open_.push_back(known);
    } else {
      open_.push_back(make_node(next, node));
    }
  }
  result.explored = static_cast<int64_t>(nodes_.size());
  result.exhausted = open_.empty();
  if (goal_node_) {
    result.solved = true;
    result.cost = goal_node_->g;
    reported_cost_ = goal_node_->g;
    for (HighLevelNode* h = goal_node_; h; h = h->parent) {
      result.solution.emplace_back(h->config.begin(), h->config.begin() + n_);
      if (turning_) result.headings.emplace_back(h->config.begin() + n_, h->config.begin() + 2 * n_);
    }
    std::reverse(result.solution.begin(), result.solution.end());
    std::reverse(result.headings.begin(), result.headings.end());
  }
  return result;
}

std::vector<int> LacamSearch::State::bfs_around_blocked(Vertex target) const {
  std::vector<int> dist(graph_.vertex_count(), kUnreachable);
  std::vector<Vertex> queue{target};
  dist[target] = 0;
  for (size_t head = 0; head < queue.size(); ++head) {
    for (Vertex u : graph_.neighbours(queue[head])) {
      if (dist[u] == kUnreachable && !blocked_[u]) {
        dist[u] = dist[queue[head]] + 1;
        queue.push_back(u);
      }
    }
  }
  return dist;
}

HighLevelNode* LacamSearch::State::make_node(const Config& config, HighLevelNode* parent) {
  auto node = std::make_unique<HighLevelNode>();
  node->config = config;
  node->parent = parent;
  node->id = static_cast<int64_t>(nodes_.size());
  node->priority.resize(n_);
  grew_.assign(n_, 0);
  for (int i = 0; i < n_; ++i) {
    const int k = current(config, i);
    if (!parent) {
      node->priority[i] = static_cast<float>(distance_from(config, i)) / static_cast<float>(n_ * 4 + 1);
    } else if (!home(config, i) && k == current(parent->config, i)) {
      // dynamic priorities: grow until the next waypoint or the goal is reached
      node->priority[i] = parent->priority[i] + 1;
      grew_[i] = 1;
    } else {
      node->priority[i] = parent->priority[i] - static_cast<float>(static_cast<int64_t>(parent->priority[i]));
    }
  }
  if (parent) {
    node->g = parent->g + transition_cost(parent->config, config);
    if (config_.refine) parent->neighbours.push_back(node.get());
  }
  order_by_priority(*node, parent);
  node->constraints.push_back({});
  HighLevelNode* raw = node.get();
  explored_.insert(raw);
  nodes_.push_back(std::move(node));
  return raw;
}

void LacamSearch::State::order_by_priority(HighLevelNode& node, const HighLevelNode* parent) {
  const std::vector<float>& priority = node.priority;
  const auto before = [&](int a, int b) { return priority[a] > priority[b] || (priority[a] == priority[b] && a < b); };
  node.order.resize(n_);
  if (!parent) {
    std::iota(node.order.begin(), node.order.end(), 0);
    std::sort(node.order.begin(), node.order.end(), before);
    return;
  }
  grown_.clear();
  kept_.clear();
  reset_.clear();
  for (int i : parent->order) {
    if (grew_[i]) {
      grown_.push_back(i);
    } else if (priority[i] == parent->priority[i]) {
      kept_.push_back(i);
    } else {
      reset_.push_back(i);
    }
  }
  for (size_t k = 1; k < grown_.size(); ++k) {
    for (size_t j = k; j > 0 && before(grown_[j], grown_[j - 1]); --j) std::swap(grown_[j], grown_[j - 1]);
  }
  std::sort(reset_.begin(), reset_.end(), before);
  merged_.clear();
  std::merge(grown_.begin(), grown_.end(), kept_.begin(), kept_.end(), std::back_inserter(merged_), before);
  std::merge(merged_.begin(), merged_.end(), reset_.begin(), reset_.end(), node.order.begin(), before);
}

void LacamSearch::State::grow_constraints(HighLevelNode& node, const Constraint& constraint) {
  const int depth = static_cast<int>(constraint.who.size());
  if (depth >= n_) return;
  const int agent = node.order[depth];
  const Vertex here = node.config[agent];
  Moves moves;
  int count = 0;
  if (turning_) {
    count = turning_actions(node.config, agent, moves);
  } else {
    for (Vertex u : graph_.neighbours(here)) {
      if (!is_blocked(u)) moves[count++] = u;
    }
    moves[count++] = here;
  }
  std::shuffle(moves.begin(), moves.begin() + count, rng_);
  for (int k = 0; k < count; ++k) {
    Constraint child = constraint;
    child.who.push_back(agent);
    child.where.push_back(moves[k]);
    node.constraints.push_back(std::move(child));
  }
}

void LacamSearch::State::settle_costs() {
  using Entry = std::tuple<int64_t, int64_t, HighLevelNode*>;  // g, id, node
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (const std::unique_ptr<HighLevelNode>& node : nodes_) node->g = INT64_MAX;
  HighLevelNode* start = nodes_.front().get();
  start->g = 0;
  start->parent = nullptr;
  queue.push({0, start->id, start});
  while (!queue.empty()) {
    const auto [g, id, node] = queue.top();
    queue.pop();
    if (g > node->g) continue;
    for (HighLevelNode* next : node->neighbours) {
      const int64_t through = g + transition_cost(node->config, next->config);
      if (through < next->g) {
        next->g = through;
        next->parent = node;
        queue.push({through, next->id, next});
      }
    }
  }
}

void LacamSearch::State::rewire(HighLevelNode* from, HighLevelNode* to) {
  from->neighbours.push_back(to);
  std::deque<HighLevelNode*> queue{from};
  while (!queue.empty()) {
    HighLevelNode* node = queue.front();
    queue.pop_front();
    for (HighLevelNode* next : node->neighbours) {
      const int64_t g = node->g + transition_cost(node->config, next->config);
      if (g < next->g) {
        next->g = g;
        next->parent = node;
        queue.push_back(next);
      }
    }
  }
}

LacamSearch::LacamSearch(const Graph& graph, DistTable& dist, const LacamConfig& config, std::mt19937& rng,
                         const Config& starts, const Config& goals, const std::vector<char>& blocked,
                         const Waypoints& waypoints, const Headings& start_headings)
    : state_(std::make_unique<State>(graph, dist, config, rng, starts, goals, blocked, waypoints, start_headings)) {}

LacamSearch::~LacamSearch() = default;

LacamResult LacamSearch::run(const Deadline& deadline) { return state_->run(deadline); }

Lacam::Lacam(const Graph& graph, DistTable& dist, const LacamConfig& config, std::mt19937& rng)
    : graph_(graph), dist_(dist), config_(config), rng_(rng) {}

LacamResult Lacam::solve(const Config& starts, const Config& goals, const std::vector<char>& blocked,
                         const Deadline& deadline, const Waypoints& waypoints) {
  LacamSearch search(graph_, dist_, config_, rng_, starts, goals, blocked, waypoints);
  return search.run(deadline);
}

}  // namespace planner_core
