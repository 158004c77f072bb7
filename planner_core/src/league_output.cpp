#include "planner_core/league_output.hpp"

#include <fstream>
#include <nlohmann/json.hpp>

#include "planner_core/action_model.hpp"
#include "planner_core/input_error.hpp"

namespace planner_core {

std::string league_segments(const Graph& graph, Vertex start, int start_heading, const std::string& letters,
                            int ticks_per_action, int segment_ticks) {
  std::string out;
  Vertex cell = start;
  int heading = start_heading;
  int counter = 0;  // ticks into the action under way
  for (size_t from = 0; from < letters.size(); from += static_cast<size_t>(segment_ticks)) {
    const Cell at = graph.cell_of(cell);
    out += "[(" + std::to_string(from) + "," + std::to_string(at.y) + "," + std::to_string(at.x) + "," +
           std::to_string(heading) + "," + std::to_string(counter) + "):(";
    const size_t to = std::min(letters.size(), from + static_cast<size_t>(segment_ticks));
    for (size_t t = from; t < to;) {
      size_t run = t;
      while (run < to && letters[run] == letters[t]) ++run;
      if (t > from) out += ',';
      out += letters[t];
      out += ' ';
      out += std::to_string(run - t);
      // Replays the run so the next segment starts from the right pose.
      for (size_t k = t; k < run && letters[t] != 'W'; ++k) {
        if (++counter < ticks_per_action) continue;
        counter = 0;
        if (letters[t] == 'F') {
          cell = ahead(graph, cell, heading);
        } else {
          heading = letters[t] == 'R' ? turned_clockwise(heading) : turned_counter_clockwise(heading);
        }
      }
      t = run;
    }
    out += ")]";
  }
  return out;
}

void write_league_output(const std::string& path, const LorrProblem& problem, const LeagueRunSettings& settings,
                         const LeagueRunResult& result, const LeagueLog& log, int segment_ticks) {
  const Graph& graph = *problem.graph;
  const int team = static_cast<int>(log.starts.size());
  nlohmann::ordered_json out;
  out["actionModel"] = "MAPF_T";
  out["version"] = "2026 LoRR";
  out["teamSize"] = team;
  out["numTaskFinished"] = result.tasks_finished;
  out["makespan"] = static_cast<int>(result.tasks_per_tick.size());
  out["numPlannerErrors"] = result.invalid_steps + result.faults;
  out["numScheduleErrors"] = 0;
  out["numEntryTimeouts"] = result.late_steps;
  out["agentMaxCounter"] = problem.ticks_per_action;
  out["outputSegmentSize"] = segment_ticks;
  out["delaysOn"] = settings.delays && problem.delays.has_value();
  nlohmann::json delays = nlohmann::json::array();
  for (const auto& of_robot : log.delay_intervals) {
    nlohmann::json intervals = nlohmann::json::array();
    for (const auto& [first, last] : of_robot) intervals.push_back({first, last});
    delays.push_back(intervals);
  }
  out["delayIntervals"] = delays;
  nlohmann::json starts = nlohmann::json::array();
  for (int r = 0; r < team; ++r) {
    const Cell cell = graph.cell_of(log.starts[r]);
    starts.push_back({cell.y, cell.x, std::string(1, heading_letter(log.start_headings[r]))});
  }
  out["start"] = starts;
  nlohmann::json paths = nlohmann::json::array();
  for (int r = 0; r < team; ++r) {
    paths.push_back(league_segments(graph, log.starts[r], log.start_headings[r], log.actual[r],
                                    problem.ticks_per_action, segment_ticks));
  }
  out["actualPaths"] = paths;
  nlohmann::json events = nlohmann::json::array();
  for (const LeagueLog::Event& event : log.events) {
    events.push_back({event.tick, event.robot, event.task, event.errands_done});
  }
  out["events"] = events;
  // [id, the tick it was first handed to a robot, [row, column, row, column...]]: the pool's
  // reveal ticks are not kept.
  std::vector<int> handed_out(static_cast<size_t>(log.tasks_revealed), -1);
  for (const auto& of_robot : log.schedule) {
    for (const auto& [tick, task] : of_robot) {
      if (handed_out[task] < 0 || tick < handed_out[task]) handed_out[task] = tick;
    }
  }
  nlohmann::json tasks = nlohmann::json::array();
  for (int64_t k = 0; k < log.tasks_revealed; ++k) {
    nlohmann::json errands = nlohmann::json::array();
    for (Vertex errand : problem.tasks[static_cast<size_t>(k) % problem.tasks.size()]) {
      const Cell cell = graph.cell_of(errand);
      errands.push_back(cell.y);
      errands.push_back(cell.x);
    }
    tasks.push_back({k, handed_out[k], errands});
  }
  out["tasks"] = tasks;
  nlohmann::json times = nlohmann::json::array();
  for (double ms : result.plan_ms) times.push_back(ms / 1000);
  out["plannerTimes"] = times;
  nlohmann::json errors = nlohmann::json::array();
  for (const LifelongLog::Error& error : log.errors) errors.push_back({error.agent1, error.agent2, error.step, error.what});
  out["errors"] = errors;
  nlohmann::json schedules = nlohmann::json::array();
  for (const auto& of_robot : log.schedule) {
    std::string text;
    for (const auto& [tick, task] : of_robot) {
      if (!text.empty()) text += ',';
      text += std::to_string(tick);
      text += ':';
      text += std::to_string(task);
    }
    schedules.push_back(text);
  }
  out["actualSchedule"] = schedules;
  std::ofstream file(path, std::ios::trunc);
  if (!file) throw InputError(path + ": cannot write the output file");
  file << out.dump() << "\n";
  if (!file.flush()) throw InputError(path + ": writing the output file failed");
}

}  // namespace planner_core
