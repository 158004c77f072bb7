// FleetCoordinator end to end without DDS: a fake transport and robots that carry out each command
// at once (or, in one test, one robot that stops answering). Checks that the mission completes,
// that no two robots ever stand on one cell, and that each task visit is counted.
#include <gtest/gtest.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <thread>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "coordinator/fleet_coordinator.hpp"
#include "coordinator/mission_journal.hpp"
#include "coordinator/plan_execution.hpp"
#include "planner_core/action_model.hpp"
#include "planner_core/compass.hpp"
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
  uint64_t incarnation = 0;      // its process's; it obeys only commands meant for it (0: any, as before)
  bool refused = false;          // it was told it is refused (and obeys nothing more)
  int heading = 0;               // east; a move ends facing the way it went, a turn as commanded
  int turns = 0;                 // quarter turns in place it was commanded
  int moves_off_heading = 0;     // commanded moves with a heading that it did not face when they came
  int bad_turns = 0;             // commanded turns in place of other than a quarter turn, or moves
                                 // whose skipped indices cannot be the turns they need
  int folded_moves = 0;          // moves with turns folded in (their index skips the turns')
  int hand_turn_after = -1;      // turned half round by hand after this many moves
  bool knows_heading = true;     // false: reports heading -1 (a robot with no compass), turns as told

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
    s.heading = knows_heading ? heading : -1;
    s.incarnation = incarnation;
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
// `each_iteration` may add robots (announced and heard at once); `operate` is called every
// iteration with the wire (an operator's requests, the replies) and ends the run when it returns false.
using Operate = std::function<bool(FleetCoordinator&, FakeTransport&, int iteration)>;
std::map<std::string, std::vector<planner_core::Cell>> run(
    FleetCoordinator& coordinator, std::vector<FakeRobot>& robots,
    const std::function<void(std::vector<FakeRobot>&)>& each_iteration = {}, const Operate& operate = {}) {
  FakeTransport transport;
  std::map<std::string, std::vector<planner_core::Cell>> visited;
  for (FakeRobot& robot : robots) {
    coordinator.on_announcement({robot.id, "sim", "", "test", false});
    coordinator.on_state(robot.state(-1, -1, fleet_transport::RobotStatus::kIdle));
    visited[robot.id].push_back(robot.cell);
  }
  for (int iteration = 0; iteration < 200000 && coordinator.step(transport); ++iteration) {
    if (operate && !operate(coordinator, transport, iteration)) break;
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
        if (robot.incarnation != 0 && command.robot_incarnation != robot.incarnation) continue;  // another body
        if (command.refused) {
          robot.refused = true;
          continue;
        }
        if (robot.refused) continue;
        const planner_core::Cell target{command.target_x, command.target_y};
        if (const int travel = planner_core::heading_between(robot.cell, target); travel >= 0) {
          const int skipped = command.plan_epoch == robot.epoch ? command.action_index - robot.action - 1
                                                                : command.action_index;
          if (command.target_heading >= 0 && skipped > 0) {  // turns folded into the move
            ++robot.folded_moves;
            robot.turns += skipped;
            // Quarter turns folded in end facing the move's way: as many as it needs, or more by
            // pairs that undo each other (a turn and back, as PIBT plans now and then).
            const int needed = planner_core::turns_between(robot.heading, travel);
            if (needed > skipped || (skipped - needed) % 2 != 0) ++robot.bad_turns;
          } else if (command.target_heading >= 0 && robot.heading != travel) {
            ++robot.moves_off_heading;
          }
          robot.heading = travel;
        } else if (command.target_heading >= 0 && command.target_heading != robot.heading) {
          if (planner_core::turns_between(robot.heading, command.target_heading) != 1) ++robot.bad_turns;
          ++robot.turns;
          robot.heading = command.target_heading;
        }
        robot.cell = {command.target_x, command.target_y};
        robot.epoch = command.plan_epoch;
        robot.action = command.action_index;
        robot.coordinator = command.coordinator;
        if (++robot.moves == robot.teleport_after) robot.cell = robot.teleport_to;
        if (robot.moves == robot.hand_turn_after) robot.heading = (robot.heading + 2) % 4;
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

TEST(FleetCoordinator, ACoordinatorThatStoodStillBlamesNoRobotButStillFindsTheOneThatDied) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots;
  for (int r = 0; r < mission.agent_count(); ++r) {
    robots.push_back({"robot" + std::to_string(r), mission.graph->cell_of(mission.starts[r])});
  }
  FleetCoordinator coordinator(config_for(mission.agent_count()), std::move(mission));
  // Mid-mission the coordinator's thread stands still for 5 silence timeouts, as when its
  // middleware holds it: the commands of that step reach the robots only after it, so nobody is
  // heard before the next step. robot3 dies meanwhile.
  bool stalled = false;
  std::vector<fleet_transport::StepCommand> held;
  const auto stall = [&](FleetCoordinator&, FakeTransport& transport, int iteration) {
    if (!held.empty()) {  // the step after the stall: the held commands arrive now
      transport.commands.insert(transport.commands.begin(), held.begin(), held.end());
      held.clear();
    } else if (!stalled && !transport.commands.empty() && iteration % 20 != 0) {
      stalled = true;
      held.swap(transport.commands);
      robots[3].silent = true;
      std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    }
    return true;
  };
  run(coordinator, robots, {}, stall);
  ASSERT_TRUE(stalled);
  const MissionSummary& summary = coordinator.summary();
  EXPECT_EQ(summary.robots_lost, 1);  // robot3 only
  EXPECT_FALSE(summary.completed);    // its role has no robot left
}

TEST(FleetCoordinator, ACommandLostWhileARobotDiesIsSentAgainSoTheReplanDoesNotWaitForever) {
  // robot5's command is lost on the wire (as when a Fast DDS channel is not matched yet) in the
  // very step robot3 dies. The replan for robot3 waits for moves in flight, robot5's among them:
  // that move must be sent again, or the wait never ends and the mission stands still.
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots;
  for (int r = 0; r < mission.agent_count(); ++r) {
    robots.push_back({"robot" + std::to_string(r), mission.graph->cell_of(mission.starts[r])});
  }
  FleetConfig config = config_for(mission.agent_count());
  config.mission_timeout_s = 20;
  FleetCoordinator coordinator(config, std::move(mission));
  bool dropped = false;
  const auto drop = [&](FleetCoordinator&, FakeTransport& transport, int) {
    if (dropped) return true;
    const auto lost = std::find_if(transport.commands.begin(), transport.commands.end(),
                                   [](const fleet_transport::StepCommand& c) { return c.robot_id == "robot5"; });
    if (lost != transport.commands.end() && lost->action_index >= 2) {
      transport.commands.erase(lost);
      robots[3].silent = true;
      dropped = true;
    }
    return true;
  };
  run(coordinator, robots, {}, drop);
  ASSERT_TRUE(dropped);
  const MissionSummary& summary = coordinator.summary();
  EXPECT_EQ(summary.robots_lost, 1);  // robot3 only
  EXPECT_GE(summary.replans, 1);
  // The replan happened and the mission went on to its end (robot5's role finished), rather
  // than standing still until its timeout.
  for (const std::string& line : summary.pending) EXPECT_EQ(line.find("robot5"), std::string::npos) << line;
  EXPECT_LT(summary.seconds, 15) << "the mission stood still until its timeout";
}

TEST(FleetCoordinator, ARobotDeafToItsCommandsIsTakenOutAndRejoinsOnlyOnceTheCommandExpired) {
  // robot5's command channel breaks (every command to it is lost) while its states still arrive:
  // resending cannot help. Without a bound the robots waiting on it (and any replan) would wait for
  // ever. It must be taken out after timing.command_timeout_s, not rejoin while the last command
  // sent to it could still start a move, and, once its channel works again, rejoin and finish.
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots;
  for (int r = 0; r < mission.agent_count(); ++r) {
    robots.push_back({"robot" + std::to_string(r), mission.graph->cell_of(mission.starts[r])});
  }
  FleetConfig config = config_for(mission.agent_count());
  config.command_timeout_s = 2;  // step 0.2 s: resent after 1 s, valid for 1.8 s after each sending
  config.replacement_timeout_s.reset();
  config.mission_timeout_s = 30;
  FleetCoordinator coordinator(config, std::move(mission));
  using Clock = std::chrono::steady_clock;
  std::optional<Clock::time_point> channel_broken, taken_out, rejoined;
  int dropped = 0;
  const auto deaf_robot5 = [&](FleetCoordinator& c, FakeTransport& transport, int) {
    const auto now = Clock::now();
    if (!taken_out && c.summary().robots_lost == 1) taken_out = now;
    if (taken_out && !rejoined && c.summary().robots_joined == 1) rejoined = now;
    if (taken_out) return true;  // the channel works again
    const auto to_robot5 = [](const fleet_transport::StepCommand& command) { return command.robot_id == "robot5"; };
    const auto lost = std::find_if(transport.commands.begin(), transport.commands.end(), to_robot5);
    if (lost != transport.commands.end() && (channel_broken || lost->action_index >= 2)) {
      if (!channel_broken) channel_broken = now;
      dropped += static_cast<int>(std::count_if(transport.commands.begin(), transport.commands.end(), to_robot5));
      transport.commands.erase(std::remove_if(transport.commands.begin(), transport.commands.end(), to_robot5),
                               transport.commands.end());
    }
    return true;
  };
  run(coordinator, robots, {}, deaf_robot5);
  ASSERT_TRUE(channel_broken);
  ASSERT_TRUE(taken_out) << "robot5 was never taken out";
  EXPECT_GE(dropped, 2) << "its move was not sent again before it was taken out";
  const double waited_s = std::chrono::duration<double>(*taken_out - *channel_broken).count();
  EXPECT_GE(waited_s, 1.9);
  EXPECT_LT(waited_s, 4.0);
  ASSERT_TRUE(rejoined) << "robot5 never rejoined once its channel worked again";
  // The last sending was at most 1 s (the resend interval) before the take-out and stays valid for
  // 1.8 s, plus 1 s for the robots' clock estimate: no rejoin within 1.8 s of the take-out.
  EXPECT_GE(std::chrono::duration<double>(*rejoined - *taken_out).count(), 1.75);
  const MissionSummary& summary = coordinator.summary();
  EXPECT_EQ(summary.robots_lost, 1);
  EXPECT_TRUE(summary.completed) << "the mission did not finish with robot5 back";
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

// What an active coordinator 0xAC of `mission` publishes: its status (term, epoch) and its
// progress, driving robot r in role r.
struct ActiveCoordinator {
  fleet_transport::CoordinatorStatus status;
  fleet_transport::FleetStatus progress;
};
ActiveCoordinator active_coordinator(const planner_core::Instance& mission, uint32_t term, int epoch) {
  ActiveCoordinator active;
  active.status.coordinator = 0xAC;
  active.status.term = term;
  active.status.mission_id = mission_fingerprint(mission);
  active.status.plan_epoch = epoch;
  active.progress.coordinator = 0xAC;
  active.progress.plan_epoch = epoch;
  for (int r = 0; r < mission.agent_count(); ++r) {
    active.progress.assignments.push_back({"robot" + std::to_string(r), r, 0, 0});
  }
  return active;
}

// A network split: the standby's host is cut off from the active coordinator and from some of
// the robots it drives. Those robots may still be driven, so the standby must not plan around
// them as walls: it waits, without a command, until it hears every one of them again.
TEST(FleetCoordinator, AStandbyCutOffFromPartOfTheFleetTakesOverOnlyOnceItHearsEveryRobot) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  const auto [active, progress] = active_coordinator(mission, 3, 2);
  FleetCoordinator standby(config_for(mission.agent_count()), std::move(mission), {true, nullptr});  // lease 0.05 s
  FakeTransport wire;
  for (FakeRobot& robot : robots) standby.on_announcement({robot.id, "sim", "", "test", false});
  const auto hear = [&](size_t from, size_t to) {
    for (size_t r = from; r < to; ++r) standby.on_state(robots[r].state(-1, -1, fleet_transport::RobotStatus::kIdle));
  };
  // Steps for `seconds`, calling `each` before every step, or until the standby has taken over
  // when `until_it_takes_over`.
  const auto steps_for = [&](double seconds, const std::function<void()>& each, bool until_it_takes_over = false) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < until && !(until_it_takes_over && standby.summary().took_over)) {
      each();
      if (!standby.step(wire)) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  };
  steps_for(0.3, [&] {  // the split has not happened: all heard
    standby.on_coordinator_status(active);
    standby.on_fleet_status(progress);
    hear(0, robots.size());
  });
  steps_for(1.0, [] {});  // this host hears nobody: the active one's lease and a half passes twice
  EXPECT_FALSE(standby.summary().took_over);
  // The split heals: the robots' states come back 0.1 s before the active one's status.
  steps_for(0.1, [&] { hear(0, robots.size()); });
  steps_for(1.0, [&] {
    standby.on_coordinator_status(active);
    standby.on_fleet_status(progress);
    hear(0, robots.size());
  });
  EXPECT_FALSE(standby.summary().took_over);
  steps_for(1.0, [] {});  // cut off again
  steps_for(1.0, [&] { hear(0, 4); });  // half the robots are on this side of the split
  EXPECT_FALSE(standby.summary().took_over);
  EXPECT_TRUE(wire.commands.empty());
  EXPECT_EQ(wire.last_coordinator_status.role, fleet_transport::CoordinatorRole::kStandby);
  // The split heals toward the robots, not the active one: it is gone.
  steps_for(5.0, [&] { hear(0, robots.size()); }, true);
  EXPECT_TRUE(standby.summary().took_over);
  EXPECT_EQ(standby.summary().term, 4u);
}

