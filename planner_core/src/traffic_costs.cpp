#include "planner_core/traffic_costs.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace planner_core {

namespace {

const TrafficSettings& checked(const TrafficSettings& settings) {
  if (!(settings.threshold >= 0 && settings.threshold < 1)) {
    throw std::invalid_argument("TrafficCosts: the threshold must be within 0..1, not " + std::to_string(settings.threshold));
  }
  if (!(settings.slope_moves >= 0) || settings.max_moves < 0) {
    throw std::invalid_argument("TrafficCosts: the slope and the largest cost must not be negative");
  }
  if (settings.horizon_steps < 1 || settings.period_steps < 1) {
    throw std::invalid_argument("TrafficCosts: the horizon and the period must be at least one step");
  }
  return settings;
}

}  // namespace

TrafficCosts::TrafficCosts(size_t cells, const TrafficSettings& settings, int cost_unit)
    : settings_(checked(settings)), cost_unit_(cost_unit), occupancy_(cells, 0.0), costs_(cells, 0) {}

bool TrafficCosts::observe(const Config& cells) {
  const double weight = 1.0 / settings_.horizon_steps;
  for (double& share : occupancy_) share *= 1.0 - weight;
  for (Vertex v : cells) occupancy_[v] += weight;
  if (++steps_ % settings_.period_steps != 0) return false;
  const int most = settings_.max_moves * cost_unit_;
  for (size_t v = 0; v < costs_.size(); ++v) {
    const double above = std::max(0.0, occupancy_[v] - settings_.threshold);
    costs_[v] = std::min(most, static_cast<int>(std::lround(settings_.slope_moves * cost_unit_ * above)));
  }
  return true;
}

}  // namespace planner_core
