// RefusedProcesses: processes refused because another process drives their robot id (an impostor,
// or a robot started twice). Each is an obstacle at the cell it is heard at, for as long as it is
// heard, and is told now and then that it is refused (it then stands still and says so).
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "planner_core/graph.hpp"

namespace coordinator {

struct RefusedProcess {
  using Clock = std::chrono::steady_clock;
  std::string robot_id;
  uint64_t incarnation = 0;
  planner_core::Cell cell;           // where it was last heard
  planner_core::Vertex vertex = planner_core::kNoVertex;  // that cell on the mission map (kNoVertex: off it)
  Clock::time_point heard;           // when its last state arrived
  Clock::time_point told{};          // when it was last sent its refusal (never: the epoch)
};

class RefusedProcesses {
 public:
  using Clock = RefusedProcess::Clock;

  // A state of a refused process arrived at `received`; true when it is new or stands on another
  // cell than before (the cells to keep clear changed).
  bool heard(const std::string& robot_id, uint64_t incarnation, planner_core::Cell cell, planner_core::Vertex vertex,
             Clock::time_point received);
  // Forgets the processes not heard for `timeout_s` (gone: their cells are free) and returns them.
  std::vector<RefusedProcess> forget_silent(Clock::time_point now, double timeout_s);
  // The process became the one that drives its id (the other one is gone).
  void forget(const std::string& robot_id, uint64_t incarnation);
  // The processes to tell (again) that they are refused: not told for `every_s`; marked told at `now`.
  std::vector<RefusedProcess> refusals_due(Clock::time_point now, double every_s);
  // The mission-map cells they stand on.
  std::set<planner_core::Vertex> cells() const;
  size_t size() const { return processes_.size(); }

 private:
  std::map<std::pair<std::string, uint64_t>, RefusedProcess> processes_;
};

}  // namespace coordinator
