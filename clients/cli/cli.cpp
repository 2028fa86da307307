#include "cli/cli.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <system_error>

#include "transport/topic.hpp"

namespace rigid::clients {
namespace {

// rigidd's bound (DDS maps domain ids to UDP ports; above 232 they do not fit).
constexpr std::uint32_t kMaxDomain = 232;

}  // namespace

std::string quoted(std::string_view s) {
  return "'" + std::string(s) + "'";
}

ArgReader::ArgReader(std::span<const std::string_view> args,
                     std::span<const std::string_view> flags)
    : args_(args), flags_(flags) {}

std::optional<ArgReader::Arg> ArgReader::next() {
  if (i_ >= args_.size()) return std::nullopt;
  const std::string_view arg = args_[i_++];
  if (options_done_) return Arg{{}, arg};
  if (arg == "--") {
    options_done_ = true;
    return next();
  }
  const auto eq = arg.find('=');
  const std::string_view name = arg.substr(0, eq);
  if (std::find(flags_.begin(), flags_.end(), name) != flags_.end()) {
    if (eq != std::string_view::npos) throw UsageError(std::string(name) + " takes no value");
    return Arg{name, {}};
  }
  // Options are long ("--name"); anything else is a value, a negative number included ('rate -1'
  // is then refused by the parser that reads it, naming it).
  if (!arg.starts_with("--")) return Arg{{}, arg};
  if (eq != std::string_view::npos) return Arg{name, arg.substr(eq + 1)};
  if (i_ >= args_.size()) throw UsageError(std::string(name) + " needs a value");
  return Arg{name, args_[i_++]};
}

bool parse_bus_option(const ArgReader::Arg& arg, client::BusOptions& bus) {
  if (arg.name == "--transport") {
    if (arg.value == "dds") {
      bus.bus = rigid::Bus::kDds;
    } else if (arg.value == "lcm") {
      bus.bus = rigid::Bus::kLcm;
    } else {
      throw UsageError("--transport: expected dds or lcm, got " + quoted(arg.value));
    }
  } else if (arg.name == "--prefix") {
    if (!transport::is_valid_prefix(arg.value)) {
      throw UsageError("--prefix: expected letters, digits and '_' only, got " + quoted(arg.value));
    }
    bus.prefix = std::string(arg.value);
  } else if (arg.name == "--dds-domain") {
    std::uint32_t d = 0;
    const auto [end, ec] =
        std::from_chars(arg.value.data(), arg.value.data() + arg.value.size(), d);
    if (ec != std::errc() || end != arg.value.data() + arg.value.size() || d > kMaxDomain) {
      throw UsageError("--dds-domain: expected an integer 0 .. 232, got " + quoted(arg.value));
    }
    bus.dds_domain = d;
  } else if (arg.name == "--lcm-url") {
    if (arg.value.find("://") == std::string_view::npos) {
      throw UsageError(
          "--lcm-url: expected an LCM URL such as udpm://239.255.76.67:7667?ttl=0, got " +
          quoted(arg.value));
    }
    bus.lcm_url = std::string(arg.value);
  } else if (arg.name == "--security") {
    if (arg.value.empty()) throw UsageError("--security: expected an identity directory, got ''");
    bus.security = std::string(arg.value);
  } else {
    return false;
  }
  return true;
}

std::string_view bus_options_help() {
  return R"(  --transport BUS    dds or lcm (default dds)
  --prefix P         the prefix rigidd runs with (P/rigid/state, P_RIGID_STATE)
  --dds-domain N     DDS domain id, 0 .. 232 (default 0); CYCLONEDDS_URI configures the network
  --lcm-url URL      LCM URL (default udpm://239.255.76.67:7667?ttl=0: stays on this host)
  --security DIR     DDS Security: authenticate as the identity in DIR (rigid-keys add makes
                     it); needed when rigidd runs with --security
)";
}

double parse_double(std::string_view option, std::string_view text, std::string_view expected) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) {
    throw UsageError(std::string(option) + ": expected " + std::string(expected) + ", got " +
                     quoted(text));
  }
  return v;
}

double parse_positive(std::string_view option, std::string_view text, std::string_view expected,
                      bool allow_zero) {
  const double v = parse_double(option, text, expected);
  if (v < 0.0 || (v == 0.0 && !allow_zero)) {
    throw UsageError(std::string(option) + ": expected " + std::string(expected) + ", got " +
                     quoted(text));
  }
  return v;
}

std::int64_t parse_count(std::string_view option, std::string_view text, std::int64_t min) {
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || v < min) {
    throw UsageError(std::string(option) + ": expected an integer >= " + std::to_string(min) +
                     ", got " + quoted(text));
  }
  return v;
}

rigid::Vec3 parse_vec3(std::string_view option, std::string_view text) {
  rigid::Vec3 v{};
  std::string_view rest = text;
  for (std::size_t i = 0; i < 3; ++i) {
    const std::size_t comma = rest.find(',');
    if ((i < 2) == (comma == std::string_view::npos)) {
      throw UsageError(std::string(option) + ": expected three numbers x,y,z, got " + quoted(text));
    }
    v[i] = parse_double(option, rest.substr(0, comma), "three numbers x,y,z");
    if (comma != std::string_view::npos) rest = rest.substr(comma + 1);
  }
  return v;
}

std::chrono::milliseconds parse_seconds(std::string_view option, std::string_view text) {
  const double s = parse_positive(option, text, "a time in seconds > 0");
  if (s > 1e6) throw UsageError(std::string(option) + ": at most 1e6 s, got " + quoted(text));
  return std::chrono::milliseconds(static_cast<std::int64_t>(std::ceil(s * 1000.0)));
}

}  // namespace rigid::clients
