#include "fleet_transport/domain_ports.hpp"

#include <fstream>

namespace fleet_transport {

namespace {

constexpr int kPortBase = 7400;
constexpr int kDomainGain = 250;
constexpr int kLastDomain = 232;  // the highest domain id the default RTPS port mapping allows

bool overlap(PortRange a, PortRange b) { return a.first <= b.last && b.first <= a.last; }

// "A-B" or "A" for the run of domains from `first` to `last`.
std::string domains_text(int first, int last) {
  return first == last ? std::to_string(first) : std::to_string(first) + "-" + std::to_string(last);
}

}  // namespace

PortRange domain_ports(int domain) {
  const int first = kPortBase + kDomainGain * domain;
  return {first, first + kDomainGain - 1};
}

std::optional<PortRange> kernel_ephemeral_ports() {
  std::ifstream file("/proc/sys/net/ipv4/ip_local_port_range");
  PortRange range;
  if (!(file >> range.first >> range.last) || range.first > range.last) return std::nullopt;
  return range;
}

std::optional<std::string> ephemeral_port_warning(int domain, PortRange ephemeral) {
  const PortRange ports = domain_ports(domain);
  if (!overlap(ports, ephemeral)) return std::nullopt;
  std::string safe;
  for (int d = 0; d <= kLastDomain;) {  // runs of domains clear of the ephemeral range
    if (overlap(domain_ports(d), ephemeral)) {
      ++d;
      continue;
    }
    int last = d;
    while (last + 1 <= kLastDomain && !overlap(domain_ports(last + 1), ephemeral)) ++last;
    safe += (safe.empty() ? "" : " or ") + domains_text(d, last);
    d = last + 1;
  }
  return "DDS domain " + std::to_string(domain) + " uses UDP ports " + std::to_string(ports.first) + "-" +
         std::to_string(ports.last) + ", inside this host's ephemeral ports " + std::to_string(ephemeral.first) + "-" +
         std::to_string(ephemeral.last) +
         " (net.ipv4.ip_local_port_range): any program's socket may take one and participants then miss each "
         "other; use domain " +
         (safe.empty() ? std::string("ports outside that range") : safe);
}

}  // namespace fleet_transport
