// The coordinator's parts on their own, without DDS: MissionProgress, RobotRegistry, the plan
// builder and PlanExecution.
#include <gtest/gtest.h>

#include <memory>

#include "coordinator/active_coordinator_watch.hpp"
#include "coordinator/mission_progress.hpp"
#include "coordinator/plan_builder.hpp"
#include "coordinator/plan_execution.hpp"
#include "coordinator/robot_registry.hpp"
#include "coordinator/task_assignment.hpp"
#include "planner_core/validator.hpp"

namespace coordinator {
namespace {

using planner_core::Cell;
using planner_core::Vertex;

// A 5x3 open map; roles 0 and 1 with a task each and one task shared by both.
planner_core::Instance small_mission() {
  planner_core::Instance mission;
  mission.graph = std::make_shared<const planner_core::Graph>(5, 3, std::vector<std::string>{".....", ".....", "....."});
  const auto at = [&](int x, int y) { return mission.graph->vertex_at({x, y}); };
  mission.starts = {at(0, 0), at(0, 2)};
  mission.goals = {at(4, 0), at(4, 2)};
  mission.tasks = {{at(2, 0), {0}}, {at(2, 2), {1}}, {at(2, 1), {0, 1}}};
  mission.index_tasks();
  return mission;
}

TEST(MissionProgress, ASharedTaskIsDoneOnlyWhenEveryRoleVisited) {
  const planner_core::Instance mission = small_mission();
  MissionProgress progress(mission);
  EXPECT_EQ(progress.tasks_done(), 0);
  progress.visit(0, mission.graph->vertex_at({2, 1}));
  EXPECT_TRUE(progress.visited(2, 0));
  EXPECT_FALSE(progress.visited(2, 1));
  EXPECT_EQ(progress.tasks_done(), 0);
  progress.visit(1, mission.graph->vertex_at({2, 1}));
  EXPECT_EQ(progress.tasks_done(), 1);
  progress.visit(0, mission.graph->vertex_at({2, 2}));  // role 1's task: role 0's visit does not count
  EXPECT_FALSE(progress.visited(1, 0));
  EXPECT_EQ(progress.role_tasks(0), std::make_pair(2, 1));
}

TEST(MissionProgress, PendingVisitsNameRoleAndRobot) {
  const planner_core::Instance mission = small_mission();
  MissionProgress progress(mission);
  progress.bind(0, "robot7");
  EXPECT_TRUE(progress.any_role_free());
  EXPECT_TRUE(progress.work_waits_for_a_robot());  // role 1 has visits and no robot
  const auto lines = progress.pending_visits();
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "task 0 for role 0 (robot robot7)");
  EXPECT_EQ(lines[1], "task 1 for role 1 (no robot)");
  progress.bind(1, "robot8");
  EXPECT_FALSE(progress.work_waits_for_a_robot());
  progress.unbind(1);
  EXPECT_EQ(progress.robot_of(1), "");
}

TEST(MissionProgress, AddedTasksCountAndCancelledOnesCountNeitherWay) {
  planner_core::Instance mission = small_mission();
  MissionProgress progress(mission);
  progress.visit(0, mission.graph->vertex_at({2, 0}));
  EXPECT_EQ(progress.tasks_done(), 1);
  mission.tasks.push_back({mission.graph->vertex_at({3, 1}), {1}});
  mission.index_tasks();
  progress.add_task();
  EXPECT_EQ(progress.task_count(), 4);
  EXPECT_EQ(progress.tasks_to_do(), 4);
  EXPECT_EQ(progress.role_tasks(1), std::make_pair(3, 0));
  EXPECT_FALSE(progress.cancel(0));   // done already
  EXPECT_FALSE(progress.cancel(7));   // no such task
  EXPECT_TRUE(progress.cancel(3));
  EXPECT_FALSE(progress.cancel(3));   // cancelled already
  EXPECT_EQ(progress.tasks_to_do(), 3);
  EXPECT_TRUE(progress.visited(3, 0));  // nobody owes it a visit: plans leave it out
  EXPECT_TRUE(progress.visits_due_at(1, mission.graph->vertex_at({3, 1})).empty());
  EXPECT_EQ(progress.role_tasks(1), std::make_pair(2, 0));
  progress.visit(1, mission.graph->vertex_at({2, 2}));
  progress.visit(0, mission.graph->vertex_at({2, 1}));
  progress.visit(1, mission.graph->vertex_at({2, 1}));
  EXPECT_EQ(progress.tasks_done(), 3);
  EXPECT_TRUE(progress.all_tasks_done());  // the cancelled one is not waited for
  EXPECT_TRUE(progress.pending_visits().empty());
}

TEST(TaskAssignment, EarliestArrivalPicksTheRobotThatGetsThereSoonestNotTheOneWhoseWayPassesBy) {
  // 7x1 corridor and a cell cut off: robot a stands at 0 with tasks at 6 then 1 queued (goal 0);
  // robot b stands idle on its goal at 3.
  const planner_core::Graph line(9, 1, {".......@."});
  planner_core::DistTable distances(line);
  const auto v = [&](int x) { return line.vertex_at({x, 0}); };
  const std::vector<Tour> tours = {{"a", 0, {v(0), v(6), v(1), v(0)}}, {"b", 1, {v(3), v(3)}}};
  // A task at 5 lies on a's way (it costs a nothing), but a gets there only after its queue.
  EXPECT_EQ(cheapest_insertion(distances, v(5), tours).tour, 0);
  TaskPlacement placement = earliest_arrival(distances, v(5), tours);
  EXPECT_EQ(placement.tour, 1);
  EXPECT_EQ(placement.added_steps, 2);
  EXPECT_EQ(placement.position, 1u);  // after its last task, before its goal
  // Alone, a gets there after 0 -> 6 -> 1, then 1 -> 5: 6 + 5 + 4 steps; after its last task.
  placement = earliest_arrival(distances, v(5), {tours[0]});
  EXPECT_EQ(placement.added_steps, 15);
  EXPECT_EQ(placement.position, 3u);
  // Nobody reaches the cut-off cell.
  EXPECT_EQ(earliest_arrival(distances, v(8), tours).tour, -1);
}

TEST(TaskAssignment, ARobotOutOfTasksTakesAQueuedTaskItReachesSoonerThanItsHolder) {
  // 12x1 corridor and a cell cut off: robot a's plan ends at 0 and heads for 2, 9 and 11 (the
  // nearest first: 2, then 9, then 11); robot b's ends at 10 with nothing to do; robot c's at 5,
  // with a task at 6 of its own.
  const planner_core::Graph line(14, 1, {"............@."});
  planner_core::DistTable distances(line);
  const auto v = [&](int x) { return line.vertex_at({x, 0}); };
  std::vector<PoolRobot> robots = {{v(0), {v(11), v(2), v(9)}}, {v(10), {}}, {v(5), {v(6)}}};
  std::vector<PooledTask> tasks = {{40, v(2), 0}, {41, v(9), 0}, {42, v(11), 0}, {43, v(6), 2}};
  const std::vector<TaskMove> moves = rebalance_pool(distances, robots, tasks);
  // b reaches 9 and 11 in 1 step (a in 9 and 11); the pair taken first is the nearest, and b takes
  // one task per call: 9, as the first in the pool of the two.
  ASSERT_EQ(moves.size(), 1u);
  EXPECT_EQ(moves[0].task, 41);
  EXPECT_EQ(moves[0].from, 0);
  EXPECT_EQ(moves[0].to, 1);
  EXPECT_EQ(moves[0].way, 1);
  EXPECT_EQ(moves[0].holder_way, 9);  // 0 -> 2 -> 9
  EXPECT_EQ(tasks[1].holder, 1);
  EXPECT_EQ(robots[0].errands, (std::vector<planner_core::Vertex>{v(11), v(2)}));
  EXPECT_EQ(robots[1].errands, std::vector<planner_core::Vertex>{v(9)});
  // Next call: b has a task, so nothing moves; a keeps 2 (b would come from 10, farther than a).
  EXPECT_TRUE(rebalance_pool(distances, robots, tasks).empty());
  // A robot never takes a task its holder reaches as soon: c's task at 6 stays with c (1 step)
  // when b (4 steps from 6) runs out of tasks.
  robots[1].errands.clear();
  robots[0].errands = {v(2)};
  tasks = {{40, v(2), 0}, {43, v(6), 2}};
  EXPECT_TRUE(rebalance_pool(distances, robots, tasks).empty());
}

TEST(TaskAssignment, TheTasksOfARobotThatIsOutGoToTheNearestRobotsOneEach) {
  const planner_core::Graph line(14, 1, {"............@."});
  planner_core::DistTable distances(line);
  const auto v = [&](int x) { return line.vertex_at({x, 0}); };
  // Robot 0 is out holding three tasks; robots 1 and 2 are free; a fourth task is cut off.
  std::vector<PoolRobot> robots = {{planner_core::kNoVertex, {v(3), v(8), v(13)}, true}, {v(0), {}}, {v(10), {}}};
  std::vector<PooledTask> tasks = {{1, v(3), 0}, {2, v(8), 0}, {3, v(13), 0}};
  const std::vector<TaskMove> moves = rebalance_pool(distances, robots, tasks);
  ASSERT_EQ(moves.size(), 2u);
  EXPECT_EQ(moves[0].task, 2);  // robot 2 to 8: 2 steps, the nearest pair
  EXPECT_EQ(moves[0].to, 2);
  EXPECT_EQ(moves[0].holder_way, -1);
  EXPECT_EQ(moves[1].task, 1);  // robot 1 to 3
  EXPECT_EQ(moves[1].to, 1);
  EXPECT_EQ(tasks[2].holder, 0);  // nobody reaches 13: it waits
}

TEST(TaskAssignment, CheapestInsertionPicksTheTourThatGrowsLeastAtItsBestPlace) {
  // 7x1 corridor: robot a stands at 0 bound for 6; robot b stands at 3 on its goal.
  const planner_core::Graph line(7, 1, {"......."});
  planner_core::DistTable distances(line);
  const auto v = [&](int x) { return line.vertex_at({x, 0}); };
  const std::vector<Tour> tours = {{"a", 0, {v(0), v(6)}}, {"b", 1, {v(3)}}};
  // On a's way: free for a; b would go there and back.
  TaskPlacement placement = cheapest_insertion(distances, v(5), tours);
  EXPECT_EQ(placement.tour, 0);
  EXPECT_EQ(placement.position, 1u);
  EXPECT_EQ(placement.added_steps, 0);
  // A tour of one stop (parked on its goal): there and back.
  placement = cheapest_insertion(distances, v(4), {tours[1]});
  EXPECT_EQ(placement.tour, 0);
  EXPECT_EQ(placement.added_steps, 2);
  // Between two stops, where it costs least.
  const std::vector<Tour> zigzag = {{"c", 0, {v(0), v(6), v(1), v(6)}}};
  placement = cheapest_insertion(distances, v(2), zigzag);
  EXPECT_EQ(placement.added_steps, 0);
  EXPECT_EQ(placement.position, 1u);  // on the way from 0 to 6
}

TEST(TaskAssignment, UnreachableTasksFindNoTourAndBadCellsAreNamed) {
  // Two rooms: x 0-2 and x 4-6, split by a wall column.
  planner_core::Instance mission;
  mission.graph = std::make_shared<const planner_core::Graph>(7, 2, std::vector<std::string>{"...@...", "...@..."});
  planner_core::DistTable distances(*mission.graph);
  const auto v = [&](int x, int y) { return mission.graph->vertex_at({x, y}); };
  const std::vector<Tour> left = {{"a", 0, {v(0, 0), v(2, 1)}}};
  EXPECT_EQ(cheapest_insertion(distances, v(5, 0), left).tour, -1);
  EXPECT_EQ(cheapest_insertion(distances, v(5, 0), {}).tour, -1);
  EXPECT_EQ(task_cell_refusal(mission, 1, 1), "");
  EXPECT_EQ(task_cell_refusal(mission, 3, 0), "(3,0) is a wall");
  EXPECT_EQ(task_cell_refusal(mission, 7, 0), "(7,0) is off the map (7 x 2)");
  EXPECT_EQ(task_cell_refusal(mission, -1, 0), "(-1,0) is off the map (7 x 2)");
}

TEST(RobotRegistry, AdmissionRules) {
  FleetConfig config;
  config.any_robots = false;
  config.expected_robots = {"robot0"};
  RobotRegistry registry;
  fleet_transport::Announcement hello{"robot0", "sim", "", "1", false};
  EXPECT_EQ(registry.admit(hello, config), RobotRegistry::Admission::kAdmitted);
  registry["robot0"].active = true;
  EXPECT_EQ(registry.admit(hello, config), RobotRegistry::Admission::kRepeat);
  fleet_transport::Announcement other_backend{"robot0", "toio", "", "1", false};
  EXPECT_EQ(registry.admit(other_backend, config), RobotRegistry::Admission::kDuplicate);
  fleet_transport::Announcement stranger{"robot9", "sim", "", "1", false};
  EXPECT_EQ(registry.admit(stranger, config), RobotRegistry::Admission::kRefused);
  EXPECT_EQ(registry.admit(stranger, config), RobotRegistry::Admission::kRefusedAgain);
  EXPECT_EQ(registry.active_count(), 1);
  EXPECT_TRUE(registry.ready_robots().empty());  // active but no state yet
  registry["robot0"].has_state = true;
  EXPECT_EQ(registry.ready_robots().size(), 1u);
}

TEST(RobotRegistry, SilentRobotsAfterTheTimeout) {
  RobotRegistry registry;
  const auto now = RobotRegistry::Clock::now();
  RobotRecord& quiet = registry["quiet"];
  quiet.active = true;
  quiet.last_heard = now - std::chrono::seconds(3);
  RobotRecord& chatty = registry["chatty"];
  chatty.active = true;
  chatty.last_heard = now;
  const auto silent = registry.silent_robots(now, 2.0);
  ASSERT_EQ(silent.size(), 1u);
  EXPECT_EQ(silent[0]->id, "quiet");
}

TEST(PlanBuilder, RemainingVisitsOnlyAndExtrasPark) {
  const planner_core::Instance mission = small_mission();
  MissionProgress progress(mission);
  progress.visit(0, mission.graph->vertex_at({2, 0}));  // role 0's own task done
  const std::vector<PlanMember> members = {{"a", {1, 0}, 0}, {"b", {1, 2}, 1}, {"extra", {3, 1}, -1}};
  const PlanInstance built = build_plan_instance(mission, progress, members, {});
  EXPECT_TRUE(built.notes.empty());
  ASSERT_EQ(built.robots, (std::vector<std::string>{"a", "b", "extra"}));
  const planner_core::Instance& instance = built.instance;
  EXPECT_EQ(instance.graph->cell_of(instance.starts[0]), (Cell{1, 0}));
  EXPECT_EQ(instance.graph->cell_of(instance.goals[1]), (Cell{4, 2}));
  EXPECT_EQ(instance.graph->cell_of(instance.goals[2]), (Cell{3, 1}));  // parks where it stands
  // Task 0 is done; task 1 for b; the shared task for both.
  ASSERT_EQ(instance.task_count(), 2);
  EXPECT_EQ(instance.tasks[0].agents, std::vector<int>{1});
  EXPECT_EQ(instance.tasks[1].agents, (std::vector<int>{0, 1}));
  EXPECT_TRUE(instance.tasks_of_agent[2].empty());
}

TEST(PlanBuilder, TwoRobotsOnOneCellAreLeftOutAndTheirCellWalled) {
  const planner_core::Instance mission = small_mission();
  MissionProgress progress(mission);
  const std::vector<PlanMember> members = {{"a", {1, 1}, 0}, {"b", {1, 1}, 1}, {"c", {3, 1}, -1}};
  const PlanInstance built = build_plan_instance(mission, progress, members, {});
  ASSERT_EQ(built.robots, std::vector<std::string>{"c"});
  EXPECT_EQ(built.notes.size(), 2u);
  EXPECT_FALSE(built.instance.graph->is_free({1, 1}));
}

TEST(PlanBuilder, BlockedCellsAreWallsAndUnreachableTasksAreNoted) {
  const planner_core::Instance mission = small_mission();
  MissionProgress progress(mission);
  // Wall off (2,2)'s neighbours so role 1's task there cannot be reached.
  std::set<Vertex> blocked = {mission.graph->vertex_at({1, 2}), mission.graph->vertex_at({3, 2}),
                              mission.graph->vertex_at({2, 1})};
  const std::vector<PlanMember> members = {{"a", {0, 0}, 0}, {"b", {0, 2}, 1}, {"off", {9, 9}, -1}};
  const PlanInstance built = build_plan_instance(mission, progress, members, blocked);
  EXPECT_FALSE(built.instance.graph->is_free({2, 1}));
  // One vertex space: the planning map walls cells but keeps the mission's vertex ids.
  ASSERT_EQ(built.instance.graph->vertex_count(), mission.graph->vertex_count());
  EXPECT_EQ(built.instance.starts[0], mission.graph->vertex_at({0, 0}));
  EXPECT_EQ(built.instance.goals[0], mission.goals[0]);
  ASSERT_EQ(built.robots.size(), 2u);  // the robot off the map is left out
  bool unreachable_noted = false;
  for (const std::string& note : built.notes) unreachable_noted |= note.find("task 1 unreachable") != std::string::npos;
  EXPECT_TRUE(unreachable_noted);
}

TEST(PlanExecution, SendsWhenReadyResendsWhenSilentAndConfirmsOnTheTarget) {
  const auto graph = std::make_shared<const planner_core::Graph>(3, 1, std::vector<std::string>{"..."});
  const Vertex v0 = graph->vertex_at({0, 0}), v1 = graph->vertex_at({1, 0}), v2 = graph->vertex_at({2, 0});
  // Robot "front" moves 1 -> 2, then "back" follows 0 -> 1: back's move waits for front's.
  const planner_core::Solution plan = {{v1, v0}, {v2, v1}};
  PlanExecution execution(3, graph, plan, {"front", "back"}, 77);
  const auto t0 = PlanExecution::Clock::now();
  EXPECT_EQ(execution.agent_of("back"), 1);
  EXPECT_TRUE(execution.ready_to_move(0));
  EXPECT_FALSE(execution.ready_to_move(1));  // waits on the ADG
  EXPECT_FALSE(execution.due_command(1, t0, 1.0, 0).has_value());
  const auto first = execution.due_command(0, t0, 1.0, 99);
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->robot_id, "front");
  EXPECT_EQ(first->plan_epoch, 3);
  EXPECT_EQ(first->action_index, 0);
  EXPECT_EQ(first->target_x, 2);
  EXPECT_EQ(first->deadline_ms, 99);
  EXPECT_EQ(first->coordinator, 77u);
  EXPECT_TRUE(execution.in_flight(0));
  EXPECT_FALSE(execution.ready_to_move(0));  // its move is under way
  EXPECT_FALSE(execution.due_command(0, t0 + std::chrono::milliseconds(500), 1.0, 0).has_value());
  EXPECT_TRUE(execution.due_command(0, t0 + std::chrono::seconds(2), 1.0, 0).has_value());  // resent

