// A League of Robot Runners problem of a test's own, written to a fresh folder and removed after.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "planner_core/input_error.hpp"
#include "planner_core/lorr_problem.hpp"

namespace planner_core {

// A problem of our own in a fresh folder: map rows, agent locations, tasks (errands per line).
class TinyProblem {
 public:
  TinyProblem(const std::vector<std::string>& rows, const std::vector<std::string>& agents,
              const std::vector<std::string>& tasks, const std::string& extra = "\"taskAssignmentStrategy\": \"roundrobin\"") {
    dir_ = std::filesystem::temp_directory_path() / ("ctsfleet-lorr-" + std::to_string(::getpid()) + "-" + std::to_string(counter_++));
    std::filesystem::create_directories(dir_);
    std::ofstream map(dir_ / "tiny.map");
    map << "type octile\nheight " << rows.size() << "\nwidth " << rows[0].size() << "\nmap\n";
    for (const std::string& row : rows) map << row << "\n";
    write("tiny.agents", agents);
    write("tiny.tasks", tasks);
    std::ofstream json(dir_ / "tiny.json");
    json << "{\"mapFile\": \"tiny.map\", \"agentFile\": \"tiny.agents\", \"teamSize\": " << agents.size() - 1
         << ", \"taskFile\": \"tiny.tasks\", \"numTasksReveal\": 1" << (extra.empty() ? "" : ", " + extra) << "}";
  }
  ~TinyProblem() { std::filesystem::remove_all(dir_); }
  std::string path() const { return (dir_ / "tiny.json").string(); }
  std::string file(const std::string& name) const { return (dir_ / name).string(); }
  void write(const std::string& name, const std::vector<std::string>& lines) const {
    std::ofstream out(dir_ / name);
    for (const std::string& line : lines) out << line << "\n";
  }

 private:
  static inline int counter_ = 0;
  std::filesystem::path dir_;
};

// The error load_lorr_problem gives for `path`, or "" when it reads.
inline std::string lorr_error_of(const std::string& path) {
  try {
    load_lorr_problem(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace planner_core
