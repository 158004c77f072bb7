// The UDP ports of a DDS domain, and the kernel's ephemeral ports they may collide with.
//
// Both vendors give domain d the ports 7400 + 250 d to 7400 + 250 d + 249 (the RTPS defaults:
// port base 7400, domain gain 250, participant gain 2). Linux hands out its ephemeral ports
// (32768-60999 by default) to any socket bound to port 0, DDS's own sending sockets included: a
// domain whose ports fall in that range can find one of them taken, and the participant that
// wanted it moves to another port where its peers do not look for it. Seen on domain 205: two of
// five Fast DDS fleets bound nothing.
#pragma once

#include <optional>
#include <string>

namespace fleet_transport {

struct PortRange {
  int first = 0;
  int last = 0;  // inclusive
};

PortRange domain_ports(int domain);

// The kernel's ephemeral range (/proc/sys/net/ipv4/ip_local_port_range), or nullopt if unreadable.
std::optional<PortRange> kernel_ephemeral_ports();

// A one-line warning, naming the domains outside `ephemeral`, when `domain`'s ports fall inside it.
std::optional<std::string> ephemeral_port_warning(int domain, PortRange ephemeral);

}  // namespace fleet_transport
