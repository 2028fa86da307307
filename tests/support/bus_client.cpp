#include "bus_client.hpp"

#include <time.h>
#include <unistd.h>

#include <atomic>

#include "transport/dds/dds_transport.hpp"
#include "transport/lcm/lcm_transport.hpp"

namespace rigid::rigidd::testing {
namespace {

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

std::atomic<int> g_clients{0};

}  // namespace

std::string unique_prefix(const std::string& tag) {
  static std::atomic<int> counter{0};
  return tag + std::to_string(::getpid()) + "_" + std::to_string(counter++);
}

BusClient::BusClient(rigid::Bus bus, const std::string& prefix, const std::string& lcm_url,
                     int state_history)
    : bus_(bus), source_(static_cast<std::int64_t>(::getpid()) * 1000 + g_clients++) {
  if (bus == rigid::Bus::kDds) {
    transport::dds::Options o;
    o.role = transport::Role::kClient;
    o.prefix = prefix;
    o.state_history = state_history;
    transport_ = transport::dds::make_transport(o, *this);
  } else {
    transport::lcm::Options o;
    o.role = transport::Role::kClient;
    o.prefix = prefix;
    o.url = lcm_url.empty() ? std::string(transport::lcm::kDefaultUrl) + "&recv_buf_size=4194304"
                            : lcm_url;
    transport_ = transport::lcm::make_transport(o, *this);
  }
}

BusClient::~BusClient() {
  transport_.reset();
}

std::int64_t BusClient::send(rigid::WrenchCommand wrench) {
  wrench.source = source_;
  wrench.seq = next_seq();
  (void)transport_->publish(wrench);
  return wrench.seq;
}

std::int64_t BusClient::send(rigid::ControlCommand control) {
  control.source = source_;
  control.seq = next_seq();
  (void)transport_->publish(control);
  return control.seq;
}

std::int64_t BusClient::send(rigid::EditCommand edit) {
  edit.source = source_;
  edit.seq = next_seq();
  (void)transport_->publish(edit);
  return edit.seq;
}

std::optional<rigid::ControlReply> BusClient::handshake(rigid::ControlCommand control,
                                                        std::chrono::milliseconds patience) {
  const auto deadline = std::chrono::steady_clock::now() + patience;
  const std::int64_t first = seq_ + 1;
  std::optional<rigid::ControlReply> answer;
  while (std::chrono::steady_clock::now() < deadline) {
    send(control);
    const bool got = wait(
        [&] {
          for (const auto& r : replies_)
            if (r.source == source_ && r.seq >= first) {
              answer = r;
              return true;
            }
          return false;
        },
        std::chrono::milliseconds(50));
    if (got) return answer;
  }
  return std::nullopt;
}

std::optional<rigid::ControlReply> BusClient::request(rigid::ControlCommand control,
                                                      std::chrono::milliseconds patience,
                                                      std::int64_t* seq_used) {
  const std::int64_t seq = send(control);
  if (seq_used != nullptr) *seq_used = seq;
  return answer_to(seq, patience);
}

std::optional<rigid::ControlReply> BusClient::request(rigid::EditCommand edit,
                                                      std::chrono::milliseconds patience,
                                                      std::int64_t* seq_used) {
  const std::int64_t seq = send(edit);
  if (seq_used != nullptr) *seq_used = seq;
  return answer_to(seq, patience);
}

std::optional<rigid::ControlReply> BusClient::answer_to(std::int64_t seq,
                                                        std::chrono::milliseconds patience) {
  std::optional<rigid::ControlReply> answer;
  wait(
      [&] {
        for (const auto& r : replies_)
          if (r.source == source_ && r.seq == seq) {
            answer = r;
            return true;
          }
        return false;
      },
      patience);
  return answer;
}

bool BusClient::wait(const std::function<bool()>& pred, std::chrono::milliseconds patience) {
  std::unique_lock lock(mutex_);
  return changed_.wait_for(lock, patience, pred);
}

std::vector<TimedState> BusClient::states() const {
  const std::lock_guard lock(mutex_);
  return states_;
}

std::size_t BusClient::state_count() const {
  const std::lock_guard lock(mutex_);
  return states_.size();
}

std::optional<TimedState> BusClient::last_state() const {
  const std::lock_guard lock(mutex_);
  if (states_.empty()) return std::nullopt;
  return states_.back();
}

std::optional<rigid::StatsReport> BusClient::last_stats() const {
  const std::lock_guard lock(mutex_);
  return stats_;
}

std::optional<rigid::SceneDescription> BusClient::scene() const {
  const std::lock_guard lock(mutex_);
  return scene_;
}

void BusClient::on_state(const rigid::StateFrame& state) {
  const std::int64_t t = now_ns();
  {
    const std::lock_guard lock(mutex_);
    states_.push_back({state, t});
  }
  changed_.notify_all();
}

void BusClient::on_stats(const rigid::StatsReport& stats) {
  {
    const std::lock_guard lock(mutex_);
    stats_ = stats;
  }
  changed_.notify_all();
}

void BusClient::on_scene(const rigid::SceneDescription& scene) {
  {
    const std::lock_guard lock(mutex_);
    scene_ = scene;
  }
  changed_.notify_all();
}

void BusClient::on_contacts(const rigid::ContactEvents& contacts) {
  {
    const std::lock_guard lock(mutex_);
    contacts_.push_back(contacts);
  }
  changed_.notify_all();
}

std::vector<rigid::ContactEvents> BusClient::contacts() const {
  const std::lock_guard lock(mutex_);
  return contacts_;
}

void BusClient::on_control_reply(const rigid::ControlReply& reply) {
  {
    const std::lock_guard lock(mutex_);
    replies_.push_back(reply);
  }
  changed_.notify_all();
}

}  // namespace rigid::rigidd::testing
