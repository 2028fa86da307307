#include "common/session.hpp"

#include <charconv>
#include <random>

#include "transport/dds/dds_transport.hpp"
#include "transport/lcm/lcm_transport.hpp"

namespace rigid::clients {
namespace {

using Clock = std::chrono::steady_clock;

// A source id no other client picks: random, positive.
std::int64_t random_source() {
  std::random_device device;
  const std::uint64_t bits = (static_cast<std::uint64_t>(device()) << 32) ^ device();
  return static_cast<std::int64_t>(bits >> 1) | 1;
}

std::unique_ptr<transport::Transport> connect(const BusOptions& o, transport::Role role,
                                              transport::Receiver& receiver) {
  if (o.bus == transport::Bus::kDds) {
    transport::dds::Options d;
    d.role = role;
    d.domain = o.dds_domain;
    d.prefix = o.prefix;
    d.security = o.security;
    // DDS stays on loopback unless the user configured a network (CYCLONEDDS_URI).
    (void)transport::dds::ensure_dds_config();
    return transport::dds::make_transport(d, receiver);
  }
  transport::lcm::Options l;
  l.role = role;
  l.prefix = o.prefix;
  // States of ~1000 bodies and more are lost without a larger receive buffer (NETWORKING.md).
  l.url = o.lcm_url.empty() ? std::string(transport::lcm::kDefaultUrl) + "&recv_buf_size=4194304"
                            : o.lcm_url;
  return transport::lcm::make_transport(l, receiver);
}

// rigidd's answer to a copy of a request it had already accepted: a stale sequence whose "last
// one" is the request's own number (loop/command.cpp, reply_message).
bool is_own_duplicate(const transport::ControlReply& r) {
  return r.outcome == transport::Outcome::kInvalid &&
         r.message.find("stale sequence number (the source's last one is " + std::to_string(r.seq) +
                        ")") != std::string::npos;
}

// rigidd's refusal of a copy of a wrench it had already accepted (a resend).
bool is_own_duplicate_wrench(const transport::ControlReply& r) {
  return r.message.find("stale_sequence") == 0 &&
         r.message.find("is not above this session's last " + std::to_string(r.seq)) !=
             std::string::npos;
}

transport::ControlReply not_permitted(const transport::ControlCommand& c, std::string why) {
  transport::ControlReply r;
  r.source = c.source;
  r.seq = c.seq;
  r.command = c.command;
  r.outcome = transport::Outcome::kNotAllowed;
  r.message = std::move(why);
  return r;
}

}  // namespace

Session::Session(const BusOptions& options, transport::Role role)
    : options_(options), source_(random_source()) {
  transport_ = connect(options, role, *this);
}

Session::~Session() {
  transport_.reset();  // its thread calls into us: stop it first
}

void Session::on_each_state(std::function<void(const transport::StateFrame&)> handler) {
  const std::lock_guard calls(handler_mutex_);  // waits for a call in progress
  state_handler_ = std::move(handler);
}

void Session::on_each_accepted(std::function<void(const transport::AcceptedCommand&)> handler) {
  const std::lock_guard calls(handler_mutex_);  // waits for a call in progress
  accepted_handler_ = std::move(handler);
}

void Session::on_each_stats(std::function<void(const transport::StatsReport&)> handler) {
  const std::lock_guard calls(handler_mutex_);  // waits for a call in progress
  stats_handler_ = std::move(handler);
}

void Session::on_each_scene(std::function<void(const transport::SceneDescription&)> handler) {
  const std::lock_guard calls(handler_mutex_);  // waits for a call in progress
  scene_handler_ = std::move(handler);
}

bool Session::wait_server(std::chrono::milliseconds patience) {
  std::unique_lock lock(mutex_);
  return changed_.wait_for(lock, patience, [&] { return server_seen_; });
}

std::optional<transport::SceneDescription> Session::wait_scene(std::chrono::milliseconds patience) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, patience, [&] { return scene_.has_value(); });
  return scene_;
}

std::uint64_t Session::scene_generation() const {
  const std::lock_guard lock(mutex_);
  return scene_generation_;
}

