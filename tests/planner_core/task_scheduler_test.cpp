// The schedulers of a lifelong run's tasks (task_board.hpp): nearest first errand, the whole task
// soonest finished, and ours, which also takes an unopened task from an agent farther from it;
// turns counted in the rotation model.
#include <gtest/gtest.h>

#include <string>

#include "planner_core/input_error.hpp"
#include "planner_core/task_board.hpp"
#include "tiny_lorr_problem.hpp"

namespace planner_core {
namespace {

Vertex column(const LorrProblem& problem, int x) { return problem.graph->vertex_at({x, 0}); }

TEST(TaskScheduler, EachRuleNamesItsScheduler) {
  EXPECT_EQ(scheduler_for(TaskAssignment::kRoundRobin), TaskScheduler::kRoundRobin);
  EXPECT_EQ(scheduler_for(TaskAssignment::kGreedy), TaskScheduler::kNearestErrand);
  EXPECT_EQ(scheduler_for(TaskAssignment::kPool), TaskScheduler::kWholeTaskReassign);
  for (TaskScheduler scheduler : {TaskScheduler::kRoundRobin, TaskScheduler::kNearestErrand, TaskScheduler::kWholeTask,
                                  TaskScheduler::kWholeTaskReassign}) {
    EXPECT_EQ(parse_task_scheduler(to_string(scheduler), "--scheduler"), scheduler);
  }
  try {
    parse_task_scheduler("nearest", "--scheduler");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--scheduler: 'nearest'"), std::string::npos) << e.what();
  }
}

// One agent at column 4 of a corridor, two tasks in the pool: A's first errand is nearer (column
// 3) but A then goes on to column 8; B (columns 6 then 7) is finished sooner.
TEST(TaskScheduler, WholeTaskTakesTheTaskFinishedSoonest) {
  TinyProblem tiny({"........."}, {"1", "4"}, {"2", "3,8", "6,7"}, "\"numTasksReveal\": 2");
  const LorrProblem problem = load_lorr_problem(tiny.path());
  ASSERT_EQ(problem.assignment, TaskAssignment::kPool);
  const Config starts = problem.starts;
  EXPECT_EQ(TaskBoard(problem, starts, nullptr, TaskScheduler::kNearestErrand).goal(0), column(problem, 3));
  EXPECT_EQ(TaskBoard(problem, starts, nullptr, TaskScheduler::kWholeTask).goal(0), column(problem, 6));
  EXPECT_EQ(TaskBoard(problem, starts, nullptr).goal(0), column(problem, 6));
}

// In the rotation model a quarter turn costs a step: an agent at column 4 facing east reaches
// column 6 (two steps forward) sooner than column 3 behind it (two turns and a step).
TEST(TaskScheduler, TurnsCountInTheRotationModel) {
  TinyProblem tiny({"........."}, {"1", "4"}, {"2", "3", "6"}, "\"numTasksReveal\": 2");
  const LorrProblem problem = load_lorr_problem(tiny.path());
  EXPECT_EQ(TaskBoard(problem, problem.starts, nullptr, TaskScheduler::kWholeTask).goal(0), column(problem, 3));
  EXPECT_EQ(TaskBoard(problem, problem.starts, nullptr, TaskScheduler::kWholeTask, {0}).goal(0), column(problem, 6));
  EXPECT_EQ(TaskBoard(problem, problem.starts, nullptr, TaskScheduler::kWholeTask, {2}).goal(0), column(problem, 3));
}

// Turns count between errands too: columns 6 then 5 is 3 steps without turns, 5 with (2 forward,
// then turning back); column 8 is 4 either way.
TEST(TaskScheduler, TurnsBetweenErrandsCount) {
  TinyProblem tiny({"........."}, {"1", "4"}, {"2", "6,5", "8"}, "\"numTasksReveal\": 2");
  const LorrProblem problem = load_lorr_problem(tiny.path());
  EXPECT_EQ(TaskBoard(problem, problem.starts, nullptr, TaskScheduler::kWholeTask).goal(0), column(problem, 6));
  EXPECT_EQ(TaskBoard(problem, problem.starts, nullptr, TaskScheduler::kWholeTask, {0}).goal(0), column(problem, 8));
}

// Agent 0 at column 5 takes task 0 (column 6); agent 1 at column 0 is left task 1 (column 10).
// Agent 0 finishes at step 1, task 2 (column 0) is revealed: ours gives agent 0 task 1, which it
// is 4 away from while agent 1 still has about 9 to go, and agent 1 the task at its feet.
TEST(TaskScheduler, AnUnopenedTaskGoesToANearerAgent) {
  TinyProblem tiny({"............"}, {"2", "5", "0"}, {"3", "6", "10", "0"}, "\"numTasksReveal\": 1");
  const LorrProblem problem = load_lorr_problem(tiny.path());
  DistTable distances(*problem.graph);
  for (TaskScheduler scheduler : {TaskScheduler::kWholeTask, TaskScheduler::kWholeTaskReassign}) {
    TaskBoard board(problem, problem.starts, nullptr, scheduler);
    EXPECT_EQ(board.goal(0), column(problem, 6));
    EXPECT_EQ(board.goal(1), column(problem, 10));
    board.set_time(1);
    int64_t finished = 0;
    EXPECT_TRUE(board.arrive(0, column(problem, 6), 0, distances, finished));
    EXPECT_EQ(finished, 1);
    const bool ours = scheduler == TaskScheduler::kWholeTaskReassign;
    EXPECT_EQ(board.goal(0), column(problem, ours ? 10 : 0)) << to_string(scheduler);
    EXPECT_EQ(board.goal(1), column(problem, ours ? 0 : 10)) << to_string(scheduler);
    EXPECT_EQ(board.reassignments(), ours ? 1 : 0);
  }
}

// A task whose first errand is finished is opened: it stays with its agent.
TEST(TaskScheduler, AnOpenedTaskStaysWithItsAgent) {
  TinyProblem tiny({"............"}, {"2", "5", "0"}, {"3", "6", "1,11", "0"}, "\"numTasksReveal\": 1");
  const LorrProblem problem = load_lorr_problem(tiny.path());
  DistTable distances(*problem.graph);
  TaskBoard board(problem, problem.starts, nullptr);
  ASSERT_EQ(board.goal(1), column(problem, 1));
  int64_t finished = 0;
  board.set_time(1);
  EXPECT_TRUE(board.arrive(1, column(problem, 1), 0, distances, finished));  // agent 1 opens task 1
  EXPECT_EQ(board.goal(1), column(problem, 11));
  board.set_time(2);
  EXPECT_TRUE(board.arrive(0, column(problem, 6), 0, distances, finished));
  EXPECT_EQ(board.goal(1), column(problem, 11));
  EXPECT_EQ(board.goal(0), column(problem, 0));
  EXPECT_EQ(board.reassignments(), 0);
}

// The 2024 pool: numTasksReveal x teamSize tasks revealed and not finished, those held included.
TEST(TaskScheduler, ThePoolHoldsNumTasksRevealTimesTheTeam) {
  TinyProblem tiny({"............"}, {"2", "5", "0"}, {"4", "6", "10", "1", "2"}, "\"numTasksReveal\": 1");
  const LorrProblem problem = load_lorr_problem(tiny.path());
  DistTable distances(*problem.graph);
  TaskBoard board(problem, problem.starts, nullptr, TaskScheduler::kWholeTask);
  // Two agents, two tasks revealed (0 and 1): agent 1 at column 0 cannot be given task 2 (column
  // 1), which is not revealed yet.
  EXPECT_EQ(board.goal(1), column(problem, 10));
  EXPECT_EQ(board.task_of(0), 0);
  EXPECT_EQ(board.task_of(1), 1);
}

}  // namespace
}  // namespace planner_core
