#include "fastdds_participant.hpp"

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/log/Log.hpp>
#include <fastdds/rtps/attributes/ServerAttributes.h>
#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>

#include <mutex>
#include <stdexcept>

#include "fleet_transport/transport.hpp"
#include "middleware_log.hpp"
#include "network_settings.hpp"

namespace fleet_transport {

using namespace eprosima::fastdds::dds;
using eprosima::fastrtps::rtps::DiscoveryProtocol_t;

namespace {

void add_security(const SecurityFiles& files, DomainParticipantQos& qos) {
  if (!files.enabled()) return;
  auto& properties = qos.properties().properties();
  const auto file = [](const std::string& path) { return "file://" + path; };  // Fast DDS wants file://
  properties.emplace_back("dds.sec.auth.plugin", "builtin.PKI-DH");
  properties.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_ca", file(files.identity_ca));
  properties.emplace_back("dds.sec.auth.builtin.PKI-DH.identity_certificate", file(files.identity_certificate));
  properties.emplace_back("dds.sec.auth.builtin.PKI-DH.private_key", file(files.private_key));
  properties.emplace_back("dds.sec.access.plugin", "builtin.Access-Permissions");
  properties.emplace_back("dds.sec.access.builtin.Access-Permissions.permissions_ca", file(files.permissions_ca));
  properties.emplace_back("dds.sec.access.builtin.Access-Permissions.governance", file(files.governance));
  properties.emplace_back("dds.sec.access.builtin.Access-Permissions.permissions", file(files.permissions));
  properties.emplace_back("dds.sec.crypto.plugin", "builtin.AES-GCM-GMAC");
}

DomainParticipantQos profile_qos() {
  auto* factory = DomainParticipantFactory::get_instance();
  factory->load_profiles();
  DomainParticipantQos qos;
  factory->get_default_participant_qos(qos);
  return qos;
}

constexpr uint32_t kSocketBufferBytes = 4 << 20;

// UDPv4 on `address` only (no shared memory: the fleet's processes may be on other hosts).
void use_interface(const std::string& address, DomainParticipantQos& qos) {
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.push_back(address);
  udp->maxInitialPeersRange = 115;  // a peer host may run up to 115 participants of the domain
  // Room for a burst of discovery from a hundred participants, as in the loopback files (the
  // kernel caps it at net.core.rmem_max / wmem_max).
  udp->receiveBufferSize = kSocketBufferBytes;
  udp->sendBufferSize = kSocketBufferBytes;
  qos.transport().user_transports.push_back(udp);
  qos.transport().use_builtin_transports = false;
}

}  // namespace

DomainParticipantQos fastdds_participant_qos(const TransportConfig& config) {
  const SecurityFiles& security = config.security;
  const std::string& discovery_servers = config.discovery_servers;
  DomainParticipantQos qos = PARTICIPANT_QOS_DEFAULT;
  if (config.network_interface.empty()) {
    qos = profile_qos();
  } else {
    use_interface(interface_address(config.network_interface), qos);
    for (const std::string& peer : parse_peers(config.peers)) {
      eprosima::fastrtps::rtps::Locator_t locator;
      eprosima::fastrtps::rtps::IPLocator::setIPv4(locator, peer);
      qos.wire_protocol().builtin.initialPeersList.push_back(locator);
    }
  }
  add_security(security, qos);
  if (discovery_servers.empty()) return qos;  // the list was checked by make_transport
  auto& discovery = qos.wire_protocol().builtin.discovery_config;
  eprosima::fastdds::rtps::RemoteServerList_t servers;
  if (!eprosima::fastdds::rtps::load_environment_server_info(discovery_servers, servers) || servers.empty()) {
    throw std::invalid_argument("discovery servers '" + discovery_servers + "': expected HOST:PORT;HOST:PORT");
  }
  discovery.discoveryProtocol = DiscoveryProtocol_t::CLIENT;
  discovery.m_DiscoveryServers = servers;
  // A client talks to its servers only: the profile's initial peers (every participant port on
  // the host) would bring back the all-pairs traffic the servers are there to avoid.
  qos.wire_protocol().builtin.initialPeersList.clear();
  return qos;
}

DomainParticipantQos fastdds_server_qos(int server_id, const std::string& listen) {
  const HostPort address = parse_host_port(listen, "--listen");
  DomainParticipantQos qos = PARTICIPANT_QOS_DEFAULT;
  if (address.host.rfind("127.", 0) == 0) {
    qos = profile_qos();  // the loopback file's transport
  } else {
    use_interface(address.host, qos);
  }
  auto& builtin = qos.wire_protocol().builtin;
  // A backup server keeps what it knows in a file of the working directory, so that a server
  // restarted with the same id (the same GUID prefix) carries on where it stopped: a plain
  // server starting over is ignored by the clients that knew it (they have seen its sequence
  // numbers already) and a robot that joins then is never heard by the coordinator.
  builtin.discovery_config.discoveryProtocol = DiscoveryProtocol_t::BACKUP;
  if (!eprosima::fastdds::rtps::get_server_client_default_guidPrefix(server_id, qos.wire_protocol().prefix)) {
    throw std::invalid_argument("server id " + std::to_string(server_id) + " out of range (0-255)");
  }
  builtin.metatrafficUnicastLocatorList.clear();
  eprosima::fastrtps::rtps::Locator_t locator;
  eprosima::fastrtps::rtps::IPLocator::setIPv4(locator, address.host);
  locator.port = address.port;
  builtin.metatrafficUnicastLocatorList.push_back(locator);
  builtin.initialPeersList.clear();
  return qos;
}

namespace {

class LogToProcess : public LogConsumer {
 public:
  void Consume(const Log::Entry& entry) override {
    // Every robot's channels sit in its own partition, so a writer and a reader of one topic in
    // different partitions are the fleet working as meant, not a fault an operator should see.
    if (entry.message.find("Different Partitions") != std::string::npos) {
      spdlog::debug("Fast DDS: {}", entry.message);
      return;
    }
    filter_.log("Fast DDS", entry.kind == Log::Kind::Error, entry.message);
  }

 private:
  RepeatedLineFilter filter_;
};

}  // namespace

void route_fastdds_log() {
  static std::once_flag once;
  std::call_once(once, [] {
    Log::ClearConsumers();
    Log::RegisterConsumer(std::make_unique<LogToProcess>());
    Log::SetVerbosity(Log::Kind::Warning);
  });
}

}  // namespace fleet_transport
