// RobotBackend: what the agent drives, a simulated robot or a real one (toio over BLE). The agent
// asks it to move one cell; the backend reports where the robot stands.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "fleet_transport/messages.hpp"
#include "planner_core/cell.hpp"

namespace robot_agent {

// Wall-clock milliseconds since the epoch on this host's clock (with a test's skew): the time
// stamp of arrivals. Hosts' clocks may disagree; readers put stamps on their own clock.
using fleet_transport::wall_clock_ms;

using planner_core::Cell;  // the project's one cell type

struct BackendReport {
  Cell cell;          // the last cell the robot arrived at
  double pose_x = 0;      // continuous position in cell units
  double pose_y = 0;
  double pose_theta = 0;  // radians, clockwise from the grid's +x axis
  int heading = -1;       // pose_theta to the nearest quarter turn (planner_core/compass.hpp); -1 unknown
  bool moving = false;
  bool fault = false;
  int battery_percent = -1;
  int64_t arrived_ms = 0;  // wall clock of the arrival at `cell`
};

class RobotBackend {
 public:
  virtual ~RobotBackend() = default;
  virtual std::string kind() const = 0;
  // Starts a move to a neighbouring cell (or a wait on the current one) that ends facing
  // `target_heading` (0-3, planner_core/compass.hpp; -1: any). A step to a neighbour ends facing
  // the way it went; on the robot's own cell with a new heading it is a turn in place. False if busy.
  virtual bool start_move(Cell target, int target_heading) = 0;
  // Advances the backend to the present and reports.
  virtual BackendReport poll() = 0;
  // While moving: the expected time until arrival (so the agent knows when to look again).
  virtual std::optional<std::chrono::steady_clock::duration> time_to_arrival() const = 0;
  // Whether start_move and poll return at once (no I/O that may block): the agent may then start
  // a command on the thread that received it, one thread wake-up sooner.
  virtual bool starts_moves_at_once() const { return false; }
};

}  // namespace robot_agent
