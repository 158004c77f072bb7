// Which DDS domains collide with the kernel's ephemeral ports (fleet_transport/domain_ports.hpp).
#include <gtest/gtest.h>

#include "fleet_transport/domain_ports.hpp"

namespace fleet_transport {
namespace {

constexpr PortRange kLinuxDefault{32768, 60999};

TEST(DomainPorts, EachDomainHasTwoHundredFiftyPortsFrom7400) {
  EXPECT_EQ(domain_ports(0).first, 7400);
  EXPECT_EQ(domain_ports(0).last, 7649);
  EXPECT_EQ(domain_ports(205).first, 58650);
  EXPECT_EQ(domain_ports(232).first, 65400);
}

TEST(DomainPorts, DomainsInsideTheEphemeralRangeAreWarnedAboutWithTheSafeOnesNamed) {
  EXPECT_FALSE(ephemeral_port_warning(0, kLinuxDefault));
  EXPECT_FALSE(ephemeral_port_warning(100, kLinuxDefault));  // 32400-32649
  EXPECT_TRUE(ephemeral_port_warning(101, kLinuxDefault));   // 32650-32899
  EXPECT_TRUE(ephemeral_port_warning(214, kLinuxDefault));   // 60900-61149
  EXPECT_FALSE(ephemeral_port_warning(215, kLinuxDefault));
  const auto warning = ephemeral_port_warning(205, kLinuxDefault);
  ASSERT_TRUE(warning);
  EXPECT_NE(warning->find("58650-58899"), std::string::npos) << *warning;
  EXPECT_NE(warning->find("32768-60999"), std::string::npos) << *warning;
  EXPECT_NE(warning->find("use domain 0-100 or 215-232"), std::string::npos) << *warning;
}

TEST(DomainPorts, AnEphemeralRangeCoveringEveryDomainStillGivesAnAnswer) {
  const auto warning = ephemeral_port_warning(3, PortRange{1024, 65535});
  ASSERT_TRUE(warning);
  EXPECT_NE(warning->find("ports outside that range"), std::string::npos) << *warning;
}

TEST(DomainPorts, ThisHostsRangeIsReadWhenTheKernelHasOne) {
  const auto range = kernel_ephemeral_ports();
  if (!range) GTEST_SKIP() << "no /proc/sys/net/ipv4/ip_local_port_range here";
  EXPECT_LT(range->first, range->last);
  EXPECT_GT(range->first, 0);
}

}  // namespace
}  // namespace fleet_transport
