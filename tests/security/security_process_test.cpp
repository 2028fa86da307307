// rigidd against attackers, as real processes over loopback (issue: "let no one in who does not
// belong"). The attackers are built from the message definitions only (idlc's C types of
// msgs/rigid.idl, lcm-gen's of msgs/rigid.lcm, raw sockets), never from the project's clients;
// the legitimate side is rigidctl. Keystores come from scripts/rigid-keys.
//
// With DDS Security: an unauthenticated participant sees no state and moves nothing; an identity
// moves only the bodies its permissions name and controls only if it may; expired and revoked
// certificates are refused; a second identity cannot lock the first out whatever sequence
// numbers it sends; the command topics carry no plaintext on the wire.
// Without security: a hijacker's INT64_MAX sequence number does not lock out another session; a
// flood of distinct keys leaves a newcomer its share; oversized and withheld-fragment messages do
// not raise rigidd's peak memory (a plain reader of the same DDS samples, whose peak does rise, is
// the control); `rate 1000` takes no more than the loop's CPU.
#include <arpa/inet.h>
#include <dds/dds.h>
#include <gtest/gtest.h>
#include <linux/if_packet.h>
#include <net/ethernet.h>
#include <net/if.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "rigid.h"  // idlc's C types of msgs/rigid.idl
#include "rigid_lcm/Wrench.hpp"
#include "rigidd_process.hpp"

namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
using rigid::rigidd::testing::Completed;
using rigid::rigidd::testing::RigiddProcess;
using rigid::rigidd::testing::run_program_to_exit;

const std::string kScene = std::string(SECURITY_TEST_SCENES) + "/craft.pbtxt";

// A keystore made once for all tests (rigid-keys takes a second per identity): `init` with
// `init_options`, then each identity `add`ed with its options (and revoked if named in `revoke`).
class Keystore {
 public:
  Keystore(const std::string& tag, const std::vector<std::string>& init_options,
           const std::vector<std::vector<std::string>>& identities,
           const std::vector<std::string>& revoke = {}) {
    dir_ = fs::temp_directory_path() / ("rigid-keystore-" + tag + std::to_string(::getpid()));
    fs::remove_all(dir_);
    std::vector<std::string> init{"init", dir_.string()};
    init.insert(init.end(), init_options.begin(), init_options.end());
    run(init);
    for (const std::vector<std::string>& id : identities) {
      std::vector<std::string> add{"add", dir_.string()};
      add.insert(add.end(), id.begin(), id.end());
      run(add);
    }
    for (const std::string& name : revoke)
      run({"revoke", dir_.string(), name});
  }
  ~Keystore() { fs::remove_all(dir_); }
  std::string identity(const std::string& name) const {
    return (dir_ / "identities" / name).string();
  }

 private:
  static void run(const std::vector<std::string>& args) {
    const Completed r = run_program_to_exit(RIGID_KEYS, args, 60s);
    if (r.exit_code != 0) {
      throw std::runtime_error("rigid-keys " + args[0] + " failed: " + r.err);
    }
  }
  fs::path dir_;
};

Keystore& keystore() {
  static Keystore k(
      "", {},
      {{"reader", "--may", "read"},
       {"pusher", "--may", "push:zebracraft"},
       {"mallory", "--may", "push:zebracraft"},
       {"ctl", "--may", "control"},
       // May push every body: its permissions (sent in clear in the handshake, as DDS Security
       // does) then name no body, so a capture can be searched for body names.
       {"pushall", "--may", "push"},
       {"expired", "--may", "push", "--valid-from", "2020-01-01", "--valid-until", "2020-01-02"},
       {"revoked", "--may", "push"}},
      {"revoked"});
  return k;
}

// Another keystore, made the same way: its CA signs none of the first's identities.
Keystore& other_keystore() {
  static Keystore k("other-", {}, {{"stranger", "--may", "read"}});
  return k;
}

// `rigid-keys init --open-state`: unauthenticated participants may read the state.
Keystore& open_keystore() {
  static Keystore k("open-", {"--open-state"},
                    {{"reader", "--may", "read"}, {"pusher", "--may", "push:zebracraft"}});
  return k;
}

Completed rigidctl(std::vector<std::string> args, const std::string& identity = "",
                   const Keystore& ks = keystore()) {
  if (!identity.empty()) {
    args.push_back("--security");
    args.push_back(ks.identity(identity));
  }
  args.push_back("--timeout");
  args.push_back("4");
  return run_program_to_exit(RIGIDCTL_EXE, args, 20s);
}

