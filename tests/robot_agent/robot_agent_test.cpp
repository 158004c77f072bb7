// RobotAgent with a simulated robot and a fake transport: which commands it takes and which it
// refuses, before any of them can change what it accepts next.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <numbers>
#include <thread>

#include "fake_transport.hpp"
#include "robot_agent/robot_agent.hpp"
#include "robot_agent/sim_robot.hpp"

namespace robot_agent {
namespace {

using testing_support::FakeTransport;

constexpr uint64_t kCoordinator = 0xC0;
constexpr uint64_t kThisProcess = 0xB0D1;  // the agents' incarnation in these tests

fleet_transport::StepCommand move(int epoch, int index, int x, int y, int64_t deadline_ms,
                                  uint64_t coordinator = kCoordinator) {
  return {"r1", epoch, index, x, y, static_cast<double>(x), static_cast<double>(y), deadline_ms, coordinator, 0,
          kThisProcess};
}

fleet_transport::CoordinatorStatus status_of(uint64_t coordinator, uint32_t term, int epoch, int64_t claimed_ms = 1000,
                                             fleet_transport::CoordinatorRole role =
                                                 fleet_transport::CoordinatorRole::kActive) {
  return {coordinator, term, claimed_ms, role, std::string("m"), epoch};
}

int64_t in_5_s() { return fleet_transport::wall_clock_ms() + 5000; }

struct AgentFixture : ::testing::Test {
  SimSettings sim{0.01, 0.0};
  SimRobot robot{{2, 2}, sim};
  AgentSettings settings{"r1", 10, "0.1.0", 1, 2.0, kThisProcess};
  RobotAgent agent{settings, robot};
  FakeTransport transport;

  // Steps the agent until the robot stands still again (at most 2 s).
  void settle() {
    for (int i = 0; i < 400; ++i) {
      agent.step(transport, true);
      if (!robot.poll().moving && i > 2) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
};

TEST_F(AgentFixture, ACommandPastItsDeadlineIsDroppedAndChangesNothing) {
  agent.on_coordinator_status(status_of(kCoordinator, 1, 7));
  const int64_t now = fleet_transport::wall_clock_ms();
  agent.on_command(move(7, 0, 3, 2, now - 1000));  // late: its plan has moved on
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{2, 2}));
  // Its epoch was not taken: a command of an older epoch, in time, still counts.
  agent.on_command(move(5, 0, 2, 3, now + 5000));
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{2, 3}));
  EXPECT_EQ(transport.last_state.plan_epoch, 5);
}

// A coordinator on a host whose clock is `skew_ms` behind ours: its stamps and deadlines.
fleet_transport::StepCommand from_skewed_host(int epoch, int index, int x, int y, int64_t skew_ms,
                                              int64_t deadline_in_ms) {
  const int64_t its_now = fleet_transport::wall_clock_ms() - skew_ms;
  fleet_transport::StepCommand command = move(epoch, index, x, y, its_now + deadline_in_ms);
  command.sent_ms = its_now;
  return command;
}

TEST_F(AgentFixture, ACoordinatorWhoseClockIsSecondsBehindIsObeyedInTime) {
  agent.on_coordinator_status(status_of(kCoordinator, 1, 1));
  // Its deadline 1.2 s ahead on its clock is 1.8 s past on ours: still taken.
  agent.on_command(from_skewed_host(1, 0, 3, 2, 3000, 1200));
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 2}));
  agent.on_command(from_skewed_host(1, 1, 3, 3, 3000, 1200));
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 3}));
}

TEST_F(AgentFixture, ACoordinatorWhoseClockIsAheadStillCannotReplayALateCommand) {
  agent.on_coordinator_status(status_of(kCoordinator, 1, 1));
  agent.on_command(from_skewed_host(1, 0, 3, 2, -4000, 1200));  // its clock 4 s ahead of ours
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 2}));
  // The same sender's command whose deadline passed 1 s ago on its clock: refused, skew or not.
  fleet_transport::StepCommand late = from_skewed_host(1, 1, 3, 3, -4000, -1000);
  late.sent_ms -= 2200;  // sent 2.2 s ago with a 1.2 s deadline, delivered now (a replay)
  agent.on_command(late);
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 2}));
}