// A robot that says goodbye while the active coordinator is silent has left: nobody drives it,
// and the standby need not wait to hear it before it takes over.
TEST(FleetCoordinator, AStandbyDoesNotWaitForARobotThatSaidGoodbye) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  const auto [active, progress] = active_coordinator(mission, 1, 0);
  FleetCoordinator standby(config_for(mission.agent_count()), std::move(mission), {true, nullptr});
  for (FakeRobot& robot : robots) standby.on_announcement({robot.id, "sim", "", "test", false});
  FakeTransport wire;
  const auto steps_for = [&](double seconds, bool with_active, size_t robots_heard) {
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < until && !standby.summary().took_over) {
      if (with_active) {
        standby.on_coordinator_status(active);
        standby.on_fleet_status(progress);
      }
      for (size_t r = 0; r < robots_heard; ++r) {
        standby.on_state(robots[r].state(-1, -1, fleet_transport::RobotStatus::kIdle));
      }
      ASSERT_TRUE(standby.step(wire));
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  };
  steps_for(0.3, true, robots.size());
  standby.on_robot_gone("robot7", fleet_transport::GoneReason::kGoodbye);  // the active one is gone too
  steps_for(5.0, false, robots.size() - 1);
  EXPECT_TRUE(standby.summary().took_over);
}

