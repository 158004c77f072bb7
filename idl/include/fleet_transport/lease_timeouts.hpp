// The fleet's timeouts that follow from the liveliness lease (`dds.lease_s`, `--lease`), in one
// place: the coordinators and the agents must agree on them. Coordinators publish their status
// every 0.25 s, so each timeout is the lease plus a margin of several status periods.
#pragma once

namespace fleet_transport {

struct LeaseTimeouts {
  double lease_s = 1.0;

  // An active coordinator not heard for this long is gone: another coordinator no longer defers to
  // it, and an agent follows the next one.
  double coordinator_gone_s() const { return lease_s + 1.0; }
  // A standby takes over an active coordinator silent for this long (once it hears every robot that
  // one drove): sooner than coordinator_gone_s, so the robots find the new one already active.
  double standby_takes_over_after_s() const { return lease_s + 0.5; }
};

}  // namespace fleet_transport