TEST_F(AgentFixture, ACommandIsStartedAndAcknowledgedOnTheThreadThatReceivedIt) {
  agent.start_commands_where_they_arrive(transport, [] { return true; });
  agent.on_coordinator_status(status_of(kCoordinator, 1, 7));
  agent.on_command(move(7, 0, 3, 2, in_5_s()));  // no step() of the agent's loop in between
  EXPECT_TRUE(robot.poll().moving);
  EXPECT_EQ(transport.last_state.plan_epoch, 7);
  EXPECT_EQ(transport.last_state.action_index, 0);
  EXPECT_EQ(transport.last_state.status, fleet_transport::RobotStatus::kMoving);
  // The loop, asleep for a time chosen before the move, is woken to watch for the arrival.
  const auto before = std::chrono::steady_clock::now();
  agent.wait_for_command(std::chrono::seconds(5));
  EXPECT_LT(std::chrono::steady_clock::now() - before, std::chrono::seconds(4));
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 2}));
  EXPECT_EQ(transport.last_state.status, fleet_transport::RobotStatus::kArrived);
}

// A move longer than the loop's sleep: the command starts on the receiving thread and the loop
// sleeps on (one thread woken per command, not two).
TEST(AgentStartingCommands, ACommandStartedWhereItArrivesLeavesTheSleepingLoopAsleep) {
  SimRobot robot({2, 2}, SimSettings{10.0, 0.0});
  RobotAgent agent(AgentSettings{"r1", 10, "0.1.0", 1, 2.0, kThisProcess}, robot);
  FakeTransport transport;
  agent.start_commands_where_they_arrive(transport, [] { return true; });
  agent.on_coordinator_status(status_of(kCoordinator, 1, 7));
  std::atomic<bool> loop_asleep{false};
  std::chrono::steady_clock::duration slept{};
  std::thread loop([&] {
    const auto before = std::chrono::steady_clock::now();
    loop_asleep = true;
    agent.wait_for_command(std::chrono::seconds(3));
    slept = std::chrono::steady_clock::now() - before;
  });
  while (!loop_asleep) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // well inside its wait by now
  agent.on_command(move(7, 0, 3, 2, fleet_transport::wall_clock_ms() + 60000));
  EXPECT_TRUE(robot.poll().moving);
  EXPECT_EQ(transport.last_state.status, fleet_transport::RobotStatus::kMoving);
  loop.join();
  EXPECT_GE(slept, std::chrono::milliseconds(2900));  // its whole sleep: not woken by the command
}

TEST_F(AgentFixture, ACommandHeldForItsEpochStartsWhenTheStatusArrives) {
  agent.start_commands_where_they_arrive(transport, [] { return true; });
  agent.on_coordinator_status(status_of(kCoordinator, 1, 6));
  agent.on_command(move(7, 0, 3, 2, in_5_s()));  // epoch 7 not announced yet
  EXPECT_FALSE(robot.poll().moving);
  agent.on_coordinator_status(status_of(kCoordinator, 1, 7));
  EXPECT_TRUE(robot.poll().moving);
  EXPECT_EQ(transport.last_state.plan_epoch, 7);
}

// A backend whose moves may block (a toio cube over Bluetooth) never runs on DDS's thread.
struct BlockingBackend : SimRobot {
  using SimRobot::SimRobot;
  bool starts_moves_at_once() const override { return false; }
};

