// The plan builder: from the fleet as it stands (which robots, where, in which role), the mission's
// progress and the cells to keep clear, the planner instance to solve next. A pure function: no
// DDS, no clock, no logging (what could not be planned as asked comes back as notes).
#pragma once

#include <set>
#include <string>
#include <vector>

#include "coordinator/mission_progress.hpp"
#include "planner_core/instance.hpp"

namespace coordinator {

// A robot to plan for: where it stands and its role (-1: an extra robot, which parks).
struct PlanMember {
  std::string robot_id;
  planner_core::Cell cell;
  int role = -1;
  int heading = -1;  // the way it faces (0 east ... 3 north), -1 unknown: matters in plans with turns
  bool operator==(const PlanMember&) const = default;
};

struct PlanInstance {
  planner_core::Instance instance;  // on the mission map with `blocked` cells walled, in its vertex ids
  std::vector<std::string> robots;  // plan agent -> robot id
  std::vector<std::string> notes;   // robots left out, goals or tasks that cannot be reached
};

// Each member becomes a plan agent from its cell: to its role's goal through the role's task
// visits not yet done; an extra robot (or one whose goal is walled off) goes to the nearest free
// cell no other agent needs. Members off the map, on a blocked cell or sharing a cell with another
// member are left out, and their cells walled, so the instance is always well-formed. In the
// rotation model (mission.actions) agents start facing their members' headings (east if unknown).
PlanInstance build_plan_instance(const planner_core::Instance& mission, const MissionProgress& progress,
                                 const std::vector<PlanMember>& members, std::set<planner_core::Vertex> blocked);

}  // namespace coordinator
