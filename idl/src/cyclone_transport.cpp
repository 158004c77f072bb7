// Transport over Cyclone DDS (C API) with the idlc-generated types.
#include <dds/dds.h>
#include <dlfcn.h>

#include <cstring>
#include <filesystem>
#include <map>
#include <unordered_map>
#include <mutex>
#include <set>
#include <stdexcept>
#include <vector>

#include "cyclone_codec.hpp"
#include "fleet.h"
#include "middleware_log.hpp"
#include "topic_qos.hpp"
#include "transport_factories.hpp"

namespace fleet_transport {

namespace {

// A reader's and writer's QoS from the topic's (topic_qos.hpp); the caller deletes it.
dds_qos_t* cyclone_qos(const TopicQos& topic, const TransportConfig& config) {
  dds_qos_t* qos = dds_create_qos();
  if (topic.reliable) {
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  } else {
    dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
  }
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, topic.depth);
  if (topic.transient_local) {
    dds_qset_durability(qos, DDS_DURABILITY_TRANSIENT_LOCAL);
    dds_qset_durability_service(qos, 0, DDS_HISTORY_KEEP_LAST, topic.depth, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED,
                                DDS_LENGTH_UNLIMITED);
  }
  const dds_duration_t lease = static_cast<dds_duration_t>(DDS_SECS(1) * config.lease_s);
  if (topic.liveliness) dds_qset_liveliness(qos, DDS_LIVELINESS_AUTOMATIC, lease);
  if (topic.deadline) dds_qset_deadline(qos, 2 * lease);
  if (topic.exclusive) {
    dds_qset_ownership(qos, DDS_OWNERSHIP_EXCLUSIVE);
    dds_qset_ownership_strength(qos, config.command_strength);
  }
  if (!topic.dispose_on_unregister) dds_qset_writer_data_lifecycle(qos, false);
  return qos;
}

void check(dds_return_t rc, const char* what) {
  if (rc < 0) throw std::runtime_error(std::string("Cyclone DDS: ") + what + ": " + dds_strretcode(rc));
}

// Where Debian keeps Cyclone's security plugins: beside libddsc, in libddsc0debian/. Elsewhere the
// plain name, which Cyclone resolves through the library path.
std::string security_plugin(const char* name) {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&dds_create_participant), &info) != 0 && info.dli_fname) {
    const auto beside = std::filesystem::path(info.dli_fname).parent_path() / "libddsc0debian" / ("lib" + std::string(name) + ".so");
    if (std::filesystem::is_regular_file(beside)) return beside.string();
  }
  return name;
}

// Participant QoS for DDS Security with the builtin plugins (null when security is off).
dds_qos_t* security_qos(const SecurityFiles& files) {
  if (!files.enabled()) return nullptr;
  dds_qos_t* qos = dds_create_qos();
  const auto file = [](const std::string& path) { return "file:" + path; };
  dds_qset_prop(qos, "dds.sec.auth.library.path", security_plugin("dds_security_auth").c_str());
  dds_qset_prop(qos, "dds.sec.auth.library.init", "init_authentication");
  dds_qset_prop(qos, "dds.sec.auth.library.finalize", "finalize_authentication");
  dds_qset_prop(qos, "dds.sec.crypto.library.path", security_plugin("dds_security_crypto").c_str());
  dds_qset_prop(qos, "dds.sec.crypto.library.init", "init_crypto");
  dds_qset_prop(qos, "dds.sec.crypto.library.finalize", "finalize_crypto");
  dds_qset_prop(qos, "dds.sec.access.library.path", security_plugin("dds_security_ac").c_str());
  dds_qset_prop(qos, "dds.sec.access.library.init", "init_access_control");
  dds_qset_prop(qos, "dds.sec.access.library.finalize", "finalize_access_control");
  dds_qset_prop(qos, "dds.sec.auth.identity_ca", file(files.identity_ca).c_str());
  dds_qset_prop(qos, "dds.sec.auth.identity_certificate", file(files.identity_certificate).c_str());
  dds_qset_prop(qos, "dds.sec.auth.private_key", file(files.private_key).c_str());
  dds_qset_prop(qos, "dds.sec.access.permissions_ca", file(files.permissions_ca).c_str());
  dds_qset_prop(qos, "dds.sec.access.governance", file(files.governance).c_str());
  dds_qset_prop(qos, "dds.sec.access.permissions", file(files.permissions).c_str());
  if (!files.revocation_list.empty()) {
    dds_qset_prop(qos, "org.eclipse.cyclonedds.sec.auth.crl", file(files.revocation_list).c_str());
  }
  return qos;
}

