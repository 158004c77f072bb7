// What every Fast DDS participant of the fleet shares: its QoS (profile file, DDS Security,
// discovery through servers) and where the middleware's log goes.
#pragma once

#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include <string>

#include "fleet_transport/security.hpp"
#include "fleet_transport/transport.hpp"

namespace fleet_transport {

// The participant QoS of the profile file, plus DDS Security with the builtin plugins when
// `security` is on. With `discovery_servers` ("HOST:PORT;HOST:PORT", the syntax of Fast DDS's
// ROS_DISCOVERY_SERVER; server i is the one started with --server-id i) the participant is a
// client of those servers and discovers only what it matches through them. Throws
// std::invalid_argument when the list does not parse.
// On a network (config.network_interface set), the QoS is made here: UDPv4 on that interface,
// multicast discovery, or unicast discovery to config.peers.
eprosima::fastdds::dds::DomainParticipantQos fastdds_participant_qos(const TransportConfig& config);

// The QoS of discovery server `server_id` listening on `listen` ("HOST:PORT").
// Open only: see kSecureDiscoveryServerUnsupported.
eprosima::fastdds::dds::DomainParticipantQos fastdds_server_qos(int server_id, const std::string& listen);

// Fast DDS's log (errors and warnings, e.g. an access-control denial) goes to the process's log,
// each line once a minute at most, instead of to stdout in colour.
void route_fastdds_log();

}  // namespace fleet_transport
