#include "coordinator/plan_builder.hpp"

#include <map>
#include <memory>

#include "planner_core/dist_table.hpp"

namespace coordinator {

using planner_core::Cell;
using planner_core::Vertex;

PlanInstance build_plan_instance(const planner_core::Instance& mission, const MissionProgress& progress,
                                 const std::vector<PlanMember>& members, std::set<Vertex> blocked) {
  const planner_core::Graph& map = *mission.graph;
  PlanInstance out;
  // Robots that cannot be planned for stay where they are, as walls.
  std::map<Vertex, int> members_on;
  for (const PlanMember& member : members) {
    const Vertex v = map.vertex_at(member.cell);
    if (v != planner_core::kNoVertex) ++members_on[v];
  }
  std::vector<const PlanMember*> planned;
  for (const PlanMember& member : members) {
    const Vertex v = map.vertex_at(member.cell);
    if (v == planner_core::kNoVertex) {
      out.notes.push_back("robot " + member.robot_id + " left out: " + planner_core::to_string(member.cell) +
                          " is off the map or a wall");
    } else if (members_on[v] > 1) {
      out.notes.push_back("robot " + member.robot_id + " left out: another robot reports the same cell " +
                          planner_core::to_string(member.cell));
      blocked.insert(v);
    } else if (blocked.count(v)) {
      out.notes.push_back("robot " + member.robot_id + " left out: its cell " + planner_core::to_string(member.cell) +
                          " is kept clear");
    } else {
      planned.push_back(&member);
    }
  }

  // The planning map is the mission's with the blocked cells walled: the same vertex ids, so the
  // instance's starts, goals and tasks are mission vertices.
  auto graph = std::make_shared<const planner_core::Graph>(map.with_walls(blocked));
  planner_core::DistTable dist(*graph);
  planner_core::Instance& instance = out.instance;
  instance.graph = graph;
  instance.source = "replan";
  instance.actions = mission.actions;
  const auto open = [&](Vertex v) { return graph->is_open(v); };

  std::set<Vertex> goals_taken;
  for (const PlanMember* member : planned) {
    if (member->role >= 0) goals_taken.insert(mission.goals[member->role]);
  }
  std::vector<int> plan_role;
  for (const PlanMember* member : planned) {
    const Vertex start = graph->vertex_at(member->cell);
    Vertex goal = planner_core::kNoVertex;
    if (member->role >= 0) {
      goal = mission.goals[member->role];
      if (!open(goal) || dist.get(goal, start) >= planner_core::kUnreachable) {
        out.notes.push_back("role " + std::to_string(member->role) + ": goal blocked or unreachable for robot " +
                            member->robot_id + "; it holds its cell");
        goal = planner_core::kNoVertex;
      }
    }
    if (goal == planner_core::kNoVertex) {
      // Extra robots (and robots that cannot reach their goal) rest on the nearest cell nobody needs.
      int best = planner_core::kUnreachable;
      for (Vertex v = 0; v < graph->vertex_count(); ++v) {
        const int from_start = dist.get(start, v);
        if (from_start < best && !goals_taken.count(v)) best = from_start, goal = v;
      }
      goals_taken.insert(goal);
    }
    instance.starts.push_back(start);
    instance.goals.push_back(goal);
    if (instance.actions == planner_core::ActionModel::kRotate) {
      if (member->heading < 0 || member->heading > 3) {
        out.notes.push_back("robot " + member->robot_id +
                            " reports no heading; planned as facing east, its moves confirmed by their cells");
      }
      instance.start_headings.push_back(member->heading >= 0 && member->heading <= 3 ? member->heading : 0);
    }
    plan_role.push_back(member->role);
    out.robots.push_back(member->robot_id);
  }
  // The task visits still owed by the roles in the plan.
  for (int t = 0; t < mission.task_count(); ++t) {
    const planner_core::Task& task = mission.tasks[t];
    planner_core::Task remaining;
    remaining.at = task.at;
    for (size_t k = 0; k < task.agents.size(); ++k) {
      if (progress.visited(t, k)) continue;
      for (int a = 0; a < instance.agent_count(); ++a) {
        if (plan_role[a] != task.agents[k]) continue;
        if (!open(task.at) || dist.get(task.at, instance.starts[a]) >= planner_core::kUnreachable) {
          out.notes.push_back("task " + std::to_string(t) + " unreachable for robot " + out.robots[a] +
                              " (blocked by a lost robot): left pending");
          continue;
        }
        remaining.agents.push_back(a);
      }
    }
    if (!remaining.agents.empty()) instance.tasks.push_back(remaining);
  }
  instance.index_tasks();
  return out;
}

}  // namespace coordinator
