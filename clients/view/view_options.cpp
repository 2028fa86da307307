#include "view_options.hpp"

#include <array>
#include <charconv>

namespace rigid::view {
namespace {

using clients::quoted;
using clients::UsageError;

constexpr std::array<std::string_view, 3> kFlags{"--help", "-h", "--read-only"};
constexpr std::int64_t kMaxMemoryMib = 1 << 20;  // 1 TiB: beyond any machine this runs on

// A host name as DNS spells one (RFC 1123): dot-separated labels of letters, digits and '-', not
// starting or ending with '-', at most 63 characters each and 253 in all.
bool host_name(std::string_view host) {
  if (host.empty() || host.size() > 253) return false;
  std::size_t label = 0;
  char previous = '.';
  for (const char c : host) {
    const bool alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
    if (c == '.') {
      if (label == 0 || previous == '-') return false;
      label = 0;
    } else if (alnum || (c == '-' && label > 0)) {
      if (++label > 63) return false;
    } else {
      return false;
    }
    previous = c;
  }
  return label > 0 && previous != '-';
}

// An IPv6 address between brackets, as URLs write it: hex digits, ':' and '.' (its last 32 bits
// may be dotted); Asio checks it when rigid-view binds.
bool ipv6_literal(std::string_view host) {
  if (host.size() < 2 || host.size() > 45) return false;
  for (const char c : host) {
    const bool hex = (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
    if (!hex && c != ':' && c != '.') return false;
  }
  return host.find(':') != std::string_view::npos;
}

void parse_listen(std::string_view text, ViewOptions& o) {
  const auto colon = text.rfind(':');
  const std::string expected =
      "--listen: expected HOST:PORT (a host name, an IPv4 address or [an IPv6 address]; port "
      "0-65535), got " +
      quoted(text);
  if (colon == std::string_view::npos || colon == 0 || colon + 1 == text.size())
    throw UsageError(expected);
  std::string_view host = text.substr(0, colon);
  const std::string_view port = text.substr(colon + 1);
  unsigned value = 0;
  const auto [end, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
  if (ec != std::errc() || end != port.data() + port.size() || value > 65535)
    throw UsageError(expected);
  if (host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
    if (!ipv6_literal(host)) throw UsageError(expected);
  } else if (!host_name(host)) {  // dotted IPv4 addresses are host names to this check
    throw UsageError(expected);
  }
  o.host = std::string(host);
  o.port = static_cast<std::uint16_t>(value);
}

// A WebSocket Origin header's value as browsers send it: "null", or scheme://host[:port] in
// printable ASCII without spaces, commas or a path.
void parse_origin(std::string_view text, ViewOptions& o) {
  const auto scheme = text.find("://");
  bool plain = !text.empty() && text.size() <= 200;
  for (const char c : text)
    plain = plain && c > ' ' && c < 0x7f && c != ',' && c != '\'' && c != '"';
  const bool origin = text == "null" || (plain && scheme != std::string_view::npos && scheme > 0 &&
                                         text.find('/', scheme + 3) == std::string_view::npos);
  if (!plain || !origin) {
    throw UsageError(
        "--foxglove-origin: expected an origin such as https://app.foxglove.dev "
        "(scheme://host[:port], or null), got " +
        quoted(text));
  }
  o.foxglove_origins.emplace_back(text);
}

}  // namespace

ViewOptions parse_options(std::span<const std::string_view> args) {
  ViewOptions o;
  std::string bus_option;  // the first bus option other than --prefix, refused with FILE
  bool max_memory_given = false;
  clients::ArgReader reader(args, kFlags);
  while (const auto arg = reader.next()) {
    if (arg->name == "--help" || arg->name == "-h") {
      o.help = true;
    } else if (arg->name == "--read-only") {
      o.read_only = true;
    } else if (arg->name == "--listen") {
      parse_listen(arg->value, o);
    } else if (arg->name == "--max-memory") {
      o.max_memory_mib = clients::parse_count(arg->name, arg->value, 1);
      if (o.max_memory_mib > kMaxMemoryMib) {
        throw UsageError("--max-memory: expected at most " + std::to_string(kMaxMemoryMib) +
                         " (MiB), got " + quoted(arg->value));
      }
      max_memory_given = true;
    } else if (arg->name == "--foxglove-origin") {
      parse_origin(arg->value, o);
    } else if (arg->name == "--web-dir") {
      if (arg->value.empty()) throw UsageError("--web-dir: expected a directory, got ''");
      o.web_dir = std::string(arg->value);
    } else if (arg->name.empty()) {
      if (!o.file.empty())
        throw UsageError("unexpected argument " + quoted(arg->value) + " (see --help)");
      if (arg->value.empty()) throw UsageError("FILE: expected a recording, got ''");
      o.file = std::string(arg->value);
    } else if (clients::parse_bus_option(*arg, o.bus)) {
      if (arg->name == "--prefix") {
        o.prefix_given = true;
      } else if (bus_option.empty()) {
        bus_option = std::string(arg->name);
      }
    } else {
      throw UsageError("unknown option " + quoted(arg->name) + " (see --help)");
    }
  }
  if (!o.file.empty() && !bus_option.empty()) {
    throw UsageError(bus_option + ": rigid-view FILE plays a recording and joins no bus (only " +
                     "--prefix applies: it picks an lcm-logger log's channels)");
  }
  if (!o.file.empty() && !o.foxglove_origins.empty()) {
    throw UsageError(
        "--foxglove-origin: rigid-view FILE serves no Foxglove client (open "
        "rigid-record export --mcap's file in Foxglove)");
  }
  if (o.file.empty() && max_memory_given)
    throw UsageError("--max-memory: only with FILE (it bounds a recording's states in memory)");
  return o;
}

std::string usage() {
  return std::string(
             R"(usage: rigid-view [--listen HOST:PORT] [--read-only] [--web-dir DIR] [bus options]
       rigid-view [--listen HOST:PORT] [--read-only] [--web-dir DIR] [--max-memory MIB]
                  [--prefix P] FILE

Shows a running rigidd in a web browser: serves one page and a WebSocket on ADDR:PORT and prints
its URL. The page draws the scene's bodies as they move, rigidd's Stats, and buttons for pause,
resume, step N and reset (each shows rigidd's answer); drag a body with the left button held to
push it. Keeps running when rigidd restarts. Foxglove and Lichtblick connect on the same port
(ws://ADDR:PORT/): the bodies in their 3D panel, the states in their Plot panel, pushes published
on /rigid/push.

With FILE, plays a recording instead of the bus: a rigid-record recording, an lcm-logger log of
rigidd's channels (--prefix P picks P's channels when the log holds several) or a journal of
rigidd (replayed as rigid-sim --replay does; only the states whose hashes match are played, and
a journal whose replay diverges is refused). The page shows a timeline: play, pause, a slider
over the recording's sim time, the state's tick and time, the speed (1/64 to 64). The states are
read into memory, at most --max-memory MiB of them (default 512; a larger file is refused: raise
it, or play the file on a bus with `rigid-record play FILE` and watch it with a live rigid-view).
A file cut short plays up to its damaged tail.

  --listen HOST:PORT  where to serve (default 127.0.0.1:8765; port 0: any free port). HOST is a
                      host name (its first IPv4 address, else its first address), an IPv4
                      address or [an IPv6 address]. An address other than loopback serves every
                      host that can reach this one, with no authentication: a warning is printed
  --read-only         refuse every command from the page (it only watches)
  --web-dir DIR       the page's files (default: web/ next to the executable)
  --foxglove-origin ORIGIN
                      Foxglove and Lichtblick connect live at ws://ADDR:PORT/ (the WebSocket
                      subprotocol foxglove.websocket.v1; docs/foxglove.md) from no origin or the
                      page's; this admits the clients of another origin too (repeatable, exact:
                      e.g. https://app.foxglove.dev)
  --max-memory MIB    FILE: the most memory its states may take (default 512)
)") + std::string(clients::bus_options_help());
}

std::string url_host(const std::string& host) {
  return host.find(':') == std::string::npos ? host : "[" + host + "]";
}

}  // namespace rigid::view
