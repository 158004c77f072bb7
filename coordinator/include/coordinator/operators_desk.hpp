// OperatorsDesk: the coordinator's counter for operators (ctsfleet-task, dashboards): the events
// it reports, queued until the loop publishes them; the answers to task requests, remembered so
// that a request sent again gets the same answer; whether the mission info must go out again.
// What operators see never stops the fleet: a topic that cannot be written (access control of a
// fleet enrolled before it existed, a middleware error) is logged once and the mission goes on.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "fleet_transport/messages.hpp"
#include "fleet_transport/transport.hpp"

namespace coordinator {

class OperatorsDesk {
 public:
  explicit OperatorsDesk(uint64_t coordinator) : coordinator_(coordinator) {}

  // An event for operators (kinds: idl/fleet.idl), stamped now and queued.
  void report(const std::string& kind, const std::string& robot_id, const std::string& text, double value = 0);
  // Publishes the queued events.
  void publish_events(fleet_transport::Transport& transport);
  // Runs `publish`; a failure is logged once per `what` and swallowed.
  void publish(const char* what, const std::function<void()>& publish);

  // The answer already given to `request_id`, or nullptr.
  const fleet_transport::TaskReply* answer_to(const std::string& request_id) const;
  // Remembers an answer (the latest kRepliesKept).
  void remember(const fleet_transport::TaskReply& reply);

  // The mission info goes out at first and after every change of the tasks.
  bool mission_due() const { return !mission_published_ || mission_changed_; }
  void mission_changed() { mission_changed_ = true; }
  void mission_published() { mission_published_ = true, mission_changed_ = false; }

 private:
  static constexpr size_t kRepliesKept = 256;

  uint64_t coordinator_;
  std::vector<fleet_transport::FleetEvent> events_;
  std::map<std::string, fleet_transport::TaskReply> replies_;  // request id -> the answer given
  std::deque<std::string> reply_order_;                        // oldest first, to forget old ones
  std::set<std::string> topics_failed_;                        // logged once each
  bool mission_published_ = false;
  bool mission_changed_ = false;
};

}  // namespace coordinator
