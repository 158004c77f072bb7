#include "planner_core/validator.hpp"

#include <algorithm>
#include <sstream>
#include <vector>

namespace planner_core {

std::string to_string(Violation::Kind kind) {
  switch (kind) {
    case Violation::Kind::kEmpty: return "empty";
    case Violation::Kind::kAgentCount: return "agent-count";
    case Violation::Kind::kWrongStart: return "wrong-start";
    case Violation::Kind::kBlockedCell: return "blocked-cell";
    case Violation::Kind::kJump: return "jump";
    case Violation::Kind::kVertexConflict: return "vertex-conflict";
    case Violation::Kind::kSwapConflict: return "swap-conflict";
    case Violation::Kind::kNotOnGoal: return "not-on-goal";
    case Violation::Kind::kTaskMissed: return "task-missed";
    case Violation::Kind::kRotation: return "rotation";
    case Violation::Kind::kHeading: return "heading";
    case Violation::Kind::kAction: return "action";
  }
  return "unknown";
}

bool ValidationReport::has(Violation::Kind kind) const {
  return std::any_of(violations.begin(), violations.end(), [&](const Violation& v) { return v.kind == kind; });
}

std::string ValidationReport::summary(size_t max_lines) const {
  std::ostringstream out;
  for (size_t i = 0; i < violations.size() && i < max_lines; ++i) {
    out << to_string(violations[i].kind) << ": " << violations[i].message << "\n";
  }
  if (violations.size() > max_lines) out << "... and " << violations.size() - max_lines << " more\n";
  return out.str();
}

namespace {

// The rotation model's rules: every heading given and in range, the start headings at t = 0, and
// each step forward along the heading (heading kept), a quarter turn in place, or a wait.
// `on_map` and `cell` as in validate(); moves between cells that are not neighbours are reported there.
template <typename OnMap, typename CellText>
void check_actions(const Instance& instance, const Solution& solution, const HeadingPlan& headings,
                   const OnMap& on_map, const CellText& cell, std::vector<Violation>& out) {
  using Kind = Violation::Kind;
  const Graph& graph = *instance.graph;
  const int n = instance.agent_count();
  const auto at = [](int t) { return "t=" + std::to_string(t) + ": agent "; };
  if (headings.size() != solution.size()) {
    out.push_back({Kind::kHeading, -1, -1, -1,
                   "a plan in the rotation model needs headings at every timestep: " +
                       std::to_string(headings.size()) + " for " + std::to_string(solution.size()) + " timesteps"});
    return;
  }
  for (size_t t = 0; t < headings.size(); ++t) {
    const int time = static_cast<int>(t);
    if (static_cast<int>(headings[t].size()) != n) {
      out.push_back({Kind::kHeading, time, -1, -1,
                     "t=" + std::to_string(t) + ": " + std::to_string(headings[t].size()) + " headings for " +
                         std::to_string(n) + " agents"});
      return;
    }
    for (int a = 0; a < n; ++a) {
      if (headings[t][a] < 0 || headings[t][a] >= kHeadings) {
        out.push_back({Kind::kHeading, time, a, -1, at(time) + std::to_string(a) + " has no heading"});
        return;
      }
    }
  }
  for (int a = 0; a < n; ++a) {
    if (headings[0][a] != instance.start_heading(a)) {
      out.push_back({Kind::kHeading, 0, a, -1,
                     "agent " + std::to_string(a) + " starts facing " + heading_letter(headings[0][a]) + ", not " +
                         heading_letter(instance.start_heading(a))});
    }
  }
  for (size_t t = 1; t < solution.size(); ++t) {
    const int time = static_cast<int>(t);
    for (int a = 0; a < n; ++a) {
      const Vertex from = solution[t - 1][a];
      const Vertex to = solution[t][a];
      const int facing = headings[t - 1][a];
      const int next_facing = headings[t][a];
      if (!on_map(from) || !on_map(to)) continue;
      if (from == to) {
        if (turns_between(facing, next_facing) > 1) {
          out.push_back({Kind::kAction, time, a, -1,
                         at(time) + std::to_string(a) + " turns half round at " + cell(to) + " in one step"});
        }
      } else if (!graph.adjacent(from, to)) {
        continue;  // a jump, reported by validate()
      } else if (to != ahead(graph, from, facing)) {
        out.push_back({Kind::kAction, time, a, -1,
                       at(time) + std::to_string(a) + " moves " + cell(from) + " -> " + cell(to) + " facing " +
                           heading_letter(facing) + ": only the cell ahead can be entered"});
      } else if (next_facing != facing) {
        out.push_back({Kind::kAction, time, a, -1,
                       at(time) + std::to_string(a) + " moves and turns in one step at " + cell(to)});
      }
    }
  }
}

}  // namespace

ValidationReport validate(const Instance& instance, const Solution& solution, const ValidationOptions& options,
                          const HeadingPlan& headings) {
  using Kind = Violation::Kind;
  ValidationReport report;
  auto& out = report.violations;
  const Graph& graph = *instance.graph;
  const int n = instance.agent_count();
  const int vertex_count = graph.vertex_count();
  // In range and not walled; looked up once per vertex (a plan has agents x steps positions).
  std::vector<char> open(vertex_count);
  for (Vertex v = 0; v < vertex_count; ++v) open[v] = graph.is_open(v) ? 1 : 0;
  const auto on_map = [&](Vertex v) { return v >= 0 && v < vertex_count && open[v]; };
  const auto cell = [&](Vertex v) {
    return v >= 0 && v < vertex_count ? to_string(graph.cell_of(v)) : std::string("(off map)");
  };
  const auto agent_name = [](int a) { return "agent " + std::to_string(a); };

  if (solution.empty()) {
    out.push_back({Kind::kEmpty, -1, -1, -1, "the solution has no timesteps"});
    return report;
  }
  for (size_t t = 0; t < solution.size(); ++t) {
    if (static_cast<int>(solution[t].size()) != n) {
      out.push_back({Kind::kAgentCount, static_cast<int>(t), -1, -1,
                     "t=" + std::to_string(t) + ": " + std::to_string(solution[t].size()) + " positions for " +
                         std::to_string(n) + " agents"});
      return report;  // nothing else can be checked agent by agent
    }
  }
  for (int a = 0; a < n; ++a) {
    if (solution[0][a] != instance.starts[a]) {
      out.push_back({Kind::kWrongStart, 0, a, -1,
                     agent_name(a) + " starts at " + cell(solution[0][a]) + ", not " + cell(instance.starts[a])});
    }
  }
  // Who stands where, by vertex, at this timestep and the one before (the first agent found there
  // when several are); reset after each step only where it was written.
  constexpr int kNobody = -1;
  std::vector<int> agent_at(vertex_count, kNobody), agent_before(vertex_count, kNobody);
  for (size_t step = 0; step < solution.size(); ++step) {
    const int t = static_cast<int>(step);
    const Config& now = solution[step];
    for (int a = 0; a < n; ++a) {
      if (!on_map(now[a])) {
        out.push_back({Kind::kBlockedCell, t, a, -1, "t=" + std::to_string(t) + ": " + agent_name(a) +
                                                         " is outside the map or on a blocked cell"});
        continue;
      }
      int& occupant = agent_at[now[a]];
      if (occupant == kNobody) {
        occupant = a;
      } else {
        out.push_back({Kind::kVertexConflict, t, occupant, a,
                       "t=" + std::to_string(t) + ": agents " + std::to_string(occupant) + " and " +
                           std::to_string(a) + " both at " + cell(now[a])});
      }
    }
    if (step == 0) {
      std::swap(agent_before, agent_at);
      continue;
    }
    const Config& before = solution[step - 1];
    for (int a = 0; a < n; ++a) {
      if (!on_map(before[a]) || !on_map(now[a])) continue;
      if (before[a] != now[a] && !graph.adjacent(before[a], now[a])) {
        out.push_back({Kind::kJump, t, a, -1,
                       "t=" + std::to_string(t) + ": " + agent_name(a) + " jumps " + cell(before[a]) + " -> " +
                           cell(now[a])});
      }
      const int other = agent_before[now[a]];
      if (other != kNobody && other != a && a < other && now[other] == before[a]) {
        out.push_back({Kind::kSwapConflict, t, a, other,
                       "t=" + std::to_string(t) + ": agents " + std::to_string(a) + " and " + std::to_string(other) +
                           " swap " + cell(before[a]) + " <-> " + cell(now[a])});
      }
    }
    if (options.forbid_rotations) {
      // Follow each moving agent into the cell it enters; coming back to the start is a cycle.
      std::vector<int> cycle;
      for (int a = 0; a < n; ++a) {
        int agent = a;
        cycle.assign(1, a);
        for (int hops = 0; hops <= n; ++hops) {
          if (before[agent] == now[agent] || !on_map(now[agent])) break;
          const int next = agent_before[now[agent]];
          if (next == kNobody) break;
          if (next == a && hops >= 2 && a == *std::min_element(cycle.begin(), cycle.end())) {
            out.push_back({Kind::kRotation, t, a, agent,
                           "t=" + std::to_string(t) + ": agents " + std::to_string(a) + " ... " +
                               std::to_string(agent) + " move in a cycle"});
            break;
          }
          if (next == a) break;  // a swap (reported above), or a cycle reported by its smallest agent
          agent = next;
          cycle.push_back(agent);
        }
      }
    }
    for (Vertex v : before) {
      if (on_map(v)) agent_before[v] = kNobody;
    }
    std::swap(agent_before, agent_at);
  }
  if (instance.actions == ActionModel::kRotate) check_actions(instance, solution, headings, on_map, cell, out);
  report.flowtime = flowtime(solution, instance.goals);
  report.makespan = makespan(solution, instance.goals);
  if (options.first_stretch) return report;  // the plan goes on: goals and tasks come later
  const Config& last = solution.back();
  for (int a = 0; a < n; ++a) {
    if (last[a] != instance.goals[a]) {
      out.push_back({Kind::kNotOnGoal, static_cast<int>(solution.size()) - 1, a, -1,
                     agent_name(a) + " ends at " + cell(last[a]) + ", goal " + cell(instance.goals[a])});
    }
  }
  const std::vector<int> arrival = arrival_times(solution, instance.goals);
  for (int k = 0; k < instance.task_count(); ++k) {
    const Task& task = instance.tasks[k];
    for (int a : task.agents) {
      bool visited = false;
      for (int t = 0; t <= arrival[a] && !visited; ++t) visited = solution[t][a] == task.at;
      if (!visited) {
        out.push_back({Kind::kTaskMissed, arrival[a], a, k,
                       "task " + std::to_string(k) + " at " + cell(task.at) + " not visited by " + agent_name(a) +
                           " before it settles on its goal at t=" + std::to_string(arrival[a])});
      }
    }
  }
  return report;
}

}  // namespace planner_core
