// DbusEventPump: runs one sdbus-c++ connection's I/O on the calling thread. Each run_once() waits
// for bus traffic, a wake() from another thread, or a timeout, then dispatches every pending
// message (method handlers, signal callbacks). Used by the BLE thread of the toio backend and by
// the cube emulator, so that all D-Bus work of a connection happens on one thread.
#pragma once

#include <sdbus-c++/sdbus-c++.h>

#include <chrono>

namespace robot_agent {

class DbusEventPump {
 public:
  explicit DbusEventPump(sdbus::IConnection& connection);
  ~DbusEventPump();
  DbusEventPump(const DbusEventPump&) = delete;
  DbusEventPump& operator=(const DbusEventPump&) = delete;

  void run_once(std::chrono::milliseconds max_wait);
  void wake();  // any thread

 private:
  sdbus::IConnection& connection_;
  int wake_fd_ = -1;
};

}  // namespace robot_agent