// The velocity of body `name` in the newest state a permitted reader sees (rigidctl echo --csv).
std::optional<double> speed_of(const std::string& body, const std::string& identity,
                               const Keystore& ks = keystore()) {
  const Completed r = rigidctl({"echo", body, "--csv", "--count", "1"}, identity, ks);
  if (r.exit_code != 0) return std::nullopt;
  // t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz
  std::istringstream lines(r.out);
  std::string line;
  std::optional<double> v;
  while (std::getline(lines, line)) {
    if (line.find(body) == std::string::npos) continue;
    std::vector<double> cols;
    std::istringstream fields(line);
    std::string f;
    while (std::getline(fields, f, ','))
      cols.push_back(std::strtod(f.c_str(), nullptr));
    if (cols.size() >= 12) v = std::hypot(cols[9], cols[10], cols[11]);
  }
  return v;
}

// speed_of once it reads `expected` (a push's whole effect, its ttl run out), polled for up to
// 10 s so that a loaded host holding rigidd or rigidctl back fails nothing; else the last reading.
std::optional<double> speed_reaching(double expected, const std::string& body,
                                     const std::string& identity, const Keystore& ks = keystore()) {
  std::optional<double> v;
  const auto end = std::chrono::steady_clock::now() + 10s;
  do {
    v = speed_of(body, identity, ks);
    if (v && std::abs(*v - expected) < 0.005) break;
    std::this_thread::sleep_for(100ms);
  } while (std::chrono::steady_clock::now() < end);
  return v;
}

// A DDS participant written against the IDL alone: plain, or with the security plugins of an
// identity directory (the properties are Cyclone's, spelled out here, not taken from rigid).
class RawParticipant {
 public:
  explicit RawParticipant(const std::string& identity_dir = "") {
    dds_qos_t* qos = dds_create_qos();
    if (!identity_dir.empty()) {
      const std::string lib = RIGID_DDS_SECURITY_DIR;
      const auto file = [&](const char* f) { return "file:" + identity_dir + "/" + f; };
      const std::vector<std::pair<std::string, std::string>> props{
          {"dds.sec.auth.library.path", lib + "/libdds_security_auth.so"},
          {"dds.sec.auth.library.init", "init_authentication"},
          {"dds.sec.auth.library.finalize", "finalize_authentication"},
          {"dds.sec.crypto.library.path", lib + "/libdds_security_crypto.so"},
          {"dds.sec.crypto.library.init", "init_crypto"},
          {"dds.sec.crypto.library.finalize", "finalize_crypto"},
          {"dds.sec.access.library.path", lib + "/libdds_security_ac.so"},
          {"dds.sec.access.library.init", "init_access_control"},
          {"dds.sec.access.library.finalize", "finalize_access_control"},
          {"dds.sec.auth.identity_ca", file("identity_ca.pem")},
          {"dds.sec.auth.identity_certificate", file("cert.pem")},
          {"dds.sec.auth.private_key", file("key.pem")},
          {"dds.sec.access.permissions_ca", file("permissions_ca.pem")},
          {"dds.sec.access.governance", file("governance.p7s")},
          {"dds.sec.access.permissions", file("permissions.p7s")}};
      for (const auto& [k, v] : props)
        dds_qset_prop(qos, k.c_str(), v.c_str());
    }
    participant_ = dds_create_participant(0, qos, nullptr);
    dds_delete_qos(qos);
  }
  ~RawParticipant() {
    if (participant_ > 0) dds_delete(participant_);
  }
  dds_entity_t get() const { return participant_; }

  // A reliable wrench writer in `partition` ("" for the default one); <= 0 if refused.
  dds_entity_t wrench_writer(const std::string& partition) {
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(10));
    dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 256);
    const dds_entity_t topic =
        dds_create_topic(participant_, &rigid_Wrench_desc, "rigid/wrench", qos, nullptr);
    if (topic < 0) {
      dds_delete_qos(qos);
      return topic;
    }
    if (!partition.empty()) {
      const char* ps[] = {partition.c_str()};
      dds_qset_partition(qos, 1, ps);
    }
    const dds_entity_t w = dds_create_writer(participant_, topic, qos, nullptr);
    dds_delete_qos(qos);
    return w;
  }

  // Counts rigid/state samples for `patience`, or until `enough` came.
  int count_states(std::chrono::milliseconds patience, int enough = INT_MAX) {
    dds_qos_t* qos = dds_create_qos();
    dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
    const dds_entity_t topic =
        dds_create_topic(participant_, &rigid_WorldState_desc, "rigid/state", qos, nullptr);
    const dds_entity_t reader = dds_create_reader(participant_, topic, qos, nullptr);
    dds_delete_qos(qos);
    if (reader < 0) return -1;
    int n = 0;
    const auto end = std::chrono::steady_clock::now() + patience;
    while (std::chrono::steady_clock::now() < end && n < enough) {
      void* samples[8] = {};
      dds_sample_info_t infos[8];
      const dds_return_t got = dds_take(reader, samples, infos, 8, 8);
      if (got > 0) {
        n += got;
        dds_return_loan(reader, samples, got);
      }
      std::this_thread::sleep_for(10ms);
    }
    return n;
  }

 private:
  dds_entity_t participant_ = -1;
};

