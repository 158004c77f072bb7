// RobotAgent with a simulated robot and a fake transport: which commands it takes and which it
// refuses, before any of them can change what it accepts next.
#include <gtest/gtest.h>

#include <thread>

#include "fake_transport.hpp"
#include "robot_agent/robot_agent.hpp"
#include "robot_agent/sim_robot.hpp"

namespace robot_agent {
namespace {

using testing_support::FakeTransport;

fleet_transport::StepCommand move(int epoch, int index, int x, int y, int64_t deadline_ms) {
  return {"r1", epoch, index, x, y, static_cast<double>(x), static_cast<double>(y), deadline_ms};
}

struct AgentFixture : ::testing::Test {
  SimSettings sim{0.01, 0.0};
  SimRobot robot{{2, 2}, sim};
  AgentSettings settings{"r1"};
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
  const int64_t now = fleet_transport::wall_clock_ms();
  agent.on_command(move(7, 0, 3, 2, now - 1000));  // late: its plan has moved on
  settle();
  EXPECT_EQ(robot.poll().cell, (GridCell{2, 2}));
  // Its epoch was not taken: a command of an older epoch, in time, still counts.
  agent.on_command(move(5, 0, 2, 3, now + 5000));
  settle();
  EXPECT_EQ(robot.poll().cell, (GridCell{2, 3}));
  EXPECT_EQ(transport.last_state.plan_epoch, 5);
}

TEST_F(AgentFixture, IncarnationIsInEveryAnnouncementAndState) {
  EXPECT_NE(agent.incarnation(), 0u);
  EXPECT_EQ(agent.announcement().incarnation, agent.incarnation());
  agent.on_command(move(1, 0, 3, 2, fleet_transport::wall_clock_ms() + 5000));
  settle();
  EXPECT_EQ(transport.last_state.incarnation, agent.incarnation());
  SimRobot other_robot({0, 0}, sim);
  RobotAgent restarted(settings, other_robot);
  EXPECT_NE(restarted.incarnation(), agent.incarnation());  // 64 random bits: equal once in 2^64
}

TEST(SimRobot, CarriedByHandAfterItsMoves) {
  SimSettings sim{0.001, 0.0};
  sim.teleport_after_moves = 1;
  sim.teleport_to = {9, 9};
  SimRobot robot({0, 0}, sim);
  ASSERT_TRUE(robot.start_move({1, 0}));
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(robot.poll().cell, (GridCell{9, 9}));
}

}  // namespace
}  // namespace robot_agent