std::optional<transport::StatsReport> Session::wait_stats(std::chrono::milliseconds patience) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, patience, [&] { return stats_.has_value(); });
  return stats_;
}

std::optional<transport::StateFrame> Session::latest_state() const {
  const std::lock_guard lock(mutex_);
  return state_;
}

std::optional<transport::ControlReply> Session::request(transport::ControlCommand control,
                                                        std::chrono::milliseconds patience) {
  const auto deadline = Clock::now() + patience;
  // LCM needs no discovery: send at once. DDS: wait to see the server first (see the header).
  if (options_.bus == transport::Bus::kDds &&
      !wait_server(
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()))) {
    return std::nullopt;
  }
  control.source = source_;
  control.seq = ++seq_;
  std::optional<transport::ControlReply> answer;
  while (Clock::now() < deadline) {
    if (transport_->publish(control) == transport::PublishResult::kNotPermitted) {
      return not_permitted(control,
                           "not permitted: this identity's permissions do not allow control "
                           "(rigid-keys add ... --may control)");
    }
    std::unique_lock lock(mutex_);
    const bool got =
        changed_.wait_until(lock, std::min(deadline, Clock::now() + kResendPeriod), [&] {
          for (const auto& r : replies_) {
            if (r.seq == control.seq && !is_own_duplicate(r)) {
              answer = r;
              return true;
            }
          }
          return false;
        });
    if (got) return answer;
    // A duplicate's refusal proves the request arrived: wait for its answer, send no more.
    for (const auto& r : replies_) {
      if (r.seq == control.seq && is_own_duplicate(r)) {
        changed_.wait_until(lock, deadline, [&] {
          for (const auto& q : replies_)
            if (q.seq == control.seq && !is_own_duplicate(q)) {
              answer = q;
              return true;
            }
          return false;
        });
        return answer;
      }
    }
  }
  return std::nullopt;
}

std::optional<transport::AcceptedCommand> Session::push(transport::WrenchCommand wrench,
                                                        std::chrono::milliseconds patience,
                                                        std::string* refused) {
  const auto deadline = Clock::now() + patience;
  if (options_.bus == transport::Bus::kDds &&
      !wait_server(
          std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()))) {
    return std::nullopt;
  }
  wrench.source = source_;
  wrench.seq = ++seq_;
  std::optional<transport::AcceptedCommand> accepted;
  std::optional<transport::ControlReply> refusal;
  while (Clock::now() < deadline) {
    if (transport_->publish(wrench) == transport::PublishResult::kNotPermitted) {
      if (refused != nullptr) {
        *refused = "not permitted: this identity's permissions do not allow pushing '" +
                   wrench.body_name + "' (rigid-keys add ... --may push:BODY)";
      }
      return std::nullopt;
    }
    std::unique_lock lock(mutex_);
    if (changed_.wait_until(lock, std::min(deadline, Clock::now() + kResendPeriod), [&] {
          for (const auto& a : acceptances_)
            if (a.seq == wrench.seq) {
              accepted = a;
              return true;
            }
          for (const auto& r : wrench_refusals_)
            if (r.seq == wrench.seq && !is_own_duplicate_wrench(r)) {
              refusal = r;
              return true;
            }
          return false;
        })) {
      if (refusal && refused != nullptr) *refused = refusal->message;
      return accepted;
    }
  }
  return std::nullopt;
}

std::int64_t Session::send(transport::WrenchCommand wrench) {
  wrench.source = source_;
  wrench.seq = ++seq_;
  if (transport_->publish(wrench) == transport::PublishResult::kNotPermitted) {
    const std::lock_guard lock(mutex_);
    ++wrenches_refused_;
    transport::ControlReply r;
    r.source = source_;
    r.seq = wrench.seq;
    r.command = transport::kReplyToWrench;
    r.outcome = transport::Outcome::kNotAllowed;
    r.message = "not permitted: this identity's permissions do not allow pushing '" +
                wrench.body_name + "'";
    last_refusal_ = r;
  }
  return wrench.seq;
}

