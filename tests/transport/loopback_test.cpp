// A real round trip over each bus inside one process: a server-role transport and a client-role
// transport on loopback. Needs the network set up as scripts/net-setup does (LCM: a multicast route
// on lo) and CYCLONEDDS_URI pointing at config/cyclonedds.xml (ctest sets it for this test).
// Every wait is bounded; a missing network fails with a message saying what to run.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "random_messages.hpp"
#include "transport/dds/dds_transport.hpp"
#include "transport/lcm/lcm_transport.hpp"

namespace rigid::transport {
namespace {

using namespace std::chrono_literals;
using testing::RandomMessages;

constexpr auto kPatience = 10s;

// Keeps the last message of each kind; the test thread waits for one that satisfies it.
class Mailbox final : public Receiver {
 public:
  void on_wrench(const WrenchCommand& m, const Origin& /*origin*/) override { store(wrench_, m); }
  void on_control(const ControlCommand& m, const Origin& /*origin*/) override {
    store(control_, m);
  }
  void on_edit(const EditCommand& m, const Origin& /*origin*/) override { store(edit_, m); }
  void on_state(const StateFrame& m) override { store(state_, m); }
  void on_stats(const StatsReport& m) override { store(stats_, m); }
  void on_scene(const SceneDescription& m) override { store(scene_, m); }
  void on_control_reply(const ControlReply& m) override { store(reply_, m); }
  void on_contacts(const ContactEvents& m) override { store(contacts_, m); }
  void on_decode_error(const DecodeError& e) override {
    const std::lock_guard lock(mutex_);
    ++decode_errors_;
    last_error_ = e;
  }

  // Calls `send` every 20 ms until `slot` holds `expected` or kPatience runs out. Resending covers
  // discovery (DDS) and best-effort loss; for LCM it covers nothing but is harmless.
  template <class Message>
  bool await(std::optional<Message> Mailbox::*slot, const Message& expected,
             const std::function<void()>& send) {
    const auto deadline = std::chrono::steady_clock::now() + kPatience;
    std::unique_lock lock(mutex_);
    while (std::chrono::steady_clock::now() < deadline) {
      lock.unlock();
      send();
      lock.lock();
      if (changed_.wait_for(lock, 20ms, [&] { return this->*slot == expected; })) return true;
    }
    return false;
  }

  int decode_errors() {
    const std::lock_guard lock(mutex_);
    return decode_errors_;
  }

  std::optional<WrenchCommand> wrench_;
  std::optional<ControlCommand> control_;
  std::optional<EditCommand> edit_;
  std::optional<StateFrame> state_;
  std::optional<StatsReport> stats_;
  std::optional<SceneDescription> scene_;
  std::optional<ControlReply> reply_;
  std::optional<ContactEvents> contacts_;

