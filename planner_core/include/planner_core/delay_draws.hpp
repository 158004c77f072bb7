// The league's 2026 delay model (delayConfig, lorr_problem.hpp: LeagueDelays) drawn tick by tick:
// which robots are delayed, and for how many ticks. A robot delayed stands still, whatever its plan
// says, until its delay has run out. Each tick, among the robots not delayed: with "bernoulli" each
// is delayed with probability p; with "poisson" a Poisson number of events of rate teamSize x p
// falls on as many of them, drawn at random (no more than there are). A delay lasts a number of
// ticks in [min_ticks, max_ticks]: uniform, or normal around min + share x span with a spread of
// share x span, rounded and clamped. The draws follow the seed alone, so a run repeats; they are
// this project's own (std::mt19937), not the league's sequence.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "planner_core/lorr_problem.hpp"

namespace planner_core {

class DelayDraws {
 public:
  DelayDraws(const LeagueDelays& config, int robots);

  // Advances one tick: the delays under way lose a tick, then new ones are drawn among the robots
  // not delayed. Returns the robots that start a delay at this tick.
  std::vector<int> tick();

  bool delayed(int robot) const { return left_[robot] > 0; }
  int ticks_left(int robot) const { return left_[robot]; }
  // Robot-ticks spent delayed so far (the share f of the league's rule: f = this / (robots x ticks)).
  int64_t delayed_robot_ticks() const { return delayed_robot_ticks_; }

 private:
  int duration();

  LeagueDelays config_;
  std::mt19937 rng_;
  std::vector<int> left_;  // per robot, ticks of delay left (0: free)
  int64_t delayed_robot_ticks_ = 0;
};

}  // namespace planner_core
