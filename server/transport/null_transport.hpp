// A bus that accepts everything and sends nothing: the loop's and the publishers' tests, and
// bench's fanout_bench, run publishers on it. Header-only, part of the transport interface.
#pragma once

#include "transport/transport.hpp"

namespace rigid::transport {

// A bus that accepts everything and keeps nothing (a test that wants the states overrides
// publish(const StateFrame&)).
class NullTransport : public Transport {
 public:
  rigid::Bus bus() const override { return rigid::Bus::kDds; }
  Role role() const override { return Role::kServer; }
  PublishResult publish(const rigid::StateFrame&) override { return ok(); }
  PublishResult publish(const rigid::StatsReport&) override { return ok(); }
  PublishResult publish(const rigid::SceneDescription&) override { return ok(); }
  PublishResult publish(const rigid::ControlReply&) override { return ok(); }
  PublishResult publish(const rigid::WrenchCommand&) override { return ok(); }
  PublishResult publish(const rigid::ControlCommand&) override { return ok(); }
  PublishResult publish(const rigid::ContactEvents&) override { return ok(); }
  rigid::TransportCounts counts() const override { return {}; }

 protected:
  static PublishResult ok() { return PublishResult::kOk; }
};

}  // namespace rigid::transport
