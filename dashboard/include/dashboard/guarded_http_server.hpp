// GuardedHttpServer: cpp-httplib's server with limits a few sockets cannot get round. httplib
// serves each connection on a thread of its own; left alone, 32 idle event streams or 32 sockets
// sending their headers a byte at a time take every thread and the page stops answering.
//
//   connection accepted ──► over the total or per-address cap? ──► "503", closed at once
//          │ counted
//          ▼
//   reading the request (line, headers, body) ──► past request_deadline_s? ──► closed
//          │ a route's handler begins (mark_request_read)
//          ▼
//   replying: each read or write must make progress within io_timeout_s; then closed
//   (one request per connection, so a connection is never idle between requests).
//
// Event streams are counted per connection (mark_stream()); over their total or per-address cap
// a stream request gets 503 and the page's EventSource retries later. stop_connections() ends
// every connection within a quarter of a second (a slow socket must not hold the program's exit).
#pragma once

#include <httplib.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <string>

namespace dashboard {

struct HttpLimits {
  int connections = 256;             // open at once, in total (the server has a thread for each)
  int connections_per_address = 32;  // open at once from one peer address
  int streams = 64;                  // event streams at once, in total
  int streams_per_address = 8;       // event streams at once from one peer address
  double request_deadline_s = 10;    // to send a request's line, headers and body
  double io_timeout_s = 5;           // one read or write that makes no progress
  size_t max_body_bytes = 64 * 1024;
};

class GuardedHttpServer : public httplib::Server {
 public:
  explicit GuardedHttpServer(HttpLimits limits = {});

  // Called on the thread serving a request once its handler runs: the request was read whole.
  static void mark_request_read();
  // Called on the thread serving an event stream: false when over the caps (the caller answers
  // 503); true when it may go on (it is then counted until its connection closes).
  bool mark_stream();
  // Ends every open connection and refuses new ones.
  void stop_connections();

  const HttpLimits& limits() const { return limits_; }

 struct Connection;  // one open connection (defined where it is served)

 private:
  class GuardedSocketStream;

  bool process_and_close_socket(socket_t sock) override;
  int count(const std::string& address, bool streams_only) const;  // call with mutex_ held

  HttpLimits limits_;
  std::atomic<bool> stopping_{false};
  mutable std::mutex mutex_;
  std::set<Connection*> open_;
};

}  // namespace dashboard