// Before any failure: a robot the active coordinator drives that the standby never hears would
// keep it from taking over, so the standby says so while there is time to mend the network.
TEST(FleetCoordinator, AStandbySaysWhichDrivenRobotItDoesNotHear) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  const auto [active, progress] = active_coordinator(mission, 1, 0);
  FleetCoordinator standby(config_for(mission.agent_count()), std::move(mission), {true, nullptr});  // silence 0.3 s
  for (FakeRobot& robot : robots) standby.on_announcement({robot.id, "sim", "", "test", false});
  std::ostringstream log;
  const auto previous = spdlog::default_logger();
  spdlog::set_default_logger(
      std::make_shared<spdlog::logger>("test", std::make_shared<spdlog::sinks::ostream_sink_mt>(log)));
  FakeTransport wire;
  const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(1);
  while (std::chrono::steady_clock::now() < until) {
    standby.on_coordinator_status(active);
    standby.on_fleet_status(progress);
    for (size_t r = 0; r + 1 < robots.size(); ++r) {  // robot7 is on a segment this host cannot reach
      standby.on_state(robots[r].state(-1, -1, fleet_transport::RobotStatus::kIdle));
    }
    ASSERT_TRUE(standby.step(wire));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  spdlog::set_default_logger(previous);
  const std::string text = log.str();
  EXPECT_NE(text.find("standby: robot robot7, which coordinator 00000000000000ac drives, is not heard here"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("standby: robot robot6, which"), std::string::npos) << text;
  EXPECT_EQ(text.find("which coordinator 00000000000000ac drives"), text.rfind("which coordinator")) << "said once";
  EXPECT_TRUE(wire.commands.empty());
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


namespace runtime_tasks {

fleet_transport::TaskRequest add(const std::string& id, int x, int y, const std::string& robot = "") {
  fleet_transport::TaskRequest request;
  request.request_id = id;
  request.action = fleet_transport::TaskAction::kAdd;
  request.x = x;
  request.y = y;
  request.robot_id = robot;
  return request;
}

fleet_transport::TaskRequest cancel(const std::string& id, int task) {
  fleet_transport::TaskRequest request;
  request.request_id = id;
  request.action = fleet_transport::TaskAction::kCancel;
  request.task = task;
  return request;
}

// The reply to request `id` the coordinator sent last, or nullptr.
const fleet_transport::TaskReply* reply_to(const FakeTransport& wire, const std::string& id) {
  for (auto it = wire.replies.rbegin(); it != wire.replies.rend(); ++it) {
    if (it->request_id == id) return &*it;
  }
  return nullptr;
}

}  // namespace runtime_tasks

TEST(FleetCoordinator, TasksAddedWhileItRunsAreCheckedGivenToARobotAndDone) {
  using namespace runtime_tasks;
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  const int mission_tasks = mission.task_count();
  FleetCoordinator coordinator(config_for(mission.agent_count()), std::move(mission));
  bool asked = false;
  std::map<std::string, fleet_transport::TaskReply> replies;
  const auto visited = run(coordinator, robots, {}, [&](FleetCoordinator& c, FakeTransport& wire, int) {
    if (!asked && wire.last_plan.plan_epoch >= 1) {  // the mission runs
      asked = true;
      c.on_task_request(add("wall", 0, 0));
      c.on_task_request(add("off-map", 99, 1));
      c.on_task_request(add("unknown-robot", 1, 1, "nobody"));
      c.on_task_request(add("duplicate", 8, 1, "robot2"));  // task 0 waits there for role 2
      c.on_task_request(add("for-robot3", 1, 1, "robot3"));
      c.on_task_request(add("for-any", 28, 2));
      c.on_task_request(add("for-any", 28, 2));             // sent again: answered again, added once
      c.on_task_request(cancel("cancel-nothing", 99));
      fleet_transport::TaskRequest odd = add("odd-action", 1, 1);
      odd.action = static_cast<fleet_transport::TaskAction>(7);  // only a hand-made message says this
      c.on_task_request(odd);
      c.on_task_request({});                                 // no request id: cannot be answered
    }
    for (const fleet_transport::TaskReply& reply : wire.replies) replies[reply.request_id] = reply;
    return true;
  });
  ASSERT_TRUE(asked);
  const auto reason = [&](const std::string& id) { return replies.count(id) ? replies[id].reason : "(no reply)"; };
  EXPECT_NE(reason("wall").find("(0,0) is a wall"), std::string::npos) << reason("wall");
  EXPECT_NE(reason("off-map").find("off the map (32 x 32)"), std::string::npos) << reason("off-map");
  EXPECT_NE(reason("unknown-robot").find("unknown robot 'nobody'"), std::string::npos) << reason("unknown-robot");
  EXPECT_NE(reason("duplicate").find("duplicate: task 0"), std::string::npos) << reason("duplicate");
  EXPECT_NE(reason("cancel-nothing").find("no task 99"), std::string::npos) << reason("cancel-nothing");
  EXPECT_NE(reason("odd-action").find("unknown action 7"), std::string::npos) << reason("odd-action");
  for (const char* refused : {"wall", "off-map", "unknown-robot", "duplicate", "cancel-nothing", "odd-action"}) {
    EXPECT_FALSE(replies[refused].accepted) << refused;
  }
  ASSERT_TRUE(replies["for-robot3"].accepted) << reason("for-robot3");
  ASSERT_TRUE(replies["for-any"].accepted) << reason("for-any");
  EXPECT_EQ(replies["for-robot3"].task, mission_tasks);
  EXPECT_EQ(replies["for-robot3"].robot_id, "robot3");
  EXPECT_EQ(replies["for-any"].task, mission_tasks + 1);
  const MissionSummary& summary = coordinator.summary();
  EXPECT_TRUE(summary.completed);
  EXPECT_EQ(summary.tasks_total, mission_tasks + 2);  // the repeated request added nothing
  EXPECT_EQ(summary.tasks_done, summary.tasks_total);
  const auto& robot3 = visited.at("robot3");
  EXPECT_NE(std::find(robot3.begin(), robot3.end(), planner_core::Cell{1, 1}), robot3.end());
  const auto& chosen = visited.at(replies["for-any"].robot_id);
  EXPECT_NE(std::find(chosen.begin(), chosen.end(), planner_core::Cell{28, 2}), chosen.end());
}

TEST(FleetCoordinator, ALifelongMissionWaitsForTasksGivenInWaves) {
  using namespace runtime_tasks;
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  const int mission_tasks = mission.task_count();
  FleetConfig config = config_for(mission.agent_count());
  config.lifelong = true;
  config.mission_timeout_s = 0.5;  // no timeout in lifelong mode: the waves take longer than this
  FleetCoordinator coordinator(config, std::move(mission));
  const std::vector<std::vector<planner_core::Cell>> waves = {{{1, 1}}, {{28, 2}, {4, 2}}, {{16, 1}}};
  size_t wave = 0;
  int idle_rounds = 0;
  bool cancelled_checked = false;
  run(coordinator, robots, {}, [&](FleetCoordinator& c, FakeTransport& wire, int iteration) {
    const int done_events = static_cast<int>(std::count_if(wire.events.begin(), wire.events.end(),
                                                           [](const auto& e) { return e.kind == "mission_done"; }));
    if (done_events <= static_cast<int>(wave)) return true;  // still working on the last wave
    if (wave == waves.size()) return ++idle_rounds < 200;    // parked after the last wave: still running
    if (wave == 1 && !cancelled_checked) {  // between waves: a done task cannot be cancelled
      c.on_task_request(cancel("cancel-done", mission_tasks));
      cancelled_checked = true;
    }
    for (size_t t = 0; t < waves[wave].size(); ++t) {
      const planner_core::Cell cell = waves[wave][t];
      c.on_task_request(add("wave" + std::to_string(wave) + "-" + std::to_string(t) + "-" + std::to_string(iteration),
                            cell.x, cell.y));
    }
    ++wave;
    return true;
  });
  const MissionSummary& summary = coordinator.summary();
  EXPECT_EQ(wave, waves.size());
  EXPECT_EQ(idle_rounds, 200);           // it kept running after every task was done
  EXPECT_FALSE(summary.completed);       // a lifelong mission never completes by itself
  EXPECT_EQ(summary.tasks_total, mission_tasks + 4);
  EXPECT_EQ(summary.tasks_done, mission_tasks + 4);
}

// A station gets many orders: in a lifelong fleet every task is its own, even at a cell with one
// pending (a one-shot mission refuses that as a duplicate: TasksAddedWhileItRuns...).
TEST(FleetCoordinator, ALifelongFleetTakesEveryTaskAtACellThatHasOnePendingAndDoesThemAll) {
  using namespace runtime_tasks;
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  const int mission_tasks = mission.task_count();
  FleetConfig config = config_for(mission.agent_count());
  config.lifelong = true;
  config.silence_timeout_s = 5;
  FleetCoordinator coordinator(config, std::move(mission));
  const std::vector<std::string> ids{"order-any", "order-robot2", "order-any-again", "order-robot2-again"};
  bool asked = false;
  int after_done = 0;
  std::map<std::string, fleet_transport::TaskReply> replies;
  run(coordinator, robots, {}, [&](FleetCoordinator& c, FakeTransport& wire, int) {
    if (!asked && wire.last_plan.plan_epoch >= 1) {
      asked = true;
      c.on_task_request(add(ids[0], 28, 2));
      c.on_task_request(add(ids[1], 28, 2, "robot2"));
      c.on_task_request(add(ids[2], 28, 2));
      c.on_task_request(add(ids[3], 28, 2, "robot2"));
    }
    for (const fleet_transport::TaskReply& reply : wire.replies) replies[reply.request_id] = reply;
    const MissionSummary& summary = c.summary();
    return summary.tasks_total < mission_tasks + 4 || summary.tasks_done < summary.tasks_total || ++after_done < 50;
  });
  ASSERT_TRUE(asked);
  std::set<int> tasks;
  for (const std::string& id : ids) {
    ASSERT_TRUE(replies[id].accepted) << id << ": " << replies[id].reason;
    tasks.insert(replies[id].task);
  }
  EXPECT_EQ(tasks.size(), 4u) << "four tasks, not one";
  EXPECT_EQ(replies["order-robot2"].robot_id, "robot2");
  const MissionSummary& summary = coordinator.summary();
  EXPECT_EQ(summary.tasks_total, mission_tasks + 4);
  EXPECT_EQ(summary.tasks_done, summary.tasks_total);
  EXPECT_EQ(summary.replans, 0);
}

// Lifelong: a stream of tasks at random free cells keeps `pending` tasks waiting, until `total`
// were accepted.
struct TaskStream {
  int total = 60;
  int pending = 8;
  int given = 0;
  int requests = 0;
  std::mt19937 rng{7};
  std::vector<planner_core::Cell> free_cells;
  std::vector<std::string> refused;  // other than as duplicates

  explicit TaskStream(const planner_core::Graph& graph) {
    for (planner_core::Vertex v = 0; v < graph.vertex_count(); ++v) free_cells.push_back(graph.cell_of(v));
  }
  // Gives tasks while fewer than `pending` wait (counting requests not answered yet: the
  // coordinator answers at its next step); true once every one was given and is done.
  bool feed(FleetCoordinator& c, FakeTransport& wire) {
    for (auto it = outstanding.begin(); it != outstanding.end();) {
      const fleet_transport::TaskReply* reply = runtime_tasks::reply_to(wire, *it);
      if (reply == nullptr) {
        ++it;
        continue;
      }
      if (reply->accepted) ++given;
      if (!reply->accepted && reply->reason.find("duplicate") == std::string::npos) refused.push_back(*it + ": " + reply->reason);
      it = outstanding.erase(it);
    }
    const MissionSummary& summary = c.summary();
    const int waiting = summary.tasks_total - summary.tasks_done + static_cast<int>(outstanding.size());
    if (wire.last_plan.plan_epoch >= 1) {
      for (int k = waiting; k < pending && given + static_cast<int>(outstanding.size()) < total; ++k) {
        const planner_core::Cell cell = free_cells[rng() % free_cells.size()];
        const std::string id = "stream-" + std::to_string(requests++);
        c.on_task_request(runtime_tasks::add(id, cell.x, cell.y));
        outstanding.push_back(id);
      }
    }
    return given == total && summary.tasks_done == summary.tasks_total;
  }
  std::vector<std::string> outstanding;  // requests not answered yet
};

// Every robot's cells one after the other are neighbours (or the same cell): no jump was commanded.
void expect_only_steps(const std::map<std::string, std::vector<planner_core::Cell>>& visited) {
  for (const auto& [id, cells] : visited) {
    for (size_t k = 1; k < cells.size(); ++k) {
      EXPECT_LE(std::abs(cells[k].x - cells[k - 1].x) + std::abs(cells[k].y - cells[k - 1].y), 1)
          << id << " jumps from " << planner_core::to_string(cells[k - 1]) << " to " << planner_core::to_string(cells[k]);
    }
  }
}

TEST(FleetCoordinator, ALifelongStreamOfTasksIsTakenUpByThePlanAsItGrowsWithoutStoppingTheFleet) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  const int mission_tasks = mission.task_count();
  FleetConfig config = config_for(mission.agent_count());
  config.lifelong = true;
  // Nobody goes silent here: a loaded machine that stalls the loop for 0.3 s must not take a robot
  // out (and bring a replan this test is not about).
  config.silence_timeout_s = 5;
  TaskStream stream(*mission.graph);
  FleetCoordinator coordinator(config, std::move(mission));
  int after_done = 0;
  const auto visited = run(coordinator, robots, {}, [&](FleetCoordinator& c, FakeTransport& wire, int) {
    return !stream.feed(c, wire) || ++after_done < 100;
  });
  EXPECT_TRUE(stream.refused.empty()) << stream.refused.front();
  const MissionSummary& summary = coordinator.summary();
  EXPECT_EQ(summary.tasks_total, mission_tasks + stream.total);
  EXPECT_EQ(summary.tasks_done, summary.tasks_total);
  EXPECT_EQ(summary.replans, 0);   // no task stopped the fleet to replan
  EXPECT_GT(summary.windows, 10);  // the plan grew instead
  // Robots that stood still for want of a window: counted once per window, each wait bounded by it.
  EXPECT_LE(summary.windows_late, summary.windows);
  EXPECT_GE(summary.robot_s_waiting_for_windows, 0);
  EXPECT_LE(summary.robot_s_waiting_for_windows,
            static_cast<double>(summary.windows_late) * 8 * summary.wait_for_window_ms_max / 1000 + 1e-9);
  expect_only_steps(visited);
}

// Lifelong mode's pool: 24 tasks at once queue up on robots (each goes to the robot that gets there
// soonest at that moment); robots that run out of tasks take queued ones they reach sooner, and
// the journal follows every move. Three tasks named for robot0 stay with it.
TEST(FleetCoordinator, ALifelongFleetMovesQueuedTasksToRobotsThatRunOutButNotTasksNamedForARobot) {
  using namespace runtime_tasks;
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  const int mission_tasks = mission.task_count();
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("ctsfleet-pool-" + std::to_string(::getpid()) + ".journal")).string();
  std::filesystem::remove(path);
  const std::string fingerprint = mission_fingerprint(mission);
  std::vector<planner_core::Cell> free_cells;
  for (planner_core::Vertex v = 0; v < mission.graph->vertex_count(); ++v) free_cells.push_back(mission.graph->cell_of(v));
  FleetConfig config = config_for(mission.agent_count());
  config.lifelong = true;
  config.silence_timeout_s = 5;  // nobody goes silent: a stalled loop must not bring a replan
  std::map<int, std::string> robot_named;  // task -> the robot it was named for
  {
    MissionJournal journal(path, fingerprint, "test");
    FleetCoordinator coordinator(config, std::move(mission), {false, &journal});
    std::mt19937 rng(11);
    std::vector<std::string> asked;
    int after_done = 0;
    run(coordinator, robots, {}, [&](FleetCoordinator& c, FakeTransport& wire, int) {
      if (asked.empty() && wire.last_plan.plan_epoch >= 1) {
        for (int k = 0; k < 27; ++k) {
          const planner_core::Cell cell = free_cells[rng() % free_cells.size()];
          asked.push_back("pool-" + std::to_string(k));
          c.on_task_request(add(asked.back(), cell.x, cell.y, k < 3 ? "robot0" : ""));
        }
        return true;
      }
      const MissionSummary& summary = c.summary();
      const bool answered = !asked.empty() && std::all_of(asked.begin(), asked.end(), [&](const std::string& id) {
        return reply_to(wire, id) != nullptr;
      });
      if (answered && robot_named.empty()) {
        for (int k = 0; k < 3; ++k) {
          const fleet_transport::TaskReply* reply = reply_to(wire, asked[k]);
          if (reply->accepted) robot_named[reply->task] = "robot0";
        }
      }
      return !(answered && summary.tasks_done == summary.tasks_total && ++after_done > 100);
    });
    const MissionSummary& summary = coordinator.summary();
    EXPECT_GT(summary.tasks_total, mission_tasks + 20);  // a few cells drawn twice are refused as duplicates
    EXPECT_EQ(summary.tasks_done, summary.tasks_total);
    EXPECT_GT(summary.tasks_reassigned, 0);
    EXPECT_EQ(summary.replans, 0);
    ASSERT_EQ(robot_named.size(), 3u);
  }
  {
    // The journal holds each task added at runtime with the role that did it, and the named ones.
    const planner_core::Instance again = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
    MissionJournal journal(path, fingerprint, "test");
    ASSERT_TRUE(journal.resumable().has_value());
    std::map<int, int> role_of_task;
    for (const JournalResume::AddedTask& added : journal.resumable()->added_tasks) role_of_task[added.task] = added.role;
    std::set<std::pair<int, int>> visits;
    for (const fleet_transport::TaskVisit& visit : journal.resumable()->visits) visits.insert({visit.task, visit.role});
    for (const auto& [task, role] : role_of_task) {
      EXPECT_TRUE(visits.count({task, role})) << "task " << task << " journaled for role " << role << " but not visited by it";
    }
    std::vector<int> pinned = journal.resumable()->pinned_tasks;
    std::vector<int> named;
    for (const auto& [task, robot] : robot_named) named.push_back(task);
    EXPECT_EQ(pinned, named);
    // ... and robot0's role visited them, whatever the pool did.
    for (const int task : named) {
      const int role = role_of_task.at(task);
      EXPECT_EQ(journal.resumable()->bindings.at(role), "robot0") << "task " << task;
    }
  }
  std::filesystem::remove(path);
  std::filesystem::remove(path + "-wal");
  std::filesystem::remove(path + "-shm");
}