rigid_Wrench raw_wrench(std::int64_t source, std::int64_t seq, double fx, double ttl) {
  rigid_Wrench w{};
  w.source = source;
  w.seq = seq;
  w.body_id = 0;  // zebracraft
  std::strcpy(w.body_name, "zebracraft");
  w.force[0] = fx;
  w.ttl = ttl;
  return w;
}

class SecureRigidd : public ::testing::Test {
 protected:
  void SetUp() override { start(keystore()); }
  void start(const Keystore& ks) {
    daemon_ = std::make_unique<RigiddProcess>(std::vector<std::string>{
        "--scene", kScene, "--security", ks.identity("rigidd"), "--spin-us", "0"});
    // Authentication and discovery take ~0.3 s; a permitted reader sees the scene when ready.
    ASSERT_EQ(rigidctl({"bodies"}, "reader", ks).exit_code, 0) << daemon_->stderr_text();
  }
  void TearDown() override {
    if (daemon_) {
      EXPECT_EQ(daemon_->terminate(2000ms), 0) << daemon_->stderr_text();
    }
  }
  std::unique_ptr<RigiddProcess> daemon_;
};

TEST_F(SecureRigidd, APermittedIdentityPushesItsBodyAndNoOther) {
  const Completed ok =
      rigidctl({"push", "zebracraft", "--force", "2,0,0", "--for", "0.1"}, "pusher");
  EXPECT_EQ(ok.exit_code, 0) << ok.err << daemon_->stderr_text();
  const auto v = speed_reaching(2.0 / 2.0 * 0.1, "zebracraft", "reader");
  ASSERT_TRUE(v);
  EXPECT_NEAR(*v, 2.0 / 2.0 * 0.1, 0.01);  // F t / m

  const Completed other = rigidctl({"push", "okapirock", "--force", "2,0,0"}, "pusher");
  EXPECT_EQ(other.exit_code, 1) << other.err;
  EXPECT_NE(other.err.find("not permitted"), std::string::npos) << other.err;
  const auto rock = speed_of("okapirock", "reader");
  ASSERT_TRUE(rock);
  EXPECT_EQ(*rock, 0.0);
}

TEST_F(SecureRigidd, AReaderReadsButNeitherPushesNorControls) {
  const Completed bodies = rigidctl({"bodies"}, "reader");
  EXPECT_EQ(bodies.exit_code, 0);
  EXPECT_NE(bodies.out.find("zebracraft"), std::string::npos) << bodies.out;
  const Completed push = rigidctl({"push", "zebracraft", "--force", "2,0,0"}, "reader");
  EXPECT_EQ(push.exit_code, 1) << push.err;
  const Completed pause = rigidctl({"pause"}, "reader");
  EXPECT_EQ(pause.exit_code, 1) << pause.err;
  EXPECT_NE(pause.err.find("not permitted"), std::string::npos) << pause.err;
  // An identity that may push may not control either; one that may control does.
  EXPECT_EQ(rigidctl({"pause"}, "pusher").exit_code, 1);
  const Completed ctl = rigidctl({"pause"}, "ctl");
  EXPECT_EQ(ctl.exit_code, 0) << ctl.err << daemon_->stderr_text();
  EXPECT_EQ(rigidctl({"resume"}, "ctl").exit_code, 0);
}

