// FleetCoordinator end to end without DDS: a fake transport and robots that carry out each command
// at once (or, in one test, one robot that stops answering). Checks that the mission completes,
// that no two robots ever stand on one cell, and that each task visit is counted.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <map>
#include <set>
#include <thread>

#include "coordinator/fleet_coordinator.hpp"
#include "coordinator/plan_execution.hpp"
#include "fake_transport.hpp"

namespace coordinator {
namespace {

using testing_support::FakeTransport;

// A robot that ends every commanded move at once (or never, once it is `silent`).
struct FakeRobot {
  std::string id;
  planner_core::Cell cell;
  uint64_t seq = 0;
  bool silent = false;
  int epoch = -1, action = -1;  // of the last command carried out, repeated in every state
  uint64_t coordinator = 0;     // its sender
  int moves = 0;
  int teleport_after = -1;       // carried by hand to teleport_to after this many moves
  planner_core::Cell teleport_to{};

  fleet_transport::RobotState state(int epoch, int action, fleet_transport::RobotStatus status) {
    fleet_transport::RobotState s;
    s.robot_id = id;
    s.cell_x = cell.x;
    s.cell_y = cell.y;
    s.plan_epoch = epoch;
    s.action_index = action;
    s.status = status;
    s.seq_number = ++seq;
    s.coordinator = coordinator;
    return s;
  }
};

FleetConfig config_for(int robots) {
  FleetConfig config;
  config.quorum = robots;
  config.solver = "cts-pll-v2";
  config.replan_solver = "cts-pll-v2";
  config.plan_time_s = 2;
  config.replan_time_s = 2;
  config.silence_timeout_s = 0.3;
  config.replan_settle_s = 0.05;
  config.mission_timeout_s = 60;
  config.replacement_timeout_s = 0.5;
  config.lease_s = 0.05;  // listens this long for another coordinator before planning
  return config;
}

// Runs the coordinator until it ends; robots answer each command with an arrival on its target.
// Returns the cells each robot stood on, checking every step that no two robots share one.
// `each_iteration` may add robots (announced and heard at once).
std::map<std::string, std::vector<planner_core::Cell>> run(
    FleetCoordinator& coordinator, std::vector<FakeRobot>& robots,
    const std::function<void(std::vector<FakeRobot>&)>& each_iteration = {}) {
  FakeTransport transport;
  std::map<std::string, std::vector<planner_core::Cell>> visited;
  for (FakeRobot& robot : robots) {
    coordinator.on_announcement({robot.id, "sim", "", "test", false});
    coordinator.on_state(robot.state(-1, -1, fleet_transport::RobotStatus::kIdle));
    visited[robot.id].push_back(robot.cell);
  }
  for (int iteration = 0; iteration < 200000 && coordinator.step(transport); ++iteration) {
    if (each_iteration) {
      const size_t before = robots.size();
      each_iteration(robots);
      for (size_t r = before; r < robots.size(); ++r) {
        coordinator.on_announcement({robots[r].id, "sim", "", "test", false});
        coordinator.on_state(robots[r].state(-1, -1, fleet_transport::RobotStatus::kIdle));
        visited[robots[r].id].push_back(robots[r].cell);
      }
    }
    std::vector<fleet_transport::StepCommand> commands;
    commands.swap(transport.commands);
    for (const fleet_transport::StepCommand& command : commands) {
      for (FakeRobot& robot : robots) {
        if (robot.id != command.robot_id || robot.silent) continue;
        robot.cell = {command.target_x, command.target_y};
        robot.epoch = command.plan_epoch;
        robot.action = command.action_index;
        robot.coordinator = command.coordinator;
        if (++robot.moves == robot.teleport_after) robot.cell = robot.teleport_to;
        visited[robot.id].push_back(robot.cell);
        coordinator.on_state(robot.state(command.plan_epoch, command.action_index, fleet_transport::RobotStatus::kArrived));
      }
    }
    std::set<std::pair<int, int>> occupied;
    for (const FakeRobot& robot : robots) {
      EXPECT_TRUE(occupied.insert({robot.cell.x, robot.cell.y}).second)
          << "two robots on " << planner_core::to_string(robot.cell) << " at iteration " << iteration;
    }
    // Keep every live robot heard, as the agents' periodic states do.
    if (iteration % 20 == 0) {
      for (FakeRobot& robot : robots) {
        if (!robot.silent) coordinator.on_state(robot.state(robot.epoch, robot.action, fleet_transport::RobotStatus::kArrived));
      }
    }
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return visited;
}

TEST(FleetCoordinator, CompletesTheDefaultMissionWithAFakeTransport) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots;
  for (int r = 0; r < mission.agent_count(); ++r) {
    robots.push_back({"robot" + std::to_string(r), mission.graph->cell_of(mission.starts[r])});
  }
  const planner_core::Instance copy = mission;
  FleetCoordinator coordinator(config_for(mission.agent_count()), std::move(mission));
  const auto visited = run(coordinator, robots);
  const MissionSummary& summary = coordinator.summary();
  EXPECT_TRUE(summary.completed);
  EXPECT_EQ(summary.tasks_done, summary.tasks_total);
  EXPECT_EQ(summary.replans, 0);
  // Every task was really visited by each of its robots (role r = robot r: each stands on its role's start).
  for (const planner_core::Task& task : copy.tasks) {
    const planner_core::Cell at = copy.graph->cell_of(task.at);
    for (int role : task.agents) {
      const auto& cells = visited.at("robot" + std::to_string(role));
      EXPECT_NE(std::find(cells.begin(), cells.end(), at), cells.end()) << "role " << role << " never on " << planner_core::to_string(at);
    }
  }
  for (int r = 0; r < copy.agent_count(); ++r) EXPECT_EQ(robots[r].cell, copy.graph->cell_of(copy.goals[r]));
}

TEST(FleetCoordinator, ASilentRobotIsTakenOutAndTheOthersStillFinish) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots;
  for (int r = 0; r < mission.agent_count(); ++r) {
    robots.push_back({"robot" + std::to_string(r), mission.graph->cell_of(mission.starts[r])});
  }
  robots[3].silent = true;  // never moves, never reports again
  FleetCoordinator coordinator(config_for(mission.agent_count()), std::move(mission));
  run(coordinator, robots);
  const MissionSummary& summary = coordinator.summary();
  EXPECT_FALSE(summary.completed);  // robot3's role has no robot left
  EXPECT_EQ(summary.robots_lost, 1);
  EXPECT_GE(summary.replans, 1);
  bool role_without_robot = false;
  for (const std::string& line : summary.pending) role_without_robot |= line.find("(no robot)") != std::string::npos;
  EXPECT_TRUE(role_without_robot);
}

TEST(FleetCoordinator, WithoutAReplacementTimeoutTheRobotsHoldUntilARobotJoinsLate) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots;
  for (int r = 0; r < mission.agent_count(); ++r) {
    robots.push_back({"robot" + std::to_string(r), mission.graph->cell_of(mission.starts[r])});
  }
  robots[3].silent = true;  // lost before it does anything
  const planner_core::Cell spare_cell = mission.graph->cell_of(mission.goals[3]);
  FleetConfig config = config_for(mission.agent_count());
  config.replacement_timeout_s.reset();  // wait for a robot until the mission timeout
  FleetCoordinator coordinator(config, std::move(mission));
  std::optional<std::chrono::steady_clock::time_point> waiting_since;
  bool joined = false;
  run(coordinator, robots, [&](std::vector<FakeRobot>& fleet) {
    if (joined || !coordinator.waiting_for_robot()) return;
    const auto now = std::chrono::steady_clock::now();
    if (!waiting_since) waiting_since = now;
    // Four times the 0.5 s after which the mission used to end: a robot arriving late still counts.
    if (now - *waiting_since > std::chrono::seconds(2)) {
      fleet.push_back({"late", spare_cell});
      joined = true;
    }
  });
  ASSERT_TRUE(joined) << "the coordinator never waited for a robot";
  const MissionSummary& summary = coordinator.summary();
  EXPECT_TRUE(summary.completed);
  EXPECT_EQ(summary.robots_lost, 1);
  EXPECT_TRUE(summary.pending.empty());
}

