#include "coordinator/refused_processes.hpp"

namespace coordinator {

bool RefusedProcesses::heard(const std::string& robot_id, uint64_t incarnation, planner_core::Cell cell,
                             planner_core::Vertex vertex, Clock::time_point received) {
  const auto [it, inserted] = processes_.try_emplace({robot_id, incarnation});
  RefusedProcess& process = it->second;
  const bool moved = inserted || process.vertex != vertex;
  process.robot_id = robot_id;
  process.incarnation = incarnation;
  process.cell = cell;
  process.vertex = vertex;
  process.heard = std::max(process.heard, received);
  return moved;
}

std::vector<RefusedProcess> RefusedProcesses::forget_silent(Clock::time_point now, double timeout_s) {
  std::vector<RefusedProcess> gone;
  for (auto it = processes_.begin(); it != processes_.end();) {
    if (std::chrono::duration<double>(now - it->second.heard).count() > timeout_s) {
      gone.push_back(it->second);
      it = processes_.erase(it);
    } else {
      ++it;
    }
  }
  return gone;
}

void RefusedProcesses::forget(const std::string& robot_id, uint64_t incarnation) {
  processes_.erase({robot_id, incarnation});
}

std::vector<RefusedProcess> RefusedProcesses::refusals_due(Clock::time_point now, double every_s) {
  std::vector<RefusedProcess> due;
  for (auto& [key, process] : processes_) {
    if (process.told == Clock::time_point{} || std::chrono::duration<double>(now - process.told).count() >= every_s) {
      process.told = now;
      due.push_back(process);
    }
  }
  return due;
}

std::set<planner_core::Vertex> RefusedProcesses::cells() const {
  std::set<planner_core::Vertex> cells;
  for (const auto& [key, process] : processes_) {
    if (process.vertex != planner_core::kNoVertex) cells.insert(process.vertex);
  }
  return cells;
}

}  // namespace coordinator