// Edits (set_state, reset_body) go where controls go: only an identity that may control makes
// them; a reader's and a pusher's are refused (their permissions give them no writer), changing
// nothing.
TEST_F(SecureRigidd, OnlyAnIdentityThatMayControlEditsBodies) {
  for (const std::string who : {"reader", "pusher"}) {
    const Completed set = rigidctl({"set", "okapirock", "--velocity", "1,0,0"}, who);
    EXPECT_EQ(set.exit_code, 1) << who << ": " << set.err;
    EXPECT_NE(set.err.find("not permitted"), std::string::npos) << set.err;
  }
  EXPECT_EQ(rigidctl({"reset", "okapirock"}, "pusher").exit_code, 1);
  const auto still = speed_of("okapirock", "reader");
  ASSERT_TRUE(still);
  EXPECT_EQ(*still, 0.0);

  const Completed set = rigidctl({"set", "okapirock", "--velocity", "0.5,0,0"}, "ctl");
  EXPECT_EQ(set.exit_code, 0) << set.err << daemon_->stderr_text();
  const auto moving = speed_reaching(0.5, "okapirock", "reader");
  ASSERT_TRUE(moving);
  EXPECT_EQ(*moving, 0.5);
  const Completed reset = rigidctl({"reset", "okapirock"}, "ctl");
  EXPECT_EQ(reset.exit_code, 0) << reset.err;
  const auto back = speed_reaching(0.0, "okapirock", "reader");
  ASSERT_TRUE(back);
  EXPECT_EQ(*back, 0.0);
}

// An unauthenticated participant writes 20 wrenches of 50 N on zebracraft in the pusher's
// partition.
void push_unauthenticated(RawParticipant& plain) {
  const dds_entity_t w = plain.wrench_writer("push/pusher/zebracraft");
  ASSERT_GT(w, 0);
  for (int i = 1; i <= 20; ++i) {
    rigid_Wrench s = raw_wrench(42, i, 50.0, 1.0);
    dds_write(w, &s);
    std::this_thread::sleep_for(20ms);
  }
}

// Its control, that the same reader sees a rigidd's states where it may: TheUnauthenticated-
// ReaderSeesAPlainRigiddsStates and OpenStateRigidd below.
TEST_F(SecureRigidd, AnUnauthenticatedParticipantSeesNothingAndMovesNothing) {
  RawParticipant plain;
  ASSERT_GT(plain.get(), 0);
  EXPECT_EQ(plain.count_states(1500ms), 0);
  push_unauthenticated(plain);
  const auto v = speed_of("zebracraft", "reader");
  ASSERT_TRUE(v);
  EXPECT_EQ(*v, 0.0);
}

// rigid-keys init --open-state: the unauthenticated participant reads the state, and still moves
// nothing, while an identity that may push does.
class OpenStateRigidd : public SecureRigidd {
 protected:
  void SetUp() override { start(open_keystore()); }
};

TEST_F(OpenStateRigidd, AnUnauthenticatedParticipantReadsTheStateButMovesNothing) {
  RawParticipant plain;
  ASSERT_GT(plain.get(), 0);
  EXPECT_GE(plain.count_states(10s, 5), 5) << daemon_->stderr_text();
  push_unauthenticated(plain);
  auto v = speed_of("zebracraft", "reader", open_keystore());
  ASSERT_TRUE(v);
  EXPECT_EQ(*v, 0.0);
  const Completed push = rigidctl({"push", "zebracraft", "--force", "2,0,0", "--for", "0.1"},
                                  "pusher", open_keystore());
  EXPECT_EQ(push.exit_code, 0) << push.err << daemon_->stderr_text();
  v = speed_reaching(0.1, "zebracraft", "reader", open_keystore());
  ASSERT_TRUE(v);
  EXPECT_NEAR(*v, 0.1, 0.01);
}