TEST(FleetCoordinator, ARobotCarriedOffItsPlanIsTakenOutAndPlannedAround) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots;
  for (int r = 0; r < mission.agent_count(); ++r) {
    robots.push_back({"robot" + std::to_string(r), mission.graph->cell_of(mission.starts[r])});
  }
  robots[5].teleport_after = 10;
  robots[5].teleport_to = {1, 1};  // a free cell no role needs
  FleetCoordinator coordinator(config_for(mission.agent_count()), std::move(mission));
  run(coordinator, robots);  // also checks that no two robots ever share a cell
  const MissionSummary& summary = coordinator.summary();
  EXPECT_EQ(summary.off_plan, 1);
  EXPECT_GE(summary.robots_lost, 1);
  EXPECT_GE(summary.robots_joined, 1);  // back in from (1,1)
  EXPECT_TRUE(summary.completed);
}

std::vector<FakeRobot> robots_on_their_starts(const planner_core::Instance& mission) {
  std::vector<FakeRobot> robots;
  for (int r = 0; r < mission.agent_count(); ++r) {
    robots.push_back({"robot" + std::to_string(r), mission.graph->cell_of(mission.starts[r])});
  }
  return robots;
}

TEST(FleetCoordinator, OfTwoActiveCoordinatorsTheLaterOneStandsDownBeforeItCommands) {
  const planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  FleetCoordinator first(config_for(mission.agent_count()), mission);
  std::this_thread::sleep_for(std::chrono::milliseconds(5));  // claims 5 ms later
  FleetCoordinator second(config_for(mission.agent_count()), mission);
  FakeTransport first_wire, second_wire;
  for (FakeRobot& robot : robots_on_their_starts(mission)) {
    for (FleetCoordinator* c : {&first, &second}) {
      c->on_announcement({robot.id, "sim", "", "test", false});
      c->on_state(robot.state(-1, -1, fleet_transport::RobotStatus::kIdle));
    }
  }
  bool first_running = first.step(first_wire), second_running = second.step(second_wire);
  // Each hears the other's status (published at its first step, before any plan).
  first.on_coordinator_status(second_wire.last_coordinator_status);
  second.on_coordinator_status(first_wire.last_coordinator_status);
  for (int i = 0; i < 5 && second_running; ++i) {
    first_running = first.step(first_wire);
    second_running = second.step(second_wire);
  }
  EXPECT_TRUE(first_running);
  EXPECT_FALSE(second_running);
  EXPECT_TRUE(second.summary().stood_down);
  EXPECT_NE(second.summary().stood_down_because.find("claimed the fleet first"), std::string::npos);
  EXPECT_TRUE(second_wire.commands.empty());
  EXPECT_EQ(second_wire.last_coordinator_status.role, fleet_transport::CoordinatorRole::kStoodDown);
  EXPECT_FALSE(first.summary().stood_down);
}