  fleet_transport::RobotState state;
  state.robot_id = "front";
  state.coordinator = 77;
  state.plan_epoch = 3;
  state.action_index = 0;
  state.status = fleet_transport::RobotStatus::kMoving;
  state.cell_x = 2;
  const auto round_trip = execution.acknowledge(0, state, t0 + std::chrono::milliseconds(40));
  ASSERT_TRUE(round_trip.has_value());
  EXPECT_NEAR(*round_trip, 40, 1e-6);
  EXPECT_FALSE(execution.acknowledge(0, state, t0).has_value());  // once per move
  EXPECT_FALSE(execution.confirm(0, state).has_value());          // still moving
  state.status = fleet_transport::RobotStatus::kArrived;
  state.plan_epoch = 2;
  EXPECT_FALSE(execution.confirm(0, state).has_value());          // another epoch's report
  state.plan_epoch = 3;
  state.coordinator = 78;
  EXPECT_FALSE(execution.confirm(0, state).has_value());          // another coordinator's epoch 3
  state.coordinator = 77;
  const auto before_confirming = PlanExecution::Clock::now();
  const auto reached = execution.confirm(0, state);
  ASSERT_TRUE(reached.has_value());
  EXPECT_EQ(*reached, (Cell{2, 0}));
  EXPECT_TRUE(execution.done(0));
  EXPECT_FALSE(execution.ready_to_move(0));  // no move left
  EXPECT_GE(execution.agent(0).finished_at, before_confirming);  // from when it has stood with nothing to do
  EXPECT_LT(execution.agent(1).finished_at, before_confirming);  // the plan's start
  EXPECT_TRUE(execution.ready_to_move(1));
  EXPECT_TRUE(execution.due_command(1, t0, 1.0, 0).has_value());  // now back may move
}