// Cyclone's log (errors and warnings: a failed handshake names the refused certificate's subject)
// goes to the process's log on one line each (OpenSSL's reasons span several), each line once a
// minute at most.
void route_cyclone_log() {
  static RepeatedLineFilter filter;
  static std::once_flag once;
  std::call_once(once, [] {
    dds_set_log_sink(
        [](void*, const dds_log_data_t* data) {
          std::string text(data->message, data->size);
          for (char& c : text) c = c == '\n' ? ' ' : c;
          while (!text.empty() && text.back() == ' ') text.pop_back();
          if (!text.empty()) filter.log("Cyclone DDS", (data->priority & (DDS_LC_ERROR | DDS_LC_FATAL)) != 0, text);
        },
        nullptr);
  });
}

class CycloneTransport : public Transport {
 public:
  CycloneTransport(const TransportConfig& config, Handlers handlers)
      : handlers_(std::move(handlers)), commands_for_(config.commands_for), test_partition_of_(config.test_partition_of) {
    try {
      set_up(config);
    } catch (...) {  // e.g. access control refused a reader: no listener may call into a half-made object
      tear_down();
      throw;
    }
  }

  ~CycloneTransport() override { tear_down(); }

 private:
  void tear_down() {
    if (participant_ > 0) dds_delete(participant_);
    participant_ = 0;
    for (dds_qos_t** qos : {&registry_qos_, &state_qos_, &command_qos_, &events_qos_, &requests_qos_}) {
      if (*qos) dds_delete_qos(*qos);
      *qos = nullptr;
    }
  }

  void set_up(const TransportConfig& config) {
    route_cyclone_log();
    dds_qos_t* participant_qos = security_qos(config.security);
    participant_ = dds_create_participant(static_cast<dds_domainid_t>(config.domain_id), participant_qos, nullptr);
    if (participant_qos) dds_delete_qos(participant_qos);
    if (participant_ < 0 && config.security.enabled()) {
      throw std::runtime_error("Cyclone DDS: cannot create the participant of " + config.security.participant + " (" +
                               dds_strretcode(participant_) + "); with security on, the log line above says which of "
                               "its certificate, permissions or governance the plugins refused");
    }
    check(participant_, "create participant");
    registry_qos_ = cyclone_qos(kRegistryQos, config);
    state_qos_ = cyclone_qos(kStateQos, config);
    command_qos_ = cyclone_qos(kCommandQos, config);
    events_qos_ = cyclone_qos(kEventsQos, config);
    requests_qos_ = cyclone_qos(kRequestsQos, config);

    announcement_topic_ = make_topic(&fleet_Announcement_desc, "rt/fleet/announcement");
    state_topic_ = make_topic(&fleet_RobotState_desc, "rt/fleet/robot_state");
    command_topic_ = make_topic(&fleet_StepCommand_desc, "rt/fleet/step_command");
    status_topic_ = make_topic(&fleet_FleetStatus_desc, "rt/fleet/fleet_status");
    coordinator_topic_ = make_topic(&fleet_CoordinatorStatus_desc, "rt/fleet/coordinator_status");

    // Writers are made on first use: a process writes few of the topics, and every idle writer
    // would still be matched with every reader of the fleet. The ones a role surely writes are
    // made now, so readers have matched them before the first sample (volatile data is lost
    // otherwise): agents (command readers) announce and report state, the coordinator (state
    // reader) commands.
    if (handlers_.on_command && !commands_for_.empty()) {
      robot_writers(commands_for_);
    }

    listen_for_the_handlers();
  }

