// Transport over Cyclone DDS (C API) with the idlc-generated types.
#include <dds/dds.h>

#include <cstring>
#include <map>
#include <mutex>
#include <stdexcept>
#include <vector>

#include "fleet.h"
#include "transport_factories.hpp"

namespace fleet_transport {

namespace {

template <size_t N>
void copy_string(char (&out)[N], const std::string& in) {
  std::strncpy(out, in.c_str(), N - 1);
  out[N - 1] = '\0';
}

fleet_RobotStatus to_wire(RobotStatus s) {
  switch (s) {
    case RobotStatus::kIdle: return fleet_ROBOT_IDLE;
    case RobotStatus::kMoving: return fleet_ROBOT_MOVING;
    case RobotStatus::kArrived: return fleet_ROBOT_ARRIVED;
    case RobotStatus::kFault: return fleet_ROBOT_FAULT;
  }
  return fleet_ROBOT_FAULT;
}

RobotStatus from_wire(fleet_RobotStatus s) {
  switch (s) {
    case fleet_ROBOT_IDLE: return RobotStatus::kIdle;
    case fleet_ROBOT_MOVING: return RobotStatus::kMoving;
    case fleet_ROBOT_ARRIVED: return RobotStatus::kArrived;
    default: return RobotStatus::kFault;
  }
}

fleet_CoordinatorRole to_wire(CoordinatorRole r) {
  switch (r) {
    case CoordinatorRole::kActive: return fleet_COORDINATOR_ACTIVE;
    case CoordinatorRole::kStandby: return fleet_COORDINATOR_STANDBY;
    case CoordinatorRole::kStoodDown: return fleet_COORDINATOR_STOOD_DOWN;
    case CoordinatorRole::kEnded: return fleet_COORDINATOR_ENDED;
  }
  return fleet_COORDINATOR_ENDED;
}

CoordinatorRole from_wire(fleet_CoordinatorRole r) {
  switch (r) {
    case fleet_COORDINATOR_ACTIVE: return CoordinatorRole::kActive;
    case fleet_COORDINATOR_STANDBY: return CoordinatorRole::kStandby;
    case fleet_COORDINATOR_STOOD_DOWN: return CoordinatorRole::kStoodDown;
    default: return CoordinatorRole::kEnded;
  }
}

void check(dds_return_t rc, const char* what) {
  if (rc < 0) throw std::runtime_error(std::string("Cyclone DDS: ") + what + ": " + dds_strretcode(rc));
}

class CycloneTransport : public Transport {
 public:
  CycloneTransport(const TransportConfig& config, Handlers handlers)
      : handlers_(std::move(handlers)), commands_for_(config.commands_for) {
    participant_ = dds_create_participant(static_cast<dds_domainid_t>(config.domain_id), nullptr, nullptr);
    check(participant_, "create participant");
    const dds_duration_t lease = DDS_SECS(1) * config.lease_s;

    dds_qos_t* registry = registry_qos_ = dds_create_qos();
    dds_qset_reliability(registry, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_durability(registry, DDS_DURABILITY_TRANSIENT_LOCAL);
    dds_qset_history(registry, DDS_HISTORY_KEEP_LAST, 1);
    dds_qset_durability_service(registry, 0, DDS_HISTORY_KEEP_LAST, 1, DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED,
                                DDS_LENGTH_UNLIMITED);
    dds_qset_liveliness(registry, DDS_LIVELINESS_AUTOMATIC, lease);
    // A writer that dies leaves its instances "no writers", not "disposed": only a goodbye disposes.
    dds_qset_writer_data_lifecycle(registry, false);
    dds_qos_t* state = state_qos_ = dds_create_qos();
    dds_qset_reliability(state, DDS_RELIABILITY_BEST_EFFORT, 0);
    dds_qset_history(state, DDS_HISTORY_KEEP_LAST, 1);
    dds_qset_liveliness(state, DDS_LIVELINESS_AUTOMATIC, lease);
    dds_qset_deadline(state, 2 * lease);  // robots publish state several times per second
    dds_qos_t* command = command_qos_ = dds_create_qos();
    dds_qset_reliability(command, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_history(command, DDS_HISTORY_KEEP_LAST, 8);
    dds_qset_ownership(command, DDS_OWNERSHIP_EXCLUSIVE);
    dds_qset_ownership_strength(command, config.command_strength);
    dds_qset_liveliness(command, DDS_LIVELINESS_AUTOMATIC, lease);  // a dead owner is replaced after a lease

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
    if (handlers_.on_command) {
      writer(announcement_writer_, announcement_topic_, registry_qos_);
      writer(state_writer_, state_topic_, state_qos_);
    }

    if (handlers_.on_announcement || handlers_.on_robot_gone) {
      make_reader(announcement_topic_, registry, &CycloneTransport::announcements_available);
    }
    if (handlers_.on_state) make_reader(state_topic_, state, &CycloneTransport::states_available);
    if (handlers_.on_command) {
      const std::string partition =
          commands_for_.empty() ? std::string(kEveryCommandPartition) : command_partition(commands_for_);
      dds_qos_t* subscriber_qos = dds_create_qos();
      dds_qset_partition1(subscriber_qos, partition.c_str());
      const dds_entity_t subscriber = dds_create_subscriber(participant_, subscriber_qos, nullptr);
      dds_delete_qos(subscriber_qos);
      check(subscriber, "create command subscriber");
      make_reader(command_topic_, command, &CycloneTransport::commands_available, subscriber);
    }
    if (handlers_.on_fleet_status) make_reader(status_topic_, registry, &CycloneTransport::statuses_available);
    if (handlers_.on_coordinator_status) {
      make_reader(coordinator_topic_, registry, &CycloneTransport::coordinator_statuses_available);
    }
  }

  ~CycloneTransport() override {
    dds_delete(participant_);
    dds_delete_qos(registry_qos_);
    dds_delete_qos(state_qos_);
    dds_delete_qos(command_qos_);
  }

  void announce(const Announcement& a) override {
    fleet_Announcement wire{};
    copy_string(wire.robot_id, a.robot_id);
    copy_string(wire.backend, a.backend);
    copy_string(wire.capabilities, a.capabilities);
    copy_string(wire.version, a.version);
    wire.leaving = a.leaving;
    wire.incarnation = a.incarnation;
    check(dds_write(writer(announcement_writer_, announcement_topic_, registry_qos_), &wire), "write announcement");
  }

  void say_goodbye(const std::string& robot_id) override {
    fleet_Announcement wire{};
    copy_string(wire.robot_id, robot_id);
    wire.leaving = true;
    const dds_entity_t w = writer(announcement_writer_, announcement_topic_, registry_qos_);
    check(dds_write(w, &wire), "write goodbye");
    check(dds_dispose(w, &wire), "dispose announcement");
  }

  void publish_state(const RobotState& s) override {
    fleet_RobotState wire{};
    copy_string(wire.robot_id, s.robot_id);
    wire.cell_x = s.cell_x;
    wire.cell_y = s.cell_y;
    wire.pose_x = s.pose_x;
    wire.pose_y = s.pose_y;
    wire.pose_theta = s.pose_theta;
    wire.plan_epoch = s.plan_epoch;
    wire.action_index = s.action_index;
    wire.status = to_wire(s.status);
    wire.battery_percent = s.battery_percent;
    wire.seq_number = s.seq_number;
    wire.stamp_ms = s.stamp_ms;
    wire.incarnation = s.incarnation;
    wire.coordinator = s.coordinator;
    check(dds_write(writer(state_writer_, state_topic_, state_qos_), &wire), "write state");
  }

  void send_command(const StepCommand& c) override {
    fleet_StepCommand wire{};
    copy_string(wire.robot_id, c.robot_id);
    wire.plan_epoch = c.plan_epoch;
    wire.action_index = c.action_index;
    wire.target_x = c.target_x;
    wire.target_y = c.target_y;
    wire.target_pose_x = c.target_pose_x;
    wire.target_pose_y = c.target_pose_y;
    wire.deadline_ms = c.deadline_ms;
    wire.coordinator = c.coordinator;
    check(dds_write(command_writer(c.robot_id), &wire), "write command");
  }

  void prepare_commands_for(const std::string& robot_id) override { command_writer(robot_id); }

  void set_command_strength(int strength) override {
    const std::lock_guard<std::mutex> lock(writers_mutex_);
    dds_qset_ownership_strength(command_qos_, strength);
    for (const auto& [robot_id, writer] : command_writers_) check(dds_set_qos(writer, command_qos_), "set command strength");
  }

  void publish_coordinator_status(const CoordinatorStatus& s) override {
    fleet_CoordinatorStatus wire{};
    wire.coordinator = s.coordinator;
    wire.term = s.term;
    wire.claimed_ms = s.claimed_ms;
    wire.role = to_wire(s.role);
    copy_string(wire.mission_id, s.mission_id);
    wire.plan_epoch = s.plan_epoch;
    check(dds_write(writer(coordinator_writer_, coordinator_topic_, registry_qos_), &wire), "write coordinator status");
  }

  void publish_fleet_status(const FleetStatus& s) override {
    std::vector<fleet_Assignment> rows(s.assignments.size());
    for (size_t i = 0; i < rows.size(); ++i) {
      copy_string(rows[i].robot_id, s.assignments[i].robot_id);
      rows[i].role = s.assignments[i].role;
      rows[i].tasks_done = s.assignments[i].tasks_done;
      rows[i].tasks_total = s.assignments[i].tasks_total;
    }
    std::vector<fleet_TaskVisit> visits(s.done_visits.size());
    for (size_t i = 0; i < visits.size(); ++i) visits[i] = {s.done_visits[i].task, s.done_visits[i].role};
    fleet_FleetStatus wire{};
    wire.coordinator = s.coordinator;
    wire.plan_epoch = s.plan_epoch;
    wire.tasks_done = s.tasks_done;
    wire.tasks_total = s.tasks_total;
    wire.robots = s.robots;
    wire.assignments._length = wire.assignments._maximum = static_cast<uint32_t>(rows.size());
    wire.assignments._buffer = rows.data();
    wire.assignments._release = false;
    wire.done_visits._length = wire.done_visits._maximum = static_cast<uint32_t>(visits.size());
    wire.done_visits._buffer = visits.data();
    wire.done_visits._release = false;
    check(dds_write(writer(status_writer_, status_topic_, registry_qos_), &wire), "write fleet status");
  }

 private:
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
  // The command writer of one robot, in that robot's partition (see command_partition).
  dds_entity_t command_writer(const std::string& robot_id) {
    const std::lock_guard<std::mutex> lock(writers_mutex_);
    dds_entity_t& slot = command_writers_[robot_id];
    if (slot == 0) {
      dds_qos_t* publisher_qos = dds_create_qos();
      dds_qset_partition1(publisher_qos, command_partition(robot_id).c_str());
      const dds_entity_t publisher = dds_create_publisher(participant_, publisher_qos, nullptr);
      dds_delete_qos(publisher_qos);
      check(publisher, "create command publisher");
      slot = dds_create_writer(publisher, command_topic_, command_qos_, nullptr);
      check(slot, "create command writer");
    }
    return slot;
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
    take_all<fleet_Announcement>(reader, [self](const fleet_Announcement& w, const dds_sample_info_t& info) {
      if (info.valid_data) {
        if (self->handlers_.on_announcement) {
          self->handlers_.on_announcement({w.robot_id, w.backend, w.capabilities, w.version, w.leaving, w.incarnation});
        }
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
    take_all<fleet_RobotState>(reader, [self](const fleet_RobotState& w, const dds_sample_info_t& info) {
      if (!info.valid_data) return;
      RobotState s;
      s.robot_id = w.robot_id;
      s.cell_x = w.cell_x;
      s.cell_y = w.cell_y;
      s.pose_x = w.pose_x;
      s.pose_y = w.pose_y;
      s.pose_theta = w.pose_theta;
      s.plan_epoch = w.plan_epoch;
      s.action_index = w.action_index;
      s.status = from_wire(w.status);
      s.battery_percent = w.battery_percent;
      s.seq_number = w.seq_number;
      s.stamp_ms = w.stamp_ms;
      s.incarnation = w.incarnation;
      s.coordinator = w.coordinator;
      self->handlers_.on_state(s);
    });
  }

  static void commands_available(dds_entity_t reader, void* arg) {
    auto* self = static_cast<CycloneTransport*>(arg);
    take_all<fleet_StepCommand>(reader, [self](const fleet_StepCommand& w, const dds_sample_info_t& info) {
      if (!info.valid_data) return;
      if (!self->commands_for_.empty() && self->commands_for_ != w.robot_id) return;
      self->handlers_.on_command({w.robot_id, w.plan_epoch, w.action_index, w.target_x, w.target_y, w.target_pose_x,
                                  w.target_pose_y, w.deadline_ms, w.coordinator});
    });
  }

  static void coordinator_statuses_available(dds_entity_t reader, void* arg) {
    auto* self = static_cast<CycloneTransport*>(arg);
    take_all<fleet_CoordinatorStatus>(reader, [self](const fleet_CoordinatorStatus& w, const dds_sample_info_t& info) {
      if (!info.valid_data) return;
      self->handlers_.on_coordinator_status(
          {w.coordinator, w.term, w.claimed_ms, from_wire(w.role), w.mission_id, w.plan_epoch});
    });
  }

  static void statuses_available(dds_entity_t reader, void* arg) {
    auto* self = static_cast<CycloneTransport*>(arg);
    take_all<fleet_FleetStatus>(reader, [self](const fleet_FleetStatus& w, const dds_sample_info_t& info) {
      if (!info.valid_data) return;
      FleetStatus s;
      s.coordinator = w.coordinator;
      s.plan_epoch = w.plan_epoch;
      s.tasks_done = w.tasks_done;
      s.tasks_total = w.tasks_total;
      s.robots = w.robots;
      for (uint32_t i = 0; i < w.done_visits._length; ++i) {
        s.done_visits.push_back({w.done_visits._buffer[i].task, w.done_visits._buffer[i].role});
      }
      for (uint32_t i = 0; i < w.assignments._length; ++i) {
        const fleet_Assignment& row = w.assignments._buffer[i];
        s.assignments.push_back({row.robot_id, row.role, row.tasks_done, row.tasks_total});
      }
      self->handlers_.on_fleet_status(s);
    });
  }

  Handlers handlers_;
  std::string commands_for_;
  dds_entity_t participant_ = 0;
  dds_entity_t announcement_topic_ = 0, state_topic_ = 0, command_topic_ = 0, status_topic_ = 0, coordinator_topic_ = 0;
  dds_entity_t announcement_writer_ = 0, state_writer_ = 0, status_writer_ = 0, coordinator_writer_ = 0;
  std::map<std::string, dds_entity_t> command_writers_;  // robot id -> writer in its partition
  dds_qos_t *registry_qos_ = nullptr, *state_qos_ = nullptr, *command_qos_ = nullptr;
  std::mutex writers_mutex_;
};

}  // namespace

std::unique_ptr<Transport> make_cyclone_transport(const TransportConfig& config, Handlers handlers) {
  return std::make_unique<CycloneTransport>(config, std::move(handlers));
}

}  // namespace fleet_transport