TEST(AgentStartingCommands, ABackendThatMayBlockIsDrivenOnlyByTheAgentsLoop) {
  BlockingBackend robot({2, 2}, SimSettings{0.01, 0.0});
  RobotAgent agent(AgentSettings{"r1", 10, "0.1.0", 1, 2.0, kThisProcess}, robot);
  FakeTransport transport;
  agent.start_commands_where_they_arrive(transport, [] { return true; });
  agent.on_coordinator_status(status_of(kCoordinator, 1, 7));
  agent.on_command(move(7, 0, 3, 2, in_5_s()));
  EXPECT_FALSE(robot.poll().moving);
  EXPECT_TRUE(transport.last_state.robot_id.empty());  // nothing published yet
  agent.step(transport, true);
  EXPECT_TRUE(robot.poll().moving);
  EXPECT_EQ(transport.last_state.plan_epoch, 7);
}

// Published states read from another thread than the agents'.
struct SharedTransport : FakeTransport {
  void publish_state(const fleet_transport::RobotState& state) override {
    const std::lock_guard<std::mutex> lock(mutex);
    FakeTransport::publish_state(state);
  }
  fleet_transport::RobotState latest() {
    const std::lock_guard<std::mutex> lock(mutex);
    return last_state;
  }
  std::mutex mutex;
};

TEST_F(AgentFixture, TheLoopAndTheReceivingThreadStepInTurn) {
  SharedTransport shared;
  agent.start_commands_where_they_arrive(shared, [] { return true; });
  agent.on_coordinator_status(status_of(kCoordinator, 1, 7));
  std::atomic<bool> done{false};
  std::thread loop([&] {
    while (!done.load()) {
      agent.step(shared, true);
      agent.wait_for_command(std::chrono::milliseconds(2));
    }
  });
  // Back and forth between two cells, each command sent once the last move ended.
  for (int index = 0; index < 20; ++index) {
    const Cell target = index % 2 == 0 ? Cell{3, 2} : Cell{2, 2};
    agent.on_command(move(7, index, target.x, target.y, in_5_s()));
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::chrono::steady_clock::now() < deadline) {
      const fleet_transport::RobotState state = shared.latest();
      if (state.action_index == index && state.status == fleet_transport::RobotStatus::kArrived) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  done = true;
  loop.join();
  EXPECT_EQ(shared.latest().action_index, 19);
  EXPECT_EQ(shared.latest().status, fleet_transport::RobotStatus::kArrived);
  EXPECT_EQ(robot.poll().cell, (Cell{2, 2}));
}

TEST(ClockOffset, IsTheSmallestDifferenceOfItsWindow) {
  ClockOffset clock;
  EXPECT_FALSE(clock.offset_ms());
  clock.add(1000, 3010);  // 10 ms delay on a clock 2 s behind
  clock.add(2000, 4002);
  clock.add(2500, 4700);  // a slow delivery changes nothing
  EXPECT_EQ(clock.offset_ms(), 2002);
  for (std::size_t i = 0; i < ClockOffset::kWindow; ++i) clock.add(10000, 11005);  // the clock was stepped
  EXPECT_EQ(clock.offset_ms(), 1005);
}

TEST_F(AgentFixture, IncarnationIsInEveryAnnouncementAndState) {
  EXPECT_NE(agent.incarnation(), 0u);
  EXPECT_EQ(agent.announcement().incarnation, agent.incarnation());
  agent.on_coordinator_status(status_of(kCoordinator, 1, 1));
  agent.on_command(move(1, 0, 3, 2, fleet_transport::wall_clock_ms() + 5000));
  settle();
  EXPECT_EQ(transport.last_state.incarnation, agent.incarnation());
  // Unless a test fixes it, every process start draws its own.
  AgentSettings unfixed = settings;
  unfixed.incarnation = 0;
  SimRobot robot_a({0, 0}, sim), robot_b({0, 0}, sim);
  RobotAgent first(unfixed, robot_a), restarted(unfixed, robot_b);
  EXPECT_NE(first.incarnation(), 0u);
  EXPECT_NE(restarted.incarnation(), first.incarnation());  // 64 random bits: equal once in 2^64
}

TEST_F(AgentFixture, AForgedFarFutureEpochIsNeverJumpedTo) {
  agent.on_coordinator_status(status_of(kCoordinator, 1, 2));
  agent.on_command(move(1000, 0, 3, 2, in_5_s()));  // the followed coordinator's id, an epoch it never announced
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{2, 2}));
  // The real epoch-2 command still counts: nothing was locked out.
  agent.on_command(move(2, 0, 2, 3, in_5_s()));
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{2, 3}));
  EXPECT_EQ(transport.last_state.coordinator, kCoordinator);
  agent.on_coordinator_status(status_of(kCoordinator, 1, 3));  // announcing 3 releases nothing of epoch 1000
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{2, 3}));
}