  // A reader for each topic the handlers take, in the partitions they read.
  void listen_for_the_handlers() {
    const bool reads_robots = handlers_.on_announcement || handlers_.on_robot_gone || handlers_.on_state;
    const dds_entity_t every_robot = reads_robots ? subscriber_in(kEveryRobotPartition) : 0;
    if (handlers_.on_announcement || handlers_.on_robot_gone) {
      make_reader(announcement_topic_, registry_qos_, &CycloneTransport::announcements_available, every_robot);
    }
    if (handlers_.on_state) make_reader(state_topic_, state_qos_, &CycloneTransport::states_available, every_robot);
    if (handlers_.on_command) {
      const std::string partition =
          commands_for_.empty() ? std::string(kEveryRobotPartition) : command_partition(commands_for_);
      make_reader(command_topic_, command_qos_, &CycloneTransport::commands_available, subscriber_in(partition));
    }
    if (handlers_.on_fleet_status) make_reader(status_topic_, registry_qos_, &CycloneTransport::statuses_available);
    if (handlers_.on_coordinator_status) {
      make_reader(coordinator_topic_, registry_qos_, &CycloneTransport::coordinator_statuses_available);
    }
    if (handlers_.on_mission_info) make_reader(mission_topic(), registry_qos_, &CycloneTransport::missions_available);
    if (handlers_.on_fleet_plan) make_reader(plan_topic(), registry_qos_, &CycloneTransport::plans_available);
    if (handlers_.on_fleet_event) make_reader(event_topic(), events_qos_, &CycloneTransport::events_available);
    if (handlers_.on_task_request) make_reader(request_topic(), requests_qos_, &CycloneTransport::requests_available);
    if (handlers_.on_task_reply) make_reader(reply_topic(), requests_qos_, &CycloneTransport::replies_available);
  }


 public:
  void announce(const Announcement& a) override {
    const fleet_Announcement wire = cyclone_codec::to_wire(a);
    check(dds_write(robot_writers(a.robot_id).announcement, &wire), "write announcement");
  }

  void say_goodbye(const std::string& robot_id) override {
    const fleet_Announcement wire = cyclone_codec::to_wire(Announcement{.robot_id = robot_id, .leaving = true});
    const dds_entity_t w = robot_writers(robot_id).announcement;
    check(dds_write(w, &wire), "write goodbye");
    check(dds_dispose(w, &wire), "dispose announcement");
  }

  void publish_state(const RobotState& s) override {
    const fleet_RobotState wire = cyclone_codec::to_wire(s);
    check(dds_write(robot_writers(s.robot_id).state, &wire), "write state");
  }

  void send_command(const StepCommand& c) override {
    const fleet_StepCommand wire = cyclone_codec::to_wire(c);
    check(dds_write(command_writer(c.robot_id), &wire), "write command");
  }

  void open_commands_for(const std::string& robot_id) override { command_writer(robot_id); }

  void set_command_strength(int strength) override {
    const std::lock_guard<std::mutex> lock(writers_mutex_);
    dds_qset_ownership_strength(command_qos_, strength);
    for (const auto& [robot_id, writer] : command_writers_) check(dds_set_qos(writer, command_qos_), "set command strength");
  }

  void publish_coordinator_status(const CoordinatorStatus& s) override {
    const fleet_CoordinatorStatus wire = cyclone_codec::to_wire(s);
    check(dds_write(writer(coordinator_writer_, coordinator_topic_, registry_qos_), &wire), "write coordinator status");
  }

  void publish_fleet_status(const FleetStatus& s) override {
    const dds_entity_t w = writer(status_writer_, status_topic_, registry_qos_);
    cyclone_codec::with_wire(s, [w](const fleet_FleetStatus& wire) { check(dds_write(w, &wire), "write fleet status"); });
  }

  void publish_mission_info(const MissionInfo& m) override {
    const dds_entity_t w = writer(mission_writer_, mission_topic(), registry_qos_);
    cyclone_codec::with_wire(m, [w](const fleet_MissionInfo& wire) { check(dds_write(w, &wire), "write mission info"); });
  }

  void publish_fleet_plan(const FleetPlan& p) override {
    const dds_entity_t w = writer(plan_writer_, plan_topic(), registry_qos_);
    cyclone_codec::with_wire(p, [w](const fleet_FleetPlan& wire) { check(dds_write(w, &wire), "write fleet plan"); });
  }

  void publish_fleet_event(const FleetEvent& e) override {
    const fleet_FleetEvent wire = cyclone_codec::to_wire(e);
    check(dds_write(writer(event_writer_, event_topic(), events_qos_), &wire), "write fleet event");
  }

  void request_task(const TaskRequest& r) override {
    const fleet_TaskRequest wire = cyclone_codec::to_wire(r);
    check(dds_write(writer(request_writer_, request_topic(), requests_qos_), &wire), "write task request");
  }

