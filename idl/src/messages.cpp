#include "fleet_transport/messages.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "fleet_transport/transport.hpp"

namespace fleet_transport {

const char* to_string(RobotStatus status) {
  switch (status) {
    case RobotStatus::kIdle: return "idle";
    case RobotStatus::kMoving: return "moving";
    case RobotStatus::kArrived: return "arrived";
    case RobotStatus::kFault: return "fault";
  }
  return "unknown";
}

const char* to_string(TaskAction action) {
  switch (action) {
    case TaskAction::kAdd: return "add";
    case TaskAction::kCancel: return "cancel";
    case TaskAction::kList: return "list";
  }
  return "unknown";
}

const char* to_string(CoordinatorRole role) {
  switch (role) {
    case CoordinatorRole::kActive: return "active";
    case CoordinatorRole::kStandby: return "standby";
    case CoordinatorRole::kStoodDown: return "stood down";
    case CoordinatorRole::kEnded: return "ended";
  }
  return "unknown";
}

bool outranks(const CoordinatorStatus& a, const CoordinatorStatus& b) {
  if (a.term != b.term) return a.term > b.term;
  if (a.claimed_ms != b.claimed_ms) return a.claimed_ms < b.claimed_ms;
  return a.coordinator < b.coordinator;
}

namespace {
std::atomic<int64_t> g_test_skew_ms{0};
}  // namespace

int64_t wall_clock_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
             .count() +
         g_test_skew_ms.load(std::memory_order_relaxed);
}

void set_wall_clock_skew_for_tests(int64_t skew_ms) { g_test_skew_ms.store(skew_ms); }

Vendor parse_vendor(const std::string& name) {
  if (name == "cyclone") return Vendor::kCyclone;
  if (name == "fastdds") return Vendor::kFastDds;
  throw std::invalid_argument("unknown DDS vendor '" + name + "' (known: cyclone, fastdds)");
}

bool is_valid_robot_id(const std::string& id) {
  if (id.empty() || id.size() > kMaxRobotIdLength) return false;
  return std::all_of(id.begin(), id.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
  });
}

std::string printable(const std::string& text, size_t at_most) {
  std::string out;
  for (const char c : text) {
    if (out.size() >= at_most) return out + "...";
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f && c != '\\') {
      out += c;
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
      out += escaped;
    }
  }
  return out;
}

const char* to_string(Vendor vendor) { return vendor == Vendor::kCyclone ? "cyclone" : "fastdds"; }

}  // namespace fleet_transport
