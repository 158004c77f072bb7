// BackgroundOpener (fleet_transport/background_opener.hpp): keys opened in order on another
// thread, a failing open does not stop the rest, stop() drops what is left.
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <thread>
#include <vector>

#include "fleet_transport/background_opener.hpp"

namespace fleet_transport {
namespace {

struct Opened {
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<std::string> keys;
  std::thread::id thread;

  bool wait_for(size_t count) {
    std::unique_lock<std::mutex> lock(mutex);
    return changed.wait_for(lock, std::chrono::seconds(30), [&] { return keys.size() >= count; });
  }
};

TEST(BackgroundOpener, OpensEveryKeyInOrderOnAnotherThreadAndCarriesOnAfterAFailure) {
  Opened opened;
  BackgroundOpener opener([&opened](const std::string& key) {
    const std::lock_guard<std::mutex> lock(opened.mutex);
    opened.keys.push_back(key);
    opened.thread = std::this_thread::get_id();
    opened.changed.notify_all();
    if (key == "refused") throw std::runtime_error("refused by access control");
  });
  for (const char* key : {"robot1", "refused", "robot2", "robot3"}) opener.queue(key);
  ASSERT_TRUE(opened.wait_for(4));
  const std::lock_guard<std::mutex> lock(opened.mutex);
  EXPECT_EQ(opened.keys, (std::vector<std::string>{"robot1", "refused", "robot2", "robot3"}));
  EXPECT_NE(opened.thread, std::this_thread::get_id());
}

TEST(BackgroundOpener, StopWaitsForTheOpenInProgressAndDropsTheRest) {
  std::mutex gate;
  std::unique_lock<std::mutex> held(gate);  // the first open waits here until released
  Opened opened;
  BackgroundOpener opener([&](const std::string& key) {
    {
      const std::lock_guard<std::mutex> lock(opened.mutex);
      opened.keys.push_back(key);
      opened.changed.notify_all();
    }
    const std::lock_guard<std::mutex> wait(gate);
  });
  opener.queue("slow");
  opener.queue("never");
  ASSERT_TRUE(opened.wait_for(1));
  std::thread stopper([&] { opener.stop(); });
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!opener.stopping() && std::chrono::steady_clock::now() < deadline) std::this_thread::yield();
  ASSERT_TRUE(opener.stopping());
  held.unlock();
  stopper.join();
  opener.queue("after stop");  // ignored
  const std::lock_guard<std::mutex> lock(opened.mutex);
  EXPECT_EQ(opened.keys, std::vector<std::string>{"slow"});
}

}  // namespace
}  // namespace fleet_transport