TEST_F(SecureRigidd, ExpiredAndRevokedCertificatesAreRefused) {
  // rigidctl gives Cyclone the identity's files, CRL included: it cannot start with either, and
  // says why in one line of its own, with Cyclone's reason (Cyclone's own lines kept out).
  const Completed expired = rigidctl({"bodies"}, "expired");
  EXPECT_EQ(expired.exit_code, 1) << expired.out;
  EXPECT_EQ(expired.err, "rigidctl: DDS Security refused the identity in " +
                             keystore().identity("expired") +
                             ": Certificate not valid: certificate has expired; subject: "
                             "/CN=expired (rigid-keys list KEYSTORE shows its dates and status)\n");
  const Completed revoked =
      rigidctl({"push", "zebracraft", "--force", "2,0,0", "--for", "0.1"}, "revoked");
  EXPECT_EQ(revoked.exit_code, 1) << revoked.out;
  EXPECT_EQ(revoked.err.rfind("rigidctl: DDS Security refused the identity in " +
                                  keystore().identity("revoked") +
                                  ": Certificate not valid: certificate revoked; subject: "
                                  "/CN=revoked",
                              0),
            0u)
      << revoked.err;
  EXPECT_EQ(std::count(revoked.err.begin(), revoked.err.end(), '\n'), 1) << revoked.err;
  // A revoked identity that keeps its key and certificate but not the CRL (raw_dds_writer passes
  // none): rigidd, which reads the CRL at start, refuses its handshake, so its writer in its own
  // partition never matches, and nothing moves.
  const auto raw_push = [](const std::string& identity) {
    return run_program_to_exit(RAW_DDS_WRITER,
                               {"--security", keystore().identity(identity), "--partition",
                                "push/" + identity + "/zebracraft", "--force", "2", "--ttl", "0.1"},
                               20s);
  };
  const Completed raw = raw_push("revoked");
  EXPECT_EQ(raw.exit_code, 1) << "its writer matched rigidd's reader\n" << raw.err;
  const std::string log = daemon_->stderr_text() + daemon_->stdout_text();
  EXPECT_NE(log.find("certificate revoked; subject: /CN=revoked"), std::string::npos) << log;
  auto v = speed_of("zebracraft", "reader");
  ASSERT_TRUE(v);
  EXPECT_EQ(*v, 0.0);
  // The control: an identity in good standing, written the same way, moves it.
  const Completed good = raw_push("pushall");
  EXPECT_EQ(good.exit_code, 0) << good.err;
  v = speed_reaching(0.1, "zebracraft", "reader");
  ASSERT_TRUE(v);
  EXPECT_NEAR(*v, 0.1, 0.01) << daemon_->stderr_text();
}

// An identity of another keystore: the handshake with rigidd fails (neither trusts the other's
// CA). rigidctl says that authentication failed and why, in one line, instead of asking whether
// rigidd runs, and none of Cyclone's own lines (repeated every second) reach its output.
TEST_F(SecureRigidd, AnIdentityOfAnotherKeystoreIsToldThatAuthenticationFailed) {
  const Completed stranger = rigidctl({"bodies"}, "stranger", other_keystore());
  EXPECT_EQ(stranger.exit_code, 3) << stranger.err;
  EXPECT_EQ(std::count(stranger.err.begin(), stranger.err.end(), '\n'), 1) << stranger.err;
  EXPECT_EQ(stranger.err.rfind("rigidctl: no SceneInfo from rigidd within 4 s on dds domain 0: "
                               "DDS Security authentication with a participant failed: "
                               "Certificate not valid: ",
                               0),
            0u)
      << stranger.err;
  EXPECT_NE(stranger.err.find("subject: /CN=rigidd"), std::string::npos) << stranger.err;
}

TEST_F(SecureRigidd, ASecondIdentityCannotLockTheFirstOut) {
  // Each identity in its own process (raw_dds_writer: the IDL's types and Cyclone's security
  // properties, nothing of rigid's clients), as two machines would be.
  const auto write = [](const std::string& identity, const std::string& partition,
                        const std::string& seq, const std::string& force) {
    return run_program_to_exit(
        RAW_DDS_WRITER,
        {"--security", keystore().identity(identity), "--partition", partition, "--source", "7",
         "--seq", seq, "--force", force, "--ttl", "0.1"},
        20s);
  };
  // Mallory may write only in its own partition: access control refuses the writer.
  EXPECT_EQ(write("mallory", "push/pusher/zebracraft", "1", "0").exit_code, 3);
  // In its own, it writes the other's source with the largest sequence number (zero force).
  const Completed m = write("mallory", "push/mallory/zebracraft", "9223372036854775807", "0");
  ASSERT_EQ(m.exit_code, 0) << m.err;
  // The first identity's command on that source still acts: 2 N for 0.1 s on 2 kg.
  const Completed a = write("pusher", "push/pusher/zebracraft", "2", "2");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto v = speed_reaching(0.1, "zebracraft", "reader");
  ASSERT_TRUE(v);
  EXPECT_NEAR(*v, 0.1, 0.01) << daemon_->stderr_text();
}

// Captures every frame on lo while `during` runs (root: an AF_PACKET socket).
std::string capture_loopback(const std::function<void()>& during) {
  const int fd = ::socket(AF_PACKET, SOCK_RAW, htons(ETH_P_ALL));
  if (fd < 0) return {};
  sockaddr_ll addr{};
  addr.sll_family = AF_PACKET;
  addr.sll_protocol = htons(ETH_P_ALL);
  addr.sll_ifindex = static_cast<int>(if_nametoindex("lo"));
  ::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  timeval tv{0, 50'000};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  int big = 8 << 20;
  ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &big, sizeof big);
  std::string bytes;
  std::atomic<bool> stop{false};
  std::thread reader([&] {
    std::vector<char> frame(1 << 17);
    while (!stop.load()) {
      const ssize_t n = ::recv(fd, frame.data(), frame.size(), 0);
      if (n > 0) bytes.append(frame.data(), static_cast<std::size_t>(n));
    }
  });
  during();
  std::this_thread::sleep_for(200ms);
  stop = true;
  reader.join();
  ::close(fd);
  return bytes;
}