  void reply_task(const TaskReply& r) override {
    const dds_entity_t w = writer(reply_writer_, reply_topic(), requests_qos_);
    cyclone_codec::with_wire(r, [w](const fleet_TaskReply& wire) { check(dds_write(w, &wire), "write task reply"); });
  }

 private:
  // The operators' topics are made on first use: DDS Security refuses a participant even the
  // creation of a topic its permissions do not name (a robot's name none of them).
  dds_entity_t lazy_topic(dds_entity_t& slot, const dds_topic_descriptor_t* descriptor, const char* name) {
    const std::lock_guard<std::mutex> lock(topics_mutex_);
    if (slot == 0) slot = make_topic(descriptor, name);
    return slot;
  }
  dds_entity_t mission_topic() { return lazy_topic(mission_topic_, &fleet_MissionInfo_desc, "rt/fleet/mission_info"); }
  dds_entity_t plan_topic() { return lazy_topic(plan_topic_, &fleet_FleetPlan_desc, "rt/fleet/fleet_plan"); }
  dds_entity_t event_topic() { return lazy_topic(event_topic_, &fleet_FleetEvent_desc, "rt/fleet/fleet_event"); }
  dds_entity_t request_topic() { return lazy_topic(request_topic_, &fleet_TaskRequest_desc, "rt/fleet/task_request"); }
  dds_entity_t reply_topic() { return lazy_topic(reply_topic_, &fleet_TaskReply_desc, "rt/fleet/task_reply"); }

  dds_entity_t make_topic(const dds_topic_descriptor_t* descriptor, const char* name) {
    const dds_entity_t topic = dds_create_topic(participant_, descriptor, name, nullptr, nullptr);
    check(topic, name);
    return topic;
  }
  dds_entity_t writer(dds_entity_t& slot, dds_entity_t topic, const dds_qos_t* qos) {
    const std::lock_guard<std::mutex> lock(writers_mutex_);
    if (slot == 0) {
      slot = dds_create_writer(participant_, topic, qos, nullptr);
      check(slot, "create writer");
    }
    return slot;
  }
  dds_entity_t publisher_in(const std::string& partition) {
    dds_qos_t* qos = dds_create_qos();
    dds_qset_partition1(qos, partition.c_str());
    const dds_entity_t publisher = dds_create_publisher(participant_, qos, nullptr);
    dds_delete_qos(qos);
    check(publisher, ("create publisher in partition " + partition).c_str());
    return publisher;
  }
  dds_entity_t subscriber_in(const std::string& partition) {
    dds_qos_t* qos = dds_create_qos();
    dds_qset_partition1(qos, partition.c_str());
    const dds_entity_t subscriber = dds_create_subscriber(participant_, qos, nullptr);
    dds_delete_qos(qos);
    check(subscriber, ("create subscriber in partition " + partition).c_str());
    return subscriber;
  }
  // The command writer of one robot, in that robot's partition (see command_partition).
  dds_entity_t command_writer(const std::string& robot_id) {
    const std::lock_guard<std::mutex> lock(writers_mutex_);
    dds_entity_t& slot = command_writers_[robot_id];
    if (slot == 0) {
      slot = dds_create_writer(publisher_in(command_partition(robot_id)), command_topic_, command_qos_, nullptr);
      check(slot, ("create command writer for " + robot_id).c_str());
    }
    return slot;
  }
  // The announcement and state writers of one robot, in that robot's partition: under DDS
  // Security a robot's permissions allow it to write there only.
  struct RobotWriters {
    dds_entity_t announcement = 0, state = 0;
  };
  const RobotWriters& robot_writers(const std::string& robot_id) {
    const std::lock_guard<std::mutex> lock(writers_mutex_);
    RobotWriters& writers = robot_writers_[robot_id];
    if (writers.state == 0) {
      const dds_entity_t publisher = publisher_in(command_partition(test_partition_of_.empty() ? robot_id : test_partition_of_));
      writers.announcement = dds_create_writer(publisher, announcement_topic_, registry_qos_, nullptr);
      check(writers.announcement, ("create announcement writer for " + robot_id).c_str());
      writers.state = dds_create_writer(publisher, state_topic_, state_qos_, nullptr);
      check(writers.state, ("create state writer for " + robot_id).c_str());
    }
    return writers;
  }

