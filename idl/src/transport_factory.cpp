#include <arpa/inet.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <thread>

#include "network_settings.hpp"
#include "transport_factories.hpp"

namespace fleet_transport {

void exit_if_shutdown_hangs(double seconds, int exit_code) {
  std::thread([seconds, exit_code] {
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    std::fprintf(stderr, "the middleware did not shut down within %.1f s: exiting anyway\n", seconds);
    std::fflush(nullptr);
    _exit(exit_code);
  }).detach();
}

void check_discovery_servers(Vendor vendor, const std::string& servers, bool secure) {
  if (servers.empty()) return;
  if (secure) throw std::invalid_argument(kSecureDiscoveryServerUnsupported);
  if (vendor == Vendor::kCyclone) {
    throw std::invalid_argument("discovery servers (" + servers +
                                ") are a Fast DDS option: Cyclone DDS discovers through its config file's peers");
  }
  std::size_t from = 0;
  while (from <= servers.size()) {
    const std::size_t to = std::min(servers.find(';', from), servers.size());
    const std::string entry = servers.substr(from, to - from);
    from = to + 1;
    if (entry.empty() && to == servers.size() && !servers.empty() && servers.back() == ';') break;  // "A:P;"
    const std::size_t colon = entry.rfind(':');
    in_addr address{};
    const std::string host = colon == std::string::npos ? entry : entry.substr(0, colon);
    const std::string port = colon == std::string::npos ? "" : entry.substr(colon + 1);
    const bool port_ok = !port.empty() && port.size() <= 5 &&
                         port.find_first_not_of("0123456789") == std::string::npos && std::stoi(port) >= 1 &&
                         std::stoi(port) <= 65535;
    if (!port_ok || inet_pton(AF_INET, host.c_str(), &address) != 1) {
      throw std::invalid_argument("discovery server '" + entry + "' in '" + servers +
                                  "' is not an IPv4 HOST:PORT (e.g. 127.0.0.1:11811)");
    }
  }
}

std::unique_ptr<Transport> make_transport(const TransportConfig& config, Handlers handlers) {
  // The middleware reads its configuration file from the environment at participant creation.
  const bool on_network = !config.network_interface.empty() || !config.peers.empty();
  if (on_network) {
    // A network: no loopback files. Cyclone takes its configuration as XML text; Fast DDS's QoS
    // is made in code (fastdds_participant_qos).
    if (config.network_interface.empty()) {
      throw std::invalid_argument("peers (" + config.peers + ") need a network interface (--iface) to reach them on");
    }
    const std::string address = interface_address(config.network_interface);
    if (config.vendor == Vendor::kCyclone) {
      setenv("CYCLONEDDS_URI", cyclone_network_config(address, parse_peers(config.peers)).c_str(), 1);
    }
  } else if (const std::string& dir = config.loopback_config_dir; !dir.empty()) {
    // Robot agents (they read one robot's commands) discover coordinators and observers only.
    const bool agent = !config.commands_for.empty();
    const char* cyclone_file = agent ? "/cyclonedds-loopback-agent.xml" : "/cyclonedds-loopback.xml";
    // (Fast DDS agents that discover through a server take the common file: with the agents' one,
    // a coordinator heard none of 100 agents through the server; measured, not understood.)
    const bool fastdds_agent = agent && config.discovery_servers.empty();
    const char* fastdds_file = fastdds_agent ? "/fastdds-loopback-agent.xml" : "/fastdds-loopback.xml";
    setenv("CYCLONEDDS_URI", ("file://" + dir + cyclone_file).c_str(), 0);
    setenv("FASTRTPS_DEFAULT_PROFILES_FILE", (dir + fastdds_file).c_str(), 0);
  }
  check_discovery_servers(config.vendor, config.discovery_servers, config.security.enabled());
  if (config.vendor == Vendor::kCyclone) return make_cyclone_transport(config, std::move(handlers));
  return make_fastdds_transport(config, std::move(handlers));
}

}  // namespace fleet_transport
