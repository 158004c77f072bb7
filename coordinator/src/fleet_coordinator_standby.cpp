// FleetCoordinator and the other coordinators: the highest-ranked active one drives; a standby
// follows it and takes over when it falls silent; an outranked active one stands down.
#include "coordinator/fleet_coordinator.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <tuple>
#include <utility>

#include "coordinator/plan_builder.hpp"
#include "coordinator/role_assignment.hpp"
#include "fleet_transport/lease_timeouts.hpp"
#include "planner_core/dist_table.hpp"
#include "planner_core/input_error.hpp"
#include "planner_core/solver.hpp"
#include "planner_core/validator.hpp"
#include "fleet_coordinator_detail.hpp"

namespace coordinator {

using fleet_transport::RobotStatus;
using planner_core::Cell;
using planner_core::Vertex;
using namespace fleet_coordinator_detail;

void FleetCoordinator::handle_status(const fleet_transport::CoordinatorStatus& status, Clock::time_point received) {
  OtherCoordinator& other = others_[status.coordinator];
  const bool first = other.status.coordinator == 0;
  other.status = status;
  other.heard = received;
  if (first) {
    spdlog::info("heard coordinator {} ({}, term {}, mission {}, epoch {})", hex(status.coordinator),
                 fleet_transport::to_string(status.role), status.term, status.mission_id, status.plan_epoch);
  }
}

const FleetCoordinator::OtherCoordinator* FleetCoordinator::stronger_active(Clock::time_point now) const {
  const fleet_transport::CoordinatorStatus mine = own_status();
  for (const auto& [id, other] : others_) {
    if (other.status.role != fleet_transport::CoordinatorRole::kActive) continue;
    if (seconds_between(other.heard, now) > fleet_transport::LeaseTimeouts{config_.lease_s}.coordinator_gone_s()) {
      continue;  // gone
    }
    if (fleet_transport::outranks(other.status, mine)) return &other;
  }
  return nullptr;
}

void FleetCoordinator::stand_down(const OtherCoordinator& other, fleet_transport::Transport& transport) {
  const fleet_transport::CoordinatorStatus& s = other.status;
  const std::string why =
      s.term > term_
          ? fmt::format("it has a higher term ({} > {})", s.term, term_)
          : fmt::format("it claimed the fleet first ({} ms before this one)", claimed_ms_ - s.claimed_ms);
  summary_.stood_down = true;
  summary_.stood_down_because = fmt::format(
      "coordinator {} is already active on {} domain {} (term {}, mission {}{}, epoch {}) and {}", hex(s.coordinator),
      config_.dds_vendor, config_.domain_id, s.term, s.mission_id,
      s.mission_id == mission_id_ ? ", the same mission" : ", ANOTHER mission", s.plan_epoch, why);
  spdlog::error("standing down: {}. One coordinator drives a fleet: run a second one with --standby to follow the "
                "active one and take over if it fails.", summary_.stood_down_because);
  role_ = fleet_transport::CoordinatorRole::kStoodDown;
  phase_ = Phase::kDone;
  for_operators("events", [&] {
    transport.publish_fleet_event(
        {incarnation_, fleet_transport::wall_clock_ms(), "stood_down", "", summary_.stood_down_because, 0});
  });
  plan_.reset();  // not one more command
  publish_status(transport);
}

const FleetCoordinator::OtherCoordinator* FleetCoordinator::followed() const {
  const OtherCoordinator* best = nullptr;
  for (const auto& [id, other] : others_) {
    if (other.status.role != fleet_transport::CoordinatorRole::kActive || other.status.mission_id != mission_id_) continue;
    if (best == nullptr || fleet_transport::outranks(other.status, best->status)) best = &other;
  }
  return best;
}

// A standby keeps the active coordinator's progress (its done visits, its bindings, its epoch) and
// takes over once that coordinator has been silent for a lease and a half.
void FleetCoordinator::follow(fleet_transport::Transport& transport, Clock::time_point now) {
  // The followed coordinator ended the mission (completed or not): so does its standby.
  if (const auto it = others_.find(mirrored_);
      it != others_.end() && it->second.status.role == fleet_transport::CoordinatorRole::kEnded) {
    for (const fleet_transport::TaskVisit& visit : it->second.progress.done_visits) progress_.mark(visit);
    summary_.tasks_done = progress_.tasks_done();
    summary_.completed = progress_.all_tasks_done();
    spdlog::info("standby: coordinator {} ended the mission ({} of {} tasks done); the standby ends too", hex(mirrored_),
                 summary_.tasks_done, summary_.tasks_total);
    phase_ = Phase::kDone;
    return;
  }
  const OtherCoordinator* active = followed();
  if (active == nullptr) {
    if (!logged_no_active_) {
      logged_no_active_ = true;
      spdlog::info("standby: waiting for an active coordinator of mission {}", mission_id_);
    }
    return;
  }
  if (active->status.coordinator != mirrored_) {
    mirrored_ = active->status.coordinator;
    spdlog::info("standby: follows coordinator {} (term {})", hex(mirrored_), active->status.term);
  }
  if (active->mission) adopt_tasks(*active->mission);
  for (const fleet_transport::TaskVisit& visit : active->progress.done_visits) progress_.mark(visit);
  mirrored_roles_.clear();
  std::set<std::string> driven;
  for (const fleet_transport::Assignment& row : active->progress.assignments) {
    driven.insert(row.robot_id);
    if (row.role >= 0 && row.role < mission_.agent_count()) mirrored_roles_[row.robot_id] = row.role;
  }
  std::erase_if(mirrored_since_, [&](const auto& entry) { return driven.count(entry.first) == 0; });
  for (const std::string& id : driven) mirrored_since_.emplace(id, now);
  epoch_ = std::max(epoch_, active->status.plan_epoch);
  summary_.tasks_done = progress_.tasks_done();
  // The command writers get the strength of the term a takeover would have now, so that changing
  // it (which DDS announces per writer) is not on the takeover's path.
  const int next_term = static_cast<int>(active->status.term) + 1;
  if (command_strength_ != next_term) {
    transport.set_command_strength(next_term);
    command_strength_ = next_term;
  }
  // The active coordinator is silent: dead, or cut off from this host. It may still drive robots
  // this standby cannot hear (a network split with robots on both sides), and a plan that takes
  // them for walls at their last cells would drive robots into them. So it takes over only once it
  // has heard, since the active one fell silent, every robot that one drove, and has heard them
  // for two status periods: when a split heals, the robots' states may come back a little before
  // the active one's status, which must not read as its death.
  const double silent_s = seconds_between(active->heard, now);
  const Clock::duration status_gap = seconds(2 * kStatusPeriodS);
  if (now - active->heard <= status_gap) {
    if (active_fell_silent_) {  // heard again after a silence; so are the robots, a moment apart
      for (auto& [id, since] : mirrored_since_) since = now;
    }
    active_fell_silent_ = false;
    logged_unheard_robots_ = false;
    every_robot_heard_since_.reset();
    warn_of_driven_robots_not_heard(now);
    return;
  }
  active_fell_silent_ = true;
  // "Since" leaves the same gap: a robot's last state from before a split may arrive after the
  // active one's last status (sent up to a period before the split).
  const std::vector<std::string> unheard = robots_unheard_since(active->heard + status_gap);
  if (!unheard.empty()) every_robot_heard_since_.reset();
  if (unheard.empty() && !every_robot_heard_since_) every_robot_heard_since_ = now;
  if (silent_s <= fleet_transport::LeaseTimeouts{config_.lease_s}.standby_takes_over_after_s()) return;
  if (every_robot_heard_since_ && now - *every_robot_heard_since_ >= status_gap) {
    take_over(transport, *active, now);
    return;
  }
  if (!unheard.empty() && !logged_unheard_robots_) {
    logged_unheard_robots_ = true;
    constexpr size_t kNamed = 8;
    std::string names;
    for (size_t i = 0; i < std::min(unheard.size(), kNamed); ++i) names += (i == 0 ? "" : ", ") + unheard[i];
    if (unheard.size() > kNamed) names += fmt::format(" and {} more", unheard.size() - kNamed);
    spdlog::warn("standby: coordinator {} (term {}) silent for {:.2f} s, but so {} {}: this host may be cut off "
                 "from part of the fleet, which that coordinator may still drive; taking over once every robot "
                 "is heard",
                 hex(active->status.coordinator), active->status.term, silent_s, unheard.size() == 1 ? "is" : "are",
                 names);
  }
}

void FleetCoordinator::warn_of_driven_robots_not_heard(Clock::time_point now) {
  if (now < next_not_heard_check_) return;  // a standby steps every few ms; robots report ten times a second
  next_not_heard_check_ = now + seconds(kStatusPeriodS);
  const Clock::duration silence = seconds(config_.silence_timeout_s);
  for (const auto& [id, since] : mirrored_since_) {
    const RobotRecord* robot = robots_.find(id);
    const bool heard = robot != nullptr && robot->has_state && now - robot->last_state_received <= silence;
    if (heard) {
      warned_not_heard_.erase(id);
    } else if (now - since > silence && warned_not_heard_.insert(id).second) {
      spdlog::warn("standby: robot {}, which coordinator {} drives, is not heard here: this standby could not take "
                   "over while it is not (check this host's network)",
                   id, hex(mirrored_));
    }
  }
}

std::vector<std::string> FleetCoordinator::robots_unheard_since(Clock::time_point since) const {
  std::set<std::string> drivable;
  for (const auto& [id, since] : mirrored_since_) drivable.insert(id);
  for (const auto& [id, robot] : robots_) {
    if (robot.active && robot.has_state) drivable.insert(id);  // joined after the last progress heard
  }
  std::vector<std::string> unheard;
  for (const std::string& id : drivable) {
    const RobotRecord* robot = robots_.find(id);
    if (robot != nullptr && robot->said_goodbye) continue;  // it left: nobody drives it any more
    if (robot == nullptr || !robot->has_state || robot->last_state_received <= since) unheard.push_back(id);
  }
  return unheard;
}

void FleetCoordinator::take_over(fleet_transport::Transport& transport, const OtherCoordinator& old,
                                 Clock::time_point now) {
  uint32_t highest = old.status.term;
  for (const auto& [id, other] : others_) highest = std::max(highest, other.status.term);
  if (options_.journal) highest = std::max(highest, options_.journal->highest_term());
  term_ = highest + 1;
  claimed_ms_ = fleet_transport::wall_clock_ms();
  role_ = fleet_transport::CoordinatorRole::kActive;
  summary_.took_over = true;
  summary_.term = term_;
  summary_.tasks_done_before = progress_.tasks_done();
  spdlog::warn("coordinator {} (term {}) silent for {:.2f} s: taking over as term {} at epoch {}; {} task visits "
               "and {} of {} tasks done",
               hex(old.status.coordinator), old.status.term, seconds_between(old.heard, now), term_, epoch_,
               progress_.done_visits().size(), progress_.tasks_done(), progress_.task_count());
  if (command_strength_ != static_cast<int>(term_)) {  // set ahead while following, normally
    const Clock::time_point before = Clock::now();
    transport.set_command_strength(static_cast<int>(term_));
    command_strength_ = static_cast<int>(term_);
    spdlog::info("command strength set to {} in {:.0f} ms", term_, 1000 * seconds_between(before, Clock::now()));
  }
  if (options_.journal) {
    journal_write("claim", [&](MissionJournal& journal) { journal.claim(term_, incarnation_, claimed_ms_); });
    journal_added_tasks();
    for (const fleet_transport::TaskVisit& visit : progress_.done_visits()) {
      journal_write("task visit",
                    [&](MissionJournal& journal) { journal.record_visit(visit, progress_.robot_of(visit.role), epoch_); });
    }
  }
  // The old coordinator's bindings hold for the robots still here; the others are bound afresh.
  for (int role = 0; role < mission_.agent_count(); ++role) progress_.unbind(role);
  for (auto& [id, robot] : robots_) robot.role = -1;
  std::vector<RobotRecord*> rest;
  for (RobotRecord* robot : robots_.ready_robots()) {
    const auto kept = mirrored_roles_.find(robot->id);
    if (kept != mirrored_roles_.end() && progress_.robot_of(kept->second).empty()) {
      bind_role(kept->second, *robot);
    } else {
      rest.push_back(robot);
    }
  }
  bind_roles(rest);
  report("takeover", "",
         fmt::format("coordinator {} silent for {:.2f} s: {} takes over as term {}", hex(old.status.coordinator),
                     seconds_between(old.heard, now), hex(incarnation_), term_));
  others_.erase(old.status.coordinator);
  phase_ = Phase::kSettling;
  settle_deadline_ = now;
  replan_requested_at_ = now;
  awaiting_replan_latency_ = true;
  publish_status(transport);
  publish_progress(transport);
}

}  // namespace coordinator
