#include "fleet_trace.hpp"

#include <algorithm>
#include <limits>
#include <set>

#include "planner_core/action_model.hpp"

namespace coordinator {

using planner_core::Vertex;

void FleetTrace::heard_state(const fleet_transport::RobotState& state) {
  if (state.status == fleet_transport::RobotStatus::kMoving) return;  // mid-turn its heading is halfway
  std::vector<Pose>& poses = poses_[state.robot_id];
  const Pose pose{state.stamp_ms, state.cell_x, state.cell_y, state.heading};
  if (!poses.empty() && poses.back().x == pose.x && poses.back().y == pose.y && poses.back().heading == pose.heading) {
    return;
  }
  poses.push_back(pose);
}

void FleetTrace::heard_event(const fleet_transport::FleetEvent& event) {
  if (event.kind != "task_added" && event.kind != "task_reassigned" && event.kind != "task_done") return;
  // The task id comes as a double off the wire: one that is no task id (NaN, past int) is dropped.
  if (!(event.value >= 0 && event.value <= std::numeric_limits<int>::max())) return;
  task_events_.push_back({event.stamp_ms, event.kind, event.robot_id, static_cast<int>(event.value)});
}

namespace {

// The robot number in "robot<r>", or -1.
int robot_number(const std::string& robot_id, int robots) {
  if (!robot_id.starts_with("robot") || robot_id.size() == 5) return -1;
  int r = 0;
  for (size_t k = 5; k < robot_id.size(); ++k) {
    if (robot_id[k] < '0' || robot_id[k] > '9' || r > robots) return -1;
    r = r * 10 + (robot_id[k] - '0');
  }
  return r < robots ? r : -1;
}

// One robot's actions as letters per tick: each pose change is the turns and the step forward that
// explain it, put on the ticks ending at its arrival's tick (or later, when those are taken).
struct Letters {
  std::string letters;
  std::vector<std::pair<int64_t, int>> arrivals;  // a pose's stamp -> the tick its last action ends on
  int shifted = 0;
  int jumps = 0;
  int first_jump_tick = -1;
};

Letters letters_of(const std::vector<FleetTrace::Pose>& poses, const planner_core::Graph& graph, Vertex start,
                   int start_heading, int64_t start_ms, int64_t end_ms, int tick_ms, int ticks_per_action) {
  Letters out;
  Vertex at = start;
  int heading = start_heading;
  const auto put = [&](char letter, int64_t tick) {
    const int64_t first = std::max<int64_t>(static_cast<int64_t>(out.letters.size()), tick - ticks_per_action + 1);
    if (first > tick - ticks_per_action + 1) ++out.shifted;
    out.letters.resize(static_cast<size_t>(first), 'W');
    out.letters.append(static_cast<size_t>(ticks_per_action), letter);
  };
  for (const FleetTrace::Pose& pose : poses) {
    if (pose.stamp_ms < start_ms || pose.stamp_ms >= end_ms) continue;
    const int64_t tick = (pose.stamp_ms - start_ms) / tick_ms;
    const Vertex to = graph.vertex_at({pose.x, pose.y});
    const int travel = to == at || to == planner_core::kNoVertex ? -1 : planner_core::heading_towards(graph, at, to);
    const bool neighbour = travel >= 0;
    if (to != at && !neighbour) {
      ++out.jumps;
      if (out.first_jump_tick < 0) out.first_jump_tick = static_cast<int>(tick);
      at = to;
      if (pose.heading >= 0) heading = pose.heading;
      continue;
    }
    // Turns (the shorter way) to the way it travels, or to the heading it reports at rest.
    const int facing = neighbour ? travel : pose.heading >= 0 ? pose.heading : heading;
    std::vector<char> actions;
    for (int h = heading; h != facing;) {
      const bool counter_clockwise = planner_core::turned_counter_clockwise(h) == facing;  // else clockwise (once or twice)
      actions.push_back(counter_clockwise ? 'C' : 'R');
      h = counter_clockwise ? planner_core::turned_counter_clockwise(h) : planner_core::turned_clockwise(h);
    }
    if (neighbour) actions.push_back('F');
    // The last action ends on the arrival's tick, those before it on the ticks before.
    const int64_t count = static_cast<int64_t>(actions.size());
    for (int64_t k = 0; k < count; ++k) put(actions[static_cast<size_t>(k)], tick - (count - 1 - k) * ticks_per_action);
    if (count > 0) out.arrivals.emplace_back(pose.stamp_ms, static_cast<int>(out.letters.size()) - 1);
    heading = facing;
    at = to;
  }
  return out;
}

}  // namespace

FleetLeagueRun league_log_of_fleet(const FleetTrace& trace, const planner_core::LorrProblem& problem, int robots,
                                   int64_t start_ms, int64_t end_ms, int tick_ms,
                                   const std::map<int, int64_t>& problem_task_of) {
  const planner_core::Graph& graph = *problem.graph;
  const int ticks = static_cast<int>(std::max<int64_t>(0, end_ms - start_ms) / tick_ms);
  FleetLeagueRun run;
  planner_core::LeagueLog& log = run.log;
  log.starts.assign(problem.starts.begin(), problem.starts.begin() + robots);
  log.start_headings.assign(static_cast<size_t>(robots), 0);
  log.delay_intervals.resize(static_cast<size_t>(robots));
  log.schedule.resize(static_cast<size_t>(robots));
  int longest = ticks;
  std::vector<Letters> of_robot(static_cast<size_t>(robots));
  for (const auto& [robot_id, poses] : trace.poses()) {
    const int r = robot_number(robot_id, robots);
    if (r < 0) continue;
    // Where it stands at the start, and facing which way: the last it reported at rest before.
    for (const FleetTrace::Pose& pose : poses) {
      if (pose.stamp_ms >= start_ms) break;
      if (pose.heading >= 0) log.start_headings[static_cast<size_t>(r)] = pose.heading;
      if (const Vertex at = graph.vertex_at({pose.x, pose.y}); at != planner_core::kNoVertex) {
        log.starts[static_cast<size_t>(r)] = at;
      }
    }
    Letters letters = letters_of(poses, graph, log.starts[static_cast<size_t>(r)],
                                 log.start_headings[static_cast<size_t>(r)], start_ms, end_ms, tick_ms,
                                 problem.ticks_per_action);
    run.shifted += letters.shifted;
    run.jumps += letters.jumps;
    if (letters.jumps > 0) {
      log.errors.push_back({r, -1, letters.first_jump_tick, "a robot's pose changed with no action that explains it"});
    }
    longest = std::max(longest, static_cast<int>(letters.letters.size()));
    of_robot[static_cast<size_t>(r)] = std::move(letters);
  }
  // A task is done at the tick after its robot's arrival there ends (as the league counts an
  // errand: on the tick the robot stands on it), found from the robot's last arrival before the
  // coordinator's event; a robot that never moved stood there from the start.
  const auto done_tick = [&](int r, const FleetTrace::TaskEvent& event) {
    const std::vector<std::pair<int64_t, int>>& arrivals = of_robot[static_cast<size_t>(r)].arrivals;
    const auto after = std::upper_bound(arrivals.begin(), arrivals.end(), std::pair{event.stamp_ms, INT32_MAX});
    return after == arrivals.begin() ? 0 : std::prev(after)->second + 1;
  };
  // Tasks: who holds what (a robot's first task is the one it was given earliest), and when each was done.
  std::vector<std::vector<int64_t>> held(static_cast<size_t>(robots));  // problem task numbers, in order given
  std::map<int64_t, int> holder;
  for (const auto& [task, k] : problem_task_of) log.tasks_revealed = std::max(log.tasks_revealed, k + 1);
  std::vector<FleetTrace::TaskEvent> events = trace.task_events();
  std::stable_sort(events.begin(), events.end(), [](const auto& a, const auto& b) { return a.stamp_ms < b.stamp_ms; });
  for (const FleetTrace::TaskEvent& event : events) {
    const auto number = problem_task_of.find(event.task);
    const int r = robot_number(event.robot_id, robots);
    if (number == problem_task_of.end() || r < 0 || event.stamp_ms >= end_ms) continue;
    const int64_t k = number->second;
    const int tick = static_cast<int>(std::max<int64_t>(0, event.stamp_ms - start_ms) / tick_ms);
    std::set<int> changed;
    if (const auto before = holder.find(k); before != holder.end()) {
      std::erase(held[static_cast<size_t>(before->second)], k);
      changed.insert(before->second);
      holder.erase(before);
    }
    if (event.kind == "task_done") {
      if (event.stamp_ms >= start_ms) {
        const int at = done_tick(r, event);
        log.events.push_back({at, r, k, 1});
        longest = std::max(longest, at);
      }
    } else {
      held[static_cast<size_t>(r)].push_back(k);
      holder[k] = r;
      changed.insert(r);
    }
    for (const int c : changed) {
      std::vector<std::pair<int, int64_t>>& schedule = log.schedule[static_cast<size_t>(c)];
      const std::vector<int64_t>& tasks = held[static_cast<size_t>(c)];
      if (!tasks.empty() && (schedule.empty() || schedule.back().second != tasks.front())) {
        schedule.emplace_back(tick, tasks.front());
      }
    }
  }
  for (Letters& letters : of_robot) {
    letters.letters.resize(static_cast<size_t>(longest), 'W');
    log.actual.push_back(std::move(letters.letters));
  }
  // The output's makespan is the actions' length; an event may fall on the tick just after.
  run.result.tasks_per_tick.assign(static_cast<size_t>(longest), 0);
  for (const planner_core::LeagueLog::Event& event : log.events) {
    ++run.result.tasks_finished;
    ++run.result.errands_finished;
    if (longest > 0) ++run.result.tasks_per_tick[static_cast<size_t>(std::min(event.tick, longest - 1))];
  }
  run.result.robot_ticks = static_cast<int64_t>(robots) * longest;
  for (const std::string& letters : log.actual) {
    run.result.moves_finished += static_cast<int64_t>(std::count_if(letters.begin(), letters.end(), [](char c) {
      return c != 'W';
    })) / problem.ticks_per_action;
  }
  return run;
}

}  // namespace coordinator