TEST_F(AgentFixture, ACommandArrivingBeforeItsEpochIsAnnouncedWaitsForTheStatus) {
  agent.on_coordinator_status(status_of(kCoordinator, 1, 1));
  agent.on_command(move(2, 0, 3, 2, in_5_s()));  // epoch 2's status is still on its way
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{2, 2}));
  agent.on_coordinator_status(status_of(kCoordinator, 1, 2));
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 2}));
}

TEST_F(AgentFixture, ACommandBeforeAnyCoordinatorIsHeardIsHeldNotObeyed) {
  agent.on_command(move(1, 0, 3, 2, in_5_s()));
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{2, 2}));
  EXPECT_EQ(agent.followed_coordinator(), 0u);
  agent.on_coordinator_status(status_of(kCoordinator, 1, 1));
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 2}));
}

TEST_F(AgentFixture, OnlyTheFollowedCoordinatorIsObeyed) {
  constexpr uint64_t kSecond = 0xD0;
  agent.on_coordinator_status(status_of(kCoordinator, 1, 1, 1000));
  agent.on_coordinator_status(status_of(kSecond, 1, 5, 2000));  // same term, claimed later: ranks lower
  EXPECT_EQ(agent.followed_coordinator(), kCoordinator);
  agent.on_command(move(5, 0, 3, 2, in_5_s(), kSecond));
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{2, 2}));
  // A standby never drives, whatever its term.
  agent.on_coordinator_status(status_of(0xE0, 9, 1, 500, fleet_transport::CoordinatorRole::kStandby));
  EXPECT_EQ(agent.followed_coordinator(), kCoordinator);
  agent.on_command(move(1, 0, 2, 3, in_5_s()));
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{2, 3}));
}

TEST_F(AgentFixture, AHigherTermTakesOverAndItsSmallerEpochsCount) {
  agent.on_coordinator_status(status_of(kCoordinator, 1, 40));
  agent.on_command(move(40, 0, 3, 2, in_5_s()));
  settle();
  ASSERT_EQ(robot.poll().cell, (Cell{3, 2}));
  constexpr uint64_t kStandby = 0xD0;  // took over: term 2, its own epochs
  agent.on_coordinator_status(status_of(kStandby, 2, 1, 5000));
  EXPECT_EQ(agent.followed_coordinator(), kStandby);
  agent.on_command(move(1, 0, 3, 3, in_5_s(), kStandby));
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 3}));
  agent.on_command(move(41, 0, 4, 3, in_5_s()));  // the old one, back from a pause: not followed
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 3}));
}

TEST_F(AgentFixture, ACoordinatorThatEndedIsReplacedByTheNextMissionsAtOnce) {
  agent.on_coordinator_status(status_of(kCoordinator, 3, 9));
  agent.on_command(move(9, 0, 3, 2, in_5_s()));
  settle();
  agent.on_coordinator_status(status_of(kCoordinator, 3, 9, 1000, fleet_transport::CoordinatorRole::kEnded));
  constexpr uint64_t kNext = 0xD0;  // a new mission: term 1, epochs from 1
  agent.on_coordinator_status(status_of(kNext, 1, 1, 9000));
  EXPECT_EQ(agent.followed_coordinator(), kNext);
  agent.on_command(move(1, 0, 3, 3, in_5_s(), kNext));
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 3}));
}

