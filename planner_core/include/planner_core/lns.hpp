// LNS refinement (CTS-PLL paper, section III-C; destroy/repair structure after MAPF-LNS2, Li et
// al. AAAI 2022): repeatedly remove the paths of a neighbourhood of agents, replan them one by one
// with prioritized planning in random order through their fixed task orders, and keep the result
// when the neighbourhood's cost (sum of arrival times) does not increase. Four destroy operators
// with adaptive weights w <- (1 - gamma) w + gamma max(delta, 0), picked by roulette.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <random>
#include <vector>

#include "planner_core/deadline.hpp"
#include "planner_core/path_table.hpp"
#include "planner_core/solution.hpp"
#include "planner_core/safe_interval_planning.hpp"

namespace planner_core {

struct LnsConfig {
  int neighbourhood_size = 4;  // measured on dense maze instances: 4 beat 2 and 8 (docs/results/HISTORY.md)
  double gamma = 0.1;
  // CTS-PLL-v3: refinement budget for each joint sequence; 0 = half of the solve's time limit.
  double time_per_sequence_s = 0;
  // The refinement of one plan also ends after this many iterations without improvement (0 = never).
  int stall_iterations = 300;
  SpaceTimeLimits search;
};

enum class DestroyOperator { kRandom, kIntersection, kRandomWalk, kGoalBlockers };
constexpr int kDestroyOperatorCount = 4;

struct LnsStats {
  int iterations = 0;
  int accepted = 0;
  int repair_failures = 0;
  std::array<double, kDestroyOperatorCount> weights{};
};

class LnsRefiner {
 public:
  LnsRefiner(const Instance& instance, DistTable& dist, const LnsConfig& config, std::mt19937& rng);

  // Improves `plan` (feasible, following `orders`) in place until the deadline; `on_improvement`
  // gets the new flowtime whenever it drops. Called again with the plan it returned, it goes on
  // where it stopped.
  LnsStats refine(Solution& plan, const std::vector<std::vector<int>>& orders, const Deadline& deadline,
                  const std::function<void(int64_t flowtime)>& on_improvement = {}) {
    return run(plan, nullptr, orders, deadline, on_improvement);
  }
  // The same in the rotation model (the instance's actions): `headings` are the plan's, and each
  // repair is planned over cell and heading (SafeIntervalPlanner::plan_with_turns), from the
  // instance's start headings, guided by `turning` (distances with turns; null: by cells alone).
  LnsStats refine_with_turns(Solution& plan, HeadingPlan& headings, const std::vector<std::vector<int>>& orders,
                             GuidedDistances* turning, const Deadline& deadline,
                             const std::function<void(int64_t flowtime)>& on_improvement = {}) {
    turning_ = turning;
    return run(plan, &headings, orders, deadline, on_improvement);
  }

 private:
  LnsStats run(Solution& plan, HeadingPlan* headings, const std::vector<std::vector<int>>& orders,
               const Deadline& deadline, const std::function<void(int64_t flowtime)>& on_improvement);
  // Sets up paths (and their headings, when given), targets and the path table for `plan`.
  void load(const Solution& plan, const HeadingPlan* headings, const std::vector<std::vector<int>>& orders);
  // Agent a's path from its start through its targets, avoiding the table: in the rotation model
  // with its headings in `headings`. Empty when none is found within `limits`.
  Path repair(int a, const SpaceTimeLimits& limits, std::vector<int>& headings);
  std::vector<int> pick_neighbourhood(DestroyOperator op);
  std::vector<int> random_agents(std::vector<int> chosen);
  std::vector<int> intersection_agents();
  std::vector<int> random_walk_agents();
  std::vector<int> goal_blocker_agents();
  // An agent picked in proportion to its delay (arrival minus its tour length); none if no agent is late.
  std::optional<int> delayed_agent();
  DestroyOperator roulette();

  const Instance& instance_;
  DistTable& dist_;
  LnsConfig config_;
  std::mt19937& rng_;
  std::array<double, kDestroyOperatorCount> weights_;
  // State of the current refine() call.
  std::vector<Path> paths_;
  std::vector<std::vector<int>> path_headings_;  // per agent, its heading at each step (rotation model)
  GuidedDistances* turning_ = nullptr;            // rotation model: distances with turns, if any
  std::vector<std::vector<Vertex>> targets_;  // per agent: task cells in order, then the goal
  std::vector<int> tour_length_;              // per agent: its order's length, a bound on its arrival
  int max_tour_ = 0;
  PathTable table_;
  // The plan and orders the state above describes (what the last refine() call returned).
  Solution loaded_plan_;
  HeadingPlan loaded_headings_;
  std::vector<std::vector<int>> loaded_orders_;
  SafeIntervalPlanner planner_;
};

}  // namespace planner_core