// A robot lost with a move in flight: the move of the robot following it goes (it would wait for
// ever), the lost robot's move stays; back on that move's start it is sent the move again, and on
// its target the move is done; anywhere else it cannot take its place again.
TEST(PlanExecution, CutAroundALostRobotAndTakenBackWhereItWas) {
  const auto graph = std::make_shared<const planner_core::Graph>(4, 1, std::vector<std::string>{"...."});
  const Vertex v0 = graph->vertex_at({0, 0}), v1 = graph->vertex_at({1, 0}), v2 = graph->vertex_at({2, 0}),
               v3 = graph->vertex_at({3, 0});
  // "front" 1 -> 2 -> 3, "back" follows 0 -> 1 -> 2.
  const planner_core::Solution plan = {{v1, v0}, {v2, v1}, {v3, v2}};
  for (const Cell back_at : {Cell{1, 0}, Cell{2, 0}, Cell{0, 0}}) {
    SCOPED_TRACE("front back at " + planner_core::to_string(back_at));
    PlanExecution execution(1, graph, plan, {"front", "back"}, 5);
    const auto t0 = PlanExecution::Clock::now();
    ASSERT_TRUE(execution.due_command(0, t0, 1.0, 0).has_value());  // front's first move, then lost
    EXPECT_EQ(execution.cut_around(0), 3);  // front's second move; both of back's
    EXPECT_TRUE(execution.in_flight(0));
    EXPECT_TRUE(execution.done(1));
    EXPECT_EQ(execution.last_configuration(), (planner_core::Config{v2, v0}));
    EXPECT_EQ(execution.plan_steps(), 2);
    const bool taken = execution.take_back(0, back_at);
    EXPECT_EQ(taken, (back_at != Cell{0, 0}));
    if (back_at == Cell{1, 0}) {  // where it was: the move goes again, from the start
      EXPECT_FALSE(execution.in_flight(0));
      const auto again = execution.due_command(0, t0, 1.0, 0);
      ASSERT_TRUE(again.has_value());
      EXPECT_EQ(again->action_index, 0);
      EXPECT_EQ(again->target_x, 2);
    } else if (back_at == Cell{2, 0}) {  // on its target: done
      EXPECT_TRUE(execution.done(0));
      EXPECT_EQ(execution.position(0), (Cell{2, 0}));
    }
  }
}

