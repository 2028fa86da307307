// A bus that accepts everything and sends nothing: the loop's and the publishers' tests, and
// bench/fanout_bench, run publishers on it.
#pragma once

#include "transport/transport.hpp"

namespace rigid::loop::testing {

// A bus that accepts everything and keeps nothing (a test that wants the states overrides
// publish(const StateFrame&)).
class NullTransport : public transport::Transport {
 public:
  rigid::Bus bus() const override { return rigid::Bus::kDds; }
  transport::Role role() const override { return transport::Role::kServer; }
  transport::PublishResult publish(const rigid::StateFrame&) override { return ok(); }
  transport::PublishResult publish(const rigid::StatsReport&) override { return ok(); }
  transport::PublishResult publish(const rigid::SceneDescription&) override { return ok(); }
  transport::PublishResult publish(const rigid::ControlReply&) override { return ok(); }
  transport::PublishResult publish(const rigid::WrenchCommand&) override { return ok(); }
  transport::PublishResult publish(const rigid::ControlCommand&) override { return ok(); }
  rigid::TransportCounts counts() const override { return {}; }

 protected:
  static transport::PublishResult ok() { return transport::PublishResult::kOk; }
};

}  // namespace rigid::loop::testing
