#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <thread>

#include <spdlog/spdlog.h>

#include "fleet_transport/domain_ports.hpp"
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

std::string describe_network(const TransportConfig& config) {
  std::string where;
  if (!config.discovery_servers.empty()) {
    where = "discovery server " + config.discovery_servers;
  } else if (!config.network_interface.empty()) {
    where = "interface " + config.network_interface +
            (config.peers.empty() ? ", multicast discovery" : ", unicast to " + config.peers);
  } else {
    where = "loopback, DDS config " +
            (config.loopback_config_dir.empty() ? std::string("the middleware's default") : config.loopback_config_dir);
  }
  if (config.security.enabled()) where += ", DDS Security";
  return std::string(to_string(config.vendor)) + " domain " + std::to_string(config.domain_id) + " (" + where + ")";
}

std::string options_to_join(const TransportConfig& config) {
  std::string options = "--dds " + std::string(to_string(config.vendor)) + " --domain " + std::to_string(config.domain_id);
  if (!config.network_interface.empty()) {
    options += " --iface <its interface on this network>";
    if (!config.peers.empty()) options += " --peers " + config.peers;
  } else if (!config.loopback_config_dir.empty()) {
    options += " --dds-config-dir " + config.loopback_config_dir;
  }
  if (!config.discovery_servers.empty()) options += " --discovery-server '" + config.discovery_servers + "'";
  if (config.security.enabled()) options += " --security <its fleet directory>";
  if (!config.network_interface.empty() && config.peers.empty() && config.discovery_servers.empty()) {
    options += ", on a network that carries multicast between the hosts (or give both --peers)";
  }
  return options;
}

std::unique_ptr<Transport> make_transport(const TransportConfig& config, Handlers handlers) {
  check_network(config.network_interface, config.peers);
  check_discovery_servers(config.vendor, config.discovery_servers, config.security.enabled());
  if (const auto ephemeral = kernel_ephemeral_ports()) {
    if (const auto warning = ephemeral_port_warning(config.domain_id, *ephemeral)) spdlog::warn("{}", *warning);
  }
  // The middleware reads its configuration file from the environment at participant creation.
  if (!config.network_interface.empty()) {
    // A network: no loopback files. Cyclone takes its configuration as XML text; Fast DDS's QoS
    // is made in code (fastdds_participant_qos).
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
  if (config.vendor == Vendor::kCyclone) return make_cyclone_transport(config, std::move(handlers));
  return make_fastdds_transport(config, std::move(handlers));
}

}  // namespace fleet_transport
