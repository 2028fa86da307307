// What rigid's command-line tools share: their usage errors, the bus options every one of them
// takes (the same names and checks as rigidd's), and parsers that name the argument and its value
// in one line when they refuse it.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "rigid/client/bus.hpp"
#include "rigid/messages.hpp"

namespace rigid::clients {

// A bad command line: what() is one line naming the argument and its value. Exit status 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Exit statuses every tool uses.
inline constexpr int kExitOk = 0;
inline constexpr int kExitFailed = 1;   // refused by the server, a bus or a file that failed
inline constexpr int kExitUsage = 2;    // a bad command line
inline constexpr int kExitTimeout = 3;  // the server did not answer in time

// The command line as (name, value) pairs: "--name value", "--name=value", or a flag. Positional
// arguments come back with an empty name. `flags` lists the options that take no value.
class ArgReader {
 public:
  ArgReader(std::span<const std::string_view> args, std::span<const std::string_view> flags);
  struct Arg {
    std::string_view name;   // empty: a positional argument
    std::string_view value;  // the positional argument, the option's value, or empty for a flag
  };
  // The next argument; nothing at the end. Throws UsageError for an option missing its value.
  std::optional<Arg> next();

 private:
  std::span<const std::string_view> args_;
  std::span<const std::string_view> flags_;
  std::size_t i_ = 0;
  bool options_done_ = false;
};

// Takes --transport, --prefix, --dds-domain and --lcm-url into `bus`; false for any other name.
// Throws UsageError for a bad value.
bool parse_bus_option(const ArgReader::Arg& arg, client::BusOptions& bus);
// The help lines of those options.
std::string_view bus_options_help();

double parse_double(std::string_view option, std::string_view text, std::string_view expected);
// A finite number > 0 (or >= 0 when `allow_zero`).
double parse_positive(std::string_view option, std::string_view text, std::string_view expected,
                      bool allow_zero = false);
std::int64_t parse_count(std::string_view option, std::string_view text, std::int64_t min = 1);
// "x,y,z": three finite numbers.
rigid::Vec3 parse_vec3(std::string_view option, std::string_view text);
std::chrono::milliseconds parse_seconds(std::string_view option, std::string_view text);

std::string quoted(std::string_view s);

}  // namespace rigid::clients
