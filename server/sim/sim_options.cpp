// rigid-sim's command-line parsing.
#include "sim/sim_options.hpp"

#include <charconv>
#include <cmath>
#include <system_error>

#include "physics/integrator.hpp"

namespace rigid::sim {
namespace {

std::string quoted(std::string_view s) {
  return "'" + std::string(s) + "'";
}

// A whole-string number: from_chars rejects leading spaces and '+', and we reject trailing text,
// so "1e-3x" or "" are errors rather than silently 0.001 or 0.
double parse_double(std::string_view option, std::string_view text, std::string_view expected) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) {
    throw UsageError(std::string(option) + ": expected " + std::string(expected) + ", got " +
                     quoted(text));
  }
  return v;
}

std::int64_t parse_count(std::string_view option, std::string_view text) {
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || v < 1) {
    throw UsageError(std::string(option) + ": expected an integer >= 1, got " + quoted(text));
  }
  return v;
}

std::string integrator_names() {
  std::string names;
  for (const physics::IntegratorInfo& info : physics::all_integrators()) {
    names += (names.empty() ? "" : ", ") + std::string(info.name);
  }
  return names;
}

}  // namespace

SimOptions parse_options(std::span<const std::string_view> args) {
  SimOptions o;
  bool have_scene = false;
  bool options_done = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    std::string_view arg = args[i];
    if (options_done || arg.empty() || arg[0] != '-' || arg == "-") {
      if (have_scene) {
        throw UsageError("unexpected argument " + quoted(arg) + " (the scene is already " +
                         quoted(o.scene) + ")");
      }
      o.scene = std::string(arg);
      have_scene = true;
      continue;
    }
    if (arg == "--") {
      options_done = true;
      continue;
    }
    if (arg == "--help" || arg == "-h") {
      o.help = true;
      continue;
    }
    if (arg == "--list-integrators") {
      o.list_integrators = true;
      continue;
    }
    // Options with a value: "--name value" or "--name=value".
    std::string_view name = arg;
    std::optional<std::string_view> value;
    if (const auto eq = arg.find('='); eq != std::string_view::npos) {
      name = arg.substr(0, eq);
      value = arg.substr(eq + 1);
    }
    if (name != "--duration" && name != "--integrator" && name != "--dt" && name != "--csv" &&
        name != "--every" && name != "--replay" && name != "--contacts-csv") {
      throw UsageError("unknown option " + quoted(name) + " (see --help)");
    }
    if (!value) {
      if (i + 1 >= args.size()) throw UsageError(std::string(name) + " needs a value");
      value = args[++i];
    }
    if (name == "--duration") {
      o.duration = parse_double(name, *value, "a duration in seconds >= 0");
      if (o.duration < 0.0) {
        throw UsageError("--duration: expected a duration in seconds >= 0, got " + quoted(*value));
      }
      o.duration_given = true;
    } else if (name == "--dt") {
      o.dt = parse_double(name, *value, "a time step in seconds > 0");
      if (!(*o.dt > 0.0)) {
        throw UsageError("--dt: expected a time step in seconds > 0, got " + quoted(*value));
      }
    } else if (name == "--integrator") {
      if (physics::find_integrator(*value) == nullptr) {
        throw UsageError("--integrator: unknown integrator " + quoted(*value) +
                         " (valid: " + integrator_names() + ")");
      }
      o.integrator = std::string(*value);
    } else if (name == "--replay") {
      if (value->empty()) throw UsageError("--replay: expected a journal file, got ''");
      o.replay = std::string(*value);
    } else if (name == "--csv") {
      if (value->empty()) throw UsageError("--csv: expected a file name, got ''");
      o.csv = std::string(*value);
    } else if (name == "--contacts-csv") {
      if (value->empty()) throw UsageError("--contacts-csv: expected a file name, got ''");
      o.contacts_csv = std::string(*value);
    } else {
      o.every = parse_count(name, *value);
    }
  }
  if (!have_scene && !o.help && !o.list_integrators && !o.replay) {
    throw UsageError("missing the scene file (see --help)");
  }
  if (o.csv && o.contacts_csv && *o.csv == *o.contacts_csv) {
    throw UsageError("--contacts-csv: " + quoted(*o.contacts_csv) + " is also the --csv file");
  }
  if (o.replay) {
    // A replay runs the journal's session as it ran: its length, its integrator, its step.
    const char* fixed = o.duration_given ? "--duration"
                        : o.integrator   ? "--integrator"
                        : o.dt           ? "--dt"
                        : o.every        ? "--every"
                                         : nullptr;
    if (fixed != nullptr) {
      throw UsageError(std::string(fixed) +
                       " cannot be combined with --replay (a replay runs the journal's session "
                       "as it ran)");
    }
  }
  return o;
}

std::string usage() {
  return R"(Usage: rigid-sim SCENE [--duration S] [--integrator NAME] [--dt S] [--csv OUT] [--every N]
                 [--contacts-csv OUT]
       rigid-sim [SCENE] --replay JOURNAL [--csv OUT] [--contacts-csv OUT]
       rigid-sim --list-integrators | --help

Runs the rigid-body scene SCENE (protobuf text format) without real time and prints, per body,
its model, final position and the drift of kinetic energy and angular momentum, then the wall
time and the cost per body-step.

  --duration S         simulated time in seconds (default 10)
  --integrator NAME    use this integrator instead of the scene's (see --list-integrators)
  --dt S               physics step in seconds, instead of 1 / (rate_hz * substeps)
  --csv OUT            write the states to OUT: a row per body at t = 0, every N ticks and at the
                       end; columns t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz (world frame,
                       17 significant digits); OUT appears only when the run succeeds
  --every N            a CSV row every N ticks of `substeps` physics steps
                       (default: the scene's publish_every)
  --contacts-csv OUT   write the contact events with static parts to OUT, a row per event:
                       tick,t,kind,body,part,px,py,pz,nx,ny,nz,jx,jy,jz (kind impact, resting,
                       sliding, rolling or separate; t the event's exact time; world frame;
                       17 significant digits); OUT appears only when the run succeeds
  --replay JOURNAL     re-run the session rigidd journaled (rigidd --journal): apply each
                       command at the tick it took effect, compare every state hash, and report
                       the first divergence with its tick. SCENE, if given, must be the scene
                       the journal holds a copy of (by default that copy is used). With --csv, a
                       row per body for every state the journal hashed; with --contacts-csv,
                       every contact event, each tick's checked against the journal's hash
  --list-integrators   list the integrators and what each promises; * marks the default
  -h, --help           show this help

Exit status: 0 on success (replay: every state and contact event reproduced bit for bit), 1 if the CSV or the
journal cannot be written or read, 2 for a bad command line or scene, 3 a replay diverged,
4 a replay stopped at entries rigidd lost (its journal is incomplete).
)";
}

}  // namespace rigid::sim
