#include <cstdlib>

#include "transport_factories.hpp"

namespace fleet_transport {

std::unique_ptr<Transport> make_transport(const TransportConfig& config, Handlers handlers) {
  // The middleware reads its configuration file from the environment at participant creation.
  if (!config.cyclone_xml.empty()) setenv("CYCLONEDDS_URI", ("file://" + config.cyclone_xml).c_str(), 0);
  if (!config.fastdds_xml.empty()) setenv("FASTRTPS_DEFAULT_PROFILES_FILE", config.fastdds_xml.c_str(), 0);
  if (config.vendor == Vendor::kCyclone) return make_cyclone_transport(config, std::move(handlers));
  return make_fastdds_transport(config, std::move(handlers));
}

}  // namespace fleet_transport
