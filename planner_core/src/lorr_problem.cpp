#include "planner_core/lorr_problem.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "planner_core/input_error.hpp"
#include "planner_core/input_file.hpp"

namespace planner_core {

namespace fs = std::filesystem;

namespace {

// A problem file's key, with the path it names resolved against the problem's folder.
std::string file_named(const nlohmann::json& root, const std::string& key, const std::string& problem) {
  if (!root.contains(key) || !root[key].is_string()) {
    throw InputError(problem + ": \"" + key + "\" missing or not a file name");
  }
  const fs::path named = root[key].get<std::string>();
  return (named.is_relative() ? fs::path(problem).parent_path() / named : named).lexically_normal().string();
}

// The lines of a LoRR list file: a count on the first line, then that many lines of integers.
struct ListLine {
  int line_no = 0;
  std::vector<long long> values;
};

std::vector<ListLine> read_list_file(const std::string& path, const std::string& what) {
  require_regular_file(path, what);
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open " + what);
  std::string text;
  int line_no = 0;
  long long count = -1;
  std::vector<ListLine> lines;
  while (std::getline(in, text)) {
    ++line_no;
    for (char& c : text) c = c == ',' ? ' ' : c;  // later rounds separate a task's errands by commas
    std::istringstream words(text);
    ListLine line{line_no, {}};
    long long value = 0;
    while (words >> value) line.values.push_back(value);
    std::string rest;
    if (!(words.eof() || (words.clear(), words >> rest, rest.empty()))) {
      throw InputError(path + ":" + std::to_string(line_no) + ": expected integers, found '" + rest + "'");
    }
    if (line.values.empty()) continue;  // blank lines
    if (count < 0) {
      if (line.values.size() != 1 || line.values[0] < 0 || line.values[0] > 100'000'000) {
        throw InputError(path + ":" + std::to_string(line_no) + ": the first line must be the count of " + what +
                         " lines");
      }
      count = line.values[0];
      continue;
    }
    lines.push_back(std::move(line));
  }
  if (count < 0) throw InputError(path + ": empty (the first line must be the count)");
  if (static_cast<long long>(lines.size()) != count) {
    throw InputError(path + ": the first line says " + std::to_string(count) + " but " +
                     std::to_string(lines.size()) + " lines follow");
  }
  return lines;
}

Vertex location(const Graph& graph, long long linear, const std::string& path, int line_no) {
  const long long cells = static_cast<long long>(graph.width()) * graph.height();
  const std::string where = path + ":" + std::to_string(line_no) + ": location " + std::to_string(linear);
  if (linear < 0 || linear >= cells) {
    throw InputError(where + " is off the " + std::to_string(graph.width()) + "x" + std::to_string(graph.height()) +
                     " map");
  }
  const Cell cell{static_cast<int>(linear % graph.width()), static_cast<int>(linear / graph.width())};
  const Vertex v = graph.vertex_at(cell);
  if (v == kNoVertex) throw InputError(where + " (row " + std::to_string(cell.y) + ", column " + std::to_string(cell.x) + ") is a wall");
  return v;
}

std::string unreachable(const Graph& graph, Vertex v) {
  const Cell cell = graph.cell_of(v);
  return " (row " + std::to_string(cell.y) + ", column " + std::to_string(cell.x) +
         ") cannot be reached from the first agent's start: the map is cut in parts";
}

nlohmann::json read_json(const std::string& path) {
  require_regular_file(path, "problem file");
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the problem file");
  try {
    nlohmann::json root = nlohmann::json::parse(in);
    if (!root.is_object()) throw InputError(path + ": not a JSON object");
    return root;
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path + ": not JSON (" + std::string(e.what()) + ")");
  }
}

}  // namespace

LorrProblem load_lorr_problem(const std::string& path) {
  const nlohmann::json root = read_json(path);
  LorrProblem problem;
  problem.source = path;
  problem.graph = std::make_shared<const Graph>(
      load_movingai_map(file_named(root, "mapFile", path), MapSymbols::kLeagueOfRobotRunners));
  const Graph& graph = *problem.graph;
  if (!root.contains("teamSize") || !root["teamSize"].is_number_integer() || root["teamSize"].get<long long>() < 1) {
    throw InputError(path + ": \"teamSize\" missing or not a positive integer");
  }
  const long long team = root["teamSize"].get<long long>();
  if (root.contains("numTasksReveal")) {
    if (!root["numTasksReveal"].is_number() || !(root["numTasksReveal"].get<double>() >= 1) ||
        root["numTasksReveal"].get<double>() > 1000) {
      throw InputError(path + ": \"numTasksReveal\" must be a number in [1, 1000]");
    }
    problem.tasks_revealed_per_agent = root["numTasksReveal"].get<double>();
  }
  if (root.contains("taskAssignmentStrategy")) {
    const nlohmann::json& strategy = root["taskAssignmentStrategy"];
    if (strategy == "roundrobin") {
      problem.assignment = TaskAssignment::kRoundRobin;
    } else if (strategy == "greedy") {
      problem.assignment = TaskAssignment::kGreedy;
    } else {
      throw InputError(path + ": \"taskAssignmentStrategy\" must be \"roundrobin\" or \"greedy\"");
    }
  }
  const std::string agent_file = file_named(root, "agentFile", path);
  const std::vector<ListLine> agents = read_list_file(agent_file, "agent");
  if (static_cast<long long>(agents.size()) < team) {
    throw InputError(agent_file + ": " + std::to_string(agents.size()) + " agents, but \"teamSize\" is " +
                     std::to_string(team) + " in " + path);
  }
  // Every start and errand on the first agent's part of the map: an agent cut off from its errand
  // would try for ever.
  const std::vector<int> part = connected_parts(graph);
  int floor = -1;
  std::set<Vertex> taken;
  for (long long a = 0; a < team; ++a) {
    const ListLine& line = agents[a];
    if (line.values.size() != 1) throw InputError(agent_file + ":" + std::to_string(line.line_no) + ": one location per line");
    const Vertex start = location(graph, line.values[0], agent_file, line.line_no);
    if (!taken.insert(start).second) {
      throw InputError(agent_file + ":" + std::to_string(line.line_no) + ": a second agent on location " +
                       std::to_string(line.values[0]));
    }
    if (floor == -1) floor = part[start];
    if (part[start] != floor) {
      throw InputError(agent_file + ":" + std::to_string(line.line_no) + ": location " + std::to_string(line.values[0]) +
                       unreachable(graph, start));
    }
    problem.starts.push_back(start);
  }
  const std::string task_file = file_named(root, "taskFile", path);
  for (const ListLine& line : read_list_file(task_file, "task")) {
    std::vector<Vertex> errands;
    for (long long linear : line.values) {
      errands.push_back(location(graph, linear, task_file, line.line_no));
      if (part[errands.back()] != floor) {
        throw InputError(task_file + ":" + std::to_string(line.line_no) + ": location " + std::to_string(linear) +
                         unreachable(graph, errands.back()));
      }
    }
    problem.tasks.push_back(std::move(errands));
  }
  if (problem.tasks.empty()) throw InputError(task_file + ": no task");
  return problem;
}

}  // namespace planner_core