 private:
  template <class Message>
  void store(std::optional<Message>& slot, const Message& m) {
    {
      const std::lock_guard lock(mutex_);
      slot = m;
    }
    changed_.notify_all();
  }
  std::mutex mutex_;
  std::condition_variable changed_;
  int decode_errors_ = 0;
  std::optional<DecodeError> last_error_;
};

// Topic names unique to this process, so tests running in parallel (or a rigidd on this host)
// never see each other's messages.
std::string unique_prefix() {
  return "test" + std::to_string(::getpid());
}

using Factory = std::function<std::unique_ptr<Transport>(Role, Receiver&)>;

std::unique_ptr<Transport> open_or_fail(const Factory& make, Role role, Receiver& receiver) {
  try {
    return make(role, receiver);
  } catch (const TransportError& e) {
    ADD_FAILURE() << e.what()
                  << "\n(the loopback tests need scripts/net-setup to have run as root, and "
                     "CYCLONEDDS_URI=file://<repo>/config/cyclonedds.xml)";
    return nullptr;
  }
}

void round_trip(const Factory& make) {
  Mailbox server_box;
  Mailbox client_box;
  const auto server = open_or_fail(make, Role::kServer, server_box);
  const auto client = open_or_fail(make, Role::kClient, client_box);
  ASSERT_TRUE(server && client);

  RandomMessages random(99);
  // ~110 KB: fragmented on both buses.
  const StateFrame state = random.state(1000);
  EXPECT_TRUE(client_box.await(&Mailbox::state_, state, [&] {
    EXPECT_EQ(server->publish(state), PublishResult::kOk);
  })) << "no state received within 10 s";

  WrenchCommand wrench = random.wrench();
  EXPECT_TRUE(server_box.await(&Mailbox::wrench_, wrench, [&] {
    EXPECT_EQ(client->publish(wrench), PublishResult::kOk);
  })) << "no wrench received within 10 s";

  const ControlCommand control = random.control();
  EXPECT_TRUE(server_box.await(&Mailbox::control_, control, [&] {
    EXPECT_EQ(client->publish(control), PublishResult::kOk);
  })) << "no control received within 10 s";

  const EditCommand edit = random.edit();
  EXPECT_TRUE(server_box.await(&Mailbox::edit_, edit, [&] {
    EXPECT_EQ(client->publish(edit), PublishResult::kOk);
  })) << "no edit received within 10 s";

  const ControlReply reply = random.reply();
  EXPECT_TRUE(client_box.await(&Mailbox::reply_, reply, [&] {
    EXPECT_EQ(server->publish(reply), PublishResult::kOk);
  })) << "no control reply received within 10 s";

  const StatsReport stats = random.stats();
  EXPECT_TRUE(client_box.await(&Mailbox::stats_, stats, [&] {
    EXPECT_EQ(server->publish(stats), PublishResult::kOk);
  })) << "no stats received within 10 s";

  // A full tick's worth of events (~300 KB): fragmented on both buses.
  const ContactEvents contacts = random.contacts(kMaxContactEvents);
  EXPECT_TRUE(client_box.await(&Mailbox::contacts_, contacts, [&] {
    EXPECT_EQ(server->publish(contacts), PublishResult::kOk);
  })) << "no contact events received within 10 s";

  // Roles are enforced: a client does not publish state, a server does not publish commands.
  EXPECT_EQ(client->publish(state), PublishResult::kWrongRole);
  EXPECT_EQ(client->publish(contacts), PublishResult::kWrongRole);
  EXPECT_EQ(server->publish(wrench), PublishResult::kWrongRole);
  EXPECT_EQ(server->publish(edit), PublishResult::kWrongRole);

  EXPECT_EQ(server_box.decode_errors(), 0);
  EXPECT_EQ(client_box.decode_errors(), 0);
  EXPECT_GE(server->counts().sent, 3);
  EXPECT_GE(server->counts().received, 3);
  EXPECT_GE(client->counts().received, 3);
}

Factory dds_factory(const std::string& prefix = unique_prefix()) {
  return [prefix](Role role, Receiver& receiver) {
    dds::Options options;
    options.role = role;
    options.prefix = prefix;
    return dds::make_transport(options, receiver);
  };
}

Factory lcm_factory(const std::string& prefix = unique_prefix()) {
  return [prefix](Role role, Receiver& receiver) {
    lcm::Options options;
    options.role = role;
    options.prefix = prefix;
    // A 1000-body state is ~110 KB: give the receiving socket room for a few.
    options.url = std::string(lcm::kDefaultUrl) + "&recv_buf_size=4194304";
    return lcm::make_transport(options, receiver);
  };
}

TEST(Loopback, DdsRoundTrip) {
  round_trip(dds_factory());
}

TEST(Loopback, LcmRoundTrip) {
  round_trip(lcm_factory());
}

// The scene is transient-local on DDS: a client that joins after it was published still gets it.
TEST(Loopback, DdsLateJoinerGetsTheScene) {
  Mailbox server_box;
  Mailbox client_box;
  const Factory make = dds_factory();
  const auto server = open_or_fail(make, Role::kServer, server_box);
  ASSERT_TRUE(server);
  RandomMessages random(5);
  const SceneDescription scene = random.scene(10);
  ASSERT_EQ(server->publish(scene), PublishResult::kOk);

  const auto client = open_or_fail(make, Role::kClient, client_box);
  ASSERT_TRUE(client);
  EXPECT_TRUE(client_box.await(&Mailbox::scene_, scene, [] {}))
      << "late joiner did not get the scene within 10 s";
}

// LCM has no durability: the server transport keeps the scene it last published and sends those
// bytes again on republish_scene() (rigidd does so every second), which reaches a late joiner.
TEST(Loopback, LcmLateJoinerGetsTheSceneWhenItIsRepublished) {
  Mailbox server_box;
  Mailbox client_box;
  const Factory make = lcm_factory();
  const auto server = open_or_fail(make, Role::kServer, server_box);
  ASSERT_TRUE(server);
  EXPECT_EQ(server->republish_scene(), PublishResult::kInvalid) << "nothing published yet";
  RandomMessages random(6);
  const SceneDescription scene = random.scene(300);
  ASSERT_EQ(server->publish(scene), PublishResult::kOk);
  SceneDescription refused = scene;
  refused.masses.pop_back();
  ASSERT_EQ(server->publish(refused), PublishResult::kInvalid);

  const auto client = open_or_fail(make, Role::kClient, client_box);
  ASSERT_TRUE(client);
  EXPECT_EQ(client->republish_scene(), PublishResult::kWrongRole);
  // The scene went out before the client subscribed: only a republish can reach it, and what
  // arrives is the last scene published whole (the refused one left it as it was).
  EXPECT_TRUE(client_box.await(&Mailbox::scene_, scene, [&] {
    ASSERT_EQ(server->republish_scene(), PublishResult::kOk);
  })) << "late joiner did not get the republished scene within 10 s";
}

// The same bus between two processes: in one process Cyclone delivers locally without touching
// the network, so only this shows that discovery and data cross loopback with the shipped config.
// The peer (loopback_peer.cpp) waits for the state, answers with a wrench, waits for our reply.
void cross_process(const std::string& bus) {
  // Not the in-process tests' prefix: their late packets must not reach the peer.
  const std::string prefix = unique_prefix() + "x";
  const Factory make = bus == "dds" ? dds_factory(prefix) : lcm_factory(prefix);
  const std::uint64_t seed = 1234;
  std::string peer = RIGID_LOOPBACK_PEER;
  std::string seed_text = std::to_string(seed);
  char* argv[] = {peer.data(), const_cast<char*>(bus.c_str()), const_cast<char*>(prefix.c_str()),
                  seed_text.data(), nullptr};
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, peer.c_str(), nullptr, nullptr, argv, environ), 0) << peer;

