// WindowPlanner: the windows a lifelong plan grows by. Errands reached nearest first, then the
// parking cell; a window ends early once everyone is parked; errands no path leads to are counted
// and left alone.
#include <gtest/gtest.h>

#include "coordinator/window_planner.hpp"

#include <algorithm>
#include <memory>

#include "planner_core/action_dependency_graph.hpp"
#include "planner_core/validator.hpp"

namespace coordinator {
namespace {

using planner_core::ActionDependencyGraph;

using planner_core::Config;
using planner_core::Graph;
using planner_core::Vertex;

TEST(WindowPlanner, ErrandsAreReachedNearestFirstThenTheAgentParks) {
  // A corridor of 8 cells: the agent at 3, errands at 1 and 6, parking at 7.
  auto graph = std::make_shared<const Graph>(8, 1, std::vector<std::string>{"........"});
  WindowPlanner windows(graph, 1);
  const PlanWindow window = windows.plan({{3}, {}}, {{{6, 1}, 7}}, 20, planner_core::Deadline::in_seconds(5));
  EXPECT_EQ(window.reached[0], (std::vector<Vertex>{1, 6}));  // 1 is nearer
  ASSERT_EQ(window.steps.size(), 1u + 2 + 5 + 1);               // 3->1, 1->6, 6->7; then it stops
  EXPECT_EQ(window.steps.back(), Config{7});
  EXPECT_EQ(window.unreachable, 0);
}

TEST(WindowPlanner, AWindowStopsAtItsLengthAndTheNextGoesOn) {
  auto graph = std::make_shared<const Graph>(8, 1, std::vector<std::string>{"........"});
  WindowPlanner windows(graph, 1);
  const PlanWindow first = windows.plan({{0}, {}}, {{{7}, 0}}, 3, planner_core::Deadline::in_seconds(5));
  EXPECT_EQ(first.steps.size(), 4u);
  EXPECT_TRUE(first.reached[0].empty());
  const PlanWindow second = windows.plan({first.steps.back(), {}}, {{{7}, 0}}, 3, planner_core::Deadline::in_seconds(5));
  EXPECT_EQ(second.steps.back(), Config{6});
  const PlanWindow third = windows.plan({second.steps.back(), {}}, {{{7}, 0}}, 3, planner_core::Deadline::in_seconds(5));
  EXPECT_EQ(third.reached[0], std::vector<Vertex>{7});
}

TEST(WindowPlanner, AWindowInWhichNobodyMovesGoesOnUntilSomeoneDoes) {
  // Two rows of 5: agent 0 parked on (1,0), its parking cell; agent 1 at (2,0) bound for (0,0),
  // whose way (2 steps) leads through agent 0. Agents nearest their goals decide first, so agent 0
  // stays and agent 1 waits until PIBT boosts it as stuck (after 8 steps on this map). A 5-step
  // window of waits would leave the plan carried out with agent 1 short of its cell: the coordinator
  // would replan the whole fleet. The window goes on until someone moves.
  auto graph = std::make_shared<const Graph>(5, 2, std::vector<std::string>{".....", "....."});
  const auto v = [&](int x, int y) { return graph->vertex_at({x, y}); };
  WindowPlanner windows(graph, 1);
  const PlanWindow window =
      windows.plan({{v(1, 0), v(2, 0)}, {}}, {{{}, v(1, 0)}, {{}, v(0, 0)}}, 5, planner_core::Deadline::in_seconds(5));
  ASSERT_GT(window.steps.size(), 6u);
  EXPECT_NE(window.steps.back(), window.steps.front());
  EXPECT_TRUE(window.stalled.empty());
}

TEST(WindowPlanner, NothingToDoIsAWindowOfNoStep) {
  auto graph = std::make_shared<const Graph>(4, 1, std::vector<std::string>{"...."});
  WindowPlanner windows(graph, 1);
  const PlanWindow window = windows.plan({{0, 3}, {}}, {{{}, 0}, {{}, 3}}, 5, planner_core::Deadline::in_seconds(5));
  EXPECT_EQ(window.steps.size(), 1u);
}

TEST(WindowPlanner, AnErrandStoodOnIsReachedAndRepeatsAreSettledOneByOne) {
  auto graph = std::make_shared<const Graph>(4, 1, std::vector<std::string>{"...."});
  WindowPlanner windows(graph, 1);
  const PlanWindow window = windows.plan({{2}, {}}, {{{2, 2, 0}, 2}}, 10, planner_core::Deadline::in_seconds(5));
  EXPECT_EQ(window.reached[0], (std::vector<Vertex>{2, 2, 0}));
  EXPECT_EQ(window.steps.back(), Config{2});
}

TEST(WindowPlanner, ErrandsAndParkingNoPathLeadsToAreCountedAndLeftAlone) {
  // Cell (3,0) is cut off by the wall at (2,0).
  auto graph = std::make_shared<const Graph>(4, 1, std::vector<std::string>{"..@."});
  const Vertex island = graph->vertex_at({3, 0});
  WindowPlanner windows(graph, 1);
  const PlanWindow window = windows.plan({{0}, {}}, {{{island, 1}, island}}, 10, planner_core::Deadline::in_seconds(5));
  EXPECT_EQ(window.unreachable, 2);
  EXPECT_EQ(window.reached[0], std::vector<Vertex>{1});
  EXPECT_EQ(window.steps.back(), Config{0});  // it waits where it began
}

TEST(WindowPlanner, TwoAgentsThatCanNeverPassEachOtherAreReportedStalled) {
  // Head-on in a corridor with no room to pass: no step ever brings both nearer for long.
  auto graph = std::make_shared<const Graph>(5, 1, std::vector<std::string>{"....."});
  WindowPlanner windows(graph, 4);
  Config at{0, 4};
  const std::vector<WindowAgent> agents{{{4}, 4}, {{0}, 0}};
  int steps = 0;
  std::vector<int> stalled;
  while (stalled.empty() && steps < 400) {
    const PlanWindow next = windows.plan({at, {}}, agents, 5, planner_core::Deadline::in_seconds(5));
    EXPECT_TRUE(next.reached[0].empty() && next.reached[1].empty());
    stalled = next.stalled;
    at = next.steps.back();
    steps += static_cast<int>(next.steps.size()) - 1;
  }
  EXPECT_FALSE(stalled.empty());
  EXPECT_GE(steps, WindowPlanner::kStalledSteps);  // not before it had the time to get nearer
  EXPECT_LE(steps, 3 * WindowPlanner::kStalledSteps);
}

TEST(WindowPlanner, AnAgentMakingHeadwayIsNeverReportedStalled) {
  // A long winding corridor: 300 steps to the errand, each one nearer.
  std::vector<std::string> rows;
  for (int y = 0; y < 30; ++y) rows.push_back(y % 2 == 0 ? std::string(10, '.') : (y % 4 == 1 ? "@@@@@@@@@." : ".@@@@@@@@@"));
  auto graph = std::make_shared<const Graph>(10, 30, rows);
  WindowPlanner windows(graph, 1);
  const Vertex far = graph->vertex_at({0, 29 - 1});
  Config at{graph->vertex_at({0, 0})};
  for (int window = 0; window < 40; ++window) {
    const PlanWindow next = windows.plan({at, {}}, {{{far}, far}}, 5, planner_core::Deadline::in_seconds(5));
    EXPECT_TRUE(next.stalled.empty()) << "window " << window;
    at = next.steps.back();
  }
}

TEST(WindowPlanner, OneWindowAgentPerAgentOrItRefuses) {
  auto graph = std::make_shared<const Graph>(4, 1, std::vector<std::string>{"...."});
  WindowPlanner windows(graph, 1);
  EXPECT_THROW(windows.plan({{0, 3}, {}}, {{{}, 0}}, 5, planner_core::Deadline::in_seconds(5)), std::invalid_argument);
}

TEST(WindowPlanner, WithTurnsEveryWindowIsValidAndContinuesTheHeadingsOfTheLast) {
  // An open 6x4 room, three agents facing every way with two errands each; windows of 5 steps
  // until all are reached, each checked by the validator in the rotation model and carried by one
  // ADG that grows window by window (so each starts facing the way the last ended).
  auto graph = std::make_shared<const Graph>(6, 4, std::vector<std::string>{"......", "..@...", "......", "......"});
  const auto at = [&](int x, int y) { return graph->vertex_at({x, y}); };
  WindowPlanner windows(graph, 3, planner_core::ActionModel::kRotate);
  planner_core::Poses poses{{at(0, 0), at(5, 3), at(3, 2)}, {3, 0, 2}};
  std::vector<WindowAgent> agents{{{at(5, 0), at(0, 3)}, at(0, 0)}, {{at(0, 0), at(2, 3)}, at(5, 3)},
                                  {{at(1, 1), at(4, 0)}, at(3, 2)}};
  std::unique_ptr<ActionDependencyGraph> adg;
  int errands_left = 6, turns = 0;
  for (int window = 0; window < 100 && errands_left > 0; ++window) {
    const PlanWindow next = windows.plan(poses, agents, 5, planner_core::Deadline::in_seconds(5));
    ASSERT_EQ(next.headings.size(), next.steps.size());
    ASSERT_EQ(next.headings.front(), poses.headings);
    planner_core::Instance stretch;
    stretch.graph = graph;
    stretch.starts = next.steps.front();
    stretch.goals = next.steps.back();
    stretch.actions = planner_core::ActionModel::kRotate;
    stretch.start_headings = next.headings.front();
    stretch.index_tasks();
    const planner_core::ValidationReport report =
        planner_core::validate(stretch, next.steps, {.forbid_rotations = true, .first_stretch = true}, next.headings);
    ASSERT_TRUE(report.ok()) << "window " << window << ": " << report.summary();
    if (!adg) {
      adg = std::make_unique<ActionDependencyGraph>(next.steps, next.headings);
    } else {
      adg->extend(next.steps, next.headings);
    }
    for (size_t s = 1; s < next.steps.size(); ++s) {
      for (size_t a = 0; a < 3; ++a) turns += next.headings[s][a] != next.headings[s - 1][a] ? 1 : 0;
    }
    for (size_t a = 0; a < agents.size(); ++a) {
      for (Vertex reached : next.reached[a]) {
        const auto it = std::find(agents[a].errands.begin(), agents[a].errands.end(), reached);
        ASSERT_NE(it, agents[a].errands.end());
        agents[a].errands.erase(it);
        --errands_left;
      }
    }
    poses = {next.steps.back(), next.headings.back()};
  }
  EXPECT_EQ(errands_left, 0);
  EXPECT_GT(turns, 3);
  EXPECT_EQ(adg->last_headings(), poses.headings);
  // A window that does not start facing the way the plan ends is refused.
  planner_core::HeadingPlan wrong = {poses.headings};
  wrong[0][0] = (wrong[0][0] + 1) % 4;
  EXPECT_THROW(adg->extend({poses.cells}, wrong), std::invalid_argument);
  // And a window of robots that turn needs their headings.
  EXPECT_THROW(windows.plan({poses.cells, {}}, agents, 5, planner_core::Deadline::in_seconds(5)), std::invalid_argument);
}

}  // namespace
}  // namespace coordinator

