#include "robot_agent/dbus_event_pump.hpp"

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <system_error>

namespace robot_agent {

DbusEventPump::DbusEventPump(sdbus::IConnection& connection) : connection_(connection) {
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) throw std::system_error(errno, std::generic_category(), "eventfd");
}

DbusEventPump::~DbusEventPump() { close(wake_fd_); }

void DbusEventPump::wake() {
  const uint64_t one = 1;
  [[maybe_unused]] const ssize_t written = write(wake_fd_, &one, sizeof one);
}

void DbusEventPump::run_once(std::chrono::milliseconds max_wait) {
  while (connection_.processPendingRequest()) {
  }
  const sdbus::IConnection::PollData poll_data = connection_.getEventLoopPollData();
  std::chrono::milliseconds wait = max_wait;
  if (const auto bus_timeout = poll_data.getRelativeTimeout()) {
    wait = std::min(wait, std::chrono::ceil<std::chrono::milliseconds>(*bus_timeout));
  }
  pollfd fds[2] = {{poll_data.fd, poll_data.events, 0}, {wake_fd_, POLLIN, 0}};
  if (poll(fds, 2, static_cast<int>(std::max<int64_t>(wait.count(), 0))) > 0 && (fds[1].revents & POLLIN)) {
    uint64_t count = 0;
    [[maybe_unused]] const ssize_t read_bytes = read(wake_fd_, &count, sizeof count);
  }
  while (connection_.processPendingRequest()) {
  }
}

}  // namespace robot_agent