TEST(FleetCoordinator, ALifelongFleetThatLosesARobotPlansAroundItAndGoesOnGrowingThePlan) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  FleetConfig config = config_for(mission.agent_count());
  config.lifelong = true;
  config.replacement_timeout_s.reset();  // the lost robot's own tasks wait for a robot
  const int mission_tasks = mission.task_count();
  TaskStream stream(*mission.graph);
  FleetCoordinator coordinator(config, std::move(mission));
  int64_t windows_at_loss = -1;
  const auto visited = run(coordinator, robots, {}, [&](FleetCoordinator& c, FakeTransport& wire, int) {
    stream.feed(c, wire);
    if (windows_at_loss < 0 && c.summary().windows >= 5) {
      robots[5].silent = true;  // mid-stream, with windows in the plan
      windows_at_loss = c.summary().windows;
    }
    // Everything given, and done but for robot5's tasks (its role has no robot now).
    const MissionSummary& now = c.summary();
    return !(stream.given == stream.total && now.robots_lost == 1 &&
             (now.tasks_done == now.tasks_total || c.waiting_for_robot()));
  });
  const MissionSummary& summary = coordinator.summary();
  EXPECT_GT(windows_at_loss, 0);
  EXPECT_EQ(summary.robots_lost, 1);
  EXPECT_EQ(summary.robots_planned_around, 1);  // the loss brought no replan: the plan was cut round it
  EXPECT_LE(summary.replans, 2);  // the plan finished with robot5's tasks left, not one per task
  EXPECT_GT(summary.windows, windows_at_loss);  // the plan grew by windows after the loss
  for (const std::string& line : summary.pending) {
    EXPECT_NE(line.find("(no robot)"), std::string::npos) << "only the lost robot's tasks are left: " << line;
    // ... and only the mission's own, bound to its role: the pool gave those added at runtime to
    // the robots still here.
    EXPECT_LT(std::stoi(line.substr(std::string("task ").size())), mission_tasks) << line;
  }
  expect_only_steps(visited);
}

