// The league's delay model drawn tick by tick: the seed decides the run, delays last within their
// range, a delayed robot is never drawn again before it is free, and the share of robot-ticks
// delayed is what the probability and the durations make it.
#include <gtest/gtest.h>

#include "planner_core/delay_draws.hpp"

namespace planner_core {
namespace {

LeagueDelays delays(LeagueDelays::Events events, double p, int min_ticks, int max_ticks,
                    LeagueDelays::Durations durations = LeagueDelays::Durations::kUniform) {
  LeagueDelays config;
  config.seed = 11;
  config.events = events;
  config.probability = p;
  config.min_ticks = min_ticks;
  config.max_ticks = max_ticks;
  config.durations = durations;
  return config;
}

TEST(DelayDraws, TheSameSeedDrawsTheSameDelays) {
  for (auto events : {LeagueDelays::Events::kBernoulli, LeagueDelays::Events::kPoisson}) {
    DelayDraws first(delays(events, 0.05, 2, 6), 50), second(delays(events, 0.05, 2, 6), 50);
    for (int t = 0; t < 300; ++t) ASSERT_EQ(first.tick(), second.tick()) << "tick " << t;
    LeagueDelays other = delays(events, 0.05, 2, 6);
    other.seed = 12;
    DelayDraws third(other, 50), fourth(delays(events, 0.05, 2, 6), 50);
    bool differ = false;
    for (int t = 0; t < 300; ++t) differ = differ || third.tick() != fourth.tick();
    EXPECT_TRUE(differ);
  }
}

TEST(DelayDraws, NoProbabilityNoDelayAndCertaintyDelaysEveryFreeRobot) {
  DelayDraws never(delays(LeagueDelays::Events::kBernoulli, 0, 1, 4), 20);
  for (int t = 0; t < 100; ++t) EXPECT_TRUE(never.tick().empty());
  EXPECT_EQ(never.delayed_robot_ticks(), 0);
  DelayDraws always(delays(LeagueDelays::Events::kBernoulli, 1, 3, 3), 20);
  EXPECT_EQ(always.tick().size(), 20u);
  EXPECT_TRUE(always.tick().empty());  // all still delayed: none drawn twice
  EXPECT_TRUE(always.tick().empty());
  EXPECT_EQ(always.tick().size(), 20u);  // free after exactly 3 ticks, and delayed again
  EXPECT_EQ(always.delayed_robot_ticks(), 4 * 20);
}

TEST(DelayDraws, DelaysLastWithinTheirRangeAndTheDelayedAreNotDrawnAgain) {
  for (auto durations : {LeagueDelays::Durations::kUniform, LeagueDelays::Durations::kGaussian}) {
    for (auto events : {LeagueDelays::Events::kBernoulli, LeagueDelays::Events::kPoisson}) {
      DelayDraws draws(delays(events, 0.1, 2, 9, durations), 40);
      for (int t = 0; t < 500; ++t) {
        std::vector<bool> was_delayed(40);
        for (int r = 0; r < 40; ++r) was_delayed[r] = draws.ticks_left(r) > 1;  // still delayed next tick
        for (int robot : draws.tick()) {
          EXPECT_FALSE(was_delayed[robot]) << "robot " << robot << " drawn while delayed, tick " << t;
          EXPECT_GE(draws.ticks_left(robot), 2);
          EXPECT_LE(draws.ticks_left(robot), 9);
        }
      }
    }
  }
}

TEST(DelayDraws, TheShareOfDelayedRobotTicksFollowsTheModel) {
  // Bernoulli, p per free robot and tick, delays of d ticks: a robot is delayed d out of every
  // 1/p + d ticks on the mean, a share of d p / (1 + d p).
  const double p = 0.02;
  const int d = 5;
  DelayDraws bernoulli(delays(LeagueDelays::Events::kBernoulli, p, d, d), 200);
  const int ticks = 5000;
  for (int t = 0; t < ticks; ++t) bernoulli.tick();
  const double share = static_cast<double>(bernoulli.delayed_robot_ticks()) / (200.0 * ticks);
  EXPECT_NEAR(share, d * p / (1 + d * p), 0.01);
  // Poisson with rate teamSize x p over the free robots: about as many events while few are delayed.
  DelayDraws poisson(delays(LeagueDelays::Events::kPoisson, p, d, d), 200);
  for (int t = 0; t < ticks; ++t) poisson.tick();
  const double poisson_share = static_cast<double>(poisson.delayed_robot_ticks()) / (200.0 * ticks);
  EXPECT_NEAR(poisson_share, d * p, 0.02);
  EXPECT_GT(poisson_share, 0.05);
}

}  // namespace
}  // namespace planner_core