namespace coordinator {
namespace {

TEST(WindowPlanner, SettingsFromALifelongFileNeverBringLnsOrCyclesAndWindowsStayValid) {
  // The shipped settings (128 rollouts, lanes or shortest paths, held plans...) with LNS asked for:
  // the window planner takes them without LNS and without rotations, in both models.
  auto graph = std::make_shared<const Graph>(
      6, 5, std::vector<std::string>{"......", ".@..@.", "......", ".@..@.", "......"});
  const auto at = [&](int x, int y) { return graph->vertex_at({x, y}); };
  planner_core::LifelongConfig asked;
  asked.lns = "on";
  for (planner_core::ActionModel model : {planner_core::ActionModel::kMove4, planner_core::ActionModel::kRotate}) {
    const planner_core::PibtLifelongSettings pibt = window_settings(asked, *graph, 4, model);
    EXPECT_FALSE(pibt.lns);
    EXPECT_TRUE(pibt.forbid_rotations);
    EXPECT_EQ(pibt.rollouts, 128);
    WindowPlanner windows(graph, 5, model, pibt);
    const bool turning = model == planner_core::ActionModel::kRotate;
    planner_core::Poses poses{{at(0, 0), at(5, 0), at(0, 4), at(5, 4)}, {}};
    if (turning) poses.headings = {0, 1, 2, 3};
    std::vector<WindowAgent> agents{{{at(5, 4), at(2, 2)}, at(0, 0)}, {{at(0, 4), at(3, 2)}, at(5, 0)},
                                    {{at(5, 0)}, at(0, 4)}, {{at(0, 0)}, at(5, 4)}};
    int errands_left = 6;
    for (int window = 0; window < 60 && errands_left > 0; ++window) {
      const PlanWindow next = windows.plan(poses, agents, 5, planner_core::Deadline::in_seconds(5));
      planner_core::Instance stretch;
      stretch.graph = graph;
      stretch.starts = next.steps.front();
      stretch.goals = next.steps.back();
      stretch.actions = model;
      if (turning) stretch.start_headings = next.headings.front();
      stretch.index_tasks();
      const planner_core::ValidationReport report = planner_core::validate(
          stretch, next.steps, {.forbid_rotations = true, .first_stretch = true}, next.headings);
      ASSERT_TRUE(report.ok()) << "window " << window << ": " << report.summary();
      for (size_t a = 0; a < agents.size(); ++a) {
        for (Vertex reached : next.reached[a]) {
          auto& errands = agents[a].errands;
          errands.erase(std::find(errands.begin(), errands.end(), reached));
          --errands_left;
        }
      }
      poses = {next.steps.back(), turning ? next.headings.back() : planner_core::Headings{}};
    }
    EXPECT_EQ(errands_left, 0) << (turning ? "rotation model" : "four moves");
  }
  // No file: plain PIBT, as before the settings existed.
  EXPECT_EQ(window_settings(std::nullopt, *graph, 4, planner_core::ActionModel::kMove4).rollouts, 1);
}

}  // namespace
}  // namespace coordinator