// A robot joining on a cell: refused where a robot of the plan stands or is moving to, and off the
// map; elsewhere the moves into its cell go and it is the plan's next agent, with no moves.
TEST(PlanExecution, ARobotJoinsOnACellNobodyStandsOnOrIsMovingTo) {
  const auto graph = std::make_shared<const planner_core::Graph>(4, 1, std::vector<std::string>{"...@"});
  const Vertex v0 = graph->vertex_at({0, 0}), v1 = graph->vertex_at({1, 0}), v2 = graph->vertex_at({2, 0});
  const planner_core::Solution plan = {{v0}, {v1}, {v2}};  // "r" goes 0 -> 1 -> 2
  PlanExecution execution(1, graph, plan, {"r"}, 5);
  ASSERT_TRUE(execution.due_command(0, PlanExecution::Clock::now(), 1.0, 0).has_value());  // 0 -> 1 under way
  EXPECT_FALSE(execution.admit("new", {0, 0}, -1).has_value());  // where r stands
  EXPECT_FALSE(execution.admit("new", {1, 0}, -1).has_value());  // where r is moving to
  EXPECT_FALSE(execution.admit("new", {3, 0}, -1).has_value());  // a wall
  EXPECT_EQ(execution.agent_count(), 1);
  const std::optional<int64_t> dropped = execution.admit("new", {2, 0}, -1);
  ASSERT_TRUE(dropped.has_value());
  EXPECT_EQ(*dropped, 1);  // r's move into 2
  ASSERT_EQ(execution.agent_count(), 2);
  EXPECT_EQ(execution.agent_of("new"), 1);
  EXPECT_TRUE(execution.done(1));
  EXPECT_EQ(execution.position(1), (Cell{2, 0}));
  EXPECT_EQ(execution.last_configuration(), (planner_core::Config{v1, v2}));
}

