// The QoS of each kind of topic, said once for both vendors: a Cyclone DDS process and a Fast DDS
// one match only when their QoS agree. Each transport turns a TopicQos into its own QoS objects
// (cyclone_transport.cpp: cyclone_qos; fastdds_transport.cpp: writer_qos, reader_qos).
#pragma once

#include <cstdint>

namespace fleet_transport {

struct TopicQos {
  bool reliable = true;
  bool transient_local = false;  // late joiners get the last `depth` samples of each instance
  int32_t depth = 1;             // KEEP_LAST depth
  bool liveliness = false;       // automatic liveliness with the fleet's lease: a dead writer is noticed
  bool deadline = false;         // a sample within two leases is expected
  bool exclusive = false;        // exclusive ownership: only the strongest live writer's samples are taken
  // False: a writer that dies leaves its instances "no writers", not "disposed" (only a goodbye disposes).
  bool dispose_on_unregister = true;
  bool per_robot = false;        // keyed by robot id: room for a fleet of instances
};

constexpr int32_t kEventHistory = 64;

// Announcements and the coordinators' status, progress, mission and plan: the latest of each
// instance, kept for late joiners, with the writer's liveliness.
constexpr TopicQos kRegistryQos{.reliable = true, .transient_local = true, .depth = 1, .liveliness = true,
                                .dispose_on_unregister = false, .per_robot = true};
// Robots' states: several a second, the latest wins; a robot silent for two leases misses its deadline.
constexpr TopicQos kStateQos{.reliable = false, .depth = 1, .liveliness = true, .deadline = true, .per_robot = true};
// Step commands: reliable, from the strongest live coordinator (a dead owner is replaced after a lease).
constexpr TopicQos kCommandQos{.depth = 8, .liveliness = true, .exclusive = true, .per_robot = true};
// Operators' events: the last kEventHistory, for dashboards that join late.
constexpr TopicQos kEventsQos{.transient_local = true, .depth = kEventHistory};
// Task requests and replies.
constexpr TopicQos kRequestsQos{.depth = 16};

}  // namespace fleet_transport