// A robot lost mid-stream (silent; or its process restarted, a new incarnation) and back where it
// was: meanwhile the others go on, their plan cut round it (no whole replan); back, it takes its
// place in the plan and its tasks again. Nobody collides (run() checks every step).
TEST(FleetCoordinator, ALifelongRobotLostAndBackWhereItWasNeverStopsTheOthersNorBringsAReplan) {
  for (const auto& [restarted, turning] : {std::pair{false, false}, std::pair{true, false}, std::pair{true, true}}) {
    SCOPED_TRACE(std::string(restarted ? "its process restarted" : "silent, then heard again") +
                 (turning ? ", robots that turn" : ""));
    planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
    std::vector<FakeRobot> robots = robots_on_their_starts(mission);
    FleetConfig config = config_for(mission.agent_count());
    config.lifelong = true;
    if (turning) {
      config.actions = planner_core::ActionModel::kRotate;
      for (size_t r = 0; r < robots.size(); ++r) robots[r].heading = static_cast<int>(r % 4);
    }
    config.replacement_timeout_s.reset();
    TaskStream stream(*mission.graph);
    FleetCoordinator coordinator(config, std::move(mission));
    int64_t windows_at_loss = -1, windows_while_out = -1;
    int confirmed_at_loss = 0, others_at_return = 0, own_at_return = -1;
    const auto moves_of_others = [&] {
      int moves = 0;
      for (size_t r = 0; r < robots.size(); ++r) moves += r == 5 ? 0 : robots[r].moves;
      return moves;
    };
    const auto visited = run(coordinator, robots, {}, [&](FleetCoordinator& c, FakeTransport& wire, int) {
      stream.feed(c, wire);
      const MissionSummary& now = c.summary();
      if (windows_at_loss < 0 && now.windows >= 5) {
        robots[5].silent = true;  // mid-stream, with windows in the plan
        windows_at_loss = now.windows;
      }
      if (windows_while_out < 0 && now.robots_lost == 1) {
        windows_while_out = now.windows;
        confirmed_at_loss = moves_of_others();
      }
      // Back once the others have gone on a while: the same process, or a new one where it stood.
      if (robots[5].silent && windows_while_out >= 0 && now.windows >= windows_while_out + 8) {
        robots[5].silent = false;
        others_at_return = moves_of_others();
        own_at_return = robots[5].moves;
        if (restarted) {  // a new process on the same cell, facing the same way, that has carried out nothing
          robots[5].incarnation = 0x5eed;
          robots[5].seq = 0;
          c.on_state(robots[5].state(-1, -1, fleet_transport::RobotStatus::kIdle));
        }
      }
      return !(stream.given == stream.total && now.tasks_done == now.tasks_total);
    });
    const MissionSummary& summary = coordinator.summary();
    EXPECT_EQ(summary.robots_lost, 1);
    EXPECT_EQ(summary.robots_planned_around, 1);
    EXPECT_EQ(summary.robots_taken_back, 1);
    EXPECT_EQ(summary.replans, 0);  // neither the loss nor the return replanned the fleet
    EXPECT_EQ(summary.tasks_done, summary.tasks_total);
    EXPECT_GT(others_at_return, confirmed_at_loss);  // the others went on while it was out
    ASSERT_GE(own_at_return, 0);
    EXPECT_GT(robots[5].moves, own_at_return);       // and it went on once back
    expect_only_steps(visited);
    for (const FakeRobot& robot : robots) {
      EXPECT_EQ(robot.moves_off_heading, 0) << robot.id;
      EXPECT_EQ(robot.bad_turns, 0) << robot.id;
    }
  }
}

// A robot lost mid-stream for good, and a new robot started on a free cell: it joins the plan where
// it stands and takes the lost robot's role and tasks; neither brings a replan.
TEST(FleetCoordinator, ALifelongFleetTakesANewRobotIntoThePlanWhereItStandsWithoutAReplan) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  const std::shared_ptr<const planner_core::Graph> graph = mission.graph;
  FleetConfig config = config_for(mission.agent_count());
  config.lifelong = true;
  config.replacement_timeout_s.reset();
  TaskStream stream(*mission.graph);
  FleetCoordinator coordinator(config, std::move(mission));
  bool joiner_due = false;
  int64_t windows_at_join = -1;
  const auto add_joiner = [&](std::vector<FakeRobot>& fleet) {
    if (!joiner_due || fleet.size() > 8) return;
    // A free cell at least 3 steps from every robot (so no move under way ends there).
    for (planner_core::Vertex v = 0; v < graph->vertex_count(); ++v) {
      const planner_core::Cell cell = graph->cell_of(v);
      const bool far = std::all_of(fleet.begin(), fleet.end(), [&](const FakeRobot& robot) {
        return std::abs(robot.cell.x - cell.x) + std::abs(robot.cell.y - cell.y) >= 3;
      });
      if (far) {
        fleet.push_back({"robot8", cell});
        return;
      }
    }
  };
  const auto visited = run(coordinator, robots, add_joiner, [&](FleetCoordinator& c, FakeTransport& wire, int) {
    stream.feed(c, wire);
    const MissionSummary& now = c.summary();
    if (!robots[5].silent && now.windows >= 5) robots[5].silent = true;
    if (now.robots_lost == 1 && !joiner_due) {
      joiner_due = true;
      windows_at_join = now.windows;
    }
    return !(stream.given == stream.total && robots.size() > 8 && now.tasks_done == now.tasks_total);
  });
  const MissionSummary& summary = coordinator.summary();
  ASSERT_EQ(robots.size(), 9u);
  EXPECT_EQ(summary.robots_lost, 1);
  EXPECT_EQ(summary.robots_planned_around, 1);
  EXPECT_EQ(summary.robots_joined_mid_plan, 1);
  EXPECT_EQ(summary.replans, 0);
  EXPECT_EQ(summary.tasks_done, summary.tasks_total);  // robot5's role's tasks too, by robot8
  EXPECT_GT(summary.windows, windows_at_join);
  EXPECT_GT(robots[8].moves, 0);
  expect_only_steps(visited);
}

TEST(FleetCoordinator, ACancelledTaskIsNotVisitedAndCountsNeitherWay) {
  using namespace runtime_tasks;
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  const int mission_tasks = mission.task_count();
  FleetCoordinator coordinator(config_for(mission.agent_count()), std::move(mission));
  bool asked = false;
  std::optional<fleet_transport::TaskReply> added, cancelled, again;
  const auto visited = run(coordinator, robots, {}, [&](FleetCoordinator& c, FakeTransport& wire, int) {
    if (!asked && wire.last_plan.plan_epoch >= 1) {
      asked = true;
      c.on_task_request(add("add", 28, 2, "robot5"));  // handled in order in one step: added, then
      c.on_task_request(cancel("cancel", mission_tasks));  // withdrawn before any plan includes it
      c.on_task_request(cancel("cancel-again", mission_tasks));
    }
    if (const auto* r = reply_to(wire, "add")) added = *r;
    if (const auto* r = reply_to(wire, "cancel")) cancelled = *r;
    if (const auto* r = reply_to(wire, "cancel-again")) again = *r;
    return true;
  });
  ASSERT_TRUE(added && cancelled && again);
  EXPECT_TRUE(added->accepted) << added->reason;
  EXPECT_TRUE(cancelled->accepted) << cancelled->reason;
  EXPECT_FALSE(again->accepted);
  EXPECT_NE(again->reason.find("cancelled already"), std::string::npos) << again->reason;
  const MissionSummary& summary = coordinator.summary();
  EXPECT_TRUE(summary.completed);
  EXPECT_EQ(summary.tasks_total, mission_tasks);
  const auto& robot5 = visited.at("robot5");
  EXPECT_EQ(std::find(robot5.begin(), robot5.end(), planner_core::Cell{28, 2}), robot5.end());
}

TEST(FleetCoordinator, OnlyTheActiveCoordinatorAnswersTaskRequests) {
  using namespace runtime_tasks;
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  FleetCoordinator standby(config_for(mission.agent_count()), mission, {true, nullptr});
  FleetCoordinator waiting(config_for(mission.agent_count()), mission);  // no robot yet: not started
  FakeTransport standby_wire, waiting_wire;
  standby.on_task_request(add("r1", 1, 1));
  waiting.on_task_request(add("r2", 1, 1));
  standby.step(standby_wire);
  waiting.step(waiting_wire);
  EXPECT_TRUE(standby_wire.replies.empty());
  ASSERT_EQ(waiting_wire.replies.size(), 1u);
  EXPECT_FALSE(waiting_wire.replies[0].accepted);
  EXPECT_NE(waiting_wire.replies[0].reason.find("has not started"), std::string::npos);
}


