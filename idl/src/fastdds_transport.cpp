// Transport over Fast DDS 2.9 (C++ API) with the fastddsgen-generated types.
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/log/Log.hpp>
#include <fastdds/rtps/writer/WriterDiscoveryInfo.h>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <spdlog/spdlog.h>

#include <chrono>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <stdexcept>

#include "fleet_transport/background_opener.hpp"
#include "fastdds_codec.hpp"
#include "fastdds_participant.hpp"
#include "fleet.h"
#include "middleware_log.hpp"
#include "topic_qos.hpp"
#include "fleetPubSubTypes.h"
#include "transport_factories.hpp"

namespace fleet_transport {

namespace {

using namespace eprosima::fastdds::dds;

// A listener that takes every sample of one topic and passes it to `deliver`.
template <typename Wire>
class TakeAll : public DataReaderListener {
 public:
  using Deliver = std::function<void(const Wire&, const SampleInfo&)>;
  explicit TakeAll(Deliver deliver) : deliver_(std::move(deliver)) {}
  void on_data_available(DataReader* reader) override {
    Wire sample;
    SampleInfo info;
    while (reader->take_next_sample(&sample, &info) == ReturnCode_t::RETCODE_OK) deliver_(sample, info);
  }

 private:
  Deliver deliver_;
};

// Fast DDS readers and writers keep at most 10 instances by default, and every robot is an
// instance (the topics are keyed by robot id): a coordinator would hear only 10 robots. Room for
// a fleet of kMaxRobots, each keeping `depth` samples.
constexpr int32_t kMaxRobots = 1000;
void room_for_the_fleet(ResourceLimitsQosPolicy& limits, int32_t depth) {
  limits.max_instances = kMaxRobots;
  limits.max_samples_per_instance = depth;
  limits.max_samples = kMaxRobots * depth;
}

// What writers and readers of a topic share: reliability, durability, history, deadline,
// ownership, room for the fleet.
template <typename Qos>
void set_shared_qos(Qos& qos, const TopicQos& topic, const TransportConfig& config) {
  qos.reliability().kind = topic.reliable ? RELIABLE_RELIABILITY_QOS : BEST_EFFORT_RELIABILITY_QOS;
  qos.durability().kind = topic.transient_local ? TRANSIENT_LOCAL_DURABILITY_QOS : VOLATILE_DURABILITY_QOS;
  qos.history().kind = KEEP_LAST_HISTORY_QOS;
  qos.history().depth = topic.depth;
  if (topic.liveliness) {
    qos.liveliness().kind = AUTOMATIC_LIVELINESS_QOS;
    qos.liveliness().lease_duration = eprosima::fastrtps::Duration_t(config.lease_s);
  }
  if (topic.deadline) qos.deadline().period = eprosima::fastrtps::Duration_t(2 * config.lease_s);
  if (topic.exclusive) qos.ownership().kind = EXCLUSIVE_OWNERSHIP_QOS;
  if (topic.per_robot) room_for_the_fleet(qos.resource_limits(), topic.depth);
}

// A writer's QoS from the topic's (topic_qos.hpp).
DataWriterQos writer_qos(const TopicQos& topic, const TransportConfig& config) {
  DataWriterQos qos = DATAWRITER_QOS_DEFAULT;
  set_shared_qos(qos, topic, config);
  // 100 ms: late joiners (Cyclone's readers among them) are prompted soon.
  if (topic.reliable) qos.reliable_writer_qos().times.heartbeatPeriod = eprosima::fastrtps::Duration_t(0, 100000000);
  if (topic.liveliness) qos.liveliness().announcement_period = eprosima::fastrtps::Duration_t(config.lease_s / 3);
  if (topic.exclusive) qos.ownership_strength().value = static_cast<uint32_t>(config.command_strength);
  if (!topic.dispose_on_unregister) qos.writer_data_lifecycle().autodispose_unregistered_instances = false;
  return qos;
}

// A reader's QoS from the topic's (topic_qos.hpp).
DataReaderQos reader_qos(const TopicQos& topic, const TransportConfig& config) {
  DataReaderQos qos = DATAREADER_QOS_DEFAULT;
  set_shared_qos(qos, topic, config);
  return qos;
}

// Remembers the partitions of every writer the participant discovers, so that a state or
// announcement can be checked against the partition it was written in (Fast DDS 2.9 does not
// implement DataReader::get_matched_publication_data); reports participants refused by
// authentication.
class WriterPartitions : public DomainParticipantListener {
 public:
  std::function<void(const std::string&)> on_refused;