// One robot id, one body: a command meant for another process with this id is never obeyed.
TEST_F(AgentFixture, ACommandForAnotherProcessWithThisIdIsIgnored) {
  agent.on_coordinator_status(status_of(kCoordinator, 1, 1));
  fleet_transport::StepCommand other = move(1, 0, 3, 2, in_5_s());
  other.robot_incarnation = kThisProcess ^ 1;
  agent.on_command(other);
  fleet_transport::StepCommand unaddressed = move(1, 0, 2, 3, in_5_s());
  unaddressed.robot_incarnation = 0;
  agent.on_command(unaddressed);
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{2, 2}));
  agent.on_command(move(1, 0, 3, 2, in_5_s()));  // the same move, for this process
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 2}));
}

// A refused process stands still and obeys nothing until its coordinator drives it again; a
// refusal from a coordinator it does not follow changes nothing.
TEST_F(AgentFixture, ARefusedProcessStandsStillUntilItIsDrivenAgain) {
  agent.on_coordinator_status(status_of(kCoordinator, 1, 2));
  fleet_transport::StepCommand forged = move(1, -1, 2, 2, in_5_s(), 0xBAD);
  forged.refused = true;
  agent.on_command(forged);
  agent.on_command(move(1, 0, 3, 2, in_5_s()));
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 2})) << "a forged refusal stopped the robot";

  fleet_transport::StepCommand refusal = move(1, -1, 3, 2, in_5_s());
  refusal.refused = true;
  agent.on_command(refusal);
  agent.on_command(move(1, 1, 4, 2, in_5_s()));  // refused: another command of the same plan is not obeyed
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 2}));
  agent.on_command(move(2, 0, 3, 3, in_5_s()));  // a new plan for this process: driven again
  settle();
  EXPECT_EQ(robot.poll().cell, (Cell{3, 3}));
}

TEST(AgentCoordinatorSilence, ASilentCoordinatorIsReplacedByAnyActiveOne) {
  SimSettings sim{0.01, 0.0};
  SimRobot robot{{2, 2}, sim};
  AgentSettings settings{"r1", 10, "0.1.0", 1, 2.0, kThisProcess};
  settings.coordinator_silence_s = 0.2;
  RobotAgent agent{settings, robot};
  agent.on_coordinator_status(status_of(kCoordinator, 5, 3));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // longer than the silence, by design of the test
  agent.on_coordinator_status(status_of(0xD0, 1, 1, 9000));
  EXPECT_EQ(agent.followed_coordinator(), 0xD0u);
}

TEST(SimRobot, CarriedByHandAfterItsMoves) {
  SimSettings sim{0.001, 0.0};
  sim.teleport_after_moves = 1;
  sim.teleport_to = {9, 9};
  SimRobot robot({0, 0}, sim);
  ASSERT_TRUE(robot.start_move({1, 0}, -1));
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(robot.poll().cell, (Cell{9, 9}));
}

// The planned duration of the step just started, in seconds (jitter 0: exact).
double planned_s(const SimRobot& robot) {
  return std::chrono::duration<double>(robot.time_to_arrival().value_or(std::chrono::steady_clock::duration::zero()))
      .count();
}