// A state of robot "r" standing still after the move `action` of coordinator 5's epoch 1.
fleet_transport::RobotState arrived_state(int action, int heading) {
  fleet_transport::RobotState state;
  state.robot_id = "r";
  state.coordinator = 5;
  state.plan_epoch = 1;
  state.action_index = action;
  state.status = fleet_transport::RobotStatus::kArrived;
  state.heading = heading;
  return state;
}

// A robot that reports no heading (-1: a body with no compass) is confirmed by its cell alone, or
// its first turn would never be confirmed and the mission would wait for it for ever. Its cell
// still has to be the move's, and a robot that reports a heading still has to face the move's.
TEST(PlanExecution, WithTurnsARobotThatReportsNoHeadingIsConfirmedByItsCell) {
  const auto graph = std::make_shared<const planner_core::Graph>(3, 1, std::vector<std::string>{"..."});
  const Vertex v0 = graph->vertex_at({0, 0}), v1 = graph->vertex_at({1, 0});
  // Facing west at (0,0): two turns to face east, then a move east.
  const planner_core::Solution plan = {{v0}, {v0}, {v0}, {v1}};
  const planner_core::HeadingPlan headings = {{2}, {3}, {0}, {0}};
  PlanExecution execution(1, graph, plan, {"r"}, 5, headings);
  ASSERT_EQ(execution.move_count(0), 3);
  const auto t0 = PlanExecution::Clock::now();
  const auto move = execution.due_command(0, t0, 1.0, 0);  // the turns folded into the move
  ASSERT_TRUE(move.has_value());
  EXPECT_EQ(move->action_index, 2);
  fleet_transport::RobotState state = arrived_state(2, -1);
  state.cell_x = 0;  // not there yet
  EXPECT_FALSE(execution.confirm(0, state).has_value());
  state.cell_x = 1;
  state.heading = 2;  // there, but reporting the wrong way
  EXPECT_FALSE(execution.confirm(0, state).has_value());
  state.heading = -1;
  const auto reached = execution.confirm(0, state);
  ASSERT_TRUE(reached.has_value());
  EXPECT_EQ(*reached, (Cell{1, 0}));
  EXPECT_TRUE(execution.done(0));
}