TEST(FleetCoordinator, AStandbyTakesOverTheTasksAddedAtRuntime) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  const int mission_tasks = mission.task_count();
  fleet_transport::CoordinatorStatus active;
  active.coordinator = 0xAC;
  active.term = 1;
  active.claimed_ms = 1;
  active.mission_id = mission_fingerprint(mission);
  // The active coordinator's mission had two tasks added: (28,2) for role 5, then (4,2) for role 1,
  // which was cancelled.
  fleet_transport::MissionInfo info;
  info.coordinator = 0xAC;
  info.mission_id = active.mission_id;
  for (const planner_core::Task& task : mission.tasks) {
    const planner_core::Cell at = mission.graph->cell_of(task.at);
    info.tasks.push_back({at.x, at.y, task.agents, false});
  }
  info.tasks.push_back({28, 2, {5}, false});
  info.tasks.push_back({4, 2, {1}, true});
  fleet_transport::FleetStatus progress;
  progress.coordinator = 0xAC;
  for (int r = 0; r < mission.agent_count(); ++r) progress.assignments.push_back({"robot" + std::to_string(r), r, 0, 0});
  FleetCoordinator standby(config_for(mission.agent_count()), std::move(mission), {true, nullptr});
  standby.on_coordinator_status(active);
  standby.on_fleet_status(progress);
  standby.on_mission_info(info);
  fleet_transport::MissionInfo published;  // the mission as the standby publishes it once active
  const auto visited = run(standby, robots, {}, [&](FleetCoordinator& c, FakeTransport& wire, int iteration) {
    if (iteration == 0) {
      // The standby has mirrored the info above. Then the active one's pool (lifelong mode) moves
      // the task at (28,2) to role 3; and its info names a role the mission does not have for the
      // mission's own first task, which is not mirrored.
      info.tasks[mission_tasks].roles = {3};
      info.tasks[0].roles = {99};
      c.on_mission_info(info);
    }
    published = wire.last_mission;
    return true;
  });
  const MissionSummary& summary = standby.summary();
  EXPECT_TRUE(summary.took_over);
  EXPECT_TRUE(summary.completed);
  EXPECT_EQ(summary.tasks_total, mission_tasks + 1);  // the cancelled one is not owed
  ASSERT_EQ(published.tasks.size(), static_cast<size_t>(mission_tasks + 2));
  EXPECT_EQ(published.tasks[mission_tasks].roles, std::vector<int32_t>{3});
  EXPECT_NE(published.tasks[0].roles, std::vector<int32_t>{99});
  const auto& robot3 = visited.at("robot3");
  EXPECT_NE(std::find(robot3.begin(), robot3.end(), planner_core::Cell{28, 2}), robot3.end());
}

TEST(FleetCoordinator, ARestartFromTheJournalKeepsTheTasksAddedAtRuntime) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  const int mission_tasks = mission.task_count();
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("ctsfleet-restart-" + std::to_string(::getpid()) + ".journal")).string();
  std::filesystem::remove(path);
  {
    MissionJournal journal(path, mission_fingerprint(mission), "test");
    journal.claim(1, 0x11, 1);
    journal.record_task_added(mission_tasks, 28, 2, 5, "a");
    journal.record_task_added(mission_tasks + 1, 4, 2, 1, "b");
    journal.record_task_cancelled(mission_tasks + 1, "c");
  }
  {
    MissionJournal journal(path, mission_fingerprint(mission), "test");
    FleetCoordinator restarted(config_for(mission.agent_count()), std::move(mission), {false, &journal});
    EXPECT_EQ(restarted.summary().tasks_total, mission_tasks + 1);
    const auto visited = run(restarted, robots);
    EXPECT_TRUE(restarted.summary().completed);
    const auto& robot5 = visited.at("robot5");
    EXPECT_NE(std::find(robot5.begin(), robot5.end(), planner_core::Cell{28, 2}), robot5.end());
    const auto& robot1 = visited.at("robot1");
    EXPECT_EQ(std::find(robot1.begin(), robot1.end(), planner_core::Cell{4, 2}), robot1.end());
  }
  std::filesystem::remove(path);
  std::filesystem::remove(path + "-wal");
  std::filesystem::remove(path + "-shm");
}

// A journal whose records do not fit the mission (a visit by a role the task is not for, a task
// past the mission's, a binding of a role it does not have) is refused naming the record, never
// counted.
TEST(FleetCoordinator, AJournalRecordThatDoesNotFitTheMissionIsRefused) {
  const planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("ctsfleet-unfit-" + std::to_string(::getpid()) + ".journal")).string();
  const int role_not_of_task_0 = [&] {
    for (int role = 0; role < mission.agent_count(); ++role) {
      const auto& agents = mission.tasks[0].agents;
      if (std::find(agents.begin(), agents.end(), role) == agents.end()) return role;
    }
    return mission.agent_count();
  }();
  const auto refusal = [&](const std::function<void(MissionJournal&)>& record) {
    std::filesystem::remove(path);
    {
      MissionJournal journal(path, mission_fingerprint(mission), "test");
      journal.claim(1, 0x11, 1);
      record(journal);
    }
    MissionJournal journal(path, mission_fingerprint(mission), "test");
    try {
      FleetCoordinator restarted(config_for(mission.agent_count()), planner_core::Instance(mission), {false, &journal});
    } catch (const JournalError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal([&](MissionJournal& j) { j.record_visit({0, role_not_of_task_0}, "robot0", 1); })
                .find("the visit of task 0 by role " + std::to_string(role_not_of_task_0) + " does not fit"),
            std::string::npos);
  EXPECT_NE(refusal([&](MissionJournal& j) { j.record_visit({mission.task_count(), 0}, "robot0", 1); }).find("does not fit"),
            std::string::npos);
  EXPECT_NE(refusal([&](MissionJournal& j) { j.record_task_cancelled(mission.task_count() + 3, "x"); })
                .find("cancelled task"),
            std::string::npos);
  EXPECT_NE(refusal([&](MissionJournal& j) { j.record_binding(mission.agent_count(), "robot9"); })
                .find("the binding of role"),
            std::string::npos);
  EXPECT_EQ(refusal([&](MissionJournal& j) { j.record_visit({0, mission.tasks[0].agents[0]}, "robot0", 1); }),
            "accepted");
  std::filesystem::remove(path);
  std::filesystem::remove(path + "-wal");
  std::filesystem::remove(path + "-shm");
}

// The same journal, seed and robot states give the same plan: a restarted coordinator (or a
// standby taking over) plans what the one before it would have, so an operator can tell why.
// With a work budget this holds for the anytime solver too.
TEST(FleetCoordinator, TheSameJournalSeedAndRobotStatesGiveTheSamePlan) {
  const auto plan_after_restart = [](const std::string& tag) {
    planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
    std::vector<FakeRobot> robots = robots_on_their_starts(mission);
    const int mission_tasks = mission.task_count();
    const std::string path = (std::filesystem::temp_directory_path() /
                              ("ctsfleet-same-plan-" + tag + "-" + std::to_string(::getpid()) + ".journal")).string();
    std::filesystem::remove(path);
    {
      MissionJournal journal(path, mission_fingerprint(mission), "test");
      journal.claim(1, 0x11, 1);
      journal.record_task_added(mission_tasks, 28, 2, 5, "a");
      journal.record_task_added(mission_tasks + 1, 4, 2, 1, "b");
    }
    fleet_transport::FleetPlan plan;
    {
      MissionJournal journal(path, mission_fingerprint(mission), "test");
      FleetConfig config = config_for(mission.agent_count());
      config.solver = config.replan_solver = "cts-pll-v3";
      config.seed = 11;
      config.iterations = 150;
      config.plan_time_s = config.replan_time_s = 60;  // a safety stop: the budget ends the solve
      FleetCoordinator restarted(config, std::move(mission), {false, &journal});
      run(restarted, robots, {}, [&](FleetCoordinator&, FakeTransport& wire, int) {
        if (wire.last_plan.plan_epoch < 1) return true;
        plan = wire.last_plan;
        return false;
      });
    }
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
    return plan;
  };
  const fleet_transport::FleetPlan first = plan_after_restart("a");
  const fleet_transport::FleetPlan second = plan_after_restart("b");
  ASSERT_EQ(first.robots.size(), 8u);
  ASSERT_EQ(second.robots.size(), first.robots.size());
  EXPECT_EQ(second.flowtime, first.flowtime);
  for (size_t r = 0; r < first.robots.size(); ++r) {
    EXPECT_EQ(second.robots[r].robot_id, first.robots[r].robot_id);
    EXPECT_EQ(second.robots[r].role, first.robots[r].role);
    ASSERT_EQ(second.robots[r].path.size(), first.robots[r].path.size()) << first.robots[r].robot_id;
    for (size_t k = 0; k < first.robots[r].path.size(); ++k) {
      EXPECT_EQ(second.robots[r].path[k].x, first.robots[r].path[k].x);
      EXPECT_EQ(second.robots[r].path[k].y, first.robots[r].path[k].y);
    }
  }
}

