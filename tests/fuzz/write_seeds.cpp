// Writes the binary seed corpora of the fuzzers: every message type encoded for each bus
// (lcm_messages/, dds_messages/), one payload per log record kind (log_record/), small log files,
// whole and cut short (record_file/), and provider bytes (command_validation/). Small valid inputs
// give the fuzzers a start past the fingerprints, length fields and checksums. Run it when a
// message or the record format changes:
//   build-asan/tests/fuzz/write_seeds tests/fuzz/corpus
// (the scene corpus is plain text: scene/ holds copies of config/scenes plus hand-written files).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "common/log_records.hpp"
#include "common/record_file.hpp"
#include "transport/dds/dds_cdr_codec.hpp"
#include "transport/lcm/lcm_codec.hpp"

namespace {

using namespace rigid;
namespace fs = std::filesystem;

void write(const fs::path& path, std::string_view bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

void write(const fs::path& path, std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) throw std::runtime_error("nothing encoded for " + path.string());
  write(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

rigid::WrenchCommand wrench_by_id() {
  rigid::WrenchCommand w;
  w.source = 42;
  w.seq = 7;
  w.key = 1;
  w.body_id = 2;
  w.force = {10.0, 0.0, -1.5};
  w.point = {0.0, 0.1, 0.0};
  w.force_frame = rigid::Frame::kBody;
  w.torque = {0.0, 0.0, 0.25};
  w.ttl = 0.5;
  w.stamp_ns = 1'700'000'000'000'000'000;
  return w;
}

rigid::WrenchCommand wrench_by_name() {
  rigid::WrenchCommand w = wrench_by_id();
  w.body_id = -1;
  w.body_name = "top";
  w.torque_frame = rigid::Frame::kBody;
  return w;
}

rigid::ControlCommand control(rigid::ControlKind kind, std::int64_t steps, double rtf) {
  rigid::ControlCommand c;
  c.source = 42;
  c.seq = 8;
  c.command = kind;
  c.steps = steps;
  c.rtf = rtf;
  return c;
}

rigid::StateFrame state() {
  rigid::StateFrame s;
  s.tick = 1000;
  s.sim_time = 1.0;
  s.stamp_ns = 1'700'000'000'000'000'000;
  s.resize(2);
  s.ids = {0, 1};
  s.position = {0.0, 0.0, 1.0, 1.0, 0.0, 1.0};
  s.orientation = {1.0, 0.0, 0.0, 0.0, 0.996, 0.087, 0.0, 0.0};
  s.linear_velocity = {0.0, 0.0, -9.81, 3.0, 0.0, 0.0};
  s.angular_velocity = {0.01, 6.0, 0.01, 1.0, 0.0, 20.0};
  return s;
}

rigid::ControlReply reply() {
  rigid::ControlReply r;
  r.source = 42;
  r.seq = 8;
  r.command = rigid::ControlKind::kStep;
  r.outcome = rigid::Outcome::kNotAllowed;
  r.tick = 1000;
  r.message = "step needs the loop paused";
  return r;
}

rigid::StatsReport stats() {
  rigid::StatsReport s;
  s.tick = 5000;
  s.sim_time = 5.0;
  s.mode = rigid::Mode::kRealtime;
  s.paused = true;
  s.rtf_last_second = 1.0;
  s.rtf_since_start = 0.999;
  s.lateness_p50_us = 0.1;
  s.lateness_p99_us = 4.0;
  s.lateness_max_us = 30.0;
  s.overruns = 2;
  s.commands_accepted = 12;
  s.rejected.over_limit = 1;
  s.dds = {100, 0, 12, 1};
  s.lcm = {100, 0, 3, 0};
  return s;
}

rigid::SceneDescription scene() {
  rigid::SceneDescription d;
  d.scene_name = "default";
  d.dt = 0.001;
  d.substeps = 1;
  d.publish_every = 10;
  d.gravity = {0.0, 0.0, -9.81};
  d.integrator = "exact_rotor4";
  d.max_force = 1e6;
  d.max_torque = 1e6;
  d.ids = {0, 1};
  d.names = {"tumbler", "ball"};
  d.masses = {5.0, 4.19};
  d.inertia = {0.09, 0.07, 0.03, 0.0, 0.0, 0.0, 0.017, 0.017, 0.017, 0.0, 0.0, 0.0};
  d.shape_kinds = {rigid::ShapeKind::kBox, rigid::ShapeKind::kSphere};
  d.shape_dims = {0.1, 0.25, 0.4, 0.1, 0.0, 0.0};
  d.part_names = {"ground", "ramp"};
  d.part_kinds = {rigid::ShapeKind::kPlane, rigid::ShapeKind::kBox};
  d.part_position = {0.0, 0.0, 0.0, 1.0, 0.0, 0.3};
  d.part_orientation = {1.0, 0.0, 0.0, 0.0, 0.966, 0.0, 0.259, 0.0};
  d.part_dims = {0.0, 0.0, 0.0, 2.0, 1.0, 0.1};
  d.part_restitution = {0.5, 0.0};
  d.part_friction = {0.8, 0.3};
  return d;
}

rigid::ContactEvents contacts() {
  rigid::ContactEvents c;
  c.tick = 1234;
  c.sim_time = 1.234;
  c.stamp_ns = 1'700'000'000'000'000'000;
  c.dropped = 0;
  c.resize(2);
  c.kinds = {rigid::ContactKind::kImpact, rigid::ContactKind::kResting};
  c.bodies = {1, 0};
  c.parts = {0, 1};
  c.times = {1.2335, 1.234};
  c.position = {0.5, 0.0, 0.0, 1.0, 0.0, 0.35};
  c.normal = {0.0, 0.0, 1.0, -0.5, 0.0, 0.866};
  c.impulse = {0.0, 0.1, 2.5, 0.0, 0.0, 0.0};
  return c;
}

rigid::AcceptedCommand accepted_wrench() {
  const rigid::WrenchCommand w = wrench_by_id();
  rigid::AcceptedCommand a;
  a.tick = 1001;
  a.kind = rigid::AcceptedKind::kWrench;
  a.source = w.source;
  a.seq = w.seq;
  a.key = w.key;
  a.body_id = w.body_id;
  a.force = w.force;
  a.point = w.point;
  a.force_frame = w.force_frame;
  a.torque = w.torque;
  a.ttl = w.ttl;
  a.stamp_ns = w.stamp_ns;
  return a;
}

rigid::AcceptedCommand accepted_control() {
  rigid::AcceptedCommand a;
  a.tick = 2000;
  a.kind = rigid::AcceptedKind::kControl;
  a.source = 42;
  a.seq = 9;
  a.command = rigid::ControlKind::kSetRtf;
  a.rtf = 2.0;
  return a;
}

rigid::EditCommand edit_set_state() {
  rigid::EditCommand e;
  e.source = 42;
  e.seq = 9;
  e.kind = rigid::EditKind::kSetState;
  e.body_id = -1;
  e.body_name = "tumbler";
  e.set = rigid::kSetPosition | rigid::kSetOrientation | rigid::kSetAngularVelocity;
  e.position = {1.0, -2.0, 0.5};
  e.orientation = {0.5, 0.5, -0.5, 0.5};
  e.angular_velocity = {0.0, 0.0, 3.0};
  e.angular_velocity_frame = rigid::Frame::kBody;
  e.stamp_ns = 1'700'000'000'000'000'000;
  return e;
}

rigid::EditCommand edit_reset_body() {
  rigid::EditCommand e;
  e.source = 42;
  e.seq = 10;
  e.kind = rigid::EditKind::kResetBody;
  e.body_id = 2;
  return e;
}

rigid::AcceptedCommand accepted_edit() {
  const rigid::EditCommand e = edit_set_state();
  rigid::AcceptedCommand a;
  a.tick = 1030;
  a.kind = rigid::AcceptedKind::kEdit;
  a.source = e.source;
  a.seq = e.seq;
  a.body_id = 0;
  a.edit = e.kind;
  a.state_edit() = e.state_edit();
  a.stamp_ns = e.stamp_ns;
  return a;
}

// The same messages through one bus's codec (lcm::Codec or dds::CdrCodec).
template <class Codec>
void write_messages(const fs::path& dir) {
  Codec codec;
  using K = rigid::ControlKind;
  write(dir / "wrench_by_id", codec.encode(wrench_by_id()));
  write(dir / "wrench_by_name", codec.encode(wrench_by_name()));
  write(dir / "control_pause", codec.encode(control(K::kPause, 0, 0.0)));
  write(dir / "control_step", codec.encode(control(K::kStep, 10, 0.0)));
  write(dir / "control_set_rtf", codec.encode(control(K::kSetRtf, 0, 2.5)));
  write(dir / "state", codec.encode(state()));
  write(dir / "control_reply", codec.encode(reply()));
  write(dir / "stats", codec.encode(stats()));
  write(dir / "scene", codec.encode(scene()));
  write(dir / "accepted_wrench", codec.encode(accepted_wrench()));
  write(dir / "accepted_control", codec.encode(accepted_control()));
  write(dir / "contacts", codec.encode(contacts()));
  write(dir / "edit_set_state", codec.encode(edit_set_state()));
  write(dir / "edit_reset_body", codec.encode(edit_reset_body()));
  write(dir / "accepted_edit", codec.encode(accepted_edit()));
}

// One record of each kind, in the order a recording or a journal holds them.
std::vector<msgs::LogRecord> records() {
  std::vector<msgs::LogRecord> out;
  msgs::LogRecord r;
  msgs::LogHeader& h = *r.mutable_header();
  h.set_kind(msgs::LogHeader::RECORDING);
  h.set_schema_version(common::kLogSchemaVersion);
  h.set_software_version("rigid 0.1.0");
  h.set_writer("rigid-record");
  h.set_start_unix_ns(1'700'000'000'000'000'000);
  common::to_record(scene(), 0, *h.mutable_scene());
  h.set_integrator("exact_rotor4");
  h.set_rate_hz(1000.0);
  h.set_transport("dds");
  out.push_back(r);
  r.Clear();
  common::to_record(scene(), 1'000'000, *r.mutable_scene());
  out.push_back(r);
  r.Clear();
  common::to_record(state(), 2'000'000, *r.mutable_state());
  out.push_back(r);
  r.Clear();
  common::to_record(stats(), 3'000'000, *r.mutable_stats());
  out.push_back(r);
  r.Clear();
  common::to_record(accepted_wrench(), 4'000'000, *r.mutable_command());
  out.push_back(r);
  r.Clear();
  common::to_record(accepted_control(), 5'000'000, *r.mutable_command());
  out.push_back(r);
  r.Clear();
  common::to_record(accepted_edit(), 5'500'000, *r.mutable_command());
  out.push_back(r);
  r.Clear();
  common::to_record(contacts(), 6'000'000, *r.mutable_contacts());
  out.push_back(r);
  r.Clear();
  r.mutable_contact_hash()->set_tick(1234);
  r.mutable_contact_hash()->set_hash(0xfedcba9876543210ULL);
  r.mutable_contact_hash()->set_events(2);
  out.push_back(r);
  r.Clear();
  r.mutable_state_hash()->set_tick(1010);
  r.mutable_state_hash()->set_hash(0x0123456789abcdefULL);
  out.push_back(r);
  r.Clear();
  r.mutable_gap()->set_dropped(3);
  r.mutable_gap()->set_tick(1020);
  out.push_back(r);
  r.Clear();
  r.mutable_end()->set_records(static_cast<std::int64_t>(out.size()));
  out.push_back(r);
  return out;
}

std::string read_all(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void write_logs(const fs::path& dir) {
  const std::vector<msgs::LogRecord> all = records();
  static constexpr const char* kNames[] = {"header",       "scene",      "state", "stats",
                                           "wrench",       "control",    "edit",  "contacts",
                                           "contact_hash", "state_hash", "gap",   "end"};
  for (std::size_t i = 0; i < all.size(); ++i) {
    write(dir / "log_record" / kNames[i], all[i].SerializeAsString());
  }
  fs::create_directories(dir / "record_file");
  const fs::path whole = dir / "record_file" / "recording.rlog";
  {
    common::RecordWriter writer(whole.string(), /*overwrite=*/true);
    for (const msgs::LogRecord& r : all)
      writer.append(r);
    writer.close();
  }
  // Cut inside the state record's payload: a reader reports a damaged tail there.
  const std::string bytes = read_all(whole);
  write(dir / "record_file" / "cut_short.rlog",
        std::string_view(bytes).substr(0, bytes.size() / 2));
  // Format 2: the same records in zstd chunks (two: a flush after the header).
  const fs::path chunked = dir / "record_file" / "recording_zstd.rlog";
  {
    common::Compression zstd;
    zstd.zstd = true;
    common::RecordWriter writer(chunked.string(), /*overwrite=*/true, zstd);
    for (std::size_t i = 0; i < all.size(); ++i) {
      writer.append(all[i]);
      if (i == 0) writer.flush();
    }
    writer.close();
  }
  const fs::path empty = dir / "record_file" / "preamble_only.rlog";
  common::RecordWriter(empty.string(), /*overwrite=*/true).close();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: write_seeds CORPUS_DIR   (e.g. tests/fuzz/corpus)\n");
    return 2;
  }
  const fs::path dir = argv[1];
  try {
    write_messages<transport::lcm::Codec>(dir / "lcm_messages");
    write_messages<transport::dds::CdrCodec>(dir / "dds_messages");
    write_logs(dir);
    // fuzz_command_validation reads its input through FuzzedDataProvider: any bytes make commands.
    write(dir / "command_validation" / "zeros", std::string(64, '\0'));
    std::string counting;
    for (int i = 0; i < 256; ++i)
      counting += static_cast<char>(i);
    write(dir / "command_validation" / "counting", counting);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "write_seeds: %s\n", e.what());
    return 1;
  }
  return 0;
}
