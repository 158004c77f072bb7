// The Cyclone DDS codec (idl/src/cyclone_codec.hpp): the shared round-trip cases, and what a C
// sample can hold that a C++ one cannot (null strings).
#include <gtest/gtest.h>

#include "codec_round_trip.hpp"
#include "cyclone_codec.hpp"

namespace fleet_transport {
namespace {

struct CycloneCodec {
  template <typename Message>
  static Message round_trip(const Message& message) {
    if constexpr (requires { cyclone_codec::to_wire(message); }) {
      return cyclone_codec::from_wire(cyclone_codec::to_wire(message));
    } else {
      Message back;
      bool used = false;
      cyclone_codec::with_wire(message, [&](const auto& wire) {
        back = cyclone_codec::from_wire(wire);
        used = true;
      });
      EXPECT_TRUE(used) << "with_wire never called its use";
      return back;
    }
  }
};

INSTANTIATE_TYPED_TEST_SUITE_P(Cyclone, CodecRoundTrip, CycloneCodec);

TEST(CycloneCodec, NullStringsFromTheWireReadAsEmpty) {
  fleet_MissionInfo mission{};
  mission.map_rows = nullptr;
  EXPECT_EQ(cyclone_codec::from_wire(mission).map_rows, "");
  fleet_TaskReply reply{};
  reply.listing = nullptr;
  EXPECT_EQ(cyclone_codec::from_wire(reply).listing, "");
}

TEST(CycloneCodec, AnUnknownEnumeratorFromTheWireReadsAsTheSafeOne) {
  fleet_RobotState state{};
  state.status = static_cast<fleet_RobotStatus>(42);
  EXPECT_EQ(cyclone_codec::from_wire(state).status, RobotStatus::kFault);
  fleet_CoordinatorStatus status{};
  status.role = static_cast<fleet_CoordinatorRole>(42);
  EXPECT_EQ(cyclone_codec::from_wire(status).role, CoordinatorRole::kEnded);
}

}  // namespace
}  // namespace fleet_transport
