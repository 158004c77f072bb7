#include "task_stream.hpp"

#include <gtest/gtest.h>

namespace {

using coordinator::TaskStream;
using fleet_transport::TaskReply;
using fleet_transport::TaskRequest;

std::vector<planner_core::Cell> cells_of(const std::vector<TaskRequest>& requests) {
  std::vector<planner_core::Cell> cells;
  for (const TaskRequest& request : requests) cells.push_back({request.x, request.y});
  return cells;
}

void accept_all(TaskStream& stream, const std::vector<TaskRequest>& requests) {
  for (const TaskRequest& request : requests) stream.answered(TaskReply{.request_id = request.request_id, .accepted = true});
}

TEST(TaskStream, GivesAListsCellsInOrderKeepingAsManyWaitingAsAskedAndStartsOverAfterTheLast) {
  const std::vector<planner_core::Cell> cells{{1, 1}, {2, 2}, {3, 3}};
  TaskStream stream(cells, 2, 0, "league");
  const auto now = TaskStream::Clock::now();
  const std::vector<TaskRequest> first = stream.due(0, now);
  EXPECT_EQ(cells_of(first), (std::vector<planner_core::Cell>{{1, 1}, {2, 2}}));
  accept_all(stream, first);
  EXPECT_TRUE(stream.due(0, now).empty()) << "two wait already";
  const std::vector<TaskRequest> second = stream.due(1, now);
  EXPECT_EQ(cells_of(second), (std::vector<planner_core::Cell>{{3, 3}}));
  accept_all(stream, second);
  const std::vector<TaskRequest> third = stream.due(3, now);
  EXPECT_EQ(cells_of(third), (std::vector<planner_core::Cell>{{1, 1}, {2, 2}})) << "after the last, the first again";
  EXPECT_EQ(stream.accepted(), 3);
}

TEST(TaskStream, AsksAgainWhatWasNotAnsweredWithinASecondAndCountsARefusalOnce) {
  TaskStream stream(std::vector<planner_core::Cell>{{1, 1}, {2, 2}}, 1, 0, "league");
  const auto now = TaskStream::Clock::now();
  const std::vector<TaskRequest> asked = stream.due(0, now);
  ASSERT_EQ(asked.size(), 1u);
  EXPECT_TRUE(stream.due(0, now + std::chrono::milliseconds(500)).empty());
  const std::vector<TaskRequest> again = stream.due(0, now + std::chrono::milliseconds(1500));
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0], asked[0]) << "the same request, so the coordinator adds it once";
  stream.answered(TaskReply{.request_id = asked[0].request_id, .accepted = false, .reason = "on a wall"});
  stream.answered(TaskReply{.request_id = asked[0].request_id, .accepted = false, .reason = "on a wall"});
  EXPECT_EQ(stream.refused(), 1);
  EXPECT_EQ(stream.last_refusal(), "on a wall");
  const std::vector<TaskRequest> next = stream.due(0, now + std::chrono::milliseconds(1600));
  EXPECT_EQ(cells_of(next), (std::vector<planner_core::Cell>{{2, 2}})) << "a refused task is not waiting: the next comes";
}

TEST(TaskStream, AsksAgainUnderANewIdForATaskRefusedBecauseItsCellHasOneWaitingAndKeepsItWaiting) {
  TaskStream stream(std::vector<planner_core::Cell>{{1, 1}, {2, 2}}, 1, 0, "league");
  const auto now = TaskStream::Clock::now();
  const std::vector<TaskRequest> asked = stream.due(0, now);
  ASSERT_EQ(asked.size(), 1u);
  stream.answered(TaskReply{.request_id = asked[0].request_id, .accepted = false,
                            .reason = "duplicate: task 3 at (1,1) is already pending for robot robot2"});
  EXPECT_EQ(stream.refused(), 0);
  EXPECT_EQ(stream.deferred(), 1);
  EXPECT_TRUE(stream.due(0, TaskStream::Clock::now()).empty()) << "it still waits: nothing new, not yet again";
  const std::vector<TaskRequest> again = stream.due(0, TaskStream::Clock::now() + std::chrono::milliseconds(300));
  ASSERT_EQ(again.size(), 1u);
  EXPECT_NE(again[0].request_id, asked[0].request_id) << "a repeated id would be answered as before";
  EXPECT_EQ(cells_of(again), (std::vector<planner_core::Cell>{{1, 1}})) << "the list's order is kept";
  accept_all(stream, again);
  EXPECT_EQ(stream.accepted(), 1);
  EXPECT_EQ(cells_of(stream.due(1, now)), (std::vector<planner_core::Cell>{{2, 2}}));
}

}  // namespace

namespace {

// The fleet's id of each task taken -> its number in the list's order, counting on after the last
// cell; a task asked again after a duplicate refusal keeps its number.
TEST(TaskStream, KnowsTheListNumberOfEachTaskTheFleetTook) {
  TaskStream stream(std::vector<planner_core::Cell>{{1, 1}, {2, 2}}, 2, 0, "league");
  const auto now = TaskStream::Clock::now();
  const std::vector<TaskRequest> first = stream.due(0, now);
  ASSERT_EQ(first.size(), 2u);
  stream.answered(TaskReply{.request_id = first[0].request_id, .accepted = true, .task = 40});
  stream.answered(TaskReply{.request_id = first[1].request_id, .accepted = false, .reason = "duplicate: task 40"});
  const std::vector<TaskRequest> again = stream.due(0, now + std::chrono::seconds(1));
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(cells_of(again), (std::vector<planner_core::Cell>{{2, 2}}));
  stream.answered(TaskReply{.request_id = again[0].request_id, .accepted = true, .task = 41});
  const std::vector<TaskRequest> third = stream.due(1, now + std::chrono::seconds(1));
  ASSERT_EQ(third.size(), 1u);
  stream.answered(TaskReply{.request_id = third[0].request_id, .accepted = true, .task = 42});
  EXPECT_EQ(stream.list_number_of_task(), (std::map<int, int64_t>{{40, 0}, {41, 1}, {42, 2}}));
}

}  // namespace
