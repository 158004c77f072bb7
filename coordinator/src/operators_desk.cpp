#include "coordinator/operators_desk.hpp"

#include <spdlog/spdlog.h>

namespace coordinator {

void OperatorsDesk::report(const std::string& kind, const std::string& robot_id, const std::string& text,
                           double value) {
  events_.push_back({coordinator_, fleet_transport::wall_clock_ms(), kind, robot_id, text, value});
}

void OperatorsDesk::publish_events(fleet_transport::Transport& transport) {
  publish("events", [&] {
    for (const fleet_transport::FleetEvent& event : events_) transport.publish_fleet_event(event);
  });
  events_.clear();
}

void OperatorsDesk::publish(const char* what, const std::function<void()>& publish) {
  try {
    publish();
  } catch (const std::exception& e) {
    if (topics_failed_.insert(what).second) {
      spdlog::warn("cannot publish the {} for operators ({}); the mission goes on without it. With DDS Security, "
                   "re-enrol the coordinator with this version's ctsfleet-ca", what, e.what());
    }
  }
}

const fleet_transport::TaskReply* OperatorsDesk::answer_to(const std::string& request_id) const {
  const auto known = replies_.find(request_id);
  return known == replies_.end() ? nullptr : &known->second;
}

void OperatorsDesk::remember(const fleet_transport::TaskReply& reply) {
  if (!replies_.emplace(reply.request_id, reply).second) return;
  reply_order_.push_back(reply.request_id);
  if (reply_order_.size() > kRepliesKept) {
    replies_.erase(reply_order_.front());
    reply_order_.pop_front();
  }
}

}  // namespace coordinator