TEST(PlanExecution, WithTurnsATurnIsACommandOnTheRobotsCellDoneOnlyWhenTheRobotFacesItsHeading) {
  const auto graph = std::make_shared<const planner_core::Graph>(3, 2, std::vector<std::string>{"...", "..."});
  const Vertex v0 = graph->vertex_at({0, 0}), v1 = graph->vertex_at({1, 0}), v2 = graph->vertex_at({2, 0});
  const Vertex u1 = graph->vertex_at({1, 1});
  // "r" faces north at (0,0): turns clockwise (east), waits, moves east once "s" has left (1,0)
  // southwards, which "s" does after a turn of its own.
  const planner_core::Solution plan = {{v0, v1}, {v0, v1}, {v0, u1}, {v1, u1}};
  const planner_core::HeadingPlan headings = {{3, 0}, {0, 1}, {0, 1}, {0, 1}};
  PlanExecution execution(1, graph, plan, {"r", "s"}, 5, headings);
  ASSERT_EQ(execution.move_count(0), 2);  // the turn and the move; the wait is no command
  const auto t0 = PlanExecution::Clock::now();
  // r's move must wait for s: its turn goes alone, so r turns while it waits.
  const auto turn = execution.due_command(0, t0, 1.0, 0);
  ASSERT_TRUE(turn.has_value());
  EXPECT_EQ(turn->target_x, 0);
  EXPECT_EQ(turn->target_y, 0);
  EXPECT_EQ(turn->target_heading, 0);
  fleet_transport::RobotState state = arrived_state(0, 3);  // still facing north
  EXPECT_FALSE(execution.confirm(0, state).has_value());
  state.heading = 0;
  EXPECT_TRUE(execution.confirm(0, state).has_value());
  EXPECT_FALSE(execution.due_command(0, t0, 1.0, 0).has_value());  // (1,0) is still s's
  // s's turn and move south may go at once: one command, the move's, with the turn folded in.
  const auto folded = execution.due_command(1, t0, 1.0, 0);
  ASSERT_TRUE(folded.has_value());
  EXPECT_EQ(folded->action_index, 1);
  EXPECT_EQ(folded->target_x, 1);
  EXPECT_EQ(folded->target_y, 1);
  EXPECT_EQ(folded->target_heading, 1);
  EXPECT_TRUE(execution.in_flight(1));
  EXPECT_TRUE(execution.allows(1, {1, 1}));
  EXPECT_TRUE(execution.due_command(1, t0 + std::chrono::seconds(2), 1.0, 0).has_value());  // resent as it was
  fleet_transport::RobotState s_state = state;
  s_state.robot_id = "s";
  s_state.action_index = 1;
  s_state.cell_x = 1;
  s_state.cell_y = 1;
  s_state.heading = 1;
  EXPECT_TRUE(execution.confirm(1, s_state).has_value());
  EXPECT_TRUE(execution.done(1));
  const auto forward = execution.due_command(0, t0, 1.0, 0);
  ASSERT_TRUE(forward.has_value());
  EXPECT_EQ(forward->target_x, 1);
  EXPECT_EQ(forward->target_heading, 0);
  (void)v2;
  // Without headings the same plan's commands say "any heading".
  PlanExecution plain(1, graph, {{v0}, {v1}}, {"r"}, 5);
  EXPECT_EQ(plain.due_command(0, t0, 1.0, 0)->target_heading, -1);
}

