// A simulated robot delayed as the league's 2026 rules delay robots (SimSettings::league_delays):
// a move takes the ticks that fall in a delay on top of its own; the same seed gives the same
// delays, another seed others; pDelay 0 never delays, pDelay 1 never lets the robot arrive.
#include <gtest/gtest.h>

#include <chrono>
#include <vector>

#include "robot_agent/sim_robot.hpp"

namespace robot_agent {
namespace {

planner_core::LeagueDelays delays(double p, unsigned seed = 0) {
  planner_core::LeagueDelays config;
  config.seed = seed;
  config.min_ticks = 5;
  config.max_ticks = 10;
  config.probability = p;
  return config;
}

// The time a move east from (0,0) would take, in seconds: 1 s a move, ticks of 0.1 s.
double move_time(const planner_core::LeagueDelays& config, uint32_t robot_seed) {
  SimSettings sim{1.0, 0.0};
  sim.league_delays = config;
  sim.delay_tick_s = 0.1;
  sim.seed = robot_seed;
  SimRobot robot({0, 0}, sim);
  EXPECT_TRUE(robot.start_move({1, 0}, -1));
  return std::chrono::duration<double>(*robot.time_to_arrival()).count();
}

TEST(SimRobotLeagueDelays, WithoutDelaysAMoveTakesItsStep) {
  EXPECT_NEAR(move_time(delays(0.0), 0), 1.0, 0.05);
}

TEST(SimRobotLeagueDelays, DelaysLengthenMovesAsTheSeedSays) {
  std::vector<double> times;
  for (uint32_t seed = 0; seed < 8; ++seed) times.push_back(move_time(delays(0.05), seed));
  // Ten ticks a move at 5% a tick: most moves meet a delay of 5-10 ticks (0.5-1 s) or more.
  int delayed = 0;
  for (double t : times) {
    EXPECT_GE(t, 0.95);
    EXPECT_LE(t, 4.0);  // a few delays at most
    delayed += t > 1.4 ? 1 : 0;
  }
  EXPECT_GE(delayed, 2);
  EXPECT_NEAR(move_time(delays(0.05), 3), times[3], 0.05);  // the same seed, the same delays
}

TEST(SimRobotLeagueDelays, ARobotDelayedForEverNeverArrives) {
  EXPECT_GT(move_time(delays(1.0), 0), 3600.0);
}

}  // namespace
}  // namespace robot_agent
