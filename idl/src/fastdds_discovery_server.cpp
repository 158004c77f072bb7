#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/log/Log.hpp>

#include <atomic>
#include <sstream>
#include <stdexcept>

#include "fastdds_participant.hpp"
#include "fleet_transport/discovery_server.hpp"
#include "network_settings.hpp"

namespace fleet_transport {

using namespace eprosima::fastdds::dds;
using eprosima::fastrtps::rtps::ParticipantDiscoveryInfo;

namespace {

std::string prefix_of(const eprosima::fastrtps::rtps::GUID_t& guid) {
  std::ostringstream text;
  text << guid.guidPrefix;
  return text.str();
}

class ParticipantEvents : public DomainParticipantListener {
 public:
  std::function<void(const std::string&)> on_event;
  std::atomic<int> participants{0};

  void on_participant_discovery(DomainParticipant*, ParticipantDiscoveryInfo&& info) override {
    const std::string who = std::string(info.info.m_participantName.c_str()) + " (" + prefix_of(info.info.m_guid) + ")";
    switch (info.status) {
      case ParticipantDiscoveryInfo::DISCOVERED_PARTICIPANT:
        ++participants;
        say("participant joined: " + who);
        break;
      case ParticipantDiscoveryInfo::REMOVED_PARTICIPANT:
        --participants;
        say("participant left: " + who);
        break;
      case ParticipantDiscoveryInfo::DROPPED_PARTICIPANT:
        --participants;
        say("participant lost (lease expired): " + who);
        break;
      default:
        break;
    }
  }

 private:
  void say(const std::string& event) {
    if (on_event) on_event(event);
  }
};

}  // namespace

void check_listen_address(const std::string& listen) { parse_host_port(listen, "--listen"); }

struct DiscoveryServer::Impl {
  ParticipantEvents events;  // first: the listener outlives the participant
  DomainParticipant* participant = nullptr;

  ~Impl() {
    if (participant) DomainParticipantFactory::get_instance()->delete_participant(participant);
  }
};

DiscoveryServer::DiscoveryServer(const DiscoveryServerConfig& config) : impl_(std::make_unique<Impl>()) {
  if (const std::string& dir = config.loopback_config_dir; !dir.empty()) {
    setenv("FASTRTPS_DEFAULT_PROFILES_FILE", (dir + "/fastdds-loopback.xml").c_str(), 0);
  }
  route_fastdds_log();
  impl_->events.on_event = config.on_event;
  const DomainParticipantQos qos = fastdds_server_qos(config.server_id, config.listen);
  impl_->participant = DomainParticipantFactory::get_instance()->create_participant(
      config.domain_id, qos, &impl_->events, StatusMask::none());
  if (!impl_->participant) {
    Log::Flush();
    throw std::runtime_error("Fast DDS: cannot start discovery server " + std::to_string(config.server_id) + " on " +
                             config.listen + " (port in use, or the address is not one of this host's)");
  }
}

DiscoveryServer::~DiscoveryServer() = default;

int DiscoveryServer::participants() const { return impl_->events.participants.load(); }

}  // namespace fleet_transport