TEST(PlanBuilder, WithTurnsAgentsStartFacingTheirRobotsHeadingsOrEastWhenUnknown) {
  planner_core::Instance mission = small_mission();
  mission.actions = planner_core::ActionModel::kRotate;
  MissionProgress progress(mission);
  const std::vector<PlanMember> members = {{"a", {1, 0}, 0, 2}, {"b", {1, 2}, 1, -1}};
  const PlanInstance built = build_plan_instance(mission, progress, members, {});
  EXPECT_EQ(built.instance.actions, planner_core::ActionModel::kRotate);
  EXPECT_EQ(built.instance.start_headings, (planner_core::Headings{2, 0}));
  ASSERT_EQ(built.notes.size(), 1u);
  EXPECT_NE(built.notes[0].find("robot b reports no heading"), std::string::npos) << built.notes[0];
  // The four-move model has no headings at all.
  const PlanInstance plain = build_plan_instance(small_mission(), progress, members, {});
  EXPECT_TRUE(plain.instance.start_headings.empty());
  EXPECT_TRUE(plain.notes.empty());
}

TEST(ActiveCoordinatorWatch, TwoActiveLongerThanTheGraceIsOneAlarm) {
  using std::chrono::milliseconds;
  ActiveCoordinatorWatch watch(std::chrono::seconds(5));
  const auto t0 = ActiveCoordinatorWatch::Clock::now();
  fleet_transport::CoordinatorStatus a{0xa, 1, 100, fleet_transport::CoordinatorRole::kActive, "m", 1};
  fleet_transport::CoordinatorStatus b{0xb, 1, 200, fleet_transport::CoordinatorRole::kActive, "m", 0};
  std::optional<std::string> alarm;
  int alarms = 0;
  for (int ms = 0; ms <= 8000; ms += 250) {  // both heartbeat every 0.25 s for 8 s
    if ((alarm = watch.on_status(a, t0 + milliseconds(ms)))) ++alarms;
    if ((alarm = watch.on_status(b, t0 + milliseconds(ms + 10)))) ++alarms;
  }
  EXPECT_EQ(alarms, 1);
  EXPECT_EQ(watch.alarms(), 1u);
}

