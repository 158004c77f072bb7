// FleetCoordinator's roles: robots bound to the mission's roles (and unbound), the visits they
// make, each written to the journal before it counts.
#include "coordinator/fleet_coordinator.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <tuple>
#include <utility>

#include "coordinator/plan_builder.hpp"
#include "coordinator/role_assignment.hpp"
#include "fleet_transport/lease_timeouts.hpp"
#include "planner_core/dist_table.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/solver.hpp"
#include "planner_core/validator.hpp"
#include "fleet_coordinator_detail.hpp"

namespace coordinator {

using fleet_transport::RobotStatus;
using planner_core::Cell;
using planner_core::Vertex;
using namespace fleet_coordinator_detail;

void FleetCoordinator::bind_role(int role, RobotRecord& robot) {
  robot.role = role;
  progress_.bind(role, robot.id);
  schedule_.progress_changed();
  if (identity_.role == fleet_transport::CoordinatorRole::kActive) {
    journal_write("role binding", [&](MissionJournal& journal) { journal.record_binding(role, robot.id); });
  }
}

bool FleetCoordinator::journal_write(const char* what, const std::function<void(MissionJournal&)>& write) {
  if (options_.journal == nullptr || summary_.journal_failed) return options_.journal == nullptr;
  try {
    write(*options_.journal);
    return true;
  } catch (const JournalError& e) {
    // A full disk, a file gone: the mission goes on from memory; only a restart could not resume it.
    summary_.journal_failed = true;
    const std::string why = fmt::format("the journal could not record a {} ({}): the mission goes on from memory and is "
                                        "no longer recorded; a restart of this coordinator would start it over (a "
                                        "standby keeps following it)", what, e.what());
    spdlog::critical("{}", why);
    report("journal_failed", "", why);
    return false;
  }
}

void FleetCoordinator::unbind_role(int role) {
  progress_.unbind(role);
  schedule_.progress_changed();
  if (identity_.role == fleet_transport::CoordinatorRole::kActive) {
    journal_write("role binding", [&](MissionJournal& journal) { journal.record_binding(role, ""); });
  }
}

std::vector<RobotRecord*> FleetCoordinator::bind_resumed_and_on_start(const std::vector<RobotRecord*>& robots) {
  std::vector<RobotRecord*> candidates;
  // A resumed mission gives each robot back the role the journal has for it.
  for (RobotRecord* robot : robots) {
    int kept = -1;
    for (const auto& [role, id] : resumed_bindings_) {
      if (id == robot->id && role < mission_.agent_count() && progress_.robot_of(role).empty()) kept = role;
    }
    if (kept >= 0) {
      bind_role(kept, *robot);
      spdlog::info("robot {} keeps role {} (from the journal)", robot->id, kept);
    } else {
      candidates.push_back(robot);
    }
  }
  resumed_bindings_.clear();
  std::vector<RobotRecord*> unbound;
  for (RobotRecord* robot : candidates) {
    const Vertex cell = mission_vertex(robot->last.cell_x, robot->last.cell_y);
    int taken = -1;
    for (int role = 0; role < mission_.agent_count() && taken < 0; ++role) {
      if (progress_.robot_of(role).empty() && mission_.starts[role] == cell) taken = role;
    }
    if (taken >= 0) {
      bind_role(taken, *robot);
      spdlog::info("robot {} takes role {} (it stands on the role's start)", robot->id, taken);
    } else {
      unbound.push_back(robot);
    }
  }
  return unbound;
}

// The robots left are bound to the free roles by a minimum-cost assignment (steps from each
// robot's cell to each role's start).
void FleetCoordinator::bind_roles(const std::vector<RobotRecord*>& robots) {
  const std::vector<RobotRecord*> unbound = bind_resumed_and_on_start(robots);
  std::vector<int> free_roles;
  for (int role = 0; role < mission_.agent_count(); ++role) {
    if (progress_.robot_of(role).empty()) free_roles.push_back(role);
  }
  if (unbound.empty() || free_roles.empty()) {
    for (RobotRecord* robot : unbound) spdlog::info("robot {} has no role: it stays as an extra robot", robot->id);
    return;
  }
  planner_core::DistTable dist(*mission_.graph);
  std::vector<std::vector<int64_t>> cost(unbound.size(), std::vector<int64_t>(free_roles.size()));
  for (size_t r = 0; r < unbound.size(); ++r) {
    const Vertex cell = mission_vertex(unbound[r]->last.cell_x, unbound[r]->last.cell_y);
    for (size_t k = 0; k < free_roles.size(); ++k) cost[r][k] = dist.get(mission_.starts[free_roles[k]], cell);
  }
  const std::vector<int> assignment = min_cost_assignment(cost);
  for (size_t r = 0; r < unbound.size(); ++r) {
    if (assignment[r] < 0) {
      spdlog::info("robot {} has no role: it stays as an extra robot", unbound[r]->id);
      continue;
    }
    const int role = free_roles[assignment[r]];
    bind_role(role, *unbound[r]);
    spdlog::info("robot {} takes role {} ({} steps from its start)", unbound[r]->id, role, cost[r][assignment[r]]);
  }
}

// Task visits count once committed to the journal: a restart never redoes a visit it counted.
void FleetCoordinator::credit_visits(int role, Vertex cell, const std::string& robot_id) {
  for (const fleet_transport::TaskVisit& visit : progress_.visits_due_at(role, cell)) {
    // Committed to the journal before it counts; a journal that failed no longer stops it counting.
    journal_write("task visit", [&](MissionJournal& journal) { journal.record_visit(visit, robot_id, epoch_); });
    progress_.mark(visit);
    schedule_.progress_changed();
    if (progress_.task_done(visit.task)) {
      report("task_done", robot_id, fmt::format("task {} done", visit.task), visit.task);
    }
  }
}

}  // namespace coordinator