  void onParticipantAuthentication(DomainParticipant*, eprosima::fastrtps::rtps::ParticipantAuthenticationInfo&& info) override {
    if (info.status != eprosima::fastrtps::rtps::ParticipantAuthenticationInfo::UNAUTHORIZED_PARTICIPANT || !on_refused) return;
    std::ostringstream guid;
    guid << info.guid.guidPrefix;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (!refused_.insert(guid.str()).second) return;  // said once per participant
    }
    on_refused("participant " + guid.str() + " failed authentication (no certificate of this fleet's CA, or an "
               "expired, revoked or changed one): not admitted");
  }

  void on_publisher_discovery(DomainParticipant*, eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override {
    using Status = eprosima::fastrtps::rtps::WriterDiscoveryInfo;
    const std::lock_guard<std::mutex> lock(mutex_);
    if (info.status == Status::REMOVED_WRITER) {
      writers_.erase(info.info.guid());
      return;
    }
    Writer& writer = writers_[info.info.guid()];
    writer.partitions = info.info.m_qos.m_partition.names();
  }
  // True when `robot_id`'s message from writer `guid` came in the robot's own partition; else
  // the first time for this writer and robot, `refusal` says why not.
  bool own(const eprosima::fastrtps::rtps::GUID_t& guid, const std::string& robot_id, std::string& refusal) {
    const std::lock_guard<std::mutex> lock(mutex_);
    Writer& writer = writers_[guid];  // a local writer is not "discovered": no partitions, refused
    if (written_in_own_partition(robot_id, writer.partitions)) return true;
    if (writer.reported.insert(robot_id).second) {
      std::string where;
      for (const std::string& p : writer.partitions) where += (where.empty() ? "" : ",") + p;
      refusal = "a message about robot '" + robot_id + "' written in partition '" + where + "', not in its own (" +
                command_partition(robot_id) + "): dropped";
    }
    return false;
  }

 private:
  struct Writer {
    std::vector<std::string> partitions;
    std::set<std::string> reported;
  };
  std::mutex mutex_;
  std::map<eprosima::fastrtps::rtps::GUID_t, Writer> writers_;
  std::set<std::string> refused_;  // participants whose failed authentication was reported
};

class FastDdsTransport : public Transport {
 public:
  FastDdsTransport(const TransportConfig& config, Handlers handlers)
      : handlers_(std::move(handlers)), commands_for_(config.commands_for), test_partition_of_(config.test_partition_of) {
    try {
      set_up(config);
    } catch (...) {  // e.g. access control refused a reader: nothing may outlive this object
      tear_down();
      throw;
    }
  }

  ~FastDdsTransport() override { tear_down(); }

 private:
  void tear_down() {
    command_channel_opener_.stop();
    if (!participant_) return;
    // Readers first, so no listener runs while the rest goes away.
    for (DataReader* reader : readers_) const_cast<Subscriber*>(reader->get_subscriber())->delete_datareader(reader);
    readers_.clear();
    participant_->delete_contained_entities();
    DomainParticipantFactory::get_instance()->delete_participant(participant_);
    participant_ = nullptr;
  }

