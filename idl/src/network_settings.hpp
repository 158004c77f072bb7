// The DDS configuration of a fleet on a network rather than on loopback.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "fleet_transport/transport.hpp"

namespace fleet_transport {

struct HostPort {
  std::string host;  // IPv4, dotted
  uint16_t port = 0;
};
// "A.B.C.D:PORT", or std::invalid_argument naming `what` and the text.
HostPort parse_host_port(const std::string& text, const std::string& what);

// Cyclone DDS's configuration (XML text, as CYCLONEDDS_URI takes it) for interface `address`:
// multicast discovery, or unicast to `peers` when there are any.
std::string cyclone_network_config(const std::string& address, const std::vector<std::string>& peers);

}  // namespace fleet_transport
