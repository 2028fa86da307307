// rigid-sim's command line: what it accepts, and its checks (every error is one line naming the
// argument and its value).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace rigid::sim {

struct SimOptions {
  std::string scene;                        // the scene file
  double duration = 10.0;                   // simulated seconds, >= 0
  std::optional<std::string> integrator;    // overrides the scene's integrator
  std::optional<double> dt;                 // overrides the scene's physics step (s), > 0
  std::optional<std::string> csv;           // write states to this file
  std::optional<std::string> contacts_csv;  // write contact events to this file
  std::optional<std::int64_t> every;        // CSV row every N ticks; default: scene's publish_every
  std::optional<std::string> replay;  // re-run this journal (rigidd --journal); scene optional
  bool duration_given = false;        // --duration was on the command line
  bool list_integrators = false;
  bool help = false;
};

// A bad command line; what() is the one-line explanation. The program exits with status 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Parses the arguments after the program name. Options take their value as the next argument or
// after '=' (--dt=1e-3); "--" ends the options. Throws UsageError.
SimOptions parse_options(std::span<const std::string_view> args);

// The --help text.
std::string usage();

}  // namespace rigid::sim
