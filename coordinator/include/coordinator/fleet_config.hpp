// FleetConfig: the coordinator's settings from YAML (mission, robots, planner, DDS, timing).
// Errors name the file and the field.
#pragma once

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "fleet_transport/transport.hpp"
#include "planner_core/lifelong_config.hpp"
#include "planner_core/solver.hpp"

namespace coordinator {

struct FleetConfig {
  std::string source;            // the YAML file
  std::string mission;           // CTS-MAPF instance: its agents are the mission's roles
  // Lifelong: when every task is done the robots park on their goals and the coordinator keeps
  // running, waiting for tasks added at runtime (ctsfleet-task add), with no mission timeout.
  bool lifelong = false;
  // Lifelong mode: the window planner's settings (key lifelong_planner: a file as config/lifelong.yaml,
  // relative to the fleet config); none: plain PIBT (window_planner.hpp, window_settings).
  std::optional<planner_core::LifelongConfig> lifelong_planner;
  bool any_robots = true;        // robots: expected: any
  std::vector<std::string> expected_robots;
  int quorum = 1;                // start once this many robots are bound (any mode)
  double wait_timeout_s = 30;    // start with whoever is there after this long (at least one robot)
  std::string solver = "cts-pll-v3";
  double plan_time_s = 1.0;
  // Replanning after a robot leaves or joins favours speed: the first feasible plan.
  std::string replan_solver = "cts-pll-v2";
  double replan_time_s = 1.0;
  // The same seed (and journal, and robot states) gives the same plan; with `iterations` (a work
  // budget, as ctsfleet-solve --iterations) so does an anytime solver, unless the time limit ends
  // it first.
  int64_t seed = 0;
  int64_t iterations = 0;
  bool pibt_swap = true;         // Extended-PIBT's swap operation (helps in one-cell aisles)
  // The anytime solvers' LNS ends after this many repairs without a gain; 0: it refines until the
  // time limit (or the work budget) ends it.
  int lns_stall_iterations = planner_core::LnsConfig{}.stall_iterations;
  // rotate: plans with turns (the robots turn in place before they move; each turn a step of the
  // plan and a command of its own); move4: plans in which robots move any way (turns left to them).
  planner_core::ActionModel actions = planner_core::ActionModel::kMove4;
  std::string dds_vendor = "cyclone";
  int domain_id = 0;
  double lease_s = 1.0;
  std::string network_interface;  // "" = loopback (dds.config_dir); else a LAN interface
  std::string peers;              // unicast discovery to these IPv4 hosts ("" = multicast)
  std::string discovery_server;  // Fast DDS: "HOST:PORT;..." of ctsfleet-discovery servers ("" = none)
  std::string dds_config_dir;    // folder with the loopback XML files ("" = environment as is)
  double step_s = 0.2;           // nominal seconds per move, for command deadlines
  double silence_timeout_s = 2;  // a robot whose state stops this long is taken out
  // A robot that has not acknowledged its move this long (counted from the first sending; its
  // states still arrive, so its command channel is what is broken) is taken out. The config's
  // default is raised to the least allowed, 2 x resend_after_s(), for long steps.
  double command_timeout_s = 10;
  double mission_timeout_s = 300;
  double replan_settle_s = 3;    // after a loss or join: wait this long at most for moves in flight
  // When only tasks of roles without a robot are left: unset, the robots hold and the coordinator
  // waits for a robot to join until the mission timeout; set, it waits this long, then ends the
  // mission with those tasks reported as pending.
  std::optional<double> replacement_timeout_s;
  // DDS Security (section security:): the fleet directory made by ctsfleet-ca ("" = off), the
  // name this coordinator is enrolled as, and whether the fleet refuses to run without it (the
  // configs of real robots say so).
  std::string security_dir;
  std::string security_identity = "coordinator";
  bool security_required = false;

  // What the settings above mean for the solver and the middleware: the one place they are mapped.
  // The mission's first plan (full budget) or a replan (first feasible plan, fast); both
  // rotation-free, as robots execute one move at a time.
  planner_core::SolverConfig solver_config(bool first_plan) const;
  double plan_limit_s(bool first_plan) const { return first_plan ? plan_time_s : replan_time_s; }
  // A move not confirmed this long after its last sending is sent again.
  double resend_after_s() const { return std::max(1.0, 5 * step_s); }
  // How long a step command stays valid after it is sent: robots refuse it after that.
  double command_lifetime_s() const { return 4 * step_s + 1; }
  // Loads and checks the security files when security_dir is set (throws std::invalid_argument
  // naming the file); throws planner_core::InputError when security is required but not set up.
  fleet_transport::TransportConfig transport_config() const;
};

// Throws planner_core::InputError naming the file and field.
FleetConfig load_fleet_config(const std::string& path);

}  // namespace coordinator
