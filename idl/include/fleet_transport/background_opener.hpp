// Opens things on one background thread, so that a caller who only wants them ready early (a
// coordinator readying a robot's command channel when the robot announces itself) never waits
// for the middleware. Fast DDS takes up to 1.7 s to create one writer once 200 participants are
// matched (it announces the writer to each); done in the coordinator's loop, that held the loop
// for seconds while states waited.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

namespace fleet_transport {

class BackgroundOpener {
 public:
  // `open` runs on the background thread, one key at a time, in the order queued; it must be
  // safe to call again for a key already opened (a caller may need it first and open it itself).
  explicit BackgroundOpener(std::function<void(const std::string&)> open) : open_(std::move(open)) {}
  ~BackgroundOpener() { stop(); }
  BackgroundOpener(const BackgroundOpener&) = delete;
  BackgroundOpener& operator=(const BackgroundOpener&) = delete;

  void queue(const std::string& key) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return;
    keys_.push_back(key);
    if (!thread_.joinable()) thread_ = std::thread([this] { run(); });
    wake_.notify_one();
  }

  bool stopping() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return stopping_;
  }

  // Waits for the open in progress, drops the keys not yet opened. Idempotent.
  void stop() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
      keys_.clear();
    }
    wake_.notify_one();
    if (thread_.joinable()) thread_.join();
  }

 private:
  void run() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
      wake_.wait(lock, [this] { return stopping_ || !keys_.empty(); });
      if (stopping_) return;
      const std::string key = std::move(keys_.front());
      keys_.pop_front();
      lock.unlock();
      try {
        open_(key);
      } catch (...) {  // open_ reports its own failures; the key's first real use meets them again
      }
      lock.lock();
    }
  }

  std::function<void(const std::string&)> open_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::string> keys_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace fleet_transport