TEST(ActiveCoordinatorWatch, ListeningThenStandingDownTakeoversAndStandbysAreNoAlarm) {
  using std::chrono::milliseconds;
  using fleet_transport::CoordinatorRole;
  ActiveCoordinatorWatch watch(std::chrono::seconds(5));
  const auto t0 = ActiveCoordinatorWatch::Clock::now();
  fleet_transport::CoordinatorStatus first{1, 1, 100, CoordinatorRole::kActive, "m", 1};
  fleet_transport::CoordinatorStatus late{2, 1, 900, CoordinatorRole::kActive, "m", 0};
  fleet_transport::CoordinatorStatus standby{3, 0, 0, CoordinatorRole::kStandby, "m", 0};
  for (int ms = 0; ms <= 20000; ms += 250) {
    const auto now = t0 + milliseconds(ms);
    EXPECT_FALSE(watch.on_status(standby, now));
    if (ms < 10000) {  // killed at 10 s
      EXPECT_FALSE(watch.on_status(first, now));
    }
    // The late one listens 2 s, then stands down; the standby takes over at 11.5 s as term 2.
    if (ms >= 3000 && ms < 5000) {
      EXPECT_FALSE(watch.on_status(late, now));
    }
    if (ms == 5000) {
      late.role = CoordinatorRole::kStoodDown;
      EXPECT_FALSE(watch.on_status(late, now));
    }
    if (ms >= 11500) {
      standby.role = CoordinatorRole::kActive;
      standby.term = 2;
    }
  }
  EXPECT_EQ(watch.alarms(), 0u);
}

}  // namespace
}  // namespace coordinator
