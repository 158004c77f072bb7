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

void FleetCoordinator::stand_down(const OtherCoordinator& other, fleet_transport::Transport& transport) {
  const fleet_transport::CoordinatorStatus& s = other.status;
  const std::string why =
      s.term > identity_.term
          ? fmt::format("it has a higher term ({} > {})", s.term, identity_.term)
          : fmt::format("it claimed the fleet first ({} ms before this one)", identity_.claimed_ms - s.claimed_ms);
  summary_.stood_down = true;
  summary_.stood_down_because = fmt::format(
      "coordinator {} is already active on {} domain {} (term {}, mission {}{}, epoch {}) and {}", hex(s.coordinator),
      config_.dds_vendor, config_.domain_id, s.term, s.mission_id,
      s.mission_id == identity_.mission_id ? ", the same mission" : ", ANOTHER mission", s.plan_epoch, why);
  spdlog::error("standing down: {}. One coordinator drives a fleet: run a second one with --standby to follow the "
                "active one and take over if it fails.", summary_.stood_down_because);
  identity_.role = fleet_transport::CoordinatorRole::kStoodDown;
  phase_ = Phase::kDone;
  desk_.report("stood_down", "", summary_.stood_down_because);
  desk_.publish_events(transport);
  plan_.reset();  // not one more command
  publish_status(transport);
}

// A standby keeps the active coordinator's progress (its done visits, its bindings, its epoch) and
// takes over when StandbyFollower says so.
void FleetCoordinator::follow(fleet_transport::Transport& transport, Clock::time_point now) {
  if (const OtherCoordinator* followed = others_.find(follower_.followed());
      followed != nullptr && followed->status.role == fleet_transport::CoordinatorRole::kEnded) {
    end_with(*followed);
    return;
  }
  const OtherCoordinator* active = others_.highest_active(identity_.mission_id);
  if (active == nullptr) {
    follower_.no_active_coordinator(identity_.mission_id);
    return;
  }
  follower_.mirror(*active, mission_.agent_count(), now);
  if (active->mission) adopt_tasks(*active->mission);
  for (const fleet_transport::TaskVisit& visit : active->progress.done_visits) progress_.mark(visit);
  epoch_ = std::max(epoch_, active->status.plan_epoch);
  summary_.tasks_done = progress_.tasks_done();
  // The command writers get the strength of the term a takeover would have now, so that changing
  // it (which DDS announces per writer) is not on the takeover's path.
  const int next_term = static_cast<int>(active->status.term) + 1;
  if (identity_.command_strength != next_term) {
    transport.set_command_strength(next_term);
    identity_.command_strength = next_term;
  }
  if (follower_.should_take_over(*active, robots_, now)) take_over(transport, *active, now);
}

void FleetCoordinator::end_with(const OtherCoordinator& ended) {
  for (const fleet_transport::TaskVisit& visit : ended.progress.done_visits) progress_.mark(visit);
  summary_.tasks_done = progress_.tasks_done();
  summary_.completed = progress_.all_tasks_done();
  spdlog::info("standby: coordinator {} ended the mission ({} of {} tasks done); the standby ends too",
               hex(ended.status.coordinator), summary_.tasks_done, summary_.tasks_total);
  phase_ = Phase::kDone;
}

void FleetCoordinator::take_over(fleet_transport::Transport& transport, const OtherCoordinator& old,
                                 Clock::time_point now) {
  uint32_t highest = others_.highest_term(old.status.term);
  if (options_.journal) highest = std::max(highest, options_.journal->highest_term());
  identity_.term = highest + 1;
  identity_.claimed_ms = fleet_transport::wall_clock_ms();
  identity_.role = fleet_transport::CoordinatorRole::kActive;
  summary_.took_over = true;
  summary_.term = identity_.term;
  summary_.tasks_done_before = progress_.tasks_done();
  spdlog::warn("coordinator {} (term {}) silent for {:.2f} s: taking over as term {} at epoch {}; {} task visits "
               "and {} of {} tasks done",
               hex(old.status.coordinator), old.status.term, seconds_between(old.heard, now), identity_.term, epoch_,
               progress_.done_visits().size(), progress_.tasks_done(), progress_.task_count());
  if (identity_.command_strength != static_cast<int>(identity_.term)) {  // set ahead while following, normally
    const Clock::time_point before = Clock::now();
    transport.set_command_strength(static_cast<int>(identity_.term));
    identity_.command_strength = static_cast<int>(identity_.term);
    spdlog::info("command strength set to {} in {:.0f} ms", identity_.term,
                 1000 * seconds_between(before, Clock::now()));
  }
  if (options_.journal) {
    journal_write("claim", [&](MissionJournal& journal) {
      journal.claim(identity_.term, identity_.incarnation, identity_.claimed_ms);
    });
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
    const auto kept = follower_.roles().find(robot->id);
    if (kept != follower_.roles().end() && progress_.robot_of(kept->second).empty()) {
      bind_role(kept->second, *robot);
    } else {
      rest.push_back(robot);
    }
  }
  bind_roles(rest);
  report("takeover", "",
         fmt::format("coordinator {} silent for {:.2f} s: {} takes over as term {}", hex(old.status.coordinator),
                     seconds_between(old.heard, now), hex(identity_.incarnation), identity_.term));
  phase_ = Phase::kSettling;
  clocks_.settle_deadline = now;
  replans_.start_latency(now);
  others_.forget(old.status.coordinator);  // last: `old` is its record
  publish_status(transport);
  publish_progress(transport);
}

}  // namespace coordinator