TEST(SimRobot, TurnsInPlaceBeforeAMoveTheOtherWayAndEndsFacingTheWayItWent) {
  SimSettings sim{0.4, 0.0};
  sim.turn_s = 0.3;
  sim.start_heading = 0;  // east
  SimRobot robot({2, 2}, sim);
  EXPECT_EQ(robot.poll().heading, 0);
  ASSERT_TRUE(robot.start_move({3, 2}, -1));  // ahead: no turn
  EXPECT_NEAR(planned_s(robot), 0.4, 0.02);
  EXPECT_FALSE(robot.start_move({4, 2}, -1));  // busy
  const auto arrive = [&robot] {
    for (int i = 0; i < 2000 && robot.poll().moving; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return robot.poll();
  };
  EXPECT_EQ(arrive().heading, 0);
  ASSERT_TRUE(robot.start_move({2, 2}, -1));  // back west: half a turn first
  EXPECT_NEAR(planned_s(robot), 2 * 0.3 + 0.4, 0.02);
  const BackendReport back = arrive();
  EXPECT_EQ(back.cell, (Cell{2, 2}));
  EXPECT_EQ(back.heading, 2);
  ASSERT_TRUE(robot.start_move({2, 2}, 3));  // a quarter turn in place, to face north
  EXPECT_NEAR(planned_s(robot), 0.3, 0.02);
  const BackendReport turned = arrive();
  EXPECT_EQ(turned.cell, (Cell{2, 2}));
  EXPECT_EQ(turned.heading, 3);
  EXPECT_NEAR(turned.pose_theta, 3 * std::numbers::pi / 2, 1e-9);
  ASSERT_TRUE(robot.start_move({2, 2}, -1));  // a wait keeps the heading and takes a step
  EXPECT_NEAR(planned_s(robot), 0.4, 0.02);
  EXPECT_EQ(arrive().heading, 3);
}

TEST(SimRobot, WithoutTurnTimeTurnsCostNothingButTheHeadingStillFollows) {
  SimRobot robot({0, 0}, SimSettings{0.05, 0.0});
  ASSERT_TRUE(robot.start_move({0, 1}, -1));
  EXPECT_NEAR(planned_s(robot), 0.05, 0.02);
  for (int i = 0; i < 2000 && robot.poll().moving; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_EQ(robot.poll().heading, 1);  // south
  ASSERT_TRUE(robot.start_move({0, 1}, 0));
  EXPECT_NEAR(planned_s(robot), 0.0, 0.02);
}

TEST_F(AgentFixture, AHeadingThatCannotBeIsRefusedAndAMoveOffItsHeadingIsCounted) {
  // Sends command (epoch, index) to (x, y) ending facing `heading`, and lets the robot carry it out.
  const auto command = [&](int epoch, int index, int x, int y, int heading) {
    fleet_transport::StepCommand step = move(epoch, index, x, y, in_5_s());
    step.target_heading = heading;
    agent.on_command(step);
    settle();
  };
  agent.on_coordinator_status(status_of(kCoordinator, 1, 1));
  command(1, 0, 3, 2, 7);  // no such heading
  EXPECT_EQ(robot.poll().cell, (Cell{2, 2}));
  command(1, 1, 3, 2, 1);  // a move east cannot end facing south
  EXPECT_EQ(robot.poll().cell, (Cell{2, 2}));
  EXPECT_EQ(agent.moves_started_off_heading(), 0);

  // The robot faces east; a plan with turns that has it go south first thing without a turn is
  // wrong about its heading: the robot turns first, and the agent counts it.
  agent.on_coordinator_status(status_of(kCoordinator, 1, 2));
  command(2, 0, 2, 3, 1);
  EXPECT_EQ(robot.poll().cell, (Cell{2, 3}));
  EXPECT_EQ(transport.last_state.heading, 1);
  EXPECT_EQ(agent.moves_started_off_heading(), 1);
  // A turn in place, then a move the way it faces: nothing counted.
  command(2, 1, 2, 3, 0);
  EXPECT_EQ(transport.last_state.heading, 0);
  command(2, 2, 3, 3, 0);
  EXPECT_EQ(robot.poll().cell, (Cell{3, 3}));
  EXPECT_EQ(agent.moves_started_off_heading(), 1);
  // The next move in line facing the wrong way counts; one whose index skips a turn's (the turn
  // folded into it) does not: the robot is meant to turn first.
  command(2, 3, 3, 2, 3);
  EXPECT_EQ(agent.moves_started_off_heading(), 2);
  command(2, 5, 2, 2, 2);
  EXPECT_EQ(robot.poll().cell, (Cell{2, 2}));
  EXPECT_EQ(transport.last_state.heading, 2);
  EXPECT_EQ(agent.moves_started_off_heading(), 2);
}

}  // namespace
}  // namespace robot_agent
