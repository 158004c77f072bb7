// What the transport's threads hand the coordinator's loop: one type per kind of message, queued
// in the order heard and handled one by one on the loop's thread (FleetCoordinator::step, by
// std::visit), so that the coordinator's state is only ever touched by that thread.
#pragma once

#include <chrono>
#include <deque>
#include <mutex>
#include <string>
#include <variant>

#include "fleet_transport/messages.hpp"
#include "fleet_transport/transport.hpp"

namespace coordinator::inputs {

using Clock = std::chrono::steady_clock;

struct Announced {
  fleet_transport::Announcement announcement;
};
struct StateHeard {
  fleet_transport::RobotState state;
  Clock::time_point received;
};
struct RobotGone {
  std::string robot_id;
  fleet_transport::GoneReason reason{};
};
struct CoordinatorHeard {  // another coordinator's heartbeat
  fleet_transport::CoordinatorStatus status;
  Clock::time_point received;
};
struct ProgressHeard {  // another coordinator's progress (a standby mirrors it)
  fleet_transport::FleetStatus progress;
};
struct MissionHeard {  // another coordinator's mission, with the tasks added at runtime
  fleet_transport::MissionInfo mission;
};
struct TaskRequested {  // an operator's request (ctsfleet-task, the dashboard)
  fleet_transport::TaskRequest request;
};
struct Refused {  // a message the transport refused (e.g. a robot writing as another)
  std::string what;
};

using Input = std::variant<Announced, StateHeard, RobotGone, CoordinatorHeard, ProgressHeard, MissionHeard,
                           TaskRequested, Refused>;

// The hand-over between the transport's threads (push) and the loop (take_all).
class InputQueue {
 public:
  void push(Input input) {
    const std::lock_guard<std::mutex> lock(mutex_);
    inputs_.push_back(std::move(input));
  }
  // Every input queued so far, oldest first.
  std::deque<Input> take_all() {
    std::deque<Input> taken;
    const std::lock_guard<std::mutex> lock(mutex_);
    taken.swap(inputs_);
    return taken;
  }

 private:
  std::mutex mutex_;
  std::deque<Input> inputs_;
};

}  // namespace coordinator::inputs
