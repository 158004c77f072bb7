// FleetView: what the dashboard knows of the fleet, built from the messages it hears (live from
// DDS, or replayed from a history file): the mission and plan of the coordinator it follows (the
// highest-ranked active one, else the last one heard), every robot's last state, and the events.
// It turns them into the JSON the page draws: the mission and the plan (sent when they change)
// and frames (robots, tasks' states, figures, recent events; sent many times a second). Not
// thread-safe: the server guards it. Times are wall-clock ms on the dashboard's host (a replay
// gives the recorded ones).
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <utility>
#include <vector>
#include <string>

#include "fleet_transport/messages.hpp"
#include "fleet_transport/transport.hpp"

namespace dashboard {

using Json = nlohmann::json;

class FleetView {
 public:
  static constexpr double kLateFactor = 2.0;
  static constexpr size_t kMovesKept = 200;
  static constexpr size_t kMovesForTypical = 20;

  // A robot heard of nothing for `lost_after_s` is shown lost.
  explicit FleetView(double lost_after_s = 2.0) : lost_after_ms_(static_cast<int64_t>(lost_after_s * 1000)) {}

  void on_announcement(const fleet_transport::Announcement& announcement, int64_t heard_ms);
  void on_robot_gone(const std::string& robot_id, fleet_transport::GoneReason reason, int64_t heard_ms);
  void on_state(const fleet_transport::RobotState& state, int64_t heard_ms);
  void on_coordinator_status(const fleet_transport::CoordinatorStatus& status, int64_t heard_ms);
  void on_fleet_status(const fleet_transport::FleetStatus& status, int64_t heard_ms);
  void on_mission(const fleet_transport::MissionInfo& mission, int64_t heard_ms);
  void on_plan(const fleet_transport::FleetPlan& plan, int64_t heard_ms);
  void on_event(const fleet_transport::FleetEvent& event, int64_t heard_ms);

  // Grow by one whenever the followed coordinator's mission (or plan) changes.
  int mission_version() const { return mission_version_; }
  int plan_version() const { return plan_version_; }
  // {"version", "width", "height", "rows": [...], "goals": [[x,y]...], "tasks": [{"id","x","y","roles","cancelled"}], "lifelong"}
  // or null before any mission was heard.
  Json mission_json() const;
  // {"version", "epoch", "planning_ms", "flowtime", "robots": {id: {"role", "path": [[x,y]...]}}} or null.
  Json plan_json() const;
  // The live picture at `now_ms` (see docs/DASHBOARD.md for the fields).
  Json frame_json(int64_t now_ms) const;

  // What a robot is doing, as the page shows it: moving, delayed (moving, for longer than
  // kLateFactor times the fleet's typical move), waiting (on the plan's order), parked (plan done),
  // fault, off_plan, lost, left.
  std::string robot_status(const std::string& robot_id, int64_t now_ms) const;
  // The median of the fleet's last kMovesKept moves, from a robot's first state moving to its first
  // state arrived (times the dashboard heard them); -1 until kMovesForTypical moves were seen.
  int64_t typical_move_ms() const;
  // Index into the robot's plan path of the next cell it goes to (path.size() when done; -1 when it
  // is in no plan).
  int path_from(const std::string& robot_id) const;
  // A pending task of a robot's role, and how many steps ahead its plan reaches it (0: the cell it
  // stands on or leaves); kNotPlanned when the plan does not reach it yet (lifelong: it waits in
  // the pool, and the coordinator may still give it to another robot).
  struct Due {
    int task;
    int steps;
  };
  static constexpr int kNotPlanned = -1;
  // The robot's pending tasks in the order its plan visits them, those its plan does not reach last.
  std::vector<Due> schedule(const std::string& robot_id) const;
  std::vector<int> next_tasks(const std::string& robot_id) const;
  size_t robot_count() const { return robots_.size(); }

 private:
  struct Robot {
    std::optional<fleet_transport::RobotState> state;
    int64_t heard_ms = 0;
    std::string backend;
    std::optional<fleet_transport::GoneReason> gone;
    bool off_plan = false;
    int64_t moving_since_ms = -1;  // heard time of the first state of the move under way, -1: none
  };
  struct Coordinator {
    fleet_transport::CoordinatorStatus status;
    int64_t heard_ms = 0;
    std::optional<fleet_transport::MissionInfo> mission;
    std::optional<fleet_transport::FleetPlan> plan;
    std::optional<fleet_transport::FleetStatus> progress;
    // Looked up for every robot in every frame (thousands of robots when a big plan is shown):
    std::map<std::string, size_t> plan_index;       // robot -> its place in plan->robots
    std::map<std::string, int> role_index;          // robot -> role, from progress->assignments
    std::set<std::pair<int, int>> visits_done;      // (task, role), from progress->done_visits
    std::map<int, std::vector<int>> tasks_of_role;  // role -> the mission's tasks for it, in order
  };

  const Coordinator* followed() const;
  Coordinator& coordinator(uint64_t id);
  void refollow();  // re-evaluates which coordinator is followed; bumps versions on a change
  const fleet_transport::RobotPlan* plan_of(const std::string& robot_id) const;
  int role_of(const std::string& robot_id) const;
  bool visited(int task, int role) const;

  int64_t lost_after_ms_;
  std::map<std::string, Robot> robots_;
  std::map<uint64_t, Coordinator> coordinators_;
  uint64_t followed_ = 0;
  int mission_version_ = 0;
  int plan_version_ = 0;
  std::deque<Json> events_;  // newest last
  std::deque<int64_t> move_ms_;  // the fleet's last moves' durations, newest last
  mutable std::optional<int64_t> typical_move_ms_;  // their median, computed when first asked for
  int64_t events_total_ = 0;
};

}  // namespace dashboard