TEST(FleetCoordinator, AStandbyMirrorsTheActiveOneAndTakesOverWhenItFallsSilent) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  // The active coordinator, as its last status told it: term 4, epoch 9, role r on robot r, and the
  // visits of task 0 done.
  fleet_transport::CoordinatorStatus active;
  active.coordinator = 0xAC;
  active.term = 4;
  active.claimed_ms = 1;
  active.mission_id = mission_fingerprint(mission);
  active.plan_epoch = 9;
  fleet_transport::FleetStatus progress;
  progress.coordinator = 0xAC;
  progress.plan_epoch = 9;
  for (int r = 0; r < mission.agent_count(); ++r) progress.assignments.push_back({"robot" + std::to_string(r), r, 0, 0});
  for (int role : mission.tasks[0].agents) progress.done_visits.push_back({0, role});
  FleetCoordinator standby(config_for(mission.agent_count()), std::move(mission), {true, nullptr});
  standby.on_coordinator_status(active);
  standby.on_fleet_status(progress);
  run(standby, robots);  // the active one never speaks again: the standby takes over and finishes
  const MissionSummary& summary = standby.summary();
  EXPECT_TRUE(summary.took_over);
  EXPECT_EQ(summary.term, 5u);
  EXPECT_EQ(summary.tasks_done_before, 1);
  EXPECT_TRUE(summary.completed);
}

TEST(FleetCoordinator, AStandbyNeverCommandsWhileTheActiveOneIsHeard) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  fleet_transport::CoordinatorStatus active;
  active.coordinator = 0xAC;
  active.term = 1;
  active.mission_id = mission_fingerprint(mission);
  const std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  FleetCoordinator standby(config_for(mission.agent_count()), std::move(mission), {true, nullptr});
  FakeTransport wire;
  for (FakeRobot robot : robots) {
    standby.on_announcement({robot.id, "sim", "", "test", false});
    standby.on_state(robot.state(-1, -1, fleet_transport::RobotStatus::kIdle));
  }
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(2);  // > lease + 0.5 s, several times
  while (std::chrono::steady_clock::now() < until) {
    standby.on_coordinator_status(active);
    ASSERT_TRUE(standby.step(wire));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_TRUE(wire.commands.empty());
  EXPECT_EQ(wire.last_coordinator_status.role, fleet_transport::CoordinatorRole::kStandby);
  EXPECT_FALSE(standby.summary().took_over);
}

TEST(PlanExecution, AllowsOnlyThePlannedCellAndTheTargetInFlight) {
  const auto graph = std::make_shared<const planner_core::Graph>(3, 1, std::vector<std::string>{"..."});
  const planner_core::Solution plan = {{graph->vertex_at({0, 0})}, {graph->vertex_at({1, 0})}, {graph->vertex_at({2, 0})}};
  PlanExecution execution(1, graph, plan, {"r"}, 1);
  EXPECT_TRUE(execution.allows(0, {0, 0}));
  EXPECT_FALSE(execution.allows(0, {1, 0}));  // not sent yet
  ASSERT_TRUE(execution.due_command(0, PlanExecution::Clock::now(), 1.0, 0).has_value());
  EXPECT_TRUE(execution.allows(0, {1, 0}));
  EXPECT_FALSE(execution.allows(0, {2, 0}));
}

}  // namespace
}  // namespace coordinator
