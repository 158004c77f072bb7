#include "planner_core/lorr_problem.hpp"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <type_traits>

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
    const size_t first = text.find_first_not_of(" \t\r");
    if (first != std::string::npos && text[first] == '#') continue;  // a comment ("# version for LoRR 2026")
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

nlohmann::json read_json(const std::string& path, const std::string& what = "problem file") {
  require_regular_file(path, what);
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the " + what);
  try {
    nlohmann::json root = nlohmann::json::parse(in);
    if (!root.is_object()) throw InputError(path + ": not a JSON object");
    return root;
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path + ": not JSON (" + std::string(e.what()) + ")");
  }
}

// delayConfig.`key`, which must be there and of JSON type `Value`.
template <typename Value>
Value delay_key(const nlohmann::json& delays, const std::string& key, const std::string& path) {
  const std::string named = path + ": \"delayConfig\".\"" + key + "\"";
  if (!delays.contains(key)) throw InputError(named + " missing");
  const nlohmann::json& value = delays[key];
  if constexpr (std::is_same_v<Value, std::string>) {
    if (!value.is_string()) throw InputError(named + " must be a name");
  } else if constexpr (std::is_integral_v<Value>) {
    if (!value.is_number_integer()) throw InputError(named + " must be a whole number");
  } else {
    if (!value.is_number()) throw InputError(named + " must be a number");
  }
  return value.get<Value>();
}

LeagueDelays read_delays(const nlohmann::json& delays, const std::string& path) {
  if (!delays.is_object()) throw InputError(path + ": \"delayConfig\" must be an object");
  const auto fail = [&](const std::string& key, const std::string& problem) {
    throw InputError(path + ": \"delayConfig\".\"" + key + "\" " + problem);
  };
  LeagueDelays read;
  const long long seed = delay_key<long long>(delays, "seed", path);
  if (seed < 0 || seed > 4294967295LL) fail("seed", "must be in [0, 4294967295]");
  read.seed = static_cast<unsigned>(seed);
  const long long min_ticks = delay_key<long long>(delays, "minDelay", path);
  const long long max_ticks = delay_key<long long>(delays, "maxDelay", path);
  if (min_ticks < 1 || min_ticks > 1'000'000) fail("minDelay", "must be in [1, 1000000] ticks");
  if (max_ticks < min_ticks || max_ticks > 1'000'000) fail("maxDelay", "must be in [minDelay, 1000000] ticks");
  read.min_ticks = static_cast<int>(min_ticks);
  read.max_ticks = static_cast<int>(max_ticks);
  const std::string events = delay_key<std::string>(delays, "eventModel", path);
  if (events != "bernoulli" && events != "poisson") fail("eventModel", "must be \"bernoulli\" or \"poisson\"");
  read.events = events == "poisson" ? LeagueDelays::Events::kPoisson : LeagueDelays::Events::kBernoulli;
  read.probability = delay_key<double>(delays, "pDelay", path);
  if (!(read.probability >= 0 && read.probability <= 1)) fail("pDelay", "must be in [0, 1]");
  const std::string durations = delay_key<std::string>(delays, "durationModel", path);
  if (durations != "uniform" && durations != "gaussian") fail("durationModel", "must be \"uniform\" or \"gaussian\"");
  read.durations = durations == "gaussian" ? LeagueDelays::Durations::kGaussian : LeagueDelays::Durations::kUniform;
  read.gauss_mean_share = delay_key<double>(delays, "gaussMeanRatio", path);
  read.gauss_spread_share = delay_key<double>(delays, "gaussStdRatio", path);
  if (!(read.gauss_mean_share >= 0 && read.gauss_mean_share <= 1)) fail("gaussMeanRatio", "must be in [0, 1]");
  if (!(read.gauss_spread_share >= 0 && read.gauss_spread_share <= 1000)) fail("gaussStdRatio", "must be in [0, 1000]");
  return read;
}

// The 2026 rules' execution settings: agentCounter, agentSize, delayConfig, version.
void read_execution_settings(const nlohmann::json& root, const std::string& path, LorrProblem& problem) {
  if (root.contains("version")) {
    if (!root["version"].is_string()) throw InputError(path + ": \"version\" must be a text");
    problem.version = root["version"].get<std::string>();
  }
  if (root.contains("agentCounter")) {
    const nlohmann::json& counter = root["agentCounter"];
    if (!counter.is_number_integer() || counter.get<long long>() < 1 || counter.get<long long>() > 1000) {
      throw InputError(path + ": \"agentCounter\" must be a whole number of ticks in [1, 1000]");
    }
    problem.ticks_per_action = counter.get<int>();
  }
  if (root.contains("agentSize")) {
    const nlohmann::json& size = root["agentSize"];
    if (!size.is_number() || !(size.get<double>() > 0) || size.get<double>() > 1) {
      throw InputError(path + ": \"agentSize\" must be a number in (0, 1] (cells: robots stand one to a cell)");
    }
    problem.agent_size = size.get<double>();
  }
  if (root.contains("delayConfig")) problem.delays = read_delays(root["delayConfig"], path);
}

}  // namespace

LeagueDelays load_delay_config(const std::string& path) {
  const nlohmann::json root = read_json(path, "delay config");
  return read_delays(root.contains("delayConfig") ? root["delayConfig"] : root, path);
}

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
  // No strategy named (2024 on): the system schedules a pool of revealed tasks.
  problem.assignment = root.contains("taskAssignmentStrategy") ? TaskAssignment::kRoundRobin : TaskAssignment::kPool;
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
  read_execution_settings(root, path, problem);
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
