// The other process of the cross-process loopback test (loopback_test.cpp): a client on one bus.
//   transport_loopback_peer <dds|lcm> <prefix> <seed>
// Waits for the state RandomMessages(seed) makes, answers with its wrench, and repeats the wrench
// until the server acknowledges it with a control reply carrying the wrench's seq. Exit 0 on
// success; otherwise a line on stderr saying which step timed out, and exit 1.
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "random_messages.hpp"
#include "transport/dds/dds_transport.hpp"
#include "transport/lcm/lcm_transport.hpp"

namespace {

using namespace std::chrono_literals;
using namespace rigid;
using namespace rigid::transport;

class Inbox final : public Receiver {
 public:
  explicit Inbox(StateFrame expected) : expected_(std::move(expected)) {}
  void on_state(const StateFrame& state) override {
    if (state == expected_) set(got_state_);
  }
  void on_control_reply(const ControlReply& reply) override {
    if (reply.seq == acked_seq_) set(got_ack_);
  }
  bool wait_state(std::chrono::seconds patience) { return wait(got_state_, patience); }
  // Calls `send` every 20 ms until the ack arrives.
  template <class Send>
  bool wait_ack(std::int64_t seq, std::chrono::seconds patience, Send send) {
    {
      const std::lock_guard lock(mutex_);
      acked_seq_ = seq;
    }
    const auto deadline = std::chrono::steady_clock::now() + patience;
    while (std::chrono::steady_clock::now() < deadline) {
      send();
      if (wait(got_ack_, 20ms)) return true;
    }
    return false;
  }

 private:
  void set(bool& flag) {
    {
      const std::lock_guard lock(mutex_);
      flag = true;
    }
    changed_.notify_all();
  }
  template <class Duration>
  bool wait(const bool& flag, Duration patience) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, patience, [&] { return flag; });
  }
  const StateFrame expected_;
  std::mutex mutex_;
  std::condition_variable changed_;
  bool got_state_ = false;
  bool got_ack_ = false;
  std::int64_t acked_seq_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s <dds|lcm> <prefix> <seed>\n", argv[0]);
    return 2;
  }
  const std::string bus = argv[1];
  rigid::transport::testing::RandomMessages random(std::strtoull(argv[3], nullptr, 10));
  const StateFrame state = random.state(1000);
  const WrenchCommand wrench = random.wrench();

  Inbox inbox(state);
  std::unique_ptr<Transport> client;
  try {
    if (bus == "dds") {
      client = dds::make_transport({Role::kClient, 0, argv[2], false, ""}, inbox);
    } else {
      lcm::Options options{Role::kClient, std::string(lcm::kDefaultUrl) + "&recv_buf_size=4194304",
                           argv[2]};
      client = lcm::make_transport(options, inbox);
    }
  } catch (const TransportError& e) {
    std::fprintf(stderr, "peer: %s\n", e.what());
    return 1;
  }
  if (!inbox.wait_state(10s)) {
    std::fprintf(stderr, "peer (%s): no matching state within 10 s\n", bus.c_str());
    return 1;
  }
  if (!inbox.wait_ack(wrench.seq, 10s, [&] { (void)client->publish(wrench); })) {
    std::fprintf(stderr, "peer (%s): wrench not acknowledged within 10 s\n", bus.c_str());
    return 1;
  }
  return 0;
}
