// The middleware's own log lines (a refused handshake, an access-control denial) go to the
// process's log, each distinct line at most once a minute: a refused intruder retries every
// second, and an operator needs the first line and a count, not a flood.
#pragma once

#include <spdlog/spdlog.h>

#include <chrono>
#include <map>
#include <mutex>
#include <string>

namespace fleet_transport {

class RepeatedLineFilter {
 public:
  // Logs `line` (from `vendor`) unless it was logged less than a minute ago.
  void log(const char* vendor, bool error, const std::string& line) {
    const auto now = std::chrono::steady_clock::now();
    int repeats = 0;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      Seen& seen = seen_[line];
      if (seen.repeats >= 0 && now - seen.last_logged < std::chrono::minutes(1)) {
        ++seen.repeats;
        return;
      }
      repeats = seen.repeats < 0 ? 0 : seen.repeats;
      seen = {now, 0};
      if (seen_.size() > 1000) seen_.clear();  // bounded, whatever a peer sends
    }
    const std::string again = repeats > 0 ? " (and " + std::to_string(repeats) + " times in the last minute)" : "";
    if (error) {
      spdlog::error("{}: {}{}", vendor, line, again);
    } else {
      spdlog::warn("{}: {}{}", vendor, line, again);
    }
  }

 private:
  struct Seen {
    std::chrono::steady_clock::time_point last_logged;
    int repeats = -1;  // -1: never logged
  };
  std::mutex mutex_;
  std::map<std::string, Seen> seen_;
};

}  // namespace fleet_transport