// Planning runs beside the loop: during a 2 s plan the heartbeat keeps its 0.25 s period (a
// standby would otherwise take the coordinator for dead), and states are still taken in.
TEST(FleetCoordinator, TheHeartbeatGoesOnWhileAPlanIsMade) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  FleetConfig config = config_for(mission.agent_count());
  config.solver = "cts-pll-v3";  // anytime: uses its whole limit
  config.plan_time_s = 2.0;
  FleetCoordinator coordinator(config, std::move(mission));
  std::vector<std::chrono::steady_clock::time_point> beats;
  run(coordinator, robots, {}, [&](FleetCoordinator&, FakeTransport& wire, int) {
    if (wire.last_plan.plan_epoch < 1) return true;
    beats = wire.heartbeat_times;
    return false;
  });
  ASSERT_GE(beats.size(), 2u) << "no plan was made";
  std::vector<double> gaps_s;
  for (size_t k = 1; k < beats.size(); ++k) gaps_s.push_back(std::chrono::duration<double>(beats[k] - beats[k - 1]).count());
  std::sort(gaps_s.begin(), gaps_s.end());
  const double longest_gap_s = gaps_s.back();
  const double planning_s = std::chrono::duration<double>(beats.back() - beats.front()).count();
  std::printf("heartbeats over %.2f s of planning: %zu, gap median %.3f s, longest %.3f s\n", planning_s, beats.size(),
              gaps_s[gaps_s.size() / 2], longest_gap_s);
  EXPECT_GE(planning_s, 1.5) << "the plan took its whole limit";
  // 0.25 s nominal; the bound leaves room for a loaded test machine, far below the 2 s plan.
  EXPECT_LT(longest_gap_s, 0.75) << beats.size() << " heartbeats over " << planning_s << " s";
}

// A robot that dies while the plan is made: the plan, made with it, is dropped and made again
// without it; the others finish, and nobody collides (run() checks every step).
TEST(FleetCoordinator, APlanMadeForAFleetThatChangedMeanwhileIsDroppedAndMadeAgain) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  FleetConfig config = config_for(mission.agent_count());
  config.solver = "cts-pll-v3";
  config.plan_time_s = 1.5;
  FleetCoordinator coordinator(config, std::move(mission));
  const auto started = std::chrono::steady_clock::now();
  run(coordinator, robots, {}, [&](FleetCoordinator&, FakeTransport&, int) {
    // Robot 3 falls silent during the first plan (its silence timeout is 0.3 s).
    if (std::chrono::steady_clock::now() - started > std::chrono::milliseconds(300)) robots[3].silent = true;
    return true;
  });
  const MissionSummary& summary = coordinator.summary();
  EXPECT_GE(summary.plans_discarded, 1);
  EXPECT_EQ(summary.robots_lost, 1);
  EXPECT_EQ(robots[3].moves, 0) << "the plan made with robot 3 was never sent";
  EXPECT_FALSE(summary.completed);  // robot 3's role has work no one else does
  for (int r = 0; r < 8; ++r) {
    if (r != 3) {
      EXPECT_GT(robots[r].moves, 0) << "robot " << r;
    }
  }
}

// One robot id, one body: a second process claiming robot2's id while robot2 is driven (here it
// stands in the way, next to robot2's start) is refused and told so, gets no command, and is
// planned around where it stands; robot2 itself finishes its role. run() checks that no two
// bodies ever share a cell.
TEST(FleetCoordinator, ASecondProcessWithADrivenRobotsIdIsRefusedToldAndPlannedAround) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  for (size_t r = 0; r < robots.size(); ++r) robots[r].incarnation = 0x100 + r;
  const planner_core::Instance copy = mission;
  // A free cell next to robot2's start that is nobody's start.
  planner_core::Cell beside{};
  for (planner_core::Vertex v : copy.graph->neighbours(copy.starts[2])) {
    if (std::find(copy.starts.begin(), copy.starts.end(), v) == copy.starts.end()) beside = copy.graph->cell_of(v);
  }
  FleetCoordinator coordinator(config_for(mission.agent_count()), std::move(mission));
  bool impostor_started = false;
  std::vector<fleet_transport::StepCommand> sent;
  run(coordinator, robots,
      [&](std::vector<FakeRobot>& all) {
        if (impostor_started || coordinator.summary().tasks_done < 2) return;
        impostor_started = true;
        FakeRobot impostor{"robot2", beside};
        impostor.incarnation = 0xBAD;
        all.push_back(impostor);
      },
      [&](FleetCoordinator& c, FakeTransport& wire, int iteration) {
        sent.insert(sent.end(), wire.commands.begin(), wire.commands.end());
        // The impostor keeps publishing where it stands, as a live process does.
        if (impostor_started && iteration % 10 == 0) {
          for (FakeRobot& robot : robots) {
            if (robot.incarnation == 0xBAD) c.on_state(robot.state(-1, -1, fleet_transport::RobotStatus::kIdle));
          }
        }
        return true;
      });
  ASSERT_TRUE(impostor_started);
  const FakeRobot& impostor = robots.back();
  EXPECT_TRUE(impostor.refused) << "the second process was never told it is refused";
  EXPECT_EQ(impostor.moves, 0);
  EXPECT_EQ(impostor.cell, beside);
  int refusals = 0;
  for (const fleet_transport::StepCommand& command : sent) {
    if (command.robot_id != "robot2") continue;
    if (command.refused) {
      ++refusals;
      EXPECT_EQ(command.robot_incarnation, 0xBADu);
    } else {
      EXPECT_EQ(command.robot_incarnation, 0x102u) << "a move for robot2 not meant for its driven process";
    }
  }
  EXPECT_GE(refusals, 1);
  EXPECT_TRUE(coordinator.summary().completed);
  EXPECT_EQ(robots[2].cell, copy.graph->cell_of(copy.goals[2]));
}

// The journal fails mid-mission (a full disk, a file system gone read-only): the coordinator
// raises journal_failed once, keeps counting visits in memory and completes the mission; it never
// exits for it.
TEST(FleetCoordinator, AJournalThatFailsMidMissionRaisesAnAlarmAndTheMissionGoesOn) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("ctsfleet-journal-fails-" + std::to_string(::getpid()) + ".journal")).string();
  std::filesystem::remove(path);
  int journal_failed_events = 0;
  {
    MissionJournal journal(path, mission_fingerprint(mission), "test");
    FleetCoordinator coordinator(config_for(mission.agent_count()), std::move(mission), {false, &journal});
    bool failed = false;
    run(coordinator, robots, {}, [&](FleetCoordinator& c, FakeTransport& wire, int) {
      if (!failed && c.summary().tasks_done >= 3) {
        journal.refuse_writes_for_test();
        failed = true;
      }
      for (const fleet_transport::FleetEvent& event : wire.events) journal_failed_events += event.kind == "journal_failed";
      wire.events.clear();
      return true;
    });
    ASSERT_TRUE(failed);
    const MissionSummary& summary = coordinator.summary();
    EXPECT_TRUE(summary.journal_failed);
    EXPECT_TRUE(summary.completed);
    EXPECT_EQ(summary.tasks_done, summary.tasks_total);
  }
  EXPECT_EQ(journal_failed_events, 1);
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
}

TEST(FleetCoordinator, ATaskNoRobotCanReachIsRefused) {
  using namespace runtime_tasks;
  // Two robots above a wall; the free pocket below it is reachable from nowhere.
  const std::string dir = (std::filesystem::temp_directory_path() /
                           ("ctsfleet-pocket-" + std::to_string(::getpid()))).string();
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/pocket.map") << "type octile\nheight 5\nwidth 7\nmap\n.......\n.......\n.......\n@@@@@@@\n..@....\n";
  std::ofstream(dir + "/mission.yaml") << "map: pocket.map\nagents:\n  - {start: [0, 0], goal: [6, 0]}\n"
                                          "  - {start: [0, 2], goal: [6, 2]}\ntasks:\n  - {at: [3, 1], agents: [0]}\n";
  planner_core::Instance mission = planner_core::load_instance(dir + "/mission.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  FleetConfig config = config_for(mission.agent_count());
  config.lifelong = true;
  FleetCoordinator coordinator(config, std::move(mission));
  std::optional<fleet_transport::TaskReply> pocket, reachable;
  run(coordinator, robots, {}, [&](FleetCoordinator& c, FakeTransport& wire, int iteration) {
    if (iteration == 0) return true;
    if (wire.last_plan.plan_epoch >= 1 && !pocket) {
      c.on_task_request(add("pocket", 1, 4, "robot0"));
      c.on_task_request(add("pocket-any", 0, 4));
      c.on_task_request(add("reachable", 5, 1, "robot1"));
      pocket.emplace();
    }
    if (const auto* r = reply_to(wire, "pocket-any")) pocket = *r;
    if (const auto* r = reply_to(wire, "reachable")) reachable = *r;
    return !(reachable && coordinator.summary().tasks_done == 2);
  });
  ASSERT_TRUE(pocket && reachable);
  EXPECT_FALSE(pocket->accepted);
  EXPECT_EQ(pocket->reason, "(0,4) cannot be reached from any robot's cell");
  EXPECT_TRUE(reachable->accepted) << reachable->reason;
  EXPECT_EQ(coordinator.summary().tasks_done, 2);
  std::filesystem::remove_all(dir);
}


TEST(FleetCoordinator, WhatTheTransportRefusedIsAnEventForOperators) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  FleetCoordinator coordinator(config_for(mission.agent_count()), std::move(mission));
  FakeTransport wire;
  coordinator.on_refused("a message about robot 'robot2' written in partition 'robot/robot3': dropped");
  coordinator.step(wire);
  ASSERT_EQ(wire.events.size(), 1u);
  EXPECT_EQ(wire.events[0].kind, "refused");
  EXPECT_NE(wire.events[0].text.find("robot/robot3"), std::string::npos);
  EXPECT_EQ(wire.events[0].coordinator, coordinator.incarnation());
  EXPECT_EQ(wire.last_mission.mission_id, coordinator.mission_id());  // the mission is out from the first step
  EXPECT_EQ(wire.last_mission.tasks.size(), 16u);
  EXPECT_EQ(wire.last_mission.width, 32);
}

