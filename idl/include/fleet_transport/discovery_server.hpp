// A Fast DDS discovery server for the fleet: participants started with discovery servers
// (TransportConfig::discovery_servers) send their discovery traffic to it only, and it tells
// each of them about the participants it shares a topic with. A robot then discovers its
// coordinators and observers but never the other robots: discovery grows with the fleet instead
// of with its square (with DDS Security, each discovery is a certificate handshake).
#pragma once

#include <functional>
#include <memory>
#include <string>


namespace fleet_transport {

struct DiscoveryServerConfig {
  int domain_id = 0;
  int server_id = 0;                    // clients list server i at position i
  std::string listen = "127.0.0.1:11811";  // IPv4 HOST:PORT the clients reach it at
  std::string loopback_config_dir;      // as in TransportConfig
  // Participants seen and lost, failed authentications; on the middleware's threads.
  std::function<void(const std::string& event)> on_event;
};

// std::invalid_argument naming --listen when `listen` is not an IPv4 HOST:PORT: checked before a
// server's state directory is made.
void check_listen_address(const std::string& listen);

class DiscoveryServer {
 public:
  // Throws std::invalid_argument on a bad address or id, std::runtime_error when the
  // middleware cannot start the server (e.g. the port is taken).
  explicit DiscoveryServer(const DiscoveryServerConfig& config);
  ~DiscoveryServer();
  DiscoveryServer(const DiscoveryServer&) = delete;
  DiscoveryServer& operator=(const DiscoveryServer&) = delete;

  int participants() const;  // clients known now

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace fleet_transport
