#include "rigid/client/session.hpp"

#include <condition_variable>
#include <mutex>
#include <random>
#include <utility>
#include <vector>

#include "connect.hpp"

namespace rigid::client {
namespace {

using Clock = std::chrono::steady_clock;

// A source id no other client picks: random, positive.
std::int64_t random_source() {
  std::random_device device;
  const std::uint64_t bits = (static_cast<std::uint64_t>(device()) << 32) ^ device();
  return static_cast<std::int64_t>(bits >> 1) | 1;
}

// rigidd's answer to a copy of a request it had already accepted: a stale sequence whose "last
// one" is the request's own number (loop/command.cpp, reply_message).
bool is_own_duplicate(const ControlReply& r) {
  return r.outcome == Outcome::kInvalid &&
         r.message.find("stale sequence number (the source's last one is " + std::to_string(r.seq) +
                        ")") != std::string::npos;
}

// rigidd's refusal of a copy of a wrench it had already accepted (a resend).
bool is_own_duplicate_wrench(const ControlReply& r) {
  return r.message.find("stale_sequence") == 0 &&
         r.message.find("is not above this session's last " + std::to_string(r.seq)) !=
             std::string::npos;
}

ControlReply not_permitted(std::int64_t source, std::int64_t seq, ControlKind command,
                           std::string why) {
  ControlReply r;
  r.source = source;
  r.seq = seq;
  r.command = command;
  r.outcome = Outcome::kNotAllowed;
  r.message = std::move(why);
  return r;
}

ControlKind reply_kind(const ControlCommand& c) {
  return c.command;
}
ControlKind reply_kind(const EditCommand& /*e*/) {
  return kReplyToEdit;
}

std::chrono::milliseconds left(Clock::time_point deadline) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
}

}  // namespace

// The session's state and the bus's Receiver: the transport's thread calls into it.
class Session::Impl final : public transport::Receiver {
 public:
  explicit Impl(const BusOptions& options) : options_(options), source_(random_source()) {
    transport_ = connect(options, transport::Role::kClient, *this);
  }
  ~Impl() override {
    transport_.reset();  // its thread calls into us: stop it first
  }
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;

  void on_state(const StateFrame& state) override {
    // One copy of each state (the transport reuses its buffer), shared by latest_state_shared()
    // and the shared handler, so that a reader that keeps states (Python's streams) does not copy
    // it again on this thread before it is woken.
    auto fresh = std::make_shared<const StateFrame>(state);
    std::shared_ptr<const StateFrame> previous;  // released at the end, outside the lock
    {
      const std::lock_guard lock(mutex_);
      previous = std::exchange(state_, fresh);
      server_seen_ = true;
    }
    changed_.notify_all();
    const std::lock_guard calls(handler_mutex_);
    if (shared_state_handler_) shared_state_handler_(fresh);
    if (state_handler_) state_handler_(state);
  }

  void on_stats(const StatsReport& stats) override {
    {
      const std::lock_guard lock(mutex_);
      stats_ = stats;
    }
    changed_.notify_all();
    const std::lock_guard calls(handler_mutex_);
    if (stats_handler_) stats_handler_(stats);
  }