// The default mission with plans with turns: every robot's move goes the way it faces (the
// coordinator turned it first, as a command of its own), every turn is a quarter turn, and a
// robot lost part way is planned around from the headings the others report.
TEST(FleetCoordinator, PlansWithTurnsTurnEveryRobotBeforeItMovesAlsoAfterAReplan) {
  for (const bool lose_one : {false, true}) {
    SCOPED_TRACE(lose_one ? "robot3 lost after its fourth move" : "no robot lost");
    planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
    std::vector<FakeRobot> robots;
    for (int r = 0; r < mission.agent_count(); ++r) {
      robots.push_back({"robot" + std::to_string(r), mission.graph->cell_of(mission.starts[r])});
      robots.back().heading = r % 4;  // facing every way at the start
    }
    FleetConfig config = config_for(mission.agent_count());
    config.actions = planner_core::ActionModel::kRotate;
    FleetCoordinator coordinator(config, std::move(mission));
    const auto lose = [&](FleetCoordinator&, FakeTransport&, int) {
      if (lose_one && robots[3].moves >= 4) robots[3].silent = true;
      return true;
    };
    run(coordinator, robots, {}, lose);
    const MissionSummary& summary = coordinator.summary();
    EXPECT_EQ(summary.robots_lost, lose_one ? 1 : 0);
    if (!lose_one) {
      EXPECT_TRUE(summary.completed);
    }
    int turns = 0, folded = 0;
    for (const FakeRobot& robot : robots) {
      EXPECT_EQ(robot.moves_off_heading, 0) << robot.id;
      EXPECT_EQ(robot.bad_turns, 0) << robot.id;
      turns += robot.turns;
      folded += robot.folded_moves;
    }
    EXPECT_GT(turns, 8);  // they did turn: every robot but those facing their first way must
    EXPECT_GT(folded, 0);  // and turns went with the moves after them when those could start
  }
}

// Lifelong with turns: a stream of tasks taken up as the plan grows by windows planned with turns;
// every robot faces its way before each move, every task is done, the fleet never stops to replan.
TEST(FleetCoordinator, ALifelongFleetThatTurnsTakesUpAStreamOfTasksTurningBeforeEveryMove) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  for (size_t r = 0; r < robots.size(); ++r) robots[r].heading = static_cast<int>(r % 4);
  const int mission_tasks = mission.task_count();
  FleetConfig config = config_for(mission.agent_count());
  config.lifelong = true;
  config.actions = planner_core::ActionModel::kRotate;
  TaskStream stream(*mission.graph);
  FleetCoordinator coordinator(config, std::move(mission));
  int after_done = 0;
  const auto visited = run(coordinator, robots, {}, [&](FleetCoordinator& c, FakeTransport& wire, int) {
    return !stream.feed(c, wire) || ++after_done < 100;
  });
  EXPECT_TRUE(stream.refused.empty()) << stream.refused.front();
  const MissionSummary& summary = coordinator.summary();
  EXPECT_EQ(summary.tasks_total, mission_tasks + stream.total);
  EXPECT_EQ(summary.tasks_done, summary.tasks_total);
  EXPECT_EQ(summary.replans, 0);
  EXPECT_GT(summary.windows, 10);
  expect_only_steps(visited);
  int turns = 0;
  for (const FakeRobot& robot : robots) {
    EXPECT_EQ(robot.moves_off_heading, 0) << robot.id;
    EXPECT_EQ(robot.bad_turns, 0) << robot.id;
    turns += robot.turns;
  }
  EXPECT_GT(turns, 8);
}

// Plans with turns meet robots that do not face the way the plan has them: one turned half round
// by hand between two commands, one whose body reports no heading at all (-1: it is confirmed by
// its cell, as a robot in a four-way plan). Neither stops the mission: the turned robot's next
// move ends facing its way, the mission completes without a replan, and the others keep to their
// headings.
TEST(FleetCoordinator, PlansWithTurnsGoOnWithARobotTurnedByHandAndOneThatKnowsNoHeading) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  robots[2].hand_turn_after = 3;
  robots[5].hand_turn_after = 1;
  robots[6].knows_heading = false;
  FleetConfig config = config_for(mission.agent_count());
  config.actions = planner_core::ActionModel::kRotate;
  FleetCoordinator coordinator(config, std::move(mission));
  run(coordinator, robots);
  const MissionSummary& summary = coordinator.summary();
  EXPECT_TRUE(summary.completed);
  EXPECT_EQ(summary.tasks_done, summary.tasks_total);
  EXPECT_EQ(summary.replans, 0);
  EXPECT_GE(robots[2].moves, 3);
  EXPECT_GE(robots[5].moves, 1);
  for (const FakeRobot& robot : robots) {
    if (robot.id == "robot2" || robot.id == "robot5") continue;  // they turn where the plan did not expect
    EXPECT_EQ(robot.moves_off_heading, 0) << robot.id;
    EXPECT_EQ(robot.bad_turns, 0) << robot.id;
  }
}

// A robot's process restarts part way, its body now facing the other way (carried, or the agent
// started with another --heading): the restart takes it out, it rejoins, and the replan starts it
// from the heading it reports, so every move it is sent goes the way it faces after the turns
// planned for it.
TEST(FleetCoordinator, ARobotRestartedFacingAnotherWayIsReplannedFromItsNewHeading) {
  planner_core::Instance mission = planner_core::load_instance(CTSFLEET_CONFIG_DIR "/default/mission-8.yaml");
  std::vector<FakeRobot> robots = robots_on_their_starts(mission);
  for (size_t r = 0; r < robots.size(); ++r) robots[r].incarnation = 0x100 + r;
  FleetConfig config = config_for(mission.agent_count());
  config.actions = planner_core::ActionModel::kRotate;
  config.replacement_timeout_s = 10;  // the others wait for it: its role's tasks are left
  FleetCoordinator coordinator(config, std::move(mission));
  enum class Phase { kRunning, kDown, kBack } phase = Phase::kRunning;
  std::chrono::steady_clock::time_point went_down;
  FakeRobot& restarting = robots[4];
  int moves_before_restart = 0;
  run(coordinator, robots, {}, [&](FleetCoordinator& c, FakeTransport&, int) {
    if (phase == Phase::kRunning && restarting.moves >= 3) {
      phase = Phase::kDown;
      restarting.silent = true;
      went_down = std::chrono::steady_clock::now();
    } else if (phase == Phase::kDown && std::chrono::steady_clock::now() - went_down > std::chrono::milliseconds(1500)) {
      phase = Phase::kBack;
      restarting.silent = false;
      restarting.incarnation = 0x999;
      restarting.heading = (restarting.heading + 1) % 4;  // a quarter off: every first action tells
      restarting.epoch = restarting.action = -1;
      restarting.coordinator = 0;
      restarting.moves_off_heading = restarting.bad_turns = 0;  // counted from the new plan on
      moves_before_restart = restarting.moves;
      c.on_state(restarting.state(-1, -1, fleet_transport::RobotStatus::kIdle));
    }
    return true;
  });
  ASSERT_EQ(phase, Phase::kBack);
  const MissionSummary& summary = coordinator.summary();
  EXPECT_TRUE(summary.completed);
  EXPECT_EQ(summary.tasks_done, summary.tasks_total);
  EXPECT_GE(summary.robots_joined, 1);
  EXPECT_GT(restarting.moves, moves_before_restart);  // it went on, under the replan
  for (const FakeRobot& robot : robots) {
    EXPECT_EQ(robot.moves_off_heading, 0) << robot.id;
    EXPECT_EQ(robot.bad_turns, 0) << robot.id;
  }
}

}  // namespace
}  // namespace coordinator
