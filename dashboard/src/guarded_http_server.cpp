#include "dashboard/guarded_http_server.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

namespace dashboard {

using Clock = std::chrono::steady_clock;

struct GuardedHttpServer::Connection {
  std::string address;
  Clock::time_point request_due;       // the request must be read by then
  std::atomic<bool> request_read{false};
  bool stream = false;                 // under the server's mutex_
};

namespace {

// The connection the calling thread serves (each connection is served on one thread).
thread_local GuardedHttpServer::Connection* current_connection = nullptr;

constexpr int kStopCheckMs = 250;  // how often a waiting read or write looks at stop_connections()

Clock::duration seconds(double s) { return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s)); }

std::string address_of(const sockaddr_storage& where) {
  char text[INET6_ADDRSTRLEN] = {};
  if (where.ss_family == AF_INET) {
    ::inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(&where)->sin_addr, text, sizeof text);
  } else if (where.ss_family == AF_INET6) {
    ::inet_ntop(AF_INET6, &reinterpret_cast<const sockaddr_in6*>(&where)->sin6_addr, text, sizeof text);
  }
  return text;
}

int port_of(const sockaddr_storage& where) {
  if (where.ss_family == AF_INET) return ntohs(reinterpret_cast<const sockaddr_in*>(&where)->sin_port);
  if (where.ss_family == AF_INET6) return ntohs(reinterpret_cast<const sockaddr_in6*>(&where)->sin6_port);
  return -1;
}

void ends_of(int sock, bool peer, std::string& ip, int& port) {
  sockaddr_storage where{};
  socklen_t length = sizeof where;
  const int got = peer ? ::getpeername(sock, reinterpret_cast<sockaddr*>(&where), &length)
                       : ::getsockname(sock, reinterpret_cast<sockaddr*>(&where), &length);
  ip = got == 0 ? address_of(where) : "";
  port = got == 0 ? port_of(where) : -1;
}

// Best effort, never blocking: the peer is over its caps and gets one short answer. What it sent
// already is read and dropped, so that closing does not reset the connection before it reads.
void refuse_busy(int sock) {
  static const char kBusy[] =
      "HTTP/1.1 503 Service Unavailable\r\nRetry-After: 1\r\nContent-Type: text/plain\r\n"
      "Content-Length: 28\r\nConnection: close\r\n\r\ntoo many connections: retry\n";
  [[maybe_unused]] const ssize_t sent = ::send(sock, kBusy, sizeof kBusy - 1, MSG_NOSIGNAL | MSG_DONTWAIT);
  ::shutdown(sock, SHUT_WR);
  char dropped[4096];
  while (::recv(sock, dropped, sizeof dropped, MSG_DONTWAIT) > 0) {
  }
}

}  // namespace

// httplib's Stream over one accepted socket: buffered reads, each wait bounded by the I/O
// timeout, the request's deadline (until its handler runs) and stop_connections().
class GuardedHttpServer::GuardedSocketStream : public httplib::Stream {
 public:
  GuardedSocketStream(int sock, const GuardedHttpServer& server, Connection& connection)
      : sock_(sock), server_(server), connection_(connection) {}

  bool is_readable() const override { return wait_for(POLLIN); }
  bool is_writable() const override { return wait_for(POLLOUT); }

  ssize_t read(char* out, size_t size) override {
    if (buffered_ == used_) {
      if (!wait_for(POLLIN)) return -1;
      const ssize_t got = ::recv(sock_, buffer_, sizeof buffer_, 0);
      if (got <= 0) return got;
      buffered_ = static_cast<size_t>(got);
      used_ = 0;
    }
    const size_t n = std::min(size, buffered_ - used_);
    std::copy(buffer_ + used_, buffer_ + used_ + n, out);
    used_ += n;
    return static_cast<ssize_t>(n);
  }

  ssize_t write(const char* data, size_t size) override {
    if (!wait_for(POLLOUT)) return -1;
    return ::send(sock_, data, size, MSG_NOSIGNAL);
  }

  void get_remote_ip_and_port(std::string& ip, int& port) const override { ends_of(sock_, true, ip, port); }
  void get_local_ip_and_port(std::string& ip, int& port) const override { ends_of(sock_, false, ip, port); }
  socket_t socket() const override { return sock_; }

 private:
  // Waits until the socket is ready for `events`; false at a timeout, the request's deadline, a
  // stop, or an error. Buffered bytes count as readable.
  bool wait_for(short events) const {
    if (events == POLLIN && used_ < buffered_) return true;
    const bool reading_request = events == POLLIN && !connection_.request_read;
    const auto give_up = std::min(Clock::now() + seconds(server_.limits_.io_timeout_s),
                                  reading_request ? connection_.request_due : Clock::time_point::max());
    while (!server_.stopping_) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(give_up - Clock::now()).count();
      if (left <= 0) return false;
      pollfd entry{sock_, events, 0};
      const int ready = ::poll(&entry, 1, static_cast<int>(std::min<long long>(left, kStopCheckMs)));
      if (ready > 0) return (entry.revents & (POLLERR | POLLNVAL)) == 0 || (entry.revents & POLLIN) != 0;
      if (ready < 0 && errno != EINTR) return false;
    }
    return false;
  }

  int sock_;
  const GuardedHttpServer& server_;
  Connection& connection_;
  char buffer_[4096];
  size_t buffered_ = 0;
  size_t used_ = 0;
};

GuardedHttpServer::GuardedHttpServer(HttpLimits limits) : limits_(limits) {
  // A thread for every connection allowed, and a few to refuse the ones over the cap quickly.
  const auto threads = static_cast<size_t>(limits_.connections + 8);
  new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  set_payload_max_length(limits_.max_body_bytes);
}

void GuardedHttpServer::mark_request_read() {
  if (current_connection != nullptr) current_connection->request_read = true;
}

bool GuardedHttpServer::mark_stream() {
  Connection* connection = current_connection;
  if (connection == nullptr) return true;
  const std::lock_guard<std::mutex> lock(mutex_);
  if (count("", true) >= limits_.streams || count(connection->address, true) >= limits_.streams_per_address) {
    return false;
  }
  connection->stream = true;
  return true;
}

void GuardedHttpServer::stop_connections() { stopping_ = true; }

int GuardedHttpServer::count(const std::string& address, bool streams_only) const {
  return static_cast<int>(std::count_if(open_.begin(), open_.end(), [&](const Connection* connection) {
    return (address.empty() || connection->address == address) && (!streams_only || connection->stream);
  }));
}

bool GuardedHttpServer::process_and_close_socket(socket_t sock) {
  Connection connection;
  int port = -1;
  ends_of(sock, true, connection.address, port);
  connection.request_due = Clock::now() + seconds(limits_.request_deadline_s);
  bool admitted = false;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    admitted = !stopping_ && static_cast<int>(open_.size()) < limits_.connections &&
               count(connection.address, false) < limits_.connections_per_address;
    if (admitted) open_.insert(&connection);
  }
  bool served = false;
  if (admitted) {
    GuardedSocketStream stream(sock, *this, connection);
    current_connection = &connection;
    bool connection_closed = false;
    served = process_request(stream, /*close_connection=*/true, connection_closed, nullptr);
    current_connection = nullptr;
    const std::lock_guard<std::mutex> lock(mutex_);
    open_.erase(&connection);
  } else {
    refuse_busy(sock);
  }
  ::shutdown(sock, SHUT_RDWR);
  ::close(sock);
  return served;
}

}  // namespace dashboard
