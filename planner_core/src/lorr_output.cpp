#include "planner_core/lorr_output.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>

#include "planner_core/input_error.hpp"

namespace planner_core {

namespace {

// [row, column]: the league counts rows from the top, as the map file lists them.
nlohmann::json row_and_column(const Graph& graph, Vertex v) {
  const Cell cell = graph.cell_of(v);
  return nlohmann::json::array({cell.y, cell.x});
}

}  // namespace

void write_lorr_output(const std::string& path, const LorrProblem& problem, const LifelongResult& result,
                       const LifelongLog& log) {
  const Graph& graph = *problem.graph;
  nlohmann::ordered_json out;
  const bool rotate = log.actions == ActionModel::kRotate;
  out["actionModel"] = rotate ? "MAPF_T" : "MAPF";
  out["AllValid"] = result.invalid_steps == 0 ? "Yes" : "No";
  out["teamSize"] = log.starts.size();
  nlohmann::json starts = nlohmann::json::array();
  for (size_t a = 0; a < log.starts.size(); ++a) {
    nlohmann::json start = row_and_column(graph, log.starts[a]);
    start.push_back(rotate ? std::string(1, heading_letter(log.start_headings[a])) : "N/A");
    starts.push_back(start);
  }
  out["start"] = starts;
  out["numTaskFinished"] = result.tasks_finished;
  out["sumOfCost"] = std::accumulate(log.cost.begin(), log.cost.end(), int64_t{0});
  out["makespan"] = log.cost.empty() ? 0 : *std::max_element(log.cost.begin(), log.cost.end());
  out["actualPaths"] = log.actual;
  out["plannerPaths"] = log.planned;
  nlohmann::json times = nlohmann::json::array();
  for (double ms : result.step_ms) times.push_back(ms / 1000);
  out["plannerTimes"] = times;
  nlohmann::json errors = nlohmann::json::array();
  for (const LifelongLog::Error& error : log.errors) {
    errors.push_back(nlohmann::json::array({error.agent1, error.agent2, error.step, error.what}));
  }
  out["errors"] = errors;
  nlohmann::json events = nlohmann::json::array();
  for (const auto& of_agent : log.events) {
    nlohmann::json list = nlohmann::json::array();
    for (const LifelongLog::Event& event : of_agent) {
      list.push_back(nlohmann::json::array({event.task, event.step, event.finished ? "finished" : "assigned"}));
    }
    events.push_back(list);
  }
  out["events"] = events;
  // Task k is the file's task k mod its length (the file is started over at its end); a task of
  // several errands lists each errand's row and column in order.
  nlohmann::json tasks = nlohmann::json::array();
  for (int64_t k = 0; k < log.tasks_revealed; ++k) {
    nlohmann::json task = nlohmann::json::array({k});
    for (Vertex errand : problem.tasks[static_cast<size_t>(k) % problem.tasks.size()]) {
      for (const auto& coordinate : row_and_column(graph, errand)) task.push_back(coordinate);
    }
    tasks.push_back(task);
  }
  out["tasks"] = tasks;
  std::ofstream file(path, std::ios::trunc);
  if (!file) throw InputError(path + ": cannot write the output file");
  file << out.dump() << "\n";
  if (!file.flush()) throw InputError(path + ": writing the output file failed");
}

}  // namespace planner_core
