// The two transport implementations, each in its own library with its own generated types.
#pragma once

#include "fleet_transport/transport.hpp"

namespace fleet_transport {

std::unique_ptr<Transport> make_cyclone_transport(const TransportConfig& config, Handlers handlers);
std::unique_ptr<Transport> make_fastdds_transport(const TransportConfig& config, Handlers handlers);

}  // namespace fleet_transport