TEST_F(SecureRigidd, CommandsCarryNoPlaintextOnTheWire) {
  const double force = 12.345678901234;  // its 8 bytes are searched for
  Completed push;
  const std::string wire = capture_loopback([&] {
    push = rigidctl({"push", "zebracraft", "--force", "12.345678901234,0,0"}, "pushall");
  });
  ASSERT_EQ(push.exit_code, 0) << push.err;
  ASSERT_GT(wire.size(), 1000u) << "nothing captured on lo (needs root)";
  std::string needle(sizeof force, '\0');
  std::memcpy(needle.data(), &force, sizeof force);
  EXPECT_EQ(wire.find(needle), std::string::npos) << "the force went out in plaintext";
  const auto context = [&wire](std::size_t at) {
    std::string text;
    for (std::size_t i = at < 120 ? 0 : at - 120; i < std::min(wire.size(), at + 40); ++i)
      text += wire[i] >= 0x20 && wire[i] < 0x7f ? wire[i] : '.';
    return text;
  };
  const std::size_t name_at = wire.find("zebracraft");
  EXPECT_EQ(name_at, std::string::npos)
      << "the body name went out in plaintext: " << context(name_at);
  EXPECT_EQ(wire.find("okapirock"), std::string::npos) << "the scene went out in plaintext";
}

// --- Without security ----------------------------------------------------------------------

// An LCM sender with one socket (one session), writing lcm-gen's encoding of msgs/rigid.lcm.
class RawLcm {
 public:
  RawLcm() : fd_(::socket(AF_INET, SOCK_DGRAM, 0)) {
    const unsigned char ttl = 0;
    ::setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl);
  }
  ~RawLcm() { ::close(fd_); }
  bool send_datagram(const std::vector<std::uint8_t>& datagram) const {
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(7667);
    ::inet_pton(AF_INET, "239.255.76.67", &to.sin_addr);
    return ::sendto(fd_, datagram.data(), datagram.size(), 0,
                    reinterpret_cast<const sockaddr*>(&to),
                    sizeof to) == static_cast<ssize_t>(datagram.size());
  }
  bool wrench(std::int64_t source, std::int64_t seq, std::int32_t key, double fx, double ttl,
              const std::string& body = "zebracraft") const {
    rigid_lcm::Wrench w{};
    w.source = source;
    w.seq = seq;
    w.key = key;
    w.body_id = -1;
    w.body_name = body;
    w.force[0] = fx;
    w.ttl = ttl;
    std::vector<std::uint8_t> payload(static_cast<std::size_t>(w.getEncodedSize()));
    w.encode(payload.data(), 0, static_cast<int>(payload.size()));
    std::vector<std::uint8_t> d{'L', 'C', '0', '2', 0, 0, 0, 0};
    const std::string channel = "RIGID_WRENCH";
    d.insert(d.end(), channel.begin(), channel.end());
    d.push_back(0);
    d.insert(d.end(), payload.begin(), payload.end());
    return send_datagram(d);
  }

 private:
  int fd_;
};

// The peak of a process's resident memory (VmHWM), and its reset to the current resident size
// (proc(5), clear_refs "5"): what a reassembled sample costs at its largest, however soon it is
// freed.
std::int64_t peak_kb(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::strtoll(line.c_str() + 6, nullptr, 10);
  return -1;
}
bool reset_peak(pid_t pid) {
  std::ofstream clear("/proc/" + std::to_string(pid) + "/clear_refs");
  clear << "5";
  clear.flush();
  return static_cast<bool>(clear);
}

bool wait_for_output(const RigiddProcess& p, const std::string& text,
                     std::chrono::milliseconds patience) {
  const auto end = std::chrono::steady_clock::now() + patience;
  while (p.stdout_text().find(text) == std::string::npos) {
    if (std::chrono::steady_clock::now() > end || !p.running()) return false;
    std::this_thread::sleep_for(20ms);
  }
  return true;
}