  void set_up(const TransportConfig& config) {
    route_fastdds_log();
    writer_partitions_.on_refused = handlers_.on_refused;
    auto* factory = DomainParticipantFactory::get_instance();
    participant_ = factory->create_participant(config.domain_id, fastdds_participant_qos(config), &writer_partitions_,
                                               StatusMask::none());
    if (!participant_) Log::Flush();  // the reason, from the middleware's log thread, before we exit
    if (!participant_ && config.security.enabled()) {
      throw std::runtime_error("Fast DDS: the security plugins refused " + config.security.participant +
                               "'s identity: its certificate, permissions or governance");
    }
    if (!participant_) throw std::runtime_error("Fast DDS: cannot create a participant");
    publisher_ = participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
    subscriber_ = participant_->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
    if (!publisher_ || !subscriber_) throw std::runtime_error("Fast DDS: cannot create publisher/subscriber");

    registry_w_ = writer_qos(kRegistryQos, config);
    state_w_ = writer_qos(kStateQos, config);
    command_w_ = writer_qos(kCommandQos, config);
    events_w_ = writer_qos(kEventsQos, config);
    requests_w_ = writer_qos(kRequestsQos, config);

    // Writers are made on first use: a process writes few of the topics, and every idle writer
    // would still be matched with every reader of the fleet.
    announcement_topic_ = make_topic<fleet::AnnouncementPubSubType>("rt/fleet/announcement");
    state_topic_ = make_topic<fleet::RobotStatePubSubType>("rt/fleet/robot_state");
    command_topic_ = make_topic<fleet::StepCommandPubSubType>("rt/fleet/step_command");
    status_topic_ = make_topic<fleet::FleetStatusPubSubType>("rt/fleet/fleet_status");
    coordinator_topic_ = make_topic<fleet::CoordinatorStatusPubSubType>("rt/fleet/coordinator_status");
    mission_topic_ = make_topic<fleet::MissionInfoPubSubType>("rt/fleet/mission_info");
    plan_topic_ = make_topic<fleet::FleetPlanPubSubType>("rt/fleet/fleet_plan");
    event_topic_ = make_topic<fleet::FleetEventPubSubType>("rt/fleet/fleet_event");
    request_topic_ = make_topic<fleet::TaskRequestPubSubType>("rt/fleet/task_request");
    reply_topic_ = make_topic<fleet::TaskReplyPubSubType>("rt/fleet/task_reply");
    // The writers a role surely uses are made now, so readers match them before the first sample.
    if (handlers_.on_command && !commands_for_.empty()) robot_writers(commands_for_);
    listen_for_the_handlers(config);
  }

  // A reader for each topic the handlers take, in the partitions they read.
  void listen_for_the_handlers(const TransportConfig& config) {
    const DataReaderQos registry_r = reader_qos(kRegistryQos, config);
    const DataReaderQos state_r = reader_qos(kStateQos, config);
    const DataReaderQos command_r = reader_qos(kCommandQos, config);
    const DataReaderQos events_r = reader_qos(kEventsQos, config);
    const DataReaderQos requests_r = reader_qos(kRequestsQos, config);

    Subscriber* every_robot = nullptr;
    if (handlers_.on_announcement || handlers_.on_robot_gone || handlers_.on_state) {
      every_robot = subscriber_in(kEveryRobotPartition);
    }
    if (handlers_.on_announcement || handlers_.on_robot_gone) {
      listen<fleet::Announcement>(announcement_topic_, registry_r, [this](const fleet::Announcement& w, const SampleInfo& info) {
        on_announcement(w, info);
      }, every_robot);
    }
    if (handlers_.on_state) {
      listen<fleet::RobotState>(state_topic_, state_r, [this](const fleet::RobotState& w, const SampleInfo& info) {
        if (!info.valid_data || !from_own_partition(info, w.robot_id().to_string())) return;
        handlers_.on_state(fastdds_codec::from_wire(w));
      }, every_robot);
    }
    if (handlers_.on_command) {
      Subscriber* command_subscriber =
          subscriber_in(commands_for_.empty() ? std::string(kEveryRobotPartition) : command_partition(commands_for_));
      listen<fleet::StepCommand>(command_topic_, command_r, [this](const fleet::StepCommand& w, const SampleInfo& info) {
        if (!info.valid_data) return;
        if (!commands_for_.empty() && commands_for_ != w.robot_id().to_string()) return;
        handlers_.on_command(fastdds_codec::from_wire(w));
      }, command_subscriber);
    }
    if (handlers_.on_coordinator_status) {
      listen<fleet::CoordinatorStatus>(coordinator_topic_, registry_r, [this](const fleet::CoordinatorStatus& w, const SampleInfo& info) {
        if (info.valid_data) handlers_.on_coordinator_status(fastdds_codec::from_wire(w));
      });
    }
    if (handlers_.on_fleet_status) {
      listen<fleet::FleetStatus>(status_topic_, registry_r, [this](const fleet::FleetStatus& w, const SampleInfo& info) {
        if (info.valid_data) handlers_.on_fleet_status(fastdds_codec::from_wire(w));
      });
    }
    if (handlers_.on_mission_info) {
      listen<fleet::MissionInfo>(mission_topic_, registry_r, [this](const fleet::MissionInfo& w, const SampleInfo& info) {
        if (info.valid_data) handlers_.on_mission_info(fastdds_codec::from_wire(w));
      });
    }
    if (handlers_.on_fleet_plan) {
      listen<fleet::FleetPlan>(plan_topic_, registry_r, [this](const fleet::FleetPlan& w, const SampleInfo& info) {
        if (info.valid_data) handlers_.on_fleet_plan(fastdds_codec::from_wire(w));
      });
    }
    if (handlers_.on_fleet_event) {
      listen<fleet::FleetEvent>(event_topic_, events_r, [this](const fleet::FleetEvent& w, const SampleInfo& info) {
        if (info.valid_data) handlers_.on_fleet_event(fastdds_codec::from_wire(w));
      });
    }
    if (handlers_.on_task_request) {
      listen<fleet::TaskRequest>(request_topic_, requests_r, [this](const fleet::TaskRequest& w, const SampleInfo& info) {
        if (info.valid_data) handlers_.on_task_request(fastdds_codec::from_wire(w));
      });
    }
    if (handlers_.on_task_reply) {
      listen<fleet::TaskReply>(reply_topic_, requests_r, [this](const fleet::TaskReply& w, const SampleInfo& info) {
        if (info.valid_data) handlers_.on_task_reply(fastdds_codec::from_wire(w));
      });
    }
  }


