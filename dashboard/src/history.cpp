#include "dashboard/history.hpp"

#include <algorithm>
#include <map>
#include <optional>
#include <set>

#include "planner_core/input_file.hpp"
#include "dashboard/message_json.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/yaml_context.hpp"
#include "planner_core/validator.hpp"

namespace dashboard {

using fleet_transport::GoneReason;

namespace {

// Where `read` (a message read back as JSON) differs from what the file said: a number past its
// field's type (nlohmann wraps it), a fraction for an integer, a word no enum has. "" when none.
std::string first_difference(const Json& said, const Json& read, const std::string& field) {
  if (read.is_object()) {
    for (const auto& [key, value] : read.items()) {
      if (!said.contains(key)) continue;
      const std::string found = first_difference(said.at(key), value, field.empty() ? key : field + "." + key);
      if (!found.empty()) return found;
    }
    return "";
  }
  if (read.is_array() && said.is_array() && said.size() == read.size()) {
    for (size_t i = 0; i < read.size(); ++i) {
      const std::string found = first_difference(said[i], read[i], field + "[" + std::to_string(i) + "]");
      if (!found.empty()) return found;
    }
    return "";
  }
  if (said == read) return "";
  return "field " + field + " is " + planner_core::cut(said.dump(-1, ' ', false, Json::error_handler_t::replace)) +
         ", which its type cannot hold (it would read as " + read.dump() + ")";
}

// The message's fields as JSON, with one element in every list (what each element looks like).
template <typename Message>
Json shape_of() {
  return Message{};
}
template <>
Json shape_of<fleet_transport::FleetStatus>() {
  fleet_transport::FleetStatus status;
  status.assignments.resize(1);
  status.done_visits.resize(1);
  return status;
}
template <>
Json shape_of<fleet_transport::MissionInfo>() {
  fleet_transport::MissionInfo mission;
  mission.goals.resize(1);
  mission.tasks.resize(1);
  mission.tasks[0].roles.resize(1);
  return mission;
}
template <>
Json shape_of<fleet_transport::FleetPlan>() {
  fleet_transport::FleetPlan plan;
  plan.robots.resize(1);
  plan.robots[0].path.resize(1);
  return plan;
}

// A number with a fraction or an exponent where an integer goes is refused before it is converted:
// nlohmann casts it, and a cast of 1e140 (or of -1.5 to an unsigned field) is undefined behaviour.
void require_integers(const Json& said, const Json& shape, const std::string& field) {
  if (shape.is_object() && said.is_object()) {
    for (const auto& [key, value] : shape.items()) {
      if (said.contains(key)) require_integers(said.at(key), value, field.empty() ? key : field + "." + key);
    }
  } else if (shape.is_array() && said.is_array() && !shape.empty()) {
    for (size_t i = 0; i < said.size(); ++i) require_integers(said[i], shape[0], field + "[" + std::to_string(i) + "]");
  } else if (shape.is_number_integer() && said.is_number_float()) {
    throw std::invalid_argument("field " + field + " is " + planner_core::cut(said.dump()) + ", not an integer");
  }
}

// The message, refused (std::invalid_argument naming the field) unless it reads back as it was said.
template <typename Message>
Message checked(const Json& said) {
  static const Json shape = shape_of<Message>();
  require_integers(said, shape, "");
  Message message = said.get<Message>();
  const std::string difference = first_difference(said, Json(message), "");
  if (!difference.empty()) throw std::invalid_argument(difference);
  return message;
}

}  // namespace

void apply(FleetView& view, const HistoryEntry& entry) {
  const Json& m = entry.message;
  const int64_t t = entry.t_ms;
  try {
    if (entry.type == "state") {
      view.on_state(checked<fleet_transport::RobotState>(m), t);
    } else if (entry.type == "announcement") {
      view.on_announcement(checked<fleet_transport::Announcement>(m), t);
    } else if (entry.type == "gone") {
      view.on_robot_gone(m.at("robot_id").get<std::string>(),
                         m.at("reason").get<std::string>() == "goodbye" ? GoneReason::kGoodbye : GoneReason::kLivelinessLost,
                         t);
    } else if (entry.type == "coordinator") {
      view.on_coordinator_status(checked<fleet_transport::CoordinatorStatus>(m), t);
    } else if (entry.type == "status") {
      view.on_fleet_status(checked<fleet_transport::FleetStatus>(m), t);
    } else if (entry.type == "mission") {
      view.on_mission(checked<fleet_transport::MissionInfo>(m), t);
    } else if (entry.type == "plan") {
      view.on_plan(checked<fleet_transport::FleetPlan>(m), t);
    } else if (entry.type == "event") {
      view.on_event(checked<fleet_transport::FleetEvent>(m), t);
    } else {
      throw std::invalid_argument("unknown message type '" + entry.type + "'");
    }
  } catch (const nlohmann::json::exception& e) {
    throw std::invalid_argument("a '" + entry.type + "' message: " + e.what());
  }
}

HistoryRecorder::HistoryRecorder(const std::string& path) : out_(path, std::ios::trunc) {
  if (!out_) throw planner_core::InputError("--record " + path + ": cannot create the file");
  out_ << Json{{"format", kHistoryFormat}}.dump() << "\n" << std::flush;
}

void HistoryRecorder::write(const HistoryEntry& entry) {
  const std::string line = Json{{"t", entry.t_ms}, {"type", entry.type}, {"msg", entry.message}}.dump();
  const std::lock_guard<std::mutex> lock(mutex_);
  out_ << line << "\n" << std::flush;
}

std::vector<HistoryEntry> load_history(const std::string& path) {
  planner_core::require_regular_file(path, "history file");
  std::ifstream in(path);
  if (!in) throw planner_core::InputError(path + ": cannot open it");
  std::vector<HistoryEntry> entries;
  std::string line;
  int number = 0;
  FleetView check;  // every entry must apply: a bad one is reported with its line now, not mid-replay
  while (std::getline(in, line)) {
    ++number;
    const std::string where = path + ":" + std::to_string(number) + ": ";
    if (line.empty()) continue;
    Json row;
    try {
      row = Json::parse(line);
    } catch (const nlohmann::json::exception& e) {
      throw planner_core::InputError(where + "not JSON (" + planner_core::cut(e.what(), 160) + ")");
    }
    if (number == 1) {
      const bool ours = row.is_object() && row.contains("format") && row.at("format").is_string() &&
                        row.at("format").get<std::string>() == kHistoryFormat;
      if (!ours) {
        throw planner_core::InputError(where + "not a ctsfleet history (its first line must be {\"format\": \"" +
                                       std::string(kHistoryFormat) + "\"})");
      }
      continue;
    }
    try {
      const Json& t = row.at("t");
      if (!t.is_number_integer() || (t.is_number_unsigned() && t.get<uint64_t>() > INT64_MAX)) {
        throw std::invalid_argument("field t is " + t.dump().substr(0, 80) + ", not a time in ms (an integer of 64 bits)");
      }
      HistoryEntry entry{t.get<int64_t>(), row.at("type").get<std::string>(), row.at("msg")};
      apply(check, entry);
      entries.push_back(std::move(entry));
    } catch (const std::exception& e) {
      throw planner_core::InputError(where + planner_core::cut(e.what(), 240));
    }
  }
  if (number == 0) throw planner_core::InputError(path + ": empty, not a ctsfleet history");
  std::stable_sort(entries.begin(), entries.end(),
                   [](const HistoryEntry& a, const HistoryEntry& b) { return a.t_ms < b.t_ms; });
  return entries;
}

HistoryPicture history_picture(const std::vector<HistoryEntry>& entries, const std::string& source) {
  std::optional<fleet_transport::MissionInfo> mission;
  std::map<std::string, int> role_of;                      // robot -> role, from the last fleet status
  std::map<std::string, std::vector<planner_core::Cell>> trail;  // robot -> cells, in time order
  std::vector<std::pair<std::string, planner_core::Cell>> moves;  // every change of a robot's cell
  for (const HistoryEntry& entry : entries) {
    if (entry.type == "mission") mission = entry.message.get<fleet_transport::MissionInfo>();
    if (entry.type == "status") {
      role_of.clear();
      for (const auto& row : entry.message.get<fleet_transport::FleetStatus>().assignments) role_of[row.robot_id] = row.role;
    }
    if (entry.type == "state") {
      const auto state = entry.message.get<fleet_transport::RobotState>();
      const planner_core::Cell cell{state.cell_x, state.cell_y};
      auto& cells = trail[state.robot_id];
      if (cells.empty() || !(cells.back() == cell)) {
        cells.push_back(cell);
        moves.emplace_back(state.robot_id, cell);
      }
    }
  }
  if (!mission) throw planner_core::InputError(source + ": no mission in it: nothing to draw");
  if (trail.empty()) throw planner_core::InputError(source + ": no robot state in it: nothing to draw");
  std::vector<std::string> rows;
  for (size_t start = 0; start <= mission->map_rows.size();) {
    const size_t end = std::min(mission->map_rows.find('\n', start), mission->map_rows.size());
    rows.push_back(mission->map_rows.substr(start, end - start));
    start = end + 1;
  }
  HistoryPicture picture;
  planner_core::Instance& instance = picture.instance;
  try {
    instance.graph = std::make_shared<const planner_core::Graph>(mission->width, mission->height, rows);
  } catch (const std::invalid_argument& e) {
    throw planner_core::InputError(source + ": its mission's map does not fit its size (map_rows, width, height): " +
                                   e.what());
  }
  instance.source = source;
  const planner_core::Graph& map = *instance.graph;
  std::map<std::string, int> agent_of;
  for (const auto& [robot, cells] : trail) {
    const planner_core::Vertex start = map.vertex_at(cells.front()), goal = map.vertex_at(cells.back());
    if (start == planner_core::kNoVertex || goal == planner_core::kNoVertex) continue;  // reported off the map
    agent_of[robot] = instance.agent_count();
    picture.robots.push_back(robot);
    instance.starts.push_back(start);
    instance.goals.push_back(goal);
  }
  for (const fleet_transport::MissionTask& task : mission->tasks) {
    planner_core::Task drawn{map.vertex_at({task.x, task.y}), {}};
    for (const auto& [robot, role] : role_of) {
      if (std::find(task.roles.begin(), task.roles.end(), role) != task.roles.end() && agent_of.count(robot)) {
        drawn.agents.push_back(agent_of[robot]);
      }
    }
    if (drawn.at != planner_core::kNoVertex && !drawn.agents.empty() && !task.cancelled) instance.tasks.push_back(drawn);
  }
  instance.index_tasks();
  planner_core::Config now = instance.starts;
  picture.solution.push_back(now);
  for (const auto& [robot, cell] : moves) {
    const auto agent = agent_of.find(robot);
    const planner_core::Vertex v = map.vertex_at(cell);
    if (agent == agent_of.end() || v == planner_core::kNoVertex || now[agent->second] == v) continue;
    now[agent->second] = v;
    picture.solution.push_back(now);
  }
  return picture;
}

}  // namespace dashboard