class PlainRigidd : public ::testing::Test {
 protected:
  void SetUp() override {
    daemon_ = std::make_unique<RigiddProcess>(
        std::vector<std::string>{"--scene", kScene, "--spin-us", "0"});
    ASSERT_EQ(rigidctl({"bodies", "--transport", "lcm"}).exit_code, 0) << daemon_->stderr_text();
  }
  void TearDown() override {
    if (daemon_) {
      EXPECT_EQ(daemon_->terminate(2000ms), 0) << daemon_->stderr_text();
    }
  }
  std::unique_ptr<RigiddProcess> daemon_;
};

// The control of SecureRigidd's unauthenticated participant: the same reader, against rigidd
// without security, sees its states.
TEST_F(PlainRigidd, TheUnauthenticatedReaderSeesAPlainRigiddsStates) {
  RawParticipant plain;
  ASSERT_GT(plain.get(), 0);
  EXPECT_GE(plain.count_states(10s, 5), 5) << daemon_->stderr_text();
}

TEST_F(PlainRigidd, AHijackedSequenceNumberDoesNotLockOutAnotherSession) {
  RawLcm controller;
  RawLcm hijacker;
  ASSERT_TRUE(controller.wrench(7, 1, 0, 0.0, 0.0));
  // The hijacker copies the controller's source (every client sees it on rigid/accepted).
  ASSERT_TRUE(hijacker.wrench(7, INT64_MAX, 0, 0.0, 0.0));
  std::this_thread::sleep_for(100ms);
  // The controller's next command acts, and so does a restarted controller's (a new session).
  ASSERT_TRUE(controller.wrench(7, 2, 0, 2.0, 0.1));
  auto v = speed_reaching(0.1, "zebracraft", "");
  ASSERT_TRUE(v);
  EXPECT_NEAR(*v, 0.1, 0.01) << daemon_->stderr_text();
  RawLcm restarted;
  ASSERT_TRUE(restarted.wrench(7, 1, 0, 2.0, 0.1));
  v = speed_reaching(0.2, "zebracraft", "");
  ASSERT_TRUE(v);
  EXPECT_NEAR(*v, 0.2, 0.01) << daemon_->stderr_text();
}

TEST_F(PlainRigidd, AFloodOfKeysLeavesANewcomerItsShare) {
  RawLcm flooder;
  // Far more distinct keys than the table holds, each acting for 5 s (zero force).
  for (int key = 0; key < 6000; ++key) {
    flooder.wrench(9, key + 1, key, 0.0, 5.0);
    if (key % 200 == 199) std::this_thread::sleep_for(100ms);  // within its command rate
  }
  RawLcm newcomer;
  ASSERT_TRUE(newcomer.wrench(11, 1, 0, 2.0, 0.1));
  const auto v = speed_reaching(0.1, "zebracraft", "");
  ASSERT_TRUE(v);
  EXPECT_NEAR(*v, 0.1, 0.01) << daemon_->stderr_text();
  const Completed stats = rigidctl({"stats", "--once", "--transport", "lcm"});
  EXPECT_NE(stats.out.find("over_share"), std::string::npos) << stats.out;
}

TEST_F(PlainRigidd, LcmFragmentsOfOversizedMessagesCostItNoMemory) {
  ASSERT_TRUE(reset_peak(daemon_->pid()));
  const std::int64_t before = peak_kb(daemon_->pid());
  ASSERT_GT(before, 0);
  // First fragments of 10 MB messages whose other fragments never come.
  RawLcm lcm;
  for (int i = 0; i < 20; ++i) {
    std::vector<std::uint8_t> d{'L',  'C',  '0',  '3',  0, 0, 0, static_cast<std::uint8_t>(i),
                                0x00, 0xa0, 0x00, 0x00,   // message size: 10 MiB
                                0,    0,    0,    0,      // offset 0
                                0,    0,    0x00, 0xa1};  // fragment 0 of 161
    const std::string channel = "RIGID_WRENCH";
    d.insert(d.end(), channel.begin(), channel.end());
    d.push_back(0);
    d.resize(60000, 'x');
    ASSERT_TRUE(lcm.send_datagram(d));
  }
  // rigidd heard them: a valid wrench sent after them is accepted (LCM keeps a socket's order).
  ASSERT_TRUE(lcm.wrench(5, 1, 0, 2.0, 0.1));
  const auto v = speed_reaching(0.1, "zebracraft", "");
  ASSERT_TRUE(v);
  EXPECT_NEAR(*v, 0.1, 0.01) << daemon_->stderr_text();
  const std::int64_t peak = peak_kb(daemon_->pid());
  EXPECT_LT(peak - before, 4 * 1024) << before << " kB before, peak " << peak << " kB";
}

