#include "planner_core/solution.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <numeric>
#include <regex>
#include <sstream>

#include "planner_core/input_file.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/yaml_context.hpp"

namespace planner_core {

std::vector<int> arrival_times(const Solution& solution, const Config& goals) {
  std::vector<int> arrival(goals.size(), 0);
  if (solution.empty()) return arrival;
  const int last = static_cast<int>(solution.size()) - 1;
  for (size_t a = 0; a < goals.size(); ++a) {
    int t = last;
    if (solution[last][a] == goals[a]) {
      while (t > 0 && solution[t - 1][a] == goals[a]) --t;
    }
    arrival[a] = t;
  }
  return arrival;
}

int64_t flowtime(const Solution& solution, const Config& goals) {
  const std::vector<int> arrival = arrival_times(solution, goals);
  return std::accumulate(arrival.begin(), arrival.end(), int64_t{0});
}

int makespan(const Solution& solution, const Config& goals) {
  const std::vector<int> arrival = arrival_times(solution, goals);
  return arrival.empty() ? 0 : *std::max_element(arrival.begin(), arrival.end());
}

int64_t sum_of_loss(const Solution& solution, const Config& goals) {
  int64_t loss = 0;
  for (size_t t = 1; t < solution.size(); ++t) {
    for (size_t a = 0; a < goals.size(); ++a) {
      loss += (solution[t - 1][a] == goals[a] && solution[t][a] == goals[a]) ? 0 : 1;
    }
  }
  return loss;
}

void trim_idle_tail(Solution& solution) {
  while (solution.size() > 1 && solution[solution.size() - 1] == solution[solution.size() - 2]) solution.pop_back();
}

std::string SolutionFile::value(const std::string& key) const {
  for (const auto& [k, v] : header) {
    if (k == key) return v;
  }
  return "";
}

namespace {

void append_number(std::string& out, int64_t value) {
  char digits[24];
  const auto end = std::to_chars(digits, digits + sizeof digits, value).ptr;
  out.append(digits, end);
}

}  // namespace

std::string format_solution(const Graph& graph, const SolutionFile& file) {
  // Built with to_chars into one string reserved up front: a 10,000-agent plan is about 50 MB,
  // and a stream took about a second to format it, past the solver's deadline.
  std::string out;
  const size_t agents = file.solution.empty() ? 0 : file.solution.front().size();
  out.reserve(4096 + file.solution.size() * (8 + agents * 10));
  for (const auto& [key, value] : file.header) out.append(key).append("=").append(value).append("\n");
  out.append("solution=\n");
  for (size_t t = 0; t < file.solution.size(); ++t) {
    append_number(out, static_cast<int64_t>(t));
    out.push_back(':');
    const bool with_headings = t < file.headings.size();
    for (size_t a = 0; a < file.solution[t].size(); ++a) {
      const Cell c = graph.cell_of(file.solution[t][a]);
      out.push_back('(');
      append_number(out, c.x);
      out.push_back(',');
      append_number(out, c.y);
      if (with_headings) {
        out.push_back(',');
        out.push_back(heading_letter(file.headings[t][a]));
      }
      out.append("),");
    }
    out.push_back('\n');
  }
  return out;
}

void write_solution(const std::string& path, const Graph& graph, const SolutionFile& file) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot write solution file");
  out << format_solution(graph, file);
  if (!out) throw InputError(path + ": write failed");
}

SolutionFile read_solution(const std::string& path, const Graph& graph) {
  require_regular_file(path, "solution file");
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open solution file");
  SolutionFile file;
  std::string line;
  int line_no = 0;
  bool in_body = false;
  const std::regex cell_pattern(R"(\((-?\d+),(-?\d+)(,([^)]*))?\))");
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    const std::string where = path + ":" + std::to_string(line_no);
    if (!in_body) {
      if (line.rfind("solution=", 0) == 0) {
        in_body = true;
        continue;
      }
      const size_t eq = line.find('=');
      if (eq == std::string::npos) throw InputError(where + ": expected key=value before 'solution='");
      file.header.emplace_back(line.substr(0, eq), line.substr(eq + 1));
      continue;
    }
    const size_t colon = line.find(':');
    if (colon == std::string::npos) throw InputError(where + ": expected 't:(x,y),...'");
    int t = -1;
    try {
      t = std::stoi(line.substr(0, colon));
    } catch (const std::exception&) {
      throw InputError(where + ": timestep is not a number");
    }
    if (t != static_cast<int>(file.solution.size())) {
      throw InputError(where + ": expected timestep " + std::to_string(file.solution.size()) + ", got " +
                       std::to_string(t));
    }
    Config config;
    Headings headings;
    const std::string rest = line.substr(colon + 1);
    for (auto it = std::sregex_iterator(rest.begin(), rest.end(), cell_pattern); it != std::sregex_iterator(); ++it) {
      // A coordinate past int is refused naming the line, never wrapped, never an exception that
      // names nothing (a cell off the map becomes kNoVertex, which the validator names).
      Cell cell{-1, -1};
      const std::string x = (*it)[1], y = (*it)[2];
      const auto x_read = std::from_chars(x.data(), x.data() + x.size(), cell.x);
      const auto y_read = std::from_chars(y.data(), y.data() + y.size(), cell.y);
      if (x_read.ec != std::errc() || y_read.ec != std::errc()) {
        throw InputError(where + ": a cell (" + cut(x, 20) + "," + cut(y, 20) + ") past the range of a coordinate");
      }
      config.push_back(graph.vertex_at(cell));
      if ((*it)[3].matched) {
        const std::string letter = (*it)[4];
        if (letter.size() != 1 || heading_of_letter(letter[0]) < 0) {
          throw InputError(where + ": \"" + cut(letter, 20) + "\" is no heading (E, S, W or N)");
        }
        headings.push_back(heading_of_letter(letter[0]));
      }
    }
    if (!headings.empty() && headings.size() != config.size()) {
      throw InputError(where + ": some cells have a heading and some do not");
    }
    if (t > 0 && headings.empty() != file.headings.empty()) {
      throw InputError(where + ": " + (headings.empty() ? "no headings, as the lines before have"
                                                          : "headings, which the lines before do not have"));
    }
    if (!headings.empty()) file.headings.push_back(std::move(headings));
    file.solution.push_back(std::move(config));
  }
  if (!in_body) throw InputError(path + ": no 'solution=' line");
  return file;
}

}  // namespace planner_core