void Session::on_state(const transport::StateFrame& state) {
  {
    const std::lock_guard lock(mutex_);
    state_ = state;
    server_seen_ = true;
  }
  changed_.notify_all();
  const std::lock_guard calls(handler_mutex_);
  if (state_handler_) state_handler_(state);
}

void Session::on_stats(const transport::StatsReport& stats) {
  {
    const std::lock_guard lock(mutex_);
    stats_ = stats;
  }
  changed_.notify_all();
  const std::lock_guard calls(handler_mutex_);
  if (stats_handler_) stats_handler_(stats);
}

void Session::on_scene(const transport::SceneDescription& scene) {
  {
    const std::lock_guard lock(mutex_);
    if (!scene_ || *scene_ != scene) {  // LCM repeats it every second: count changes only
      scene_ = scene;
      ++scene_generation_;
    }
    server_seen_ = true;
  }
  changed_.notify_all();
  const std::lock_guard calls(handler_mutex_);
  if (scene_handler_) scene_handler_(scene);
}

void Session::on_control_reply(const transport::ControlReply& reply) {
  if (reply.source != source_) return;  // another client's
  {
    const std::lock_guard lock(mutex_);
    if (reply.command == transport::kReplyToWrench) {
      // Kept for push() and take_refusal(); bounded (rigidd answers a few a second at most).
      if (!is_own_duplicate_wrench(reply)) {
        ++wrenches_refused_;
        last_refusal_ = reply;
      }
      if (wrench_refusals_.size() >= 64) wrench_refusals_.erase(wrench_refusals_.begin());
      wrench_refusals_.push_back(reply);
    } else {
      replies_.push_back(reply);
    }
  }
  changed_.notify_all();
}

std::optional<transport::ControlReply> Session::take_refusal() {
  const std::lock_guard lock(mutex_);
  std::optional<transport::ControlReply> r;
  r.swap(last_refusal_);
  return r;
}

std::int64_t Session::wrenches_refused() const {
  const std::lock_guard lock(mutex_);
  return wrenches_refused_;
}

void Session::on_accepted(const transport::AcceptedCommand& accepted) {
  {
    const std::lock_guard lock(mutex_);
    if (accepted.source == source_ && accepted.kind == transport::AcceptedKind::kWrench) {
      acceptances_.push_back(accepted);
    }
  }
  changed_.notify_all();
  const std::lock_guard calls(handler_mutex_);
  if (accepted_handler_) accepted_handler_(accepted);
}

std::string_view control_name(transport::ControlKind kind) {
  switch (kind) {
    case transport::ControlKind::kPause:
      return "pause";
    case transport::ControlKind::kResume:
      return "resume";
    case transport::ControlKind::kStep:
      return "step";
    case transport::ControlKind::kReset:
      return "reset";
    case transport::ControlKind::kSetRtf:
      return "rate";
    case transport::ControlKind::kNone:
      break;
  }
  return "none";
}

std::string_view outcome_name(transport::Outcome outcome) {
  switch (outcome) {
    case transport::Outcome::kOk:
      return "ok";
    case transport::Outcome::kInvalid:
      return "invalid";
    case transport::Outcome::kNotAllowed:
      return "not allowed";
    case transport::Outcome::kFailed:
      return "failed";
  }
  return "unknown outcome";
}

std::optional<std::int32_t> find_body(const transport::SceneDescription& scene,
                                      std::string_view name_or_id) {
  for (std::size_t i = 0; i < scene.names.size(); ++i)
    if (scene.names[i] == name_or_id) return scene.ids[i];
  std::int32_t id = 0;
  const auto [end, ec] =
      std::from_chars(name_or_id.data(), name_or_id.data() + name_or_id.size(), id);
  if (ec == std::errc() && end == name_or_id.data() + name_or_id.size()) {
    for (const std::int32_t known : scene.ids)
      if (known == id) return id;
  }
  return std::nullopt;
}

std::string body_list(const transport::SceneDescription& scene) {
  std::string text;
  for (const std::string& n : scene.names)
    text += (text.empty() ? "" : ", ") + n;
  return text.empty() ? "none" : text;
}

}  // namespace rigid::clients
