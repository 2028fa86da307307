// rigidd itself failing or going away, on each bus: stopped with SIGTERM while a recorder records
// and its journal is written (both files complete, the journal replays bit for bit), and restarted
// under running clients (rigidctl echo and rigid-attitude resume without being restarted, also
// when the new rigidd runs another scene).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <charconv>
#include <cmath>
#include <random>
#include <sstream>
#include <string>

#include "common/log_records.hpp"
#include "common/record_file.hpp"
#include "fault_rig.hpp"
#include "physics/math.hpp"
#include "test_dir.hpp"

namespace rigid::faults::testing {
namespace {

using rigidd::testing::TimedState;
using sim::testing::TestDir;

const std::string kAttitudeMoved = std::string(RIGID_FAULT_SCENES) + "/attitude_moved.pbtxt";

class ServerFault : public ::testing::TestWithParam<Bus> {};

TEST_P(ServerFault, SigtermWhileRecordingAndJournalingLeavesBothFilesCompleteAndReplayable) {
  TestDir dir;
  const std::string journal = dir.file("run.journal");
  const std::string recording = dir.file("run.rlog");
  Rig rig(GetParam(), kDefault, {"--journal", journal});
  ASSERT_TRUE(rig.handshake()) << rig.daemon->stderr_text();
  RigiddProcess recorder(RIGID_RECORD_EXE, concat({"record", recording}, rig.bus_args()), {});
  ASSERT_TRUE(poll_until(
      [&] {
        std::error_code ec;
        return std::filesystem::file_size(recording, ec) > 5'000 && !ec;
      },
      10s))
      << recorder.stderr_text();

  const auto before = rig.stats_after(rig.monitor->last_state()->state.tick);
  ASSERT_TRUE(before);

  // Random pushes on every body, right up to the signal.
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int pushes = 0;
  for (; pushes < 100; ++pushes) {
    rigid::WrenchCommand w;
    w.body_id = static_cast<std::int32_t>(random() % 5);
    w.force = {10 * unit(random), 10 * unit(random), 10 * unit(random)};
    w.point = {0.1 * unit(random), 0, 0.1 * unit(random)};
    w.ttl = 0.01 * static_cast<double>(random() % 5);
    rig.monitor->send(w);
    std::this_thread::sleep_for(5ms);
  }
  // Every push taken in (Stats counts them), then SIGTERM at once.
  ASSERT_TRUE(rig.monitor->wait(
      [&] {
        const auto& s = rig.monitor->stats_locked();
        return s && s->commands_accepted - before->commands_accepted == pushes;
      },
      5s));
  EXPECT_EQ(rig.daemon->terminate(1000ms), 0) << rig.daemon->stderr_text();
  const std::int64_t last_seen = rig.monitor->last_state()->state.tick;
  recorder.signal(SIGINT);  // rigid-record outlives rigidd; it closes its file on a signal
  const auto status = recorder.wait_exit(5s);
  ASSERT_TRUE(status && WIFEXITED(*status) && WEXITSTATUS(*status) == 0) << recorder.stderr_text();

  // The journal: closed cleanly, every push in it, and a replay reproduces every state it hashed,
  // up to the last one published.
  const Completed info = rigidd::testing::run_program_to_exit(RIGID_RECORD_EXE, {"info", journal});
  EXPECT_EQ(info.exit_code, 0) << info.err;
  EXPECT_NE(info.out.find("ends cleanly"), std::string::npos) << info.out;
  EXPECT_EQ(info.out.find("damaged"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("(" + std::to_string(pushes) + " wrenches, "), std::string::npos)
      << info.out;
  const Completed replay =
      rigidd::testing::run_program_to_exit(RIGID_SIM_EXE, {kDefault, "--replay", journal}, 30s);
  EXPECT_EQ(replay.exit_code, 0) << replay.out << replay.err;
  const std::string identical =
      "identical: every journaled state reproduced bit for bit (last at "
      "tick ";
  const auto at = replay.out.find(identical);
  ASSERT_NE(at, std::string::npos) << replay.out;
  std::int64_t last_hashed = -1;
  std::from_chars(replay.out.data() + at + identical.size(), replay.out.data() + replay.out.size(),
                  last_hashed);
  EXPECT_GE(last_hashed, last_seen) << "the journal stops before the last state published";

  // The recording: closed cleanly, with every push rigidd accepted.
  const Completed rec_info =
      rigidd::testing::run_program_to_exit(RIGID_RECORD_EXE, {"info", recording});
  EXPECT_EQ(rec_info.exit_code, 0) << rec_info.err;
  EXPECT_NE(rec_info.out.find("ends cleanly"), std::string::npos) << rec_info.out;
  EXPECT_NE(rec_info.out.find("(" + std::to_string(pushes) + " wrenches, "), std::string::npos)
      << rec_info.out;
}

// The CSV rows a running `rigidctl echo --csv` printed: (t, body, x).
struct Row {
  double t = 0;
  std::string body;
  double x = 0;
};

std::vector<Row> csv_rows(const std::string& text) {
  std::vector<Row> rows;
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::istringstream fields(line);
    for (std::string x; std::getline(fields, x, ',');)
      f.push_back(x);
    if (f.size() != 15) continue;  // the last line may be cut short
    Row r;
    std::from_chars(f[0].data(), f[0].data() + f[0].size(), r.t);
    r.body = f[1];
    std::from_chars(f[2].data(), f[2].data() + f[2].size(), r.x);
    rows.push_back(r);
  }
  return rows;
}

// The craft's angle from the identity (the controller's target) in a state, in degrees.
double error_deg(const rigid::StateFrame& f, std::size_t craft) {
  const double w = std::abs(f.orientation[4 * craft]);
  return 2.0 * std::acos(std::min(1.0, w)) * 180.0 / M_PI;
}

// rigidd on the attitude scene with rigidctl echo and rigid-attitude running; rigidd stopped and
// a new one started on `second_scene` (the craft is body `craft_after` there). Neither client is
// restarted: echo must print the new rigidd's states, named from its scene, and the controller must
// turn the new rigidd's craft.
void clients_resume_after_restart(Bus bus, const std::string& second_scene,
                                  std::size_t craft_after) {
  Rig rig(bus, kAttitude);
  ASSERT_TRUE(rig.monitor->wait([&] { return !rig.monitor->states_locked().empty(); }, 10s))
      << rig.daemon->stderr_text();
  RigiddProcess echo(RIGIDCTL_EXE, concat({"echo", "--csv"}, rig.bus_args()), {});
  RigiddProcess controller(RIGID_ATTITUDE_EXE, concat({"craft"}, rig.bus_args()), {});
  ASSERT_TRUE(poll_until([&] { return csv_rows(echo.stdout_text()).size() > 20; }, 10s))
      << echo.stderr_text();
  ASSERT_TRUE(rig.monitor->wait(
      [&] {
        return rig.monitor->stats_locked() && rig.monitor->stats_locked()->commands_accepted > 50;
      },
      10s))
      << controller.stdout_text() << controller.stderr_text();

  EXPECT_EQ(rig.daemon->terminate(1000ms), 0) << rig.daemon->stderr_text();
  const std::size_t rows_before = csv_rows(echo.stdout_text()).size();
  const std::size_t states_before = rig.monitor->state_count();
  std::this_thread::sleep_for(500ms);  // half a second without rigidd (the clients wait 5 s)
  ASSERT_TRUE(echo.running()) << echo.stderr_text();
  ASSERT_TRUE(controller.running()) << controller.stdout_text() << controller.stderr_text();
  rig.start_daemon(second_scene);

  // The new rigidd's craft, seen by the monitor: starts 90 degrees off and is brought back.
  const auto new_states = [&] {
    std::vector<rigid::StateFrame> s;
    const auto all = rig.monitor->states();
    for (std::size_t i = states_before; i < all.size(); ++i)
      s.push_back(all[i].state);
    return s;
  };
  ASSERT_TRUE(poll_until(
      [&] {
        const auto s = new_states();
        return !s.empty() && s.back().body_count() > craft_after &&
               error_deg(s.back(), craft_after) < 10.0;
      },
      10s))
      << "the controller did not act on the new rigidd's craft\n"
      << controller.stdout_text() << controller.stderr_text() << rig.daemon->stderr_text();
  EXPECT_NEAR(error_deg(new_states().front(), craft_after), 90.0, 1.0);

  // echo printed the new rigidd's states with its names: rows after the restart whose time went
  // back to the start, every body named from the new scene.
  const std::vector<Row> rows = csv_rows(echo.stdout_text());
  ASSERT_GT(rows.size(), rows_before);
  std::size_t restart = 0;  // the first row of the new rigidd: its time starts again from 0
  for (std::size_t i = std::max<std::size_t>(rows_before, 1); i < rows.size() && restart == 0; ++i)
    if (rows[i].t < rows[i - 1].t) restart = i;
  ASSERT_GT(restart, 0u) << "echo printed nothing from the new rigidd";
  int craft_rows = 0;
  for (std::size_t i = restart; i < rows.size(); ++i) {
    EXPECT_TRUE(rows[i].body == "craft" || rows[i].body == "marker") << rows[i].body;
    // Each body under its own name: the craft at x = 0 (thrust in couples: barely any net
    // force), the marker at x = 5.
    if (rows[i].body == "craft") {
      ++craft_rows;
      EXPECT_NEAR(rows[i].x, 0.0, 0.1);
    } else {
      EXPECT_NEAR(rows[i].x, 5.0, 0.1);
    }
  }
  EXPECT_GT(craft_rows, 20);

  // Both still running, and they stop cleanly.
  EXPECT_EQ(echo.terminate(3000ms), 0) << echo.stderr_text();
  EXPECT_EQ(controller.terminate(3000ms), 0) << controller.stderr_text();
  EXPECT_EQ(rig.daemon->terminate(1000ms), 0) << rig.daemon->stderr_text();
}

TEST_P(ServerFault, ClientsResumeWhenRigiddRestarts) {
  clients_resume_after_restart(GetParam(), kAttitude, 0);
}

TEST_P(ServerFault, ClientsPickUpTheNewSceneWhenRigiddRestartsOnAnotherOne) {
  clients_resume_after_restart(GetParam(), kAttitudeMoved, 1);
}

INSTANTIATE_TEST_SUITE_P(Bus, ServerFault, ::testing::Values(Bus::kDds, Bus::kLcm), param_name);

}  // namespace
}  // namespace rigid::faults::testing
