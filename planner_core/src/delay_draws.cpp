#include "planner_core/delay_draws.hpp"

#include <algorithm>
#include <cmath>

namespace planner_core {

DelayDraws::DelayDraws(const LeagueDelays& config, int robots)
    : config_(config), rng_(config.seed), left_(static_cast<size_t>(std::max(0, robots)), 0) {}

int DelayDraws::duration() {
  if (config_.min_ticks >= config_.max_ticks) return config_.min_ticks;
  if (config_.durations == LeagueDelays::Durations::kUniform) {
    return std::uniform_int_distribution<int>(config_.min_ticks, config_.max_ticks)(rng_);
  }
  const double span = config_.max_ticks - config_.min_ticks;
  const double mean = config_.min_ticks + span * config_.gauss_mean_share;
  const double spread = span * config_.gauss_spread_share;
  const double drawn = spread > 0 ? std::normal_distribution<double>(mean, spread)(rng_) : mean;
  return std::clamp(static_cast<int>(std::lround(drawn)), config_.min_ticks, config_.max_ticks);
}

std::vector<int> DelayDraws::tick() {
  std::vector<int> free;
  for (size_t robot = 0; robot < left_.size(); ++robot) {
    if (left_[robot] > 0) --left_[robot];
    if (left_[robot] == 0) free.push_back(static_cast<int>(robot));
  }
  std::vector<int> started;
  if (config_.events == LeagueDelays::Events::kBernoulli) {
    std::bernoulli_distribution event(config_.probability);
    for (int robot : free) {
      if (event(rng_)) started.push_back(robot);
    }
  } else if (!free.empty() && config_.probability > 0) {
    const double rate = static_cast<double>(left_.size()) * config_.probability;
    const size_t events = std::min(free.size(), static_cast<size_t>(std::poisson_distribution<int64_t>(rate)(rng_)));
    // The first `events` of a partial shuffle: distinct robots, each free one equally likely.
    for (size_t k = 0; k < events; ++k) {
      std::swap(free[k], free[std::uniform_int_distribution<size_t>(k, free.size() - 1)(rng_)]);
      started.push_back(free[k]);
    }
    std::sort(started.begin(), started.end());
  }
  for (int robot : started) left_[robot] = duration();
  for (int left : left_) delayed_robot_ticks_ += left > 0 ? 1 : 0;
  return started;
}

}  // namespace planner_core
