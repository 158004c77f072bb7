// What the parts of FleetCoordinator's implementation share (not part of its interface): time
// arithmetic, the waits it allows, and how it writes ids (its publishing periods: PublishSchedule).
#pragma once

#include <spdlog/fmt/fmt.h>

#include <chrono>
#include <cstdint>
#include <random>
#include <string>

#include "coordinator/fleet_coordinator.hpp"

namespace coordinator::fleet_coordinator_detail {

inline double seconds_between(FleetCoordinator::Clock::time_point a, FleetCoordinator::Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

inline FleetCoordinator::Clock::duration seconds(double s) {
  return std::chrono::duration_cast<FleetCoordinator::Clock::duration>(std::chrono::duration<double>(s));
}

// A random 64-bit number, never 0.
inline uint64_t new_incarnation() {
  std::random_device device;
  uint64_t value = 0;
  while (value == 0) value = (static_cast<uint64_t>(device()) << 32) ^ device();
  return value;
}

inline std::string hex(uint64_t value) { return fmt::format("{:016x}", value); }

constexpr double kStoodStillS = 1.0;  // a step this long after the last one heard nobody
// How long a step waits for a plan it just started before it lets the loop go on (see step()).
constexpr std::chrono::milliseconds kQuickPlanWait{50};
// Robots judge a command's deadline on their own clock through an offset they estimate from send
// stamps; this much is allowed for that estimate's error.
constexpr double kClockMarginS = 1.0;

}  // namespace coordinator::fleet_coordinator_detail
