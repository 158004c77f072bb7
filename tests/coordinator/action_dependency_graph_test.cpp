#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>
#include <tuple>

#include "planner_core/action_dependency_graph.hpp"
#include "coordinator/window_planner.hpp"
#include "planner_core/action_model.hpp"
#include "planner_core/solver.hpp"
#include "planner_core/validator.hpp"

namespace coordinator {
namespace {

using planner_core::ActionDependencyGraph;
using planner_core::Move;

using planner_core::Vertex;

// Executes the ADG with random delays: at each event a random ready move starts and moves take
// random durations. Checks that no two robots ever hold one cell, that nothing deadlocks, and that
// every robot ends where its plan ends.
void execute_with_random_delays(const planner_core::Solution& plan, uint32_t seed,
                                const planner_core::HeadingPlan& headings = {}) {
  const ActionDependencyGraph adg(plan, headings);
  const int robots = adg.robot_count();
  std::mt19937 rng(seed);
  std::vector<int> finished(robots, 0);
  std::vector<double> busy_until(robots, -1);  // -1: idle
  std::vector<Vertex> at = plan[0];
  std::vector<Vertex> entering(robots, planner_core::kNoVertex);
  double now = 0;
  for (int guard = 0; guard < 1000000; ++guard) {
    // Finish the earliest move in progress.
    int next = -1;
    for (int r = 0; r < robots; ++r) {
      if (busy_until[r] >= 0 && (next < 0 || busy_until[r] < busy_until[next])) next = r;
    }
    // Start every ready move (in random order), holding both cells while it runs.
    std::vector<int> order(robots);
    for (int r = 0; r < robots; ++r) order[r] = r;
    std::shuffle(order.begin(), order.end(), rng);
    bool started = false;
    for (int r : order) {
      if (busy_until[r] >= 0 || finished[r] >= static_cast<int>(adg.moves(r).size())) continue;
      if (!adg.ready(r, finished[r], finished)) continue;
      const Vertex target = adg.moves(r)[finished[r]].to;
      for (int other = 0; other < robots; ++other) {
        if (other == r) continue;
        ASSERT_NE(at[other], target) << "robot " << r << " enters a cell robot " << other << " stands on";
        ASSERT_NE(entering[other], target) << "robots " << r << " and " << other << " enter one cell";
      }
      entering[r] = target;
      busy_until[r] = now + std::uniform_real_distribution<double>(1.0, 4.0)(rng);  // up to 4x delays
      started = true;
    }
    if (next < 0 && !started) break;
    if (next < 0) continue;
    now = busy_until[next];
    at[next] = entering[next];
    entering[next] = planner_core::kNoVertex;
    busy_until[next] = -1;
    ++finished[next];
  }
  for (int r = 0; r < robots; ++r) {
    EXPECT_EQ(finished[r], static_cast<int>(adg.moves(r).size())) << "robot " << r << " deadlocked";
    EXPECT_EQ(at[r], plan.back()[r]);
  }
}

// A plan for tests/data/instances/`file` by `solver` with no rotations, checked by the validator
// (empty when there is none).
planner_core::Solution rotation_free_plan(const std::string& file, const std::string& solver, int max_sequences = 0,
                                          double seconds = 10) {
  const planner_core::Instance instance = planner_core::load_instance(std::string(CTSFLEET_TEST_DATA) + "/instances/" + file);
  planner_core::SolverConfig config;
  config.solver = solver;
  config.forbid_rotations = true;
  config.max_sequences = max_sequences;
  const planner_core::SolveResult result =
      planner_core::make_solver(config)->solve(instance, {planner_core::Deadline::in_seconds(seconds), {}});
  EXPECT_TRUE(result.solved);
  EXPECT_TRUE(planner_core::validate(instance, result.solution, {true}).ok());
  return result.solved ? result.solution : planner_core::Solution{};
}

TEST(ActionDependencyGraph, DelayedRobotsNeverCollideNorDeadlock) {
  const planner_core::Solution plan = rotation_free_plan("random-32-32-20-N10-M30-00.yaml", "cts-pll-v2");
  ASSERT_FALSE(plan.empty());
  for (uint32_t seed = 0; seed < 20; ++seed) execute_with_random_delays(plan, seed);
}

TEST(ActionDependencyGraph, DenseMazePlan) {
  const planner_core::Solution plan = rotation_free_plan("maze-32-32-2-N50-M60-00.yaml", "cts-pll-v3", 2, 3);
  ASSERT_FALSE(plan.empty());
  for (uint32_t seed = 0; seed < 3; ++seed) execute_with_random_delays(plan, seed);
}

// The plan's moves as a comparable list: (robot, from, to, plan time, dependencies sorted).
std::vector<std::tuple<int, Vertex, Vertex, int, std::vector<std::pair<int, int>>>> moves_of(const ActionDependencyGraph& adg) {
  std::vector<std::tuple<int, Vertex, Vertex, int, std::vector<std::pair<int, int>>>> all;
  for (int r = 0; r < adg.robot_count(); ++r) {
    for (const Move& move : adg.moves(r)) {
      std::vector<std::pair<int, int>> after = move.after;
      std::sort(after.begin(), after.end());
      all.emplace_back(r, move.from, move.to, move.plan_time, after);
    }
  }
  return all;
}

TEST(ActionDependencyGraph, APlanGrownPieceByPieceHasTheDependenciesOfThePlanWhole) {
  const planner_core::Solution plan = rotation_free_plan("maze-32-32-2-N50-M60-00.yaml", "cts-pibt");
  ASSERT_FALSE(plan.empty());
  const ActionDependencyGraph whole(plan);
  for (size_t piece : {size_t{1}, size_t{7}, plan.size() / 3}) {
    ActionDependencyGraph grown(planner_core::Solution(plan.begin(), plan.begin() + 1));
    for (size_t from = 0; from + 1 < plan.size(); from += piece) {
      const size_t to = std::min(plan.size() - 1, from + piece);
      grown.extend(planner_core::Solution(plan.begin() + static_cast<std::ptrdiff_t>(from),
                                          plan.begin() + static_cast<std::ptrdiff_t>(to) + 1));
    }
    EXPECT_EQ(grown.plan_steps(), static_cast<int>(plan.size()) - 1);
    EXPECT_EQ(grown.last_configuration(), plan.back());
    EXPECT_EQ(moves_of(grown), moves_of(whole)) << "pieces of " << piece << " steps";
  }
  ActionDependencyGraph grown(plan);
  EXPECT_THROW(grown.extend({plan.front()}), std::invalid_argument);  // not where the plan ends
  EXPECT_EQ(moves_of(grown), moves_of(whole));                         // and nothing changed
}

TEST(ActionDependencyGraph, ForgettingFinishedMovesChangesNoAnswer) {
  const planner_core::Solution plan = rotation_free_plan("maze-32-32-2-N50-M60-00.yaml", "cts-pibt");
  ASSERT_FALSE(plan.empty());
  const ActionDependencyGraph whole(plan);
  ActionDependencyGraph trimmed(plan);
  // Halfway through each robot's moves (as if each had finished that many), the rest kept.
  std::vector<int> finished(whole.robot_count());
  for (int r = 0; r < whole.robot_count(); ++r) {
    finished[r] = whole.move_count(r) / 2;
    trimmed.forget_before(r, finished[r]);
    EXPECT_EQ(trimmed.move_count(r), whole.move_count(r));
    EXPECT_EQ(trimmed.moves(r).size(), whole.moves(r).size() - static_cast<size_t>(finished[r]));
  }
  for (int r = 0; r < whole.robot_count(); ++r) {
    for (int m = finished[r]; m < whole.move_count(r); ++m) {
      EXPECT_EQ(trimmed.move(r, m).to, whole.move(r, m).to);
      EXPECT_EQ(trimmed.move(r, m).after, whole.move(r, m).after);
    }
    if (finished[r] < whole.move_count(r)) {
      EXPECT_EQ(trimmed.ready(r, finished[r], finished), whole.ready(r, finished[r], finished));
    }
  }
}

// Lifelong windows, one after the other, errands drawn at random: the plan they make together
// runs under random delays without a collision or a deadlock (a rotation would deadlock it).
TEST(ActionDependencyGraph, LifelongWindowsRunUnderDelaysWithoutCollisionOrDeadlock) {
  const planner_core::Instance instance =
      planner_core::load_instance(std::string(CTSFLEET_TEST_DATA) + "/instances/maze-32-32-2-N50-M60-00.yaml");
  const planner_core::Graph& graph = *instance.graph;
  WindowPlanner windows(instance.graph, 3);
  std::mt19937 rng(11);
  std::vector<WindowAgent> agents(instance.agent_count());
  for (int a = 0; a < instance.agent_count(); ++a) agents[a].park = instance.goals[a];
  planner_core::Solution plan{instance.starts};
  int reached = 0, given = 0;
  for (int window = 0; window < 60; ++window) {
    for (WindowAgent& agent : agents) {
      if (agent.errands.empty() && rng() % 3 == 0) {
        agent.errands.push_back(static_cast<Vertex>(rng() % graph.vertex_count()));
        ++given;
      }
    }
    const PlanWindow next = windows.plan({plan.back(), {}}, agents, 5, planner_core::Deadline::in_seconds(5));
    for (int a = 0; a < instance.agent_count(); ++a) {
      for (Vertex cell : next.reached[a]) {
        const auto at = std::find(agents[a].errands.begin(), agents[a].errands.end(), cell);
        ASSERT_NE(at, agents[a].errands.end());
        agents[a].errands.erase(at);
        ++reached;
      }
    }
    plan.insert(plan.end(), next.steps.begin() + 1, next.steps.end());
  }
  EXPECT_GT(reached, given / 2);
  for (uint32_t seed = 0; seed < 3; ++seed) execute_with_random_delays(plan, seed);
}

TEST(ActionDependencyGraph, APlanWithTurnsHasTurnsAsMovesOfTheirOwnAndRunsUnderDelays) {
  planner_core::Instance instance =
      planner_core::load_instance(std::string(CTSFLEET_TEST_DATA) + "/instances/random-32-32-20-N10-M30-00.yaml");
  instance.actions = planner_core::ActionModel::kRotate;
  planner_core::SolverConfig config;
  config.solver = "cts-pll-v2";
  config.forbid_rotations = true;
  const planner_core::SolveResult result =
      planner_core::make_solver(config)->solve(instance, {planner_core::Deadline::in_seconds(10), {}});
  ASSERT_TRUE(result.solved);
  ASSERT_TRUE(planner_core::validate(instance, result.solution, {true}, result.headings).ok());
  const ActionDependencyGraph adg(result.solution, result.headings);
  int turns = 0;
  for (int r = 0; r < adg.robot_count(); ++r) {
    int heading = instance.start_heading(r);
    for (const Move& move : adg.moves(r)) {
      if (move.from == move.to) {  // a turn: a quarter, waiting for nobody
        EXPECT_EQ(planner_core::turns_between(heading, move.heading), 1) << "robot " << r << " at t " << move.plan_time;
        EXPECT_TRUE(move.after.empty());
        ++turns;
      } else {  // forward, the way it faces
        EXPECT_EQ(move.heading, heading) << "robot " << r << " at t " << move.plan_time;
        EXPECT_EQ(planner_core::ahead(*instance.graph, move.from, heading), move.to);
      }
      heading = move.heading;
    }
  }
  EXPECT_GT(turns, 10);
  for (uint32_t seed = 0; seed < 10; ++seed) execute_with_random_delays(result.solution, seed, result.headings);
  EXPECT_THROW(ActionDependencyGraph(result.solution, {result.headings.front()}), std::invalid_argument);
}

TEST(ActionDependencyGraph, FollowerWaitsForTheLeader) {
  // Robot 0 moves 0->1->2; robot 1 follows it from the left: 3 is left of 0 in a corridor.
  const planner_core::Solution plan = {{0, 3}, {1, 0}, {2, 1}};
  const ActionDependencyGraph adg(plan);
  ASSERT_EQ(adg.moves(1).size(), 2u);
  std::vector<int> finished{0, 0};
  EXPECT_FALSE(adg.ready(1, 0, finished));  // cell 0 is still robot 0's
  finished[0] = 1;
  EXPECT_TRUE(adg.ready(1, 0, finished));
}

TEST(ActionDependencyGraph, ALostLeaderTakesItsFollowersMovesAndNobodyElses) {
  // A corridor 3-0-1-2 and, apart, 5-6: robot 0 moves 0->1->2, robot 1 follows it from 3, robot 2
  // moves 5->6. Robot 0 is lost on its first move (sent, never confirmed).
  const planner_core::Solution plan = {{0, 3, 5}, {1, 0, 6}, {2, 1, 6}};
  ActionDependencyGraph adg(plan);
  const std::vector<int> finished{0, 0, 0};
  const auto finished_of = [&](int r) { return finished[r]; };
  const std::vector<int> kept = adg.moves_kept_around(0, 0, 1, finished_of);
  EXPECT_EQ(kept, (std::vector<int>{1, 0, 1}));  // its move in flight; none of the follower's; robot 2's
  adg.keep_moves(kept);
  EXPECT_EQ(adg.last_configuration(), (planner_core::Config{1, 3, 6}));
  EXPECT_EQ(adg.plan_steps(), 2);
  EXPECT_EQ(adg.move_count(1), 0);
  // The plan grows from there: the follower's way into 0 waits on robot 0's move in flight, which
  // is never confirmed while it is lost (so the window planner keeps others off its cells).
  adg.extend({{1, 3, 6}, {1, 0, 6}});
  EXPECT_EQ(adg.move(1, 0).after, (std::vector<std::pair<int, int>>{{0, 0}}));
  // Lost before its first move: only its own moves go, and its follower's.
  ActionDependencyGraph again(plan);
  EXPECT_EQ(again.moves_kept_around(0, 0, 0, finished_of), (std::vector<int>{0, 0, 1}));
}

TEST(ActionDependencyGraph, ARobotJoiningOnACellTakesTheMovesIntoItAndThoseWaitingOnThem) {
  // Robot 0 goes along a corridor 0-1-2-3, robot 1 stands still on 4. Once robot 0 has made its
  // first move, a robot joins on 2.
  const planner_core::Solution plan = {{0, 4}, {1, 4}, {2, 4}, {3, 4}};
  ActionDependencyGraph adg(plan);
  const std::vector<int> finished{1, 0};  // robot 0 has made its first move
  const std::vector<int> kept = adg.moves_kept_clear_of(2, [&](int r) { return finished[r]; });
  EXPECT_EQ(kept, (std::vector<int>{1, 0}));  // its move into 2 goes, and the one after it
  adg.keep_moves(kept);
  adg.add_robot(2);
  ASSERT_EQ(adg.robot_count(), 3);
  EXPECT_EQ(adg.move_count(2), 0);
  EXPECT_EQ(adg.last_configuration(), (planner_core::Config{1, 4, 2}));
  // The plan grows: the newcomer leaves 2 for 3 and robot 0 follows it into 2, after it left.
  adg.extend({{1, 4, 2}, {2, 4, 3}});
  EXPECT_EQ(adg.move(0, 1).after, (std::vector<std::pair<int, int>>{{2, 0}}));
}

// Random delays, then a robot lost (its move in flight, if any, never ends): the plan cut around it
// keeps every move sent, and the rest runs without a collision (the lost robot holding both its
// cells) or a deadlock, ending on distinct cells from which the plan can grow.
TEST(ActionDependencyGraph, APlanCutAroundALostRobotRunsWithoutIt) {
  const planner_core::Solution plan = rotation_free_plan("maze-32-32-2-N50-M60-00.yaml", "cts-pibt");
  ASSERT_FALSE(plan.empty());
  int64_t dropped = 0;
  for (uint32_t seed = 0; seed < 12; ++seed) {
    ActionDependencyGraph adg(plan);
    const int robots = adg.robot_count();
    std::mt19937 rng(seed);
    std::vector<int> finished(robots, 0);
    std::vector<double> busy_until(robots, -1);
    std::vector<Vertex> at = plan[0];
    std::vector<Vertex> entering(robots, planner_core::kNoVertex);
    double now = 0;
    int lost = -1;
    const int lose_after = 40 + static_cast<int>(rng() % 200);
    for (int event = 0; event < 1000000; ++event) {
      if (event == lose_after) {  // a robot with moves left is lost, preferably mid-move
        std::vector<int> candidates;
        for (int r = 0; r < robots; ++r) {
          if (busy_until[r] >= 0) candidates.push_back(r);
        }
        for (int r = 0; r < robots && candidates.empty(); ++r) {
          if (finished[r] < adg.move_count(r)) candidates.push_back(r);
        }
        if (candidates.empty()) break;
        lost = candidates[rng() % candidates.size()];
        const int keep = busy_until[lost] >= 0 ? finished[lost] + 1 : finished[lost];
        const std::vector<int> kept =
            adg.moves_kept_around(lost, finished[lost], keep, [&](int r) { return finished[r]; });
        for (int r = 0; r < robots; ++r) {
          ASSERT_GE(kept[r], finished[r] + (busy_until[r] >= 0 ? 1 : 0)) << "a move under way dropped";
          dropped += adg.move_count(r) - kept[r];
        }
        adg.keep_moves(kept);
        for (int r = 0; r < robots; ++r) ASSERT_EQ(adg.move_count(r), kept[r]);
      }
      int next = -1;
      for (int r = 0; r < robots; ++r) {
        if (r != lost && busy_until[r] >= 0 && (next < 0 || busy_until[r] < busy_until[next])) next = r;
      }
      std::vector<int> order(robots);
      for (int r = 0; r < robots; ++r) order[r] = r;
      std::shuffle(order.begin(), order.end(), rng);
      bool started = false;
      for (int r : order) {
        if (r == lost || busy_until[r] >= 0 || finished[r] >= adg.move_count(r)) continue;
        if (!adg.ready(r, finished[r], finished)) continue;
        const Vertex target = adg.move(r, finished[r]).to;
        for (int other = 0; other < robots; ++other) {
          if (other == r) continue;
          ASSERT_NE(at[other], target) << "robot " << r << " enters a cell robot " << other << " stands on";
          ASSERT_NE(entering[other], target) << "robots " << r << " and " << other << " enter one cell";
        }
        entering[r] = target;
        busy_until[r] = now + std::uniform_real_distribution<double>(1.0, 4.0)(rng);
        started = true;
      }
      if (next < 0 && !started && event >= lose_after) break;
      if (next < 0) continue;
      now = busy_until[next];
      at[next] = entering[next];
      entering[next] = planner_core::kNoVertex;
      busy_until[next] = -1;
      ++finished[next];
    }
    ASSERT_GE(lost, 0);
    const planner_core::Config& end = adg.last_configuration();
    for (int r = 0; r < robots; ++r) {
      if (r == lost) {
        EXPECT_EQ(end[r], busy_until[r] >= 0 ? entering[r] : at[r]);
        continue;
      }
      EXPECT_EQ(finished[r], adg.move_count(r)) << "robot " << r << " deadlocked (seed " << seed << ")";
      EXPECT_EQ(at[r], end[r]);
    }
    std::vector<Vertex> cells = end;
    std::sort(cells.begin(), cells.end());
    EXPECT_EQ(std::adjacent_find(cells.begin(), cells.end()), cells.end()) << "two robots end on one cell";
    EXPECT_NO_THROW(adg.extend({end, end}));
  }
  EXPECT_GT(dropped, 0);  // the cut did cut
}

}  // namespace
}  // namespace coordinator
