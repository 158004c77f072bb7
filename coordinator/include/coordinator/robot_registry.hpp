// RobotRegistry: every robot the coordinator has heard of, by id: whether it announced itself, was
// refused, is active (announced, on a free cell, not lost), its last state and when it was heard,
// its role and its agent in the current plan. Admission rules for announcements live here; the
// coordinator decides what a loss or a join means for the plan.
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "coordinator/fleet_config.hpp"
#include "fleet_transport/messages.hpp"
#include "planner_core/graph.hpp"

namespace coordinator {

struct RobotRecord {
  using Clock = std::chrono::steady_clock;
  std::string id;
  std::string backend;
  bool announced = false;
  bool active = false;   // announced, has a free cell, not lost
  bool refused = false;
  bool has_state = false;
  fleet_transport::RobotState last;
  Clock::time_point last_heard;        // for its silence (moved on when the coordinator stood still)
  Clock::time_point last_state_received{};  // when the transport handed over its latest state
  bool said_goodbye = false;  // since its latest state: it left, and no coordinator drives it
  int role = -1;          // mission role, -1 for an extra robot
  int plan_agent = -1;    // agent in the current plan, -1 when not in it
  // A robot taken out for not acknowledging a command rejoins only once that command has expired
  // (it can no longer start the move the next plan would not know of).
  Clock::time_point rejoin_not_before{};
  bool finished_plan = false;
  uint64_t incarnation = 0;               // of the process whose states are accepted
  std::set<uint64_t> refused_incarnations;  // other live processes claiming this id (reported once each)
  // Heard but not announced: its cell is kept clear until it announces itself.
  std::optional<planner_core::Vertex> unannounced_at;
  bool warned_unannounced = false;
};

class RobotRegistry {
 public:
  using Clock = RobotRecord::Clock;

  enum class Admission {
    kAdmitted,        // first announcement (or again after a loss): now known
    kRepeat,          // an active robot repeating its announcement
    kDuplicate,       // an announcement under an active robot's id from another backend
    kRefused,         // not in robots.expected (first time)
    kRefusedAgain,    // the same, already refused
  };

  // The record of `id`, created empty on first use.
  RobotRecord& operator[](const std::string& id);
  // The same, or nullptr when `id` breaks the rule for robot ids (a name, not markup: refused
  // before it becomes a record, a role or an event's robot). `refused(why)` is called the first
  // time each such id is heard, for the first kBadIdsReported of them; later ones are refused
  // without a word (a flood).
  RobotRecord* valid_record(const std::string& id, const std::function<void(const std::string& why)>& refused);
  const RobotRecord* find(const std::string& id) const;
  // Applies the admission rules of `config` to an announcement (not a goodbye).
  Admission admit(const fleet_transport::Announcement& announcement, const FleetConfig& config);

  int active_count() const;
  // Active robots that have reported a cell, in id order.
  std::vector<RobotRecord*> ready_robots();
  std::vector<const RobotRecord*> ready_robots() const;
  // Active robots not heard for more than `timeout_s` at `now`.
  std::vector<RobotRecord*> silent_robots(Clock::time_point now, double timeout_s);
  // The coordinator itself stood still until `now` (its loop or its middleware blocked), so it
  // could hear nobody: every active robot's silence is counted from `now`.
  void restart_silence_clocks(Clock::time_point now);

  std::map<std::string, RobotRecord>::iterator begin() { return robots_.begin(); }
  std::map<std::string, RobotRecord>::iterator end() { return robots_.end(); }
  std::map<std::string, RobotRecord>::const_iterator begin() const { return robots_.begin(); }
  std::map<std::string, RobotRecord>::const_iterator end() const { return robots_.end(); }

 private:
  static constexpr size_t kBadIdsReported = 64;
  std::map<std::string, RobotRecord> robots_;
  std::set<std::string> bad_ids_reported_;
};

}  // namespace coordinator
