// Running a scene in batch, and the report at the end.
#include "sim/sim_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <memory>
#include <optional>
#include <ostream>

#include "common/contact_csv.hpp"
#include "common/state_conversion.hpp"
#include "common/world_csv.hpp"
#include "util/atomic_file.hpp"

namespace rigid::sim {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// printf-style formatting into a std::string; the attribute lets the compiler check the arguments
// against the format.
[[gnu::format(printf, 1, 2)]] std::string fmt(const char* format, ...) {
  std::va_list args;
  va_start(args, format);
  std::va_list again;
  va_copy(again, args);
  const int n = std::vsnprintf(nullptr, 0, format, args);
  va_end(args);
  std::string s(static_cast<std::size_t>(std::max(n, 0)) + 1, '\0');
  std::vsnprintf(s.data(), s.size(), format, again);
  va_end(again);
  s.resize(static_cast<std::size_t>(std::max(n, 0)));
  return s;
}

// Relative change (x - x0) / |x0|; where x0 is 0 the relative change is undefined, so the absolute
// change is shown instead, marked "abs".
// `signed_change` false is for norms of vector changes, which have no sign.
std::string change(double x0, double dx, bool signed_change = true) {
  if (dx == 0.0) return "0";
  const double shown = x0 != 0.0 ? dx / std::abs(x0) : dx;
  return (signed_change ? fmt("%+.2e", shown) : fmt("%.2e", shown)) + (x0 != 0.0 ? "" : " abs");
}

std::string pad(std::string s, std::size_t width) {
  if (s.size() < width) s.append(width - s.size(), ' ');
  return s;
}

constexpr std::size_t kCsvChunk = 1 << 20;  // bytes buffered before a write

}  // namespace

RunSummary run(const scene::Scene& scene, const SimOptions& options) {
  const auto t_start = Clock::now();
  physics::WorldSpec spec = scene.world;
  if (options.integrator) spec.integrator = *options.integrator;
  if (options.dt) spec.dt = *options.dt;

  const double n_steps = options.duration / spec.dt;
  // Beyond 2^53 steps the step count is no longer an exact double (and no run would finish).
  if (!(n_steps < 9.0e15)) {
    throw UsageError(fmt("--duration %.17g s with dt = %.17g s is %.3g steps; too many",
                         options.duration, spec.dt, n_steps));
  }
  const std::int64_t steps = std::llround(n_steps);

  std::optional<physics::World> world_storage;
  try {
    world_storage.emplace(spec);
  } catch (const physics::SpecError& e) {
    throw UsageError(std::string("the scene does not accept these options: ") + e.what());
  }
  physics::World& world = *world_storage;

  RunSummary r;
  r.scene = scene.path;
  r.integrator = std::string(world.integrator().name);
  r.default_integrator = world.integrator().id == physics::default_integrator().id;
  r.dt = world.dt();
  r.steps = steps;
  r.every = options.every.value_or(scene.publish_every);
  for (int id = 0; id < world.body_count(); ++id) {
    BodySummary b;
    b.name = world.body_name(id);
    b.motion = world.body_motion(id);
    b.ke0 = world.kinetic_energy(id);
    b.L0 = world.angular_momentum_W(id);
    r.bodies.push_back(b);
  }
  r.energy0 = world.total_energy();

  std::unique_ptr<util::AtomicFile> csv;
  std::string buffer;
  if (options.csv) {
    csv = std::make_unique<util::AtomicFile>(*options.csv);
    r.csv = *options.csv;
    buffer.reserve(kCsvChunk + 4096);
    buffer += util::kStateCsvHeader;
    common::append_state_rows(world, buffer);
    r.csv_rows += world.body_count();
  }

  std::unique_ptr<util::AtomicFile> contacts_csv;
  std::string contact_rows;
  rigid::ContactEvents contacts;
  common::ContactNames contact_names;
  if (options.contacts_csv) {
    contacts_csv = std::make_unique<util::AtomicFile>(*options.contacts_csv);
    r.contacts_csv = *options.contacts_csv;
    contact_rows += common::kContactCsvHeader;
    contact_names = common::ContactNames(common::describe_scene(scene, world));
  }

  // Without a CSV the whole run is one call; with one, a row every `every` ticks of `substeps`
  // steps, and one at the end if the run does not end on a row; with the contact CSV, a call a
  // tick, whose events are that tick's (as rigidd publishes them).
  const std::int64_t row_stride = std::max<std::int64_t>(
      1, std::min<std::int64_t>(r.every, INT64_MAX / scene.substeps) * scene.substeps);
  const std::int64_t stride = contacts_csv ? std::max<std::int64_t>(scene.substeps, 1)
                              : csv        ? row_stride
                                           : std::max<std::int64_t>(steps, 1);
  for (std::int64_t done = 0; done < steps;) {
    const std::int64_t n = std::min(stride, steps - done);
    const auto t0 = Clock::now();
    world.step(n);
    r.step_seconds += seconds_since(t0);
    done += n;
    if (contacts_csv && !world.contact_events().empty()) {
      const std::int64_t tick = (done + scene.substeps - 1) / scene.substeps;
      common::fill_contact_events(world.contact_events(), tick, world.time(), contacts);
      r.contact_events += static_cast<std::int64_t>(contacts.event_count());
      common::append_contact_rows(contacts, contact_names, contact_rows);
      if (contact_rows.size() >= kCsvChunk) {
        contacts_csv->write(contact_rows);
        contact_rows.clear();
      }
    }
    if (csv && (done % row_stride == 0 || done == steps)) {
      common::append_state_rows(world, buffer);
      r.csv_rows += world.body_count();
      if (buffer.size() >= kCsvChunk) {
        csv->write(buffer);
        buffer.clear();
      }
    }
  }
  if (csv) {
    csv->write(buffer);
    csv->commit();
  }
  if (contacts_csv) {
    contacts_csv->write(contact_rows);
    contacts_csv->commit();
  }
  r.contact_events_dropped = world.contact_events_dropped();

  for (int id = 0; id < world.body_count(); ++id) {
    BodySummary& b = r.bodies[static_cast<std::size_t>(id)];
    b.p_final = world.state(id).p_WBo;
    b.ke = world.kinetic_energy(id);
    b.L = world.angular_momentum_W(id);
  }
  r.energy = world.total_energy();
  r.t_end = world.time();
  r.wall_seconds = seconds_since(t_start);
  return r;
}

