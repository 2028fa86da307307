// Writes a rigid-record recording without rigidd, through the records API, deterministically:
// STATES states of BODIES bodies (one of each shape kind in turn, and a shapeless body with a full
// inertia tensor), 100 states a second of recorded time, a Stats record a second and one accepted
// command. Poses are pseudo-random doubles over many magnitudes plus edge values (-0.0, the
// smallest subnormal, the largest double), so that an export can be checked bit for bit.
//
//   synthetic_recording OUT [STATES] [BODIES] [journal]
//
// (default 6000 states of 1000 bodies: 60 s). With `journal`, a journal's header and a state hash
// per state instead of states (what rigidd --journal writes), for export's refusal of journals.
//
// bench: a 60 s recording of 1000 bodies for timing rigid-record export --mcap; tests/mcap: a
// small one for the MCAP test.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <limits>
#include <string>

#include "common/log_records.hpp"
#include "common/record_file.hpp"

namespace {

using rigid::ShapeKind;

// SplitMix64: a fixed, portable sequence (std:: distributions are not the same on every library).
struct Random {
  std::uint64_t s;
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
};

rigid::SceneDescription scene(int bodies) {
  rigid::SceneDescription s;
  s.scene_name = "synthetic";
  s.dt = 0.001;
  s.publish_every = 10;
  s.integrator = "hybrid4";
  s.max_force = 1e6;
  s.max_torque = 1e6;
  s.max_ttl = 60;
  s.max_wrenches_per_source = 64;
  s.max_commands_per_second = 2000;
  const ShapeKind kinds[] = {ShapeKind::kBox,     ShapeKind::kSphere,    ShapeKind::kCylinder,
                             ShapeKind::kCapsule, ShapeKind::kEllipsoid, ShapeKind::kNone};
  for (int i = 0; i < bodies; ++i) {
    s.ids.push_back(i);
    char name[32];
    std::snprintf(name, sizeof name, "body%04d", i);
    s.names.emplace_back(name);
    s.masses.push_back(1.0 + i % 7);
    const ShapeKind k = kinds[i % 6];
    s.shape_kinds.push_back(k);
    const double a = 0.1 + 0.01 * (i % 5);
    s.shape_dims.insert(s.shape_dims.end(), {a, 2 * a, 3 * a});
    // Shapeless: a full tensor with products of inertia (its principal axes are turned).
    if (k == ShapeKind::kNone) {
      s.inertia.insert(s.inertia.end(), {0.45, 0.42, 0.05, 0.01, 0.002, -0.003});
    } else {
      s.inertia.insert(s.inertia.end(), {0.1, 0.2, 0.3, 0, 0, 0});
    }
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 5) {
    std::fprintf(stderr, "usage: synthetic_recording OUT [STATES] [BODIES] [journal]\n");
    return 2;
  }
  try {
    const std::string out = argv[1];
    const long states = argc > 2 ? std::stol(argv[2]) : 6000;
    const int bodies = argc > 3 ? std::stoi(argv[3]) : 1000;
    const bool journal = argc > 4 && std::string(argv[4]) == "journal";
    constexpr std::int64_t kStart = 1'767'225'600'000'000'000;  // 2026-01-01T00:00:00Z
    constexpr std::int64_t kPeriod = 10'000'000;                // 100 states a second

    rigid::common::RecordWriter w(out, /*overwrite=*/true);
    rigid::msgs::LogRecord r;
    const rigid::SceneDescription sc = scene(bodies);
    {
      rigid::msgs::LogHeader* h = r.mutable_header();
      h->set_kind(journal ? rigid::msgs::LogHeader::JOURNAL : rigid::msgs::LogHeader::RECORDING);
      h->set_schema_version(rigid::common::kLogSchemaVersion);
      h->set_software_version(rigid::common::software_version());
      h->set_writer("synthetic_recording");
      h->set_start_unix_ns(kStart);
      rigid::common::to_record(sc, 0, *h->mutable_scene());
      h->set_integrator(sc.integrator);
      h->set_rate_hz(1000);
      h->set_transport("dds");
      w.append(r);
    }
    r.Clear();
    rigid::common::to_record(sc, 1'000'000, *r.mutable_scene());
    w.append(r);

    Random rng{42};
    rigid::StateFrame f;
    f.ids = sc.ids;
    const std::size_t n = static_cast<std::size_t>(bodies);
    f.position.resize(3 * n);
    f.orientation.resize(4 * n);
    f.linear_velocity.resize(3 * n);
    f.angular_velocity.resize(3 * n);
    for (long k = 0; k < states; ++k) {
      f.tick = 10 * (k + 1);
      f.sim_time = 0.01 * static_cast<double>(k + 1);
      f.stamp_ns = kStart + (k + 1) * kPeriod - 200'000;
      for (std::size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
          // Many magnitudes: an exponent from -30 to 30, either sign.
          const double m =
              (rng.uniform() - 0.5) * std::ldexp(1.0, static_cast<int>(rng.next() % 61) - 30);
          f.position[3 * i + c] = m;
          f.linear_velocity[3 * i + c] = rng.uniform() - 0.5;
          f.angular_velocity[3 * i + c] = 10 * (rng.uniform() - 0.5);
        }
        double q[4];
        double norm = 0;
        for (double& v : q) {
          v = rng.uniform() - 0.5;
          norm += v * v;
        }
        for (int c = 0; c < 4; ++c)
          f.orientation[4 * i + c] = q[c] / std::sqrt(norm);
      }
      if (k == 0 && n >= 3) {  // values a lossy export would change
        f.position[0] = -0.0;
        f.position[1] = std::numeric_limits<double>::denorm_min();
        f.position[2] = std::numeric_limits<double>::max();
        f.orientation[4] = -0.0;
      }
      r.Clear();
      if (journal) {
        r.mutable_state_hash()->set_tick(f.tick);
        r.mutable_state_hash()->set_hash(static_cast<std::uint64_t>(k) * 0x9E3779B97F4A7C15ull);
      } else {
        rigid::common::to_record(f, (k + 1) * kPeriod, *r.mutable_state());
      }
      w.append(r);
      if (k % 100 == 99) {
        rigid::StatsReport st;
        st.tick = f.tick;
        st.sim_time = f.sim_time;
        st.rtf_last_second = 1.0;
        r.Clear();
        rigid::common::to_record(st, (k + 1) * kPeriod + 1000, *r.mutable_stats());
        w.append(r);
      }
      if (k == 5) {
        rigid::AcceptedCommand a;
        a.tick = f.tick;
        a.kind = rigid::AcceptedKind::kWrench;
        a.body_id = 1;
        a.force = {0, 0, 50};
        a.ttl = 0.2;
        r.Clear();
        rigid::common::to_record(a, (k + 1) * kPeriod + 2000, *r.mutable_command());
        w.append(r);
      }
    }
    r.Clear();
    r.mutable_end()->set_records(w.records());
    w.append(r);
    w.close();
    std::printf("%s: %ld states of %d bodies\n", out.c_str(), states, bodies);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "synthetic_recording: %s\n", e.what());
    return 1;
  }
}