 public:
  void announce(const Announcement& a) override {
    fleet::Announcement wire = fastdds_codec::to_wire(a);
    robot_writers(a.robot_id).announcement->write(&wire);
  }

  void say_goodbye(const std::string& robot_id) override {
    fleet::Announcement wire = fastdds_codec::to_wire(Announcement{.robot_id = robot_id, .leaving = true});
    DataWriter* w = robot_writers(robot_id).announcement;
    w->write(&wire);
    w->dispose(&wire, HANDLE_NIL);  // the key is taken from the sample (2.9 has no lookup_instance)
  }

  void publish_state(const RobotState& s) override {
    fleet::RobotState wire = fastdds_codec::to_wire(s);
    robot_writers(s.robot_id).state->write(&wire);
  }

  void send_command(const StepCommand& c) override {
    fleet::StepCommand wire = fastdds_codec::to_wire(c);
    command_writer(c.robot_id)->write(&wire);
  }

  void open_commands_for(const std::string& robot_id) override { command_writer(robot_id); }
  // In the background: see BackgroundOpener. A command sent before then opens the channel itself.
  void prepare_commands_for(const std::string& robot_id) override { command_channel_opener_.queue(robot_id); }

  void set_command_strength(int strength) override {
    const std::lock_guard<std::mutex> lock(writers_mutex_);
    command_w_.ownership_strength().value = static_cast<uint32_t>(strength);
    for (const auto& [robot_id, writer] : command_writers_) {
      if (writer->set_qos(command_w_) != ReturnCode_t::RETCODE_OK) {
        throw std::runtime_error("Fast DDS: cannot change the command strength of " + robot_id);
      }
    }
  }

  void publish_coordinator_status(const CoordinatorStatus& s) override {
    fleet::CoordinatorStatus wire = fastdds_codec::to_wire(s);
    writer(coordinator_writer_, coordinator_topic_, registry_w_)->write(&wire);
  }

  void publish_fleet_status(const FleetStatus& s) override {
    fleet::FleetStatus wire = fastdds_codec::to_wire(s);
    writer(status_writer_, status_topic_, registry_w_)->write(&wire);
  }

  void publish_mission_info(const MissionInfo& m) override {
    fleet::MissionInfo wire = fastdds_codec::to_wire(m);
    writer(mission_writer_, mission_topic_, registry_w_)->write(&wire);
  }

  void publish_fleet_plan(const FleetPlan& p) override {
    fleet::FleetPlan wire = fastdds_codec::to_wire(p);
    writer(plan_writer_, plan_topic_, registry_w_)->write(&wire);
  }

  void publish_fleet_event(const FleetEvent& e) override {
    fleet::FleetEvent wire = fastdds_codec::to_wire(e);
    writer(event_writer_, event_topic_, events_w_)->write(&wire);
  }

  void request_task(const TaskRequest& r) override {
    fleet::TaskRequest wire = fastdds_codec::to_wire(r);
    writer(request_writer_, request_topic_, requests_w_)->write(&wire);
  }

  void reply_task(const TaskReply& r) override {
    fleet::TaskReply wire = fastdds_codec::to_wire(r);
    writer(reply_writer_, reply_topic_, requests_w_)->write(&wire);
  }

