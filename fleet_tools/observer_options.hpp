// The DDS options of the fleet's observer programs (ctsfleet-task, ctsfleet-dashboard): which
// middleware, domain, network and identity to join the fleet with, checked before the middleware
// starts (a bad value ends the program with exit 2 naming it).
#pragma once

#include <CLI/CLI.hpp>

#include <string>

#include "ctsfleet/data_dir.hpp"
#include "ctsfleet/program.hpp"
#include "fleet_transport/transport.hpp"

namespace ctsfleet {

struct ObserverOptions {
  std::string vendor = "cyclone";
  int domain = 0;
  std::string dds_dir;
  std::string network_interface, peers, discovery_server;
  std::string security_dir;
  std::string identity;

  explicit ObserverOptions(std::string default_identity) : identity(std::move(default_identity)) {}

  void add_to(CLI::App& app) {
    app.add_option("--dds", vendor, "DDS implementation")->check(CLI::IsMember({"cyclone", "fastdds"}))->capture_default_str();
    app.add_option("--domain", domain, "DDS domain id")->check(dds_domain())->capture_default_str();
    app.add_option("--dds-config-dir", dds_dir, "folder with the loopback DDS XML files (default: the shipped config/dds)")
        ->check(CLI::ExistingDirectory);
    app.add_option("--iface", network_interface, fleet_transport::kInterfaceHelp);
    app.add_option("--peers", peers, fleet_transport::kPeersHelp);
    app.add_option("--discovery-server", discovery_server, fleet_transport::kDiscoveryServerHelp);
    app.add_option("--security", security_dir, "fleet directory made by ctsfleet-ca (DDS Security)");
    app.add_option("--identity", identity, "the name this program is enrolled as in the fleet directory")
        ->capture_default_str();
  }

  // Throws InputError / std::invalid_argument naming what is wrong.
  fleet_transport::TransportConfig transport_config() const {
    fleet_transport::TransportConfig config;
    config.vendor = fleet_transport::parse_vendor(vendor);
    config.domain_id = domain;
    config.loopback_config_dir = dds_dir.empty() ? data_path("config/dds").string() : dds_dir;
    config.security = fleet_transport::load_fleet_security(security_dir, identity);
    fleet_transport::check_discovery_servers(config.vendor, discovery_server, config.security.enabled());
    fleet_transport::check_network(network_interface, peers);
    config.discovery_servers = discovery_server;
    config.network_interface = network_interface;
    config.peers = peers;
    return config;
  }
};

}  // namespace ctsfleet