  // True when the sample about `robot_id` came from a writer in that robot's own partition.
  // Partitions are looked up once per writer; a writer in the wrong one is reported once.
  bool from_own_partition(dds_entity_t reader, const dds_sample_info_t& info, const char* robot_id) {
    const std::lock_guard<std::mutex> lock(partitions_mutex_);
    auto found = partitions_of_writer_.find(info.publication_handle);
    if (found == partitions_of_writer_.end()) {
      std::vector<std::string> partitions;
      if (dds_builtintopic_endpoint_t* endpoint = dds_get_matched_publication_data(reader, info.publication_handle)) {
        uint32_t n = 0;
        char** names = nullptr;
        if (endpoint->qos && dds_qget_partition(endpoint->qos, &n, &names)) {
          for (uint32_t i = 0; i < n; ++i) {
            partitions.emplace_back(names[i]);
            dds_free(names[i]);
          }
          dds_free(names);
        }
        dds_builtintopic_free_endpoint(endpoint);
      }
      found = partitions_of_writer_.emplace(info.publication_handle, WriterPartitions{partitions, {}}).first;
    }
    if (written_in_own_partition(robot_id, found->second.partitions)) return true;
    if (found->second.reported.insert(robot_id).second && handlers_.on_refused) {
      std::string where;
      for (const std::string& p : found->second.partitions) where += (where.empty() ? "" : ",") + p;
      handlers_.on_refused(std::string("a message about robot '") + robot_id + "' written in partition '" + where +
                           "', not in its own (" + command_partition(robot_id) + "): dropped");
    }
    return false;
  }
  void make_reader(dds_entity_t topic, const dds_qos_t* qos, void (*on_data)(dds_entity_t, void*),
                   dds_entity_t parent = 0) {
    dds_listener_t* listener = dds_create_listener(this);
    dds_lset_data_available(listener, on_data);
    const dds_entity_t reader = dds_create_reader(parent ? parent : participant_, topic, qos, listener);
    dds_delete_listener(listener);
    check(reader, "create reader");
  }

  // Takes every available sample and hands each to `visit(sample, info)`.
  template <typename Wire, typename Visit>
  static void take_all(dds_entity_t reader, Visit visit) {
    constexpr int kBatch = 32;
    for (;;) {
      void* samples[kBatch] = {nullptr};
      dds_sample_info_t infos[kBatch];
      const int n = dds_take(reader, samples, infos, kBatch, kBatch);
      if (n <= 0) return;
      for (int i = 0; i < n; ++i) visit(*static_cast<const Wire*>(samples[i]), infos[i]);
      dds_return_loan(reader, samples, n);
    }
  }

  static void announcements_available(dds_entity_t reader, void* arg) {
    auto* self = static_cast<CycloneTransport*>(arg);
    take_all<fleet_Announcement>(reader, [self, reader](const fleet_Announcement& w, const dds_sample_info_t& info) {
      if (!self->from_own_partition(reader, info, w.robot_id)) return;
      if (info.valid_data) {
        if (self->handlers_.on_announcement) self->handlers_.on_announcement(cyclone_codec::from_wire(w));
      } else if (self->handlers_.on_robot_gone) {
        // Invalid samples carry the key: the instance lost its writer or was disposed.
        if (info.instance_state == DDS_NOT_ALIVE_DISPOSED_INSTANCE_STATE) {
          self->handlers_.on_robot_gone(w.robot_id, GoneReason::kGoodbye);
        } else if (info.instance_state == DDS_NOT_ALIVE_NO_WRITERS_INSTANCE_STATE) {
          self->handlers_.on_robot_gone(w.robot_id, GoneReason::kLivelinessLost);
        }
      }
    });
  }

  static void states_available(dds_entity_t reader, void* arg) {
    auto* self = static_cast<CycloneTransport*>(arg);
    take_all<fleet_RobotState>(reader, [self, reader](const fleet_RobotState& w, const dds_sample_info_t& info) {
      if (!info.valid_data || !self->from_own_partition(reader, info, w.robot_id)) return;
      self->handlers_.on_state(cyclone_codec::from_wire(w));
    });
  }

  static void commands_available(dds_entity_t reader, void* arg) {
    auto* self = static_cast<CycloneTransport*>(arg);
    take_all<fleet_StepCommand>(reader, [self](const fleet_StepCommand& w, const dds_sample_info_t& info) {
      if (!info.valid_data) return;
      if (!self->commands_for_.empty() && self->commands_for_ != w.robot_id) return;
      self->handlers_.on_command(cyclone_codec::from_wire(w));
    });
  }