  void on_scene(const SceneDescription& scene) override {
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

  void on_contacts(const ContactEvents& contacts) override {
    const std::lock_guard calls(handler_mutex_);
    if (contacts_handler_) contacts_handler_(contacts);
  }

  void on_control_reply(const ControlReply& reply) override {
    if (reply.source != source_) return;  // another client's
    {
      const std::lock_guard lock(mutex_);
      if (reply.command == kReplyToWrench) {
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

  void on_accepted(const AcceptedCommand& accepted) override {
    {
      const std::lock_guard lock(mutex_);
      if (accepted.source == source_ && accepted.kind == AcceptedKind::kWrench) {
        acceptances_.push_back(accepted);
      }
    }
    changed_.notify_all();
    const std::lock_guard calls(handler_mutex_);
    if (accepted_handler_) accepted_handler_(accepted);
  }

  // Handlers: setting one waits for a call in progress (handler_mutex_ is held while one runs).
  template <class Message>
  void set_handler(std::function<void(const Message&)>& slot,
                   std::function<void(const Message&)> handler) {
    const std::lock_guard calls(handler_mutex_);
    slot = std::move(handler);
  }

  bool wait_server(std::chrono::milliseconds patience) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, patience, [&] { return server_seen_; });
  }

  // A control or an edit: both are answered on the control reply topic, matched by seq.
  template <class Request>
  std::optional<ControlReply> request(Request control, std::chrono::milliseconds patience) {
    const auto deadline = Clock::now() + patience;
    // LCM needs no discovery: send at once. DDS: wait to see the server first (see the header).
    if (options_.bus == Bus::kDds && !wait_server(left(deadline))) return std::nullopt;
    control.source = source_;
    control.seq = next_seq();
    std::optional<ControlReply> answer;
    const auto answered = [&] {
      for (const auto& r : replies_)
        if (r.seq == control.seq && !is_own_duplicate(r)) {
          answer = r;
          return true;
        }
      return false;
    };
    while (Clock::now() < deadline) {
      if (transport_->publish(control) == transport::PublishResult::kNotPermitted) {
        return not_permitted(control.source, control.seq, reply_kind(control),
                             "not permitted: this identity's permissions do not allow control "
                             "(rigid-keys add ... --may control)");
      }
      std::unique_lock lock(mutex_);
      if (changed_.wait_until(lock, std::min(deadline, Clock::now() + kResendPeriod), answered)) {
        return answer;
      }
      // A duplicate's refusal proves the request arrived: wait for its answer, send no more.
      for (const auto& r : replies_) {
        if (r.seq == control.seq && is_own_duplicate(r)) {
          changed_.wait_until(lock, deadline, answered);
          return answer;
        }
      }
    }
    return std::nullopt;
  }

  std::optional<AcceptedCommand> push(WrenchCommand wrench, std::chrono::milliseconds patience,
                                      std::string* refused) {
    const auto deadline = Clock::now() + patience;
    if (options_.bus == Bus::kDds && !wait_server(left(deadline))) return std::nullopt;
    wrench.source = source_;
    wrench.seq = next_seq();
    std::optional<AcceptedCommand> accepted;
    std::optional<ControlReply> refusal;
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

  std::int64_t send(WrenchCommand wrench) {
    wrench.source = source_;
    wrench.seq = next_seq();
    if (transport_->publish(wrench) == transport::PublishResult::kNotPermitted) {
      const std::lock_guard lock(mutex_);
      ++wrenches_refused_;
      ControlReply r;
      r.source = source_;
      r.seq = wrench.seq;
      r.command = kReplyToWrench;
      r.outcome = Outcome::kNotAllowed;
      r.message = "not permitted: this identity's permissions do not allow pushing '" +
                  wrench.body_name + "'";
      last_refusal_ = r;
    }
    return wrench.seq;
  }

  std::int64_t next_seq() {
    const std::lock_guard lock(mutex_);
    return ++seq_;
  }

  const BusOptions options_;
  const std::int64_t source_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::int64_t seq_ = 0;
  bool server_seen_ = false;
  std::optional<SceneDescription> scene_;
  std::uint64_t scene_generation_ = 0;
  std::shared_ptr<const StateFrame> state_;
  std::optional<StatsReport> stats_;
  std::vector<ControlReply> replies_;          // ours only
  std::vector<AcceptedCommand> acceptances_;   // ours only
  std::vector<ControlReply> wrench_refusals_;  // ours, the newest 64
  std::optional<ControlReply> last_refusal_;
  std::int64_t wrenches_refused_ = 0;
  std::mutex handler_mutex_;  // guards the handlers and is held while one runs
  std::function<void(const StateFrame&)> state_handler_;
  std::function<void(const std::shared_ptr<const StateFrame>&)> shared_state_handler_;
  std::function<void(const AcceptedCommand&)> accepted_handler_;
  std::function<void(const StatsReport&)> stats_handler_;
  std::function<void(const SceneDescription&)> scene_handler_;
  std::function<void(const ContactEvents&)> contacts_handler_;
  std::unique_ptr<transport::Transport> transport_;  // last: its thread stops first
};

Session::Session(const BusOptions& options) : impl_(std::make_unique<Impl>(options)) {}

Session::~Session() = default;

const BusOptions& Session::options() const {
  return impl_->options_;
}

std::int64_t Session::source() const {
  return impl_->source_;
}

void Session::on_each_state(std::function<void(const StateFrame&)> handler) {
  impl_->set_handler(impl_->state_handler_, std::move(handler));
}

void Session::on_each_state_shared(
    std::function<void(const std::shared_ptr<const StateFrame>&)> handler) {
  impl_->set_handler(impl_->shared_state_handler_, std::move(handler));
}

void Session::on_each_accepted(std::function<void(const AcceptedCommand&)> handler) {
  impl_->set_handler(impl_->accepted_handler_, std::move(handler));
}

void Session::on_each_stats(std::function<void(const StatsReport&)> handler) {
  impl_->set_handler(impl_->stats_handler_, std::move(handler));
}

void Session::on_each_scene(std::function<void(const SceneDescription&)> handler) {
  impl_->set_handler(impl_->scene_handler_, std::move(handler));
}

void Session::on_each_contacts(std::function<void(const ContactEvents&)> handler) {
  impl_->set_handler(impl_->contacts_handler_, std::move(handler));
}

bool Session::wait_server(std::chrono::milliseconds patience) {
  return impl_->wait_server(patience);
}

std::optional<SceneDescription> Session::wait_scene(std::chrono::milliseconds patience) {
  std::unique_lock lock(impl_->mutex_);
  impl_->changed_.wait_for(lock, patience, [&] { return impl_->scene_.has_value(); });
  return impl_->scene_;
}

std::uint64_t Session::scene_generation() const {
  const std::lock_guard lock(impl_->mutex_);
  return impl_->scene_generation_;
}

std::optional<StatsReport> Session::wait_stats(std::chrono::milliseconds patience) {
  std::unique_lock lock(impl_->mutex_);
  impl_->changed_.wait_for(lock, patience, [&] { return impl_->stats_.has_value(); });
  return impl_->stats_;
}

std::optional<StateFrame> Session::latest_state() const {
  const std::shared_ptr<const StateFrame> s = latest_state_shared();
  if (!s) return std::nullopt;
  return *s;
}

std::shared_ptr<const StateFrame> Session::latest_state_shared() const {
  const std::lock_guard lock(impl_->mutex_);
  return impl_->state_;
}

std::optional<ControlReply> Session::request(ControlCommand control,
                                             std::chrono::milliseconds patience) {
  return impl_->request(std::move(control), patience);
}

std::optional<ControlReply> Session::pause(std::chrono::milliseconds patience) {
  ControlCommand c;
  c.command = ControlKind::kPause;
  return request(c, patience);
}

std::optional<ControlReply> Session::resume(std::chrono::milliseconds patience) {
  ControlCommand c;
  c.command = ControlKind::kResume;
  return request(c, patience);
}

std::optional<ControlReply> Session::step(std::int64_t ticks, std::chrono::milliseconds patience) {
  ControlCommand c;
  c.command = ControlKind::kStep;
  c.steps = ticks;
  return request(c, patience);
}

std::optional<ControlReply> Session::reset(std::chrono::milliseconds patience) {
  ControlCommand c;
  c.command = ControlKind::kReset;
  return request(c, patience);
}

std::optional<ControlReply> Session::set_rtf(double rtf, std::chrono::milliseconds patience) {
  ControlCommand c;
  c.command = ControlKind::kSetRtf;
  c.rtf = rtf;
  return request(c, patience);
}

std::optional<ControlReply> Session::edit(EditCommand edit, std::chrono::milliseconds patience) {
  if (edit.stamp_ns == 0) {
    edit.stamp_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                        std::chrono::system_clock::now().time_since_epoch())
                        .count();
  }
  return impl_->request(std::move(edit), patience);
}

std::optional<ControlReply> Session::set_state(std::int32_t body, const StateEdit& state,
                                               std::chrono::milliseconds patience) {
  EditCommand e;
  e.kind = EditKind::kSetState;
  e.body_id = body;
  e.state_edit() = state;
  return edit(std::move(e), patience);
}

std::optional<ControlReply> Session::reset_body(std::int32_t body,
                                                std::chrono::milliseconds patience) {
  EditCommand e;
  e.kind = EditKind::kResetBody;
  e.body_id = body;
  return edit(std::move(e), patience);
}

std::optional<AcceptedCommand> Session::push(WrenchCommand wrench,
                                             std::chrono::milliseconds patience,
                                             std::string* refused) {
  return impl_->push(std::move(wrench), patience, refused);
}

std::int64_t Session::send(WrenchCommand wrench) {
  return impl_->send(std::move(wrench));
}

std::optional<ControlReply> Session::take_refusal() {
  const std::lock_guard lock(impl_->mutex_);
  std::optional<ControlReply> r;
  r.swap(impl_->last_refusal_);
  return r;
}

std::int64_t Session::wrenches_refused() const {
  const std::lock_guard lock(impl_->mutex_);
  return impl_->wrenches_refused_;
}

}  // namespace rigid::client
