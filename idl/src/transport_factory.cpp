#include <cstdlib>

#include "transport_factories.hpp"

namespace fleet_transport {

std::unique_ptr<Transport> make_transport(const TransportConfig& config, Handlers handlers) {
  // The middleware reads its configuration file from the environment at participant creation.
  if (const std::string& dir = config.loopback_config_dir; !dir.empty()) {
    setenv("CYCLONEDDS_URI", ("file://" + dir + "/cyclonedds-loopback.xml").c_str(), 0);
    setenv("FASTRTPS_DEFAULT_PROFILES_FILE", (dir + "/fastdds-loopback.xml").c_str(), 0);
  }
  if (config.vendor == Vendor::kCyclone) return make_cyclone_transport(config, std::move(handlers));
  return make_fastdds_transport(config, std::move(handlers));
}

}  // namespace fleet_transport