 private:
  template <typename PubSubType>
  Topic* make_topic(const std::string& name) {
    TypeSupport type(new PubSubType());
    type.register_type(participant_);
    Topic* topic = participant_->create_topic(name, type.get_type_name(), TOPIC_QOS_DEFAULT);
    if (!topic) throw std::runtime_error("Fast DDS: cannot create topic " + name);
    return topic;
  }

  DataWriter* writer(DataWriter*& slot, Topic* topic, const DataWriterQos& qos) {
    const std::lock_guard<std::mutex> lock(writers_mutex_);
    if (!slot) {
      slot = publisher_->create_datawriter(topic, qos);
      if (!slot) throw std::runtime_error("Fast DDS: cannot create a writer on " + topic->get_name());
    }
    return slot;
  }

  Publisher* publisher_in(const std::string& partition) {
    PublisherQos qos = PUBLISHER_QOS_DEFAULT;
    qos.partition().push_back(partition.c_str());
    Publisher* publisher = participant_->create_publisher(qos);
    if (!publisher) throw std::runtime_error("Fast DDS: cannot create a publisher in partition " + partition);
    return publisher;
  }
  Subscriber* subscriber_in(const std::string& partition) {
    SubscriberQos qos = SUBSCRIBER_QOS_DEFAULT;
    qos.partition().push_back(partition.c_str());
    Subscriber* subscriber = participant_->create_subscriber(qos);
    if (!subscriber) throw std::runtime_error("Fast DDS: cannot create a subscriber in partition " + partition);
    return subscriber;
  }

  // The command writer of one robot, in that robot's partition (see command_partition).
  DataWriter* command_writer(const std::string& robot_id) {
    {
      const std::lock_guard<std::mutex> lock(writers_mutex_);
      if (const auto found = command_writers_.find(robot_id); found != command_writers_.end()) return found->second;
    }
    // Made outside writers_mutex_ (it can take a second: BackgroundOpener), so that commands to
    // robots whose writers exist go out meanwhile; one at a time, so no robot gets two.
    const std::lock_guard<std::mutex> creating(command_writer_creation_mutex_);
    DataWriterQos qos;
    {
      const std::lock_guard<std::mutex> lock(writers_mutex_);
      if (const auto found = command_writers_.find(robot_id); found != command_writers_.end()) return found->second;
      qos = command_w_;
    }
    DataWriter* writer = publisher_in(command_partition(robot_id))->create_datawriter(command_topic_, qos);
    if (!writer) throw std::runtime_error("Fast DDS: cannot create the command writer of " + robot_id + " (refused by access control?)");
    const std::lock_guard<std::mutex> lock(writers_mutex_);
    // The command strength may have changed while the writer was made (set_command_strength).
    if (command_w_.ownership_strength().value != qos.ownership_strength().value) writer->set_qos(command_w_);
    command_writers_[robot_id] = writer;
    return writer;
  }

  // The announcement and state writers of one robot, in that robot's partition: under DDS
  // Security a robot's permissions allow it to write there only.
  struct RobotWriters {
    DataWriter* announcement = nullptr;
    DataWriter* state = nullptr;
  };
  const RobotWriters& robot_writers(const std::string& robot_id) {
    const std::lock_guard<std::mutex> lock(writers_mutex_);
    RobotWriters& writers = robot_writers_[robot_id];
    if (!writers.state) {
      Publisher* publisher = publisher_in(command_partition(test_partition_of_.empty() ? robot_id : test_partition_of_));
      writers.announcement = publisher->create_datawriter(announcement_topic_, registry_w_);
      writers.state = publisher->create_datawriter(state_topic_, state_w_);
      if (!writers.announcement || !writers.state) {
        throw std::runtime_error("Fast DDS: cannot create the state and announcement writers of " + robot_id +
                                 " (refused by access control?)");
      }
    }
    return writers;
  }

  bool from_own_partition(const SampleInfo& info, const std::string& robot_id) {
    std::string refusal;
    if (writer_partitions_.own(info.sample_identity.writer_guid(), robot_id, refusal)) return true;
    if (!refusal.empty() && handlers_.on_refused) handlers_.on_refused(refusal);
    return false;
  }