// A 10 MB sample dies at its first fragment in rigidd (Cyclone's MaxSampleSize, which rigidd caps
// at its own largest sample: transport::dds::limit_sample_size), so its peak memory does not
// move. The control shows that the measure sees a reassembly: a plain reader of the same samples
// (raw_dds_reader, Cyclone's default cap) receives them whole, and its peak grows by more than a
// sample.
TEST_F(PlainRigidd, OversizedDdsSamplesDieAtTheirFirstFragment) {
  RigiddProcess control(RAW_DDS_READER, {"3"}, {});
  ASSERT_TRUE(wait_for_output(control, "ready", 10s)) << control.stderr_text();
  ASSERT_TRUE(reset_peak(daemon_->pid()));
  ASSERT_TRUE(reset_peak(control.pid()));
  const std::int64_t before = peak_kb(daemon_->pid());
  const std::int64_t control_before = peak_kb(control.pid());
  ASSERT_GT(before, 0);
  ASSERT_GT(control_before, 0);
  // Wrenches whose body name is 10 MB, from a writer whose IDL has no bound on it, once both
  // rigidd and the control are matched.
  const Completed dds = run_program_to_exit(
      RAW_DDS_WRITER,
      {"--name-bytes", "10485760", "--count", "3", "--force", "1", "--readers", "2"}, 30s);
  ASSERT_EQ(dds.exit_code, 0) << dds.err;
  ASSERT_TRUE(wait_for_output(control, "received 3 largest 10485760", 20s))
      << control.stdout_text() << control.stderr_text();
  const std::int64_t peak = peak_kb(daemon_->pid());
  const std::int64_t control_peak = peak_kb(control.pid());
  EXPECT_GT(control_peak - control_before, 10 * 1024)
      << "the control: " << control_before << " kB before, peak " << control_peak << " kB";
  EXPECT_LT(peak - before, 4 * 1024) << before << " kB before, peak " << peak << " kB\n"
                                     << daemon_->stderr_text();
  EXPECT_EQ(control.terminate(5000ms), 0);
}

// The CPU time all of a process's threads have taken (proc(5) stat: utime + stime), in seconds.
double cpu_seconds(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  const std::string stat((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t close = stat.rfind(')');
  if (close == std::string::npos) return -1;
  std::istringstream fields(stat.substr(close + 2));  // from field 3 on
  std::vector<std::string> f;
  for (std::string w; fields >> w;)
    f.push_back(w);
  if (f.size() < 13) return -1;
  return static_cast<double>(std::stoll(f[14 - 3]) + std::stoll(f[15 - 3])) /
         static_cast<double>(::sysconf(_SC_CLK_TCK));
}

// The overruns in `rigidctl stats --once`'s output; -1 if absent.
long long overruns_in(const std::string& stats) {
  const std::size_t at = stats.find("overruns ");
  return at == std::string::npos ? -1 : std::atoll(stats.c_str() + at + 9);
}

// `rate 1000` asks the loop for 500 kHz: it falls behind on its own CPU, skipping the slots it
// misses (rigidd's own overrun count grows by thousands), and rigidd takes no more than that CPU
// from the host: all its threads' CPU time over a window, against the window's length, stays
// under 1.25 CPUs (the loop's, and the buses' receive threads' little on the others). CPU time,
// not another job's wall time beside it: a host loaded by others cannot raise it, and a stall of
// this test only lengthens the window.
TEST_F(PlainRigidd, RateOf1000TakesNoMoreThanItsLoopsCpu) {
  const Completed rate = rigidctl({"rate", "1000"});
  ASSERT_EQ(rate.exit_code, 0) << rate.err << daemon_->stderr_text();
  const long long overruns_before = overruns_in(rigidctl({"stats", "--once"}).out);
  const double cpu_before = cpu_seconds(daemon_->pid());
  const auto t0 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(3s);
  const double cpu = cpu_seconds(daemon_->pid()) - cpu_before;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const Completed stats = rigidctl({"stats", "--once"});
  const Completed back = rigidctl({"rate", "1"});
  EXPECT_EQ(back.exit_code, 0) << back.err;
  ASSERT_GE(cpu_before, 0.0);
  EXPECT_LT(cpu / wall, 1.25) << cpu << " CPU-s in " << wall << " s\n" << daemon_->stderr_text();
  ASSERT_GE(overruns_before, 0) << "no overruns in rigidctl stats";
  EXPECT_GT(overruns_in(stats.out), overruns_before + 1000) << stats.out;
}

}  // namespace
