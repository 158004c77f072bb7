#include "fleet_trace.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace {

using coordinator::FleetTrace;
using fleet_transport::RobotStatus;

// A corridor of four cells, robot0 starting at (0,0) facing east; the problem's tasks at (3,0), (1,0).
struct FleetTraceTest : ::testing::Test {
  planner_core::LorrProblem problem;
  FleetTrace trace;
  void SetUp() override {
    problem.graph = std::make_shared<const planner_core::Graph>(4, 1, std::vector<std::string>{"...."});
    const planner_core::Graph& graph = *problem.graph;
    problem.starts = {graph.vertex_at({0, 0})};
    problem.tasks = {{graph.vertex_at({3, 0})}, {graph.vertex_at({1, 0})}};
  }
  void at_rest(const std::string& id, int x, int heading, int64_t stamp_ms, RobotStatus status = RobotStatus::kArrived) {
    fleet_transport::RobotState state;
    state.robot_id = id;
    state.cell_x = x;
    state.heading = heading;
    state.stamp_ms = stamp_ms;
    state.status = status;
    trace.heard_state(state);
  }
  void event(const std::string& kind, int task, int64_t stamp_ms) {
    trace.heard_event({1, stamp_ms, kind, "robot0", "", static_cast<double>(task)});
  }
};

// Ticks of 200 ms from 1000: each action on the tick of its arrival (a second arrival within one
// tick on the next, counted), a task done on the tick after its robot's arrival there.
TEST_F(FleetTraceTest, ARunBecomesTheLeaguesActionsPerTickWithEachTaskDoneTheTickAfterItsRobotArrived) {
  at_rest("robot0", 0, 0, 900);                          // before the start: where it starts
  at_rest("robot0", 0, 3, 1100, RobotStatus::kMoving);   // mid-turn: not a pose
  at_rest("robot0", 1, 0, 1250);                         // tick 1: F
  at_rest("robot0", 1, 0, 1260);                         // the same pose again (a wait): nothing
  at_rest("robot0", 2, 0, 1399);                         // tick 1 again: F on tick 2, shifted
  at_rest("robot0", 2, 1, 1700);                         // tick 3: R
  at_rest("robot0", 2, 0, 1900);                         // tick 4: C
  at_rest("robot0", 3, 0, 2050);                         // tick 5: F
  at_rest("robot9", 3, 0, 2050);                         // not one of the run's robots
  event("task_added", 10, 1000);
  event("task_added", 11, 1010);
  event("task_done", 11, 1262);                          // robot0 arrived at (1,0) on tick 1
  event("task_added", 99, 1300);                         // not one of the problem's
  trace.heard_event({1, 1300, "task_done", "robot0", "", std::nan("")});  // no task id: dropped
  trace.heard_event({1, 1300, "task_done", "robot0", "", 1e300});
  event("task_done", 10, 2060);                          // ... at (3,0) on tick 5
  event("task_done", 10, 2500);                          // after the end: left out
  const coordinator::FleetLeagueRun run =
      coordinator::league_log_of_fleet(trace, problem, 1, 1000, 2400, 200, {{10, 0}, {11, 1}});
  ASSERT_EQ(run.log.actual.size(), 1u);
  EXPECT_EQ(run.log.actual[0], "WFFRCFW");
  EXPECT_EQ(run.shifted, 1);
  EXPECT_EQ(run.jumps, 0);
  EXPECT_TRUE(run.log.errors.empty());
  EXPECT_EQ(trace.task_events().size(), 6u);  // the two without a task id dropped as heard
  ASSERT_EQ(run.log.events.size(), 2u);
  EXPECT_EQ((std::vector<int>{run.log.events[0].tick, run.log.events[1].tick}), (std::vector<int>{2, 6}));
  EXPECT_EQ((std::vector<int64_t>{run.log.events[0].task, run.log.events[1].task}), (std::vector<int64_t>{1, 0}));
  EXPECT_EQ(run.result.tasks_finished, 2);
  EXPECT_EQ(run.result.tasks_per_tick.size(), 7u);
  EXPECT_EQ(run.log.tasks_revealed, 2);
  EXPECT_EQ(run.log.start_headings, (planner_core::Headings{0}));
  // Its first task: task 0 (given first) all along, until it was done.
  EXPECT_EQ(run.log.schedule[0], (std::vector<std::pair<int, int64_t>>{{0, 0}}));
}

TEST_F(FleetTraceTest, APoseNoActionExplainsIsCountedAndLoggedAsAnError) {
  at_rest("robot0", 0, 0, 900);
  at_rest("robot0", 3, 0, 1500);  // three cells in one arrival: put down elsewhere
  const coordinator::FleetLeagueRun run = coordinator::league_log_of_fleet(trace, problem, 1, 1000, 2000, 200, {});
  EXPECT_EQ(run.jumps, 1);
  ASSERT_EQ(run.log.errors.size(), 1u);
  EXPECT_EQ(run.log.errors[0].step, 2);
  EXPECT_EQ(run.log.actual[0], "WWWWW");
}

}  // namespace