  static void coordinator_statuses_available(dds_entity_t reader, void* arg) {
    auto* self = static_cast<CycloneTransport*>(arg);
    take_all<fleet_CoordinatorStatus>(reader, [self](const fleet_CoordinatorStatus& w, const dds_sample_info_t& info) {
      if (info.valid_data) self->handlers_.on_coordinator_status(cyclone_codec::from_wire(w));
    });
  }

  static void statuses_available(dds_entity_t reader, void* arg) {
    auto* self = static_cast<CycloneTransport*>(arg);
    take_all<fleet_FleetStatus>(reader, [self](const fleet_FleetStatus& w, const dds_sample_info_t& info) {
      if (info.valid_data) self->handlers_.on_fleet_status(cyclone_codec::from_wire(w));
    });
  }

  static void missions_available(dds_entity_t reader, void* arg) {
    auto* self = static_cast<CycloneTransport*>(arg);
    take_all<fleet_MissionInfo>(reader, [self](const fleet_MissionInfo& w, const dds_sample_info_t& info) {
      if (info.valid_data) self->handlers_.on_mission_info(cyclone_codec::from_wire(w));
    });
  }

  static void plans_available(dds_entity_t reader, void* arg) {
    auto* self = static_cast<CycloneTransport*>(arg);
    take_all<fleet_FleetPlan>(reader, [self](const fleet_FleetPlan& w, const dds_sample_info_t& info) {
      if (info.valid_data) self->handlers_.on_fleet_plan(cyclone_codec::from_wire(w));
    });
  }

  static void events_available(dds_entity_t reader, void* arg) {
    auto* self = static_cast<CycloneTransport*>(arg);
    take_all<fleet_FleetEvent>(reader, [self](const fleet_FleetEvent& w, const dds_sample_info_t& info) {
      if (info.valid_data) self->handlers_.on_fleet_event(cyclone_codec::from_wire(w));
    });
  }

  static void requests_available(dds_entity_t reader, void* arg) {
    auto* self = static_cast<CycloneTransport*>(arg);
    take_all<fleet_TaskRequest>(reader, [self](const fleet_TaskRequest& w, const dds_sample_info_t& info) {
      if (info.valid_data) self->handlers_.on_task_request(cyclone_codec::from_wire(w));
    });
  }

  static void replies_available(dds_entity_t reader, void* arg) {
    auto* self = static_cast<CycloneTransport*>(arg);
    take_all<fleet_TaskReply>(reader, [self](const fleet_TaskReply& w, const dds_sample_info_t& info) {
      if (info.valid_data) self->handlers_.on_task_reply(cyclone_codec::from_wire(w));
    });
  }

  Handlers handlers_;
  std::string commands_for_;
  std::string test_partition_of_;  // see TransportConfig::test_partition_of
  dds_entity_t participant_ = 0;
  dds_entity_t announcement_topic_ = 0, state_topic_ = 0, command_topic_ = 0, status_topic_ = 0, coordinator_topic_ = 0;
  dds_entity_t mission_topic_ = 0, plan_topic_ = 0, event_topic_ = 0, request_topic_ = 0, reply_topic_ = 0;
  dds_entity_t status_writer_ = 0, coordinator_writer_ = 0, mission_writer_ = 0, plan_writer_ = 0, event_writer_ = 0,
               request_writer_ = 0, reply_writer_ = 0;
  std::map<std::string, dds_entity_t> command_writers_;  // robot id -> writer in its partition
  std::map<std::string, RobotWriters> robot_writers_;   // robot id -> its writers, in its partition
  struct WriterPartitions {
    std::vector<std::string> partitions;
    std::set<std::string> reported;  // robot ids it wrote about out of their partition, logged once
  };
  std::unordered_map<dds_instance_handle_t, WriterPartitions> partitions_of_writer_;
  std::mutex partitions_mutex_;
  dds_qos_t *registry_qos_ = nullptr, *state_qos_ = nullptr, *command_qos_ = nullptr, *events_qos_ = nullptr,
            *requests_qos_ = nullptr;
  std::mutex writers_mutex_;
  std::mutex topics_mutex_;
};

}  // namespace

std::unique_ptr<Transport> make_cyclone_transport(const TransportConfig& config, Handlers handlers) {
  return std::make_unique<CycloneTransport>(config, std::move(handlers));
}

}  // namespace fleet_transport
