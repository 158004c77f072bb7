// A fleet's history: every message the dashboard heard, with the time it heard it, one JSON object
// per line (JSON Lines; the first line names the format). Written live by `ctsfleet-dashboard
// --record FILE`, replayed at any speed by `--replay FILE` (playback.hpp; a plan written by
// ctsfleet-solve plays there too).
#pragma once

#include <cstdint>
#include <fstream>
#include <mutex>
#include <string>
#include <vector>

#include "dashboard/fleet_view.hpp"
#include "planner_core/instance.hpp"
#include "planner_core/solution.hpp"

namespace dashboard {

inline constexpr const char* kHistoryFormat = "ctsfleet-history-1";

// One message: its kind ("state", "announcement", "gone", "coordinator", "status", "mission",
// "plan", "event") and the message as message_json.hpp writes it.
struct HistoryEntry {
  int64_t t_ms = 0;
  std::string type;
  Json message;
};

// Feeds one entry to the view; throws std::invalid_argument naming what is wrong with it.
void apply(FleetView& view, const HistoryEntry& entry);

class HistoryRecorder {
 public:
  // Creates (truncates) `path`; throws planner_core::InputError when it cannot.
  explicit HistoryRecorder(const std::string& path);
  // Thread-safe; each line is flushed, so a killed dashboard leaves a readable file.
  void write(const HistoryEntry& entry);

 private:
  std::mutex mutex_;
  std::ofstream out_;
};

// Reads a history file, sorted by time. Throws planner_core::InputError naming the file and line.
std::vector<HistoryEntry> load_history(const std::string& path);

// What a history shows, as a plan for planner_core's SVG picture (write_svg): the last mission's
// map and tasks, and each robot that reported a cell as an agent whose path is the cells it stood
// on, one timestep per change of any robot's cell (agents in robot-id order; a task's agents are the
// robots last bound to its roles). Throws planner_core::InputError when the history has no mission
// or no robot state.
struct HistoryPicture {
  planner_core::Instance instance;
  planner_core::Solution solution;
  std::vector<std::string> robots;  // agent -> robot id
};
HistoryPicture history_picture(const std::vector<HistoryEntry>& entries, const std::string& source);

}  // namespace dashboard