  Mailbox server_box;
  const auto server = open_or_fail(make, Role::kServer, server_box);
  RandomMessages random(seed);
  const StateFrame state = random.state(1000);
  const WrenchCommand wrench = random.wrench();
  if (server) {
    EXPECT_TRUE(server_box.await(&Mailbox::wrench_, wrench, [&] { (void)server->publish(state); }))
        << "no wrench from the peer within 10 s";
  }
  ControlReply ack;
  ack.seq = wrench.seq;
  int status = 0;
  const auto deadline = std::chrono::steady_clock::now() + kPatience;
  pid_t done = 0;
  while ((done = ::waitpid(pid, &status, WNOHANG)) == 0 &&
         std::chrono::steady_clock::now() < deadline) {
    if (server) (void)server->publish(ack);
    std::this_thread::sleep_for(20ms);
  }
  if (done == 0) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
    ADD_FAILURE() << "peer still running after 10 s: killed";
    return;
  }
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "the peer failed (its stderr is above)";
}

TEST(Loopback, DdsBetweenTwoProcesses) {
  cross_process("dds");
}

TEST(Loopback, LcmBetweenTwoProcesses) {
  cross_process("lcm");
}

TEST(Loopback, BadSettingsAreRefusedWithAnError) {
  Mailbox box;
  dds::Options dds_options;
  dds_options.prefix = "bad prefix";
  EXPECT_THROW(dds::make_transport(dds_options, box), TransportError);
  dds_options.prefix.clear();
  dds_options.role = Role::kClient;
  for (const int history : {0, -1, dds::kMaxStateHistory + 1}) {
    dds_options.state_history = history;
    try {
      (void)dds::make_transport(dds_options, box);
      ADD_FAILURE() << "state_history " << history << " accepted";
    } catch (const TransportError& e) {
      EXPECT_NE(std::string(e.what()).find("state_history " + std::to_string(history)),
                std::string::npos)
          << e.what();
    }
  }
  dds_options.state_history = dds::kMaxStateHistory;
  EXPECT_NO_THROW((void)dds::make_transport(dds_options, box));
  lcm::Options lcm_options;
  lcm_options.prefix = "a.*";
  EXPECT_THROW(lcm::make_transport(lcm_options, box), TransportError);
  lcm_options.prefix.clear();
  lcm_options.url = "udpm://999.0.0.1:7667";
  EXPECT_THROW(lcm::make_transport(lcm_options, box), TransportError);
}

}  // namespace
}  // namespace rigid::transport