void print_summary(std::ostream& out, const RunSummary& r) {
  out << fmt("%s: %zu %s, integrator %s%s, dt = %.6g s, %lld steps to t = %.6g s\n",
             r.scene.c_str(), r.bodies.size(), r.bodies.size() == 1 ? "body" : "bodies",
             r.integrator.c_str(), r.default_integrator ? " (default)" : "", r.dt,
             static_cast<long long>(r.steps), r.t_end);
  if (!r.bodies.empty()) {
    std::size_t name_width = 4;
    for (const BodySummary& b : r.bodies)
      name_width = std::max(name_width, b.name.size());
    name_width += 2;
    out << '\n'
        << pad("body", name_width) << pad("motion", 14)
        << fmt("%12s %12s %12s   %-14s %s\n", "x (m)", "y (m)", "z (m)", "dKE/KE(0)",
               "|dL|/|L(0)|");
    for (const BodySummary& b : r.bodies) {
      out << pad(b.name, name_width) << pad(std::string(physics::to_string(b.motion)), 14)
          << fmt("%12.5g %12.5g %12.5g   ", b.p_final.x(), b.p_final.y(), b.p_final.z())
          << pad(change(b.ke0, b.ke - b.ke0), 14) << ' '
          << change(b.L0.norm(), (b.L - b.L0).norm(), false) << '\n';
    }
    out << "dKE/KE(0), |dL|/|L(0)|: relative change since t = 0 of the kinetic energy and the\n"
           "angular momentum about the centre of mass (\"abs\": zero at t = 0, so the absolute\n"
           "change in J or N m s)\n\n";
  }
  out << fmt("total energy: %.10g J at t = 0, %.10g J at the end, relative change %s\n", r.energy0,
             r.energy, change(r.energy0, r.energy - r.energy0).c_str());
  const double body_steps = static_cast<double>(r.steps) * static_cast<double>(r.bodies.size());
  out << fmt("wall time %.3g s, stepping %.3g s", r.wall_seconds, r.step_seconds);
  if (body_steps > 0) out << fmt(": %.3g ns per body-step", 1e9 * r.step_seconds / body_steps);
  out << '\n';
  if (!r.csv.empty()) {
    out << fmt("csv: %s, %lld rows (a row per body every %lld ticks)\n", r.csv.c_str(),
               static_cast<long long>(r.csv_rows), static_cast<long long>(r.every));
  }
  if (!r.contacts_csv.empty()) {
    out << fmt("contacts csv: %s, %lld events", r.contacts_csv.c_str(),
               static_cast<long long>(r.contact_events));
    if (r.contact_events_dropped > 0) {
      out << fmt(" (%lld more dropped: over 4096 in a tick)",
                 static_cast<long long>(r.contact_events_dropped));
    }
    out << '\n';
  }
}

void print_integrators(std::ostream& out) {
  const physics::IntegratorInfo& def = physics::default_integrator();
  std::size_t width = 4;
  for (const physics::IntegratorInfo& i : physics::all_integrators()) {
    width = std::max(width, i.name.size());
  }
  width += 4;
  out << pad("  name", width) << "order  symplectic  gyroscopic  summary\n";
  for (const physics::IntegratorInfo& i : physics::all_integrators()) {
    out << (i.id == def.id ? "* " : "  ") << pad(std::string(i.name), width - 2)
        << fmt("%5d  %-10s  %-10s  ", i.order, i.symplectic ? "yes" : "no",
               i.gyroscopic ? "yes" : "no")
        << i.summary << '\n';
  }
  out << "* default (used when the scene names no integrator)\n";
}

}  // namespace rigid::sim
