// The fleet benchmark's yardstick for the task-stream scenario: the same fleet in one process.
// The coordinator and one RobotAgent per robot, each driving a simulated robot (the very classes
// the programs run), pass their messages by function call on one thread: no DDS, no processes,
// no scheduling between them. What the fleet of processes loses against it is the runtime's cost.
#pragma once

#include <atomic>

#include "coordinator/fleet_config.hpp"
#include "planner_core/instance.hpp"
#include "task_stream.hpp"

namespace coordinator {

struct StreamTimeline {
  double warmup_s = 15;    // from the first plan, before counting starts
  double measure_s = 60;   // tasks done counted over this long
  // Fleets of processes: this long into the counted time, one robot's process is SIGKILLed and,
  // once the coordinator has had time to miss it, started again where it stood (-1: never).
  double restart_robot_at_s = -1;
};

struct StreamFigures {
  int tasks_done = 0;          // within the counted time
  double seconds = 0;          // the counted time
  double tasks_per_minute = 0;
  int accepted = 0;            // tasks the stream gave, over the whole run
  int refused = 0;
  int deferred = 0;            // refused as a duplicate of a task waiting at that cell, asked again
  int64_t windows = 0;         // lifelong windows the plan grew by
  double window_ms_max = 0;
  int64_t windows_late = 0;    // windows some robot stood still for (FleetSummary::windows_late)
  double robot_s_waiting_for_windows = 0;
  int64_t tasks_reassigned = 0;  // pooled tasks moved to a robot that got there sooner
  int replans = 0;
  int64_t robot_steps = 0;     // plan steps the robots carried out within the counted time, all robots'
  bool interrupted = false;
};

// Runs `mission` with `config` (lifelong) and robots whose moves take `step_s` * (1 + U[0, jitter])
// (and a quarter turn `turn_s` as much).
StreamFigures run_in_process_fleet(const FleetConfig& config, const planner_core::Instance& mission, double step_s,
                                   double jitter, double turn_s, TaskStream& stream, const StreamTimeline& timeline,
                                   const std::atomic<bool>& stop);

}  // namespace coordinator
