// Interfaces and peers of a fleet on a network (see TransportConfig::network_interface, peers),
// and the Cyclone DDS configuration they make.
#include <arpa/inet.h>
#include <ifaddrs.h>
#include <net/if.h>

#include <sstream>
#include <stdexcept>

#include "network_settings.hpp"

namespace fleet_transport {

namespace {

bool is_ipv4(const std::string& text) {
  in_addr address{};
  return inet_pton(AF_INET, text.c_str(), &address) == 1;
}

}  // namespace

HostPort parse_host_port(const std::string& text, const std::string& what) {
  const std::size_t colon = text.rfind(':');
  const std::string host = colon == std::string::npos ? text : text.substr(0, colon);
  const std::string port = colon == std::string::npos ? "" : text.substr(colon + 1);
  const bool port_ok = !port.empty() && port.size() <= 5 && port.find_first_not_of("0123456789") == std::string::npos &&
                       std::stoi(port) >= 1 && std::stoi(port) <= 65535;
  if (!port_ok || !is_ipv4(host)) {
    throw std::invalid_argument(what + " '" + text + "' is not an IPv4 HOST:PORT (e.g. 127.0.0.1:11811)");
  }
  return {host, static_cast<uint16_t>(std::stoi(port))};
}

void check_discovery_servers(Vendor vendor, const std::string& servers, bool secure) {
  if (servers.empty()) return;
  if (secure) throw std::invalid_argument(kSecureDiscoveryServerUnsupported);
  if (vendor == Vendor::kCyclone) {
    throw std::invalid_argument("discovery servers (" + servers +
                                ") are a Fast DDS option: Cyclone DDS discovers through its config file's peers");
  }
  std::size_t from = 0;
  for (;;) {  // every entry but an empty last one ("A:P;")
    const std::size_t semicolon = servers.find(';', from);
    const std::string entry = servers.substr(from, semicolon == std::string::npos ? std::string::npos : semicolon - from);
    if (semicolon == std::string::npos && entry.empty()) return;
    parse_host_port(entry, "discovery server in '" + servers + "':");
    if (semicolon == std::string::npos) return;
    from = semicolon + 1;
  }
}

std::string interface_address(const std::string& name_or_address) {
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) throw std::runtime_error("cannot list this host's network interfaces");
  std::string found, known;
  for (const ifaddrs* entry = list; entry; entry = entry->ifa_next) {
    if (!entry->ifa_addr || entry->ifa_addr->sa_family != AF_INET) continue;
    char text[INET_ADDRSTRLEN] = {};
    inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in*>(entry->ifa_addr)->sin_addr, text, sizeof text);
    known += std::string(known.empty() ? "" : ", ") + entry->ifa_name + " " + text;
    if (found.empty() && (name_or_address == entry->ifa_name || name_or_address == text)) found = text;
  }
  freeifaddrs(list);
  if (found.empty()) {
    throw std::invalid_argument("network interface '" + name_or_address +
                                "': no such interface with an IPv4 address on this host (it has: " + known + ")");
  }
  return found;
}

std::vector<std::string> parse_peers(const std::string& peers) {
  std::vector<std::string> result;
  if (peers.empty()) return result;
  std::size_t from = 0;
  for (;;) {  // every entry, empty ones too ("a,,b", "a,")
    const std::size_t comma = peers.find(',', from);
    const std::string peer = peers.substr(from, comma == std::string::npos ? std::string::npos : comma - from);
    if (!is_ipv4(peer)) {
      throw std::invalid_argument("peer '" + peer + "' in '" + peers + "' is not an IPv4 address (A.B.C.D,A.B.C.D)");
    }
    result.push_back(peer);
    if (comma == std::string::npos) return result;
    from = comma + 1;
  }
}

void check_network(const std::string& network_interface, const std::string& peers) {
  if (!peers.empty() && network_interface.empty()) {
    throw std::invalid_argument("peers (" + peers + ") need a network interface (--iface) to reach them on");
  }
  if (!network_interface.empty()) interface_address(network_interface);
  parse_peers(peers);
}

std::string cyclone_network_config(const std::string& address, const std::vector<std::string>& peers) {
  std::ostringstream xml;
  xml << "<CycloneDDS><Domain id=\"any\"><General><Interfaces><NetworkInterface address=\"" << address
      << "\"/></Interfaces>";
  if (!peers.empty()) xml << "<AllowMulticast>false</AllowMulticast>";
  xml << "</General><Discovery>";
  if (!peers.empty()) {
    // Unicast discovery reaches the ports of participant indices on each peer.
    xml << "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>115</MaxAutoParticipantIndex><Peers>";
    for (const std::string& peer : peers) xml << "<Peer address=\"" << peer << "\"/>";
    xml << "</Peers>";
  }
  xml << "</Discovery></Domain></CycloneDDS>";
  return xml.str();
}

}  // namespace fleet_transport