  template <typename Wire>
  void listen(Topic* topic, const DataReaderQos& qos, typename TakeAll<Wire>::Deliver deliver,
              Subscriber* subscriber = nullptr) {
    auto listener = std::make_unique<TakeAll<Wire>>(std::move(deliver));
    DataReader* reader = (subscriber ? subscriber : subscriber_)->create_datareader(topic, qos, listener.get());
    if (!reader) throw std::runtime_error("Fast DDS: cannot create a reader on " + topic->get_name());
    listeners_.push_back(std::move(listener));
    readers_.push_back(reader);
  }

  void on_announcement(const fleet::Announcement& w, const SampleInfo& info) {
    if (info.valid_data) {
      const std::string id = w.robot_id().to_string();
      if (!from_own_partition(info, id)) return;
      {
        const std::lock_guard<std::mutex> lock(instances_mutex_);
        robot_of_instance_[info.instance_handle] = id;
      }
      if (handlers_.on_announcement) handlers_.on_announcement(fastdds_codec::from_wire(w));
      return;
    }
    // Invalid samples carry no data here: find the robot by the instance it announced on.
    std::string id;
    {
      const std::lock_guard<std::mutex> lock(instances_mutex_);
      const auto found = robot_of_instance_.find(info.instance_handle);
      if (found == robot_of_instance_.end()) return;
      id = found->second;
    }
    if (!handlers_.on_robot_gone) return;
    if (info.instance_state == NOT_ALIVE_DISPOSED_INSTANCE_STATE) {
      handlers_.on_robot_gone(id, GoneReason::kGoodbye);
    } else if (info.instance_state == NOT_ALIVE_NO_WRITERS_INSTANCE_STATE) {
      handlers_.on_robot_gone(id, GoneReason::kLivelinessLost);
    }
  }

  WriterPartitions writer_partitions_;  // first: the participant's listener outlives the participant
  Handlers handlers_;
  std::string commands_for_;
  std::string test_partition_of_;  // see TransportConfig::test_partition_of
  DomainParticipant* participant_ = nullptr;
  Publisher* publisher_ = nullptr;
  Subscriber* subscriber_ = nullptr;
  DataWriter *status_writer_ = nullptr, *coordinator_writer_ = nullptr, *mission_writer_ = nullptr,
             *plan_writer_ = nullptr, *event_writer_ = nullptr, *request_writer_ = nullptr, *reply_writer_ = nullptr;
  Topic *coordinator_topic_ = nullptr, *mission_topic_ = nullptr, *plan_topic_ = nullptr, *event_topic_ = nullptr,
        *request_topic_ = nullptr, *reply_topic_ = nullptr;
  std::map<std::string, DataWriter*> command_writers_;  // robot id -> writer in its partition
  std::map<std::string, RobotWriters> robot_writers_;   // robot id -> its writers, in its partition
  Topic *announcement_topic_ = nullptr, *state_topic_ = nullptr, *command_topic_ = nullptr, *status_topic_ = nullptr;
  DataWriterQos registry_w_ = DATAWRITER_QOS_DEFAULT, state_w_ = DATAWRITER_QOS_DEFAULT,
                command_w_ = DATAWRITER_QOS_DEFAULT, events_w_ = DATAWRITER_QOS_DEFAULT,
                requests_w_ = DATAWRITER_QOS_DEFAULT;
  std::mutex writers_mutex_;
  std::mutex command_writer_creation_mutex_;
  std::vector<std::unique_ptr<DataReaderListener>> listeners_;
  std::vector<DataReader*> readers_;
  std::mutex instances_mutex_;
  std::map<InstanceHandle_t, std::string> robot_of_instance_;
  // Last, so it is stopped (by tear_down, and destroyed) before anything it uses goes away.
  BackgroundOpener command_channel_opener_{[this](const std::string& robot_id) {
    try {
      const auto started = std::chrono::steady_clock::now();
      command_writer(robot_id);
      const double took_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      if (took_s > 0.5) spdlog::info("Fast DDS took {:.1f} s to open {}'s command channel", took_s, robot_id);
    } catch (const std::exception& error) {
      if (handlers_.on_refused) handlers_.on_refused(error.what());
    }
  }};
};

}  // namespace

std::unique_ptr<Transport> make_fastdds_transport(const TransportConfig& config, Handlers handlers) {
  return std::make_unique<FastDdsTransport>(config, std::move(handlers));
}

}  // namespace fleet_transport
