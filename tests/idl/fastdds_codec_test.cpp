// The Fast DDS codec (idl/src/fastdds_codec.hpp): the shared round-trip cases, each message also
// serialized to CDR and back through its fastddsgen type support, as a writer and reader do.
#include <gtest/gtest.h>

#include <fastdds/rtps/common/SerializedPayload.h>

#include "codec_round_trip.hpp"
#include "fastdds_codec.hpp"
#include "fleetPubSubTypes.h"

namespace fleet_transport {
namespace {

template <typename TypeSupport, typename Message>
Message through_cdr(const Message& message) {
  auto wire = fastdds_codec::to_wire(message);
  TypeSupport type;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.getSerializedSizeProvider(&wire)());
  EXPECT_TRUE(type.serialize(&wire, &payload));
  decltype(wire) back;
  EXPECT_TRUE(type.deserialize(&payload, &back));
  return fastdds_codec::from_wire(back);
}

struct FastDdsCodec {
  static Announcement round_trip(const Announcement& m) { return through_cdr<fleet::AnnouncementPubSubType>(m); }
  static RobotState round_trip(const RobotState& m) { return through_cdr<fleet::RobotStatePubSubType>(m); }
  static StepCommand round_trip(const StepCommand& m) { return through_cdr<fleet::StepCommandPubSubType>(m); }
  static CoordinatorStatus round_trip(const CoordinatorStatus& m) {
    return through_cdr<fleet::CoordinatorStatusPubSubType>(m);
  }
  static FleetStatus round_trip(const FleetStatus& m) { return through_cdr<fleet::FleetStatusPubSubType>(m); }
  static MissionInfo round_trip(const MissionInfo& m) { return through_cdr<fleet::MissionInfoPubSubType>(m); }
  static FleetPlan round_trip(const FleetPlan& m) { return through_cdr<fleet::FleetPlanPubSubType>(m); }
  static FleetEvent round_trip(const FleetEvent& m) { return through_cdr<fleet::FleetEventPubSubType>(m); }
  static TaskRequest round_trip(const TaskRequest& m) { return through_cdr<fleet::TaskRequestPubSubType>(m); }
  static TaskReply round_trip(const TaskReply& m) { return through_cdr<fleet::TaskReplyPubSubType>(m); }
};

INSTANTIATE_TYPED_TEST_SUITE_P(FastDds, CodecRoundTrip, FastDdsCodec);

TEST(FastDdsCodec, AnUnknownEnumeratorFromTheWireReadsAsTheSafeOne) {
  fleet::RobotState state;
  state.status(static_cast<fleet::RobotStatus>(42));
  EXPECT_EQ(fastdds_codec::from_wire(state).status, RobotStatus::kFault);
  fleet::CoordinatorStatus status;
  status.role(static_cast<fleet::CoordinatorRole>(42));
  EXPECT_EQ(fastdds_codec::from_wire(status).role, CoordinatorRole::kEnded);
}

}  // namespace
}  // namespace fleet_transport
