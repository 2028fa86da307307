#include "transport/ros/sim_server.hpp"

#include <regex.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <limits>

#include "transport/ros/ros_names.hpp"
#include "transport/ros/ros_qos.hpp"

namespace rigid::transport::ros {
namespace {

// rmw's default service QoS: reliable, volatile, keep last 10.
constexpr std::int32_t kServiceDepth = 10;
// A reply waits this long for the client's reader to be matched (rmw_cyclonedds waits 100 ms,
// blocking; rigidd keeps the reply instead and sends it on the match).
constexpr std::int64_t kReplyWaitNs = 1'000'000'000;
constexpr std::size_t kMaxDeferred = 256;
// Each client's budget of immediate answers: kBudgetPerSecond a second, kBudgetBurst at once. A
// GetEntities costs 1 plus 1 per kBodiesPerToken bodies it scans, at most the burst.
constexpr double kBudgetPerSecond = 100.0;
constexpr double kBudgetBurst = 100.0;
constexpr double kBodiesPerToken = 1000.0;
// Per-writer caches (client ids, budgets, identities) are cleared when they reach this size.
constexpr std::size_t kMaxWriters = 1024;

constexpr std::uint16_t kFeatures[] = {
    feature::kEntityStateGetting,     feature::kSimulationReset,
    feature::kSimulationStateGetting, feature::kSimulationStateSetting,
    feature::kSimulationStatePause,   feature::kStepSimulationSingle,
    feature::kStepSimulationMultiple,
};

// rmw_cyclonedds's client/service id text (csid_to_string): the 16 bytes in hex, '.'-separated,
// the first one padded to two places with a space.
std::string csid_text(const Guid& participant, std::uint32_t counter) {
  std::uint8_t id[16];
  std::copy(participant.begin(), participant.begin() + 12, id);
  for (int i = 0; i < 4; ++i)
    id[12 + i] = static_cast<std::uint8_t>(counter >> (24 - 8 * i));
  char buffer[8];
  std::snprintf(buffer, sizeof buffer, "%2x", id[0]);
  std::string text = buffer;
  for (int i = 1; i < 16; ++i) {
    std::snprintf(buffer, sizeof buffer, ".%x", id[i]);
    text += buffer;
  }
  return text;
}

std::string hex(const std::uint8_t* bytes, std::size_t n) {
  std::string text;
  char buffer[4];
  for (std::size_t i = 0; i < n; ++i) {
    std::snprintf(buffer, sizeof buffer, "%02x", bytes[i]);
    text += buffer;
  }
  return text;
}

// POSIX extended regular expression, compiled once per request (regcomp allocates).
class Regex {
 public:
  explicit Regex(const std::string& pattern) {
    error_ = regcomp(&re_, pattern.c_str(), REG_EXTENDED | REG_NOSUB);
  }
  ~Regex() {
    if (error_ == 0) regfree(&re_);
  }
  Regex(const Regex&) = delete;
  Regex& operator=(const Regex&) = delete;
  bool ok() const { return error_ == 0; }
  std::string error() const {
    char text[128];
    regerror(error_, &re_, text, sizeof text);
    return text;
  }
  bool search(const std::string& s) const { return regexec(&re_, s.c_str(), 0, nullptr, 0) == 0; }

 private:
  regex_t re_{};
  int error_ = 0;
};

}  // namespace

std::int64_t SimServer::now_ns() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<std::int64_t>(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

SimServer::SimServer(dds_entity_t participant, Setup setup, Receiver& receiver,
                     TrafficCounter& counter)
    : setup_(std::move(setup)), receiver_(receiver), counter_(counter) {
  body_index_.reserve(setup_.body_names.size());
  for (std::size_t i = 0; i < setup_.body_names.size(); ++i)
    body_index_.emplace(setup_.body_names[i], static_cast<std::int32_t>(i));
  paused_ = setup_.mode == rigid::Mode::kLockstep;
  const Guid me = guid_of(participant);
  // This server's controls carry one source, made from the participant's GUID (FNV-1a): replies
  // to it are this server's.
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const std::uint8_t b : me) {
    h ^= b;
    h *= 0x100000001b3ULL;
  }
  source_ = static_cast<std::int64_t>(h >> 1) | 1;

  services_.reserve(kSimServices.size());
  std::uint32_t counter_id = 1;
  for (const SimServiceInfo& info : kSimServices) {
    const std::string fq = setup_.node_fq_name + "/" + std::string(info.name);
    // A service's reader and writer share one "serviceid": clients look for both (rmw_cyclonedds
    // check_for_service_reader_writer).
    const std::string user_data = "serviceid=" + csid_text(me, counter_id++) + ";";
    const dds::Qos qos = ros_qos(Durability::kVolatile, kServiceDepth, user_data);
    Endpoints e;
    e.kind = info.kind;
    e.request_topic = RawTopic(participant, dds_request_topic(fq),
                               dds_request_type("simulation_interfaces", info.type), qos.get());
    e.reply_topic = RawTopic(participant, dds_reply_topic(fq),
                             dds_response_type("simulation_interfaces", info.type), qos.get());
    e.reader =
        dds::Entity(dds_create_reader(participant, e.request_topic.get(), qos.get(), nullptr),
                    "reader for " + e.request_topic.name());
    e.writer = dds::Entity(dds_create_writer(participant, e.reply_topic.get(), qos.get(), nullptr),
                           "writer for " + e.reply_topic.name());
    e.read_condition = dds::Entity(dds_create_readcondition(e.reader.get(), DDS_ANY_STATE),
                                   "read condition for " + e.request_topic.name());
    // The writer itself is waited on for its matches (a reply may be waiting for one).
    dds_set_status_mask(e.writer.get(), DDS_PUBLICATION_MATCHED_STATUS);
    services_.push_back(std::move(e));
  }
}

std::vector<dds_entity_t> SimServer::conditions() const {
  std::vector<dds_entity_t> c;
  for (const Endpoints& e : services_)
    c.push_back(e.read_condition.get());
  for (const Endpoints& e : services_)
    c.push_back(e.writer.get());
  return c;
}

std::vector<dds_entity_t> SimServer::readers() const {
  std::vector<dds_entity_t> r;
  for (const Endpoints& e : services_)
    r.push_back(e.reader.get());
  return r;
}

std::vector<dds_entity_t> SimServer::writers() const {
  std::vector<dds_entity_t> w;
  for (const Endpoints& e : services_)
    w.push_back(e.writer.get());
  return w;
}

void SimServer::close() {
  const std::lock_guard lock(mutex_);
  deferred_.clear();
  services_.clear();
}

void SimServer::on_triggered(std::size_t index) {
  if (index >= services_.size()) {
    if (index < 2 * services_.size()) {
      dds_publication_matched_status_t status;
      (void)dds_get_publication_matched_status(services_[index - services_.size()].writer.get(),
                                               &status);  // resets the trigger
    }
    retry_deferred();
    return;
  }
  // At most a few requests per turn, so that rigid's own commands keep their turns.
  for (int n = 0; n < 16; ++n) {
    const int taken =
        take_raw(services_[index].reader.get(),
                 [&](std::span<const std::uint8_t> bytes, const dds_sample_info_t& info) {
                   if (info.valid_data) on_request(index, bytes, info);
                 });
    if (taken <= 0) break;
  }
  retry_deferred();
}

void SimServer::on_request(std::size_t service, std::span<const std::uint8_t> bytes,
                           const dds_sample_info_t& info) {
  const SimService kind = services_[service].kind;
  const DecodeStatus status = decode_request(kind, bytes, request_);
  if (status != DecodeStatus::kOk) {
    counter_.decode_failed();
    receiver_.on_decode_error({Bus::kDds, Topic::kControl, status, bytes.size()});
    return;
  }
  counter_.received();
  answer(service, request_, info, client_id_of(service, info.publication_handle));
}

void SimServer::answer(std::size_t service, const SimRequest& request,
                       const dds_sample_info_t& info, const std::string& client_id) {
  const SimService kind = services_[service].kind;
  const RequestHeader& h = request.header;
  const auto result = [&](SimResult r, std::string_view message) {
    encode_result_response(h, r, message, scratch_);
    reply(service, client_id, scratch_);
  };
  const bool lockstep = setup_.mode == rigid::Mode::kLockstep;
  switch (kind) {
    case SimService::kGetSimulatorFeatures:
      if (!take_budget(info.publication_handle, 1.0)) break;
      encode_features_response(h, kFeatures,
                               "rigid: rigid-body simulation server; SetEntityState, spawning and "
                               "deleting are not available yet",
                               scratch_);
      reply(service, client_id, scratch_);
      return;
    case SimService::kGetSimulationState: {
      if (!take_budget(info.publication_handle, 1.0)) break;
      SimState state = SimState::kPlaying;
      {
        const std::lock_guard lock(mutex_);
        state = stopped_ ? SimState::kStopped : paused_ ? SimState::kPaused : SimState::kPlaying;
      }
      encode_simulation_state_response(h, state, SimResult::kOk, "", scratch_);
      reply(service, client_id, scratch_);
      return;
    }
    case SimService::kSetSimulationState: {
      bool paused = false;
      bool stopped = false;
      {
        const std::lock_guard lock(mutex_);
        paused = paused_;
        stopped = stopped_;
      }
      const auto already = [](bool yes) {
        return yes ? SimResult::kAlreadyInTargetState : SimResult::kOk;
      };
      switch (static_cast<SimState>(request.state)) {
        case SimState::kPlaying:
          if (lockstep) {
            result(SimResult::kOperationFailed,
                   "rigidd runs in lockstep mode: it ticks only on step requests");
            return;
          }
          send_controls(service, kind, request, info, client_id, {ControlKind::kResume}, 0,
                        already(!paused && !stopped), false);
          return;
        case SimState::kPaused:
          if (lockstep) {
            result(SimResult::kAlreadyInTargetState, "lockstep mode: always paused between steps");
            return;
          }
          send_controls(service, kind, request, info, client_id, {ControlKind::kPause}, 0,
                        already(paused && !stopped), false);
          return;
        case SimState::kStopped:
          // Stopped is paused at the initial state (simulation_interfaces SimulationState.msg).
          if (lockstep) {
            send_controls(service, kind, request, info, client_id, {ControlKind::kReset}, 0,
                          already(stopped), true);
          } else {
            send_controls(service, kind, request, info, client_id,
                          {ControlKind::kPause, ControlKind::kReset}, 0, already(stopped), true);
          }
          return;
        case SimState::kQuitting:
          result(SimResult::kFeatureUnsupported,
                 "rigidd does not quit on request: stop it with SIGTERM (systemctl stop rigidd)");
          return;
      }
      result(SimResult::kFeatureUnsupported,
             "state " + std::to_string(request.state) + " is not one rigid has (0 .. 3)");
      return;
    }
    case SimService::kStepSimulation:
      if (request.steps == 0 ||
          request.steps > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
        result(SimResult::kOperationFailed,
               "steps " + std::to_string(request.steps) + " out of range (1 .. 2^63 - 1)");
        return;
      }
      send_controls(service, kind, request, info, client_id, {ControlKind::kStep},
                    static_cast<std::int64_t>(request.steps), SimResult::kOk, false);
      return;
    case SimService::kResetSimulation: {
      const std::uint8_t s = request.scope;
      const bool both = (s & (kScopeTime | kScopeState)) == (kScopeTime | kScopeState);
      if (s != 0 && s != kScopeAll && !both) {
        result(SimResult::kFeatureUnsupported,
               "scope " + std::to_string(s) +
                   ": rigid resets time and state together (SCOPE_DEFAULT, SCOPE_ALL, or "
                   "SCOPE_TIME | SCOPE_STATE)");
        return;
      }
      send_controls(service, kind, request, info, client_id, {ControlKind::kReset}, 0,
                    SimResult::kOk, false);
      return;
    }
    case SimService::kGetEntityState: {
      if (!take_budget(info.publication_handle, 1.0)) break;
      EntityState state;
      state.frame_id = setup_.world_frame;
      SimResult r = SimResult::kOk;
      std::string message;
      const auto it = body_index_.find(request.entity);
      if (it == body_index_.end()) {
        r = SimResult::kNotFound;
        message = "no body named '" + request.entity.substr(0, 64) + "'";
      } else {
        const std::lock_guard lock(latest_mutex_);
        const auto i = static_cast<std::size_t>(it->second);
        if (!have_latest_ || i >= latest_.body_count()) {
          r = SimResult::kOperationFailed;
          message = "no state published yet";
        } else {
          state.stamp = ros_time(latest_.sim_time);
          std::copy_n(&latest_.position[3 * i], 3, state.position.begin());
          std::copy_n(&latest_.orientation[4 * i], 4, state.orientation_wxyz.begin());
          std::copy_n(&latest_.linear_velocity[3 * i], 3, state.linear_velocity.begin());
          std::copy_n(&latest_.angular_velocity[3 * i], 3, state.angular_velocity.begin());
        }
      }
      encode_entity_state_response(h, r, message, state, scratch_);
      reply(service, client_id, scratch_);
      return;
    }
    case SimService::kSetEntityState:
      if (!take_budget(info.publication_handle, 1.0)) break;
      result(SimResult::kFeatureUnsupported,
             "rigid cannot set a body's state while it runs yet (GetSimulatorFeatures lists what "
             "it can do)");
      return;
    case SimService::kGetEntities: {
      const double cost = std::min(
          kBudgetBurst, 1.0 + static_cast<double>(setup_.body_names.size()) / kBodiesPerToken);
      if (!take_budget(info.publication_handle, cost)) break;
      if (request.other_filters) {
        result(SimResult::kFeatureUnsupported,
               "rigid has no entity categories, tags or bounds filters: filter by name");
        return;
      }
      std::vector<std::string_view> names;
      names.reserve(setup_.body_names.size());
      if (request.filter.empty()) {
        for (const std::string& n : setup_.body_names)
          names.push_back(n);
      } else {
        const Regex re(request.filter);
        if (!re.ok()) {
          encode_entities_response(h, SimResult::kOperationFailed,
                                   "filter: not a POSIX extended regular expression: " + re.error(),
                                   {}, scratch_);
          reply(service, client_id, scratch_);
          return;
        }
        for (const std::string& n : setup_.body_names)
          if (re.search(n)) names.push_back(n);
      }
      encode_entities_response(h, SimResult::kOk, "", names, scratch_);
      reply(service, client_id, scratch_);
      return;
    }
  }
  // Over the client's budget (the only break above).
  const std::string why = "over this client's share of answers (" +
                          std::to_string(static_cast<int>(kBudgetPerSecond)) + " a second)";
  switch (kind) {
    case SimService::kGetSimulatorFeatures:
      // The response has no result field: the client gets an empty feature list and the reason.
      encode_features_response(h, {}, why, scratch_);
      break;
    case SimService::kGetSimulationState:
      encode_simulation_state_response(h, SimState::kPlaying, SimResult::kOperationFailed, why,
                                       scratch_);
      break;
    case SimService::kGetEntityState:
      encode_entity_state_response(h, SimResult::kOperationFailed, why, EntityState{}, scratch_);
      break;
    case SimService::kGetEntities:
      encode_entities_response(h, SimResult::kOperationFailed, why, {}, scratch_);
      break;
    default:
      encode_result_response(h, SimResult::kOperationFailed, why, scratch_);
      break;
  }
  reply(service, client_id, scratch_);
}

void SimServer::send_controls(std::size_t service, SimService kind, const SimRequest& request,
                              const dds_sample_info_t& info, const std::string& client_id,
                              std::initializer_list<ControlKind> controls, std::int64_t steps,
                              SimResult ok_result, bool stopping) {
  std::int64_t first = 0;
  {
    const std::lock_guard lock(mutex_);
    Pending* slot = nullptr;
    for (Pending& p : pending_)
      if (!p.used) {
        slot = &p;
        break;
      }
    if (slot == nullptr) {
      // Every slot waits for the loop: the oldest goes (a request the loop never answered, such as
      // one whose refusal was not answered to stay within the reply rate).
      slot = &*std::min_element(
          pending_.begin(), pending_.end(),
          [](const Pending& a, const Pending& b) { return a.since_ns < b.since_ns; });
    }
    first = seq_ + 1;
    seq_ += static_cast<std::int64_t>(controls.size());
    *slot = Pending{true,
                    kind,
                    service,
                    request.header,
                    client_id,
                    first,
                    static_cast<int>(controls.size()),
                    static_cast<int>(controls.size()),
                    ok_result,
                    *(controls.end() - 1),
                    stopping,
                    false,
                    {},
                    now_ns()};
  }
  const Origin origin = origin_of(service, info.publication_handle);
  std::int64_t seq = first;
  for (const ControlKind k : controls) {
    ControlCommand c;
    c.source = source_;
    c.seq = seq++;
    c.command = k;
    c.steps = k == ControlKind::kStep ? steps : 0;
    receiver_.on_control(c, origin);
  }
}

bool SimServer::on_control_reply(const ControlReply& r) {
  if (r.source != source_) return false;
  std::size_t service = 0;
  std::string client_id;
  {
    const std::lock_guard lock(mutex_);
    Pending* p = nullptr;
    for (Pending& q : pending_)
      if (q.used && r.seq >= q.first_seq && r.seq < q.first_seq + q.count) {
        p = &q;
        break;
      }
    if (p == nullptr) return true;  // ours, for a request given up
    if (r.outcome != Outcome::kOk && !p->failed) {
      p->failed = true;
      p->message = r.message;
    }
    if (--p->remaining > 0) return true;
    // The state this request made, at once: its controls' rigid/accepted records may come later
    // (on_accepted leaves this server's own controls alone).
    if (!p->failed) {
      if (p->stopping) {
        paused_ = stopped_ = true;
      } else if (p->last_kind == ControlKind::kPause) {
        paused_ = true;
        stopped_ = false;
      } else if (p->last_kind == ControlKind::kResume) {
        paused_ = stopped_ = false;
      } else if (p->last_kind == ControlKind::kStep) {
        stopped_ = false;
      }
    }
    const SimResult result = p->failed ? SimResult::kOperationFailed : p->ok_result;
    encode_result_response(p->header, result, p->message, reply_scratch_);
    service = p->service;
    client_id = std::move(p->client_id);
    p->used = false;
  }
  reply(service, client_id, reply_scratch_);
  return true;
}

void SimServer::on_accepted(const AcceptedCommand& a) {
  // Others' controls (rigidctl, another client); this server's own change the state when
  // answered (on_control_reply).
  if (a.kind != AcceptedKind::kControl || a.source == source_) return;
  const std::lock_guard lock(mutex_);
  switch (a.command) {
    case ControlKind::kPause:
      paused_ = true;
      break;
    case ControlKind::kResume:
      paused_ = false;
      stopped_ = false;
      break;
    case ControlKind::kStep:
      stopped_ = false;
      break;
    default:
      break;
  }
}

void SimServer::on_state(const StateFrame& state) {
  const std::lock_guard lock(latest_mutex_);
  // Copies into the kept frame's storage: no allocation once it has the state's size.
  latest_.tick = state.tick;
  latest_.sim_time = state.sim_time;
  latest_.position.assign(state.position.begin(), state.position.end());
  latest_.orientation.assign(state.orientation.begin(), state.orientation.end());
  latest_.linear_velocity.assign(state.linear_velocity.begin(), state.linear_velocity.end());
  latest_.angular_velocity.assign(state.angular_velocity.begin(), state.angular_velocity.end());
  latest_.ids.assign(state.ids.begin(), state.ids.end());
  have_latest_ = true;
}

void SimServer::reply(std::size_t service, const std::string& client_id,
                      std::vector<std::uint8_t>& bytes) {
  const std::lock_guard lock(mutex_);
  if (service >= services_.size()) return;  // closed
  if (client_id.empty() || client_matched(service, client_id)) {
    const Endpoints& e = services_[service];
    counter_.count(e.reply_topic.write(e.writer.get(), bytes) >= 0 ? PublishResult::kOk
                                                                   : PublishResult::kFailed);
    return;
  }
  if (deferred_.size() >= kMaxDeferred) deferred_.erase(deferred_.begin());
  deferred_.push_back({service, client_id, bytes, now_ns() + kReplyWaitNs});
}

bool SimServer::client_matched(std::size_t service, const std::string& client_id) const {
  const dds_entity_t writer = services_[service].writer.get();
  dds_instance_handle_t handles[64];
  const dds_return_t n = dds_get_matched_subscriptions(writer, handles, 64);
  for (dds_return_t i = 0; i < std::min<dds_return_t>(n, 64); ++i) {
    dds_builtintopic_endpoint_t* ep = dds_get_matched_subscription_data(writer, handles[i]);
    if (ep == nullptr) continue;
    const bool same = user_data_value(ep->qos, "clientid") == client_id;
    dds_builtintopic_free_endpoint(ep);
    if (same) return true;
  }
  return false;
}

void SimServer::retry_deferred() {
  const std::lock_guard lock(mutex_);
  if (deferred_.empty()) return;
  const std::int64_t now = now_ns();
  std::erase_if(deferred_, [&](Deferred& d) {
    if (d.service >= services_.size() || now > d.give_up_ns) return true;
    if (!client_matched(d.service, d.client_id)) return false;
    const Endpoints& e = services_[d.service];
    counter_.count(e.reply_topic.write(e.writer.get(), d.bytes) >= 0 ? PublishResult::kOk
                                                                     : PublishResult::kFailed);
    return true;
  });
}

std::string SimServer::client_id_of(std::size_t service, dds_instance_handle_t writer) {
  if (auto it = client_ids_.find(writer); it != client_ids_.end()) return it->second;
  if (client_ids_.size() >= kMaxWriters) client_ids_.clear();
  std::string id;
  if (dds_builtintopic_endpoint_t* ep =
          dds_get_matched_publication_data(services_[service].reader.get(), writer)) {
    id = user_data_value(ep->qos, "clientid").value_or("");
    dds_builtintopic_free_endpoint(ep);
  }
  return client_ids_.emplace(writer, id).first->second;
}

bool SimServer::take_budget(dds_instance_handle_t writer, double cost) {
  const std::int64_t now = now_ns();
  if (budgets_.size() >= kMaxWriters && !budgets_.contains(writer)) budgets_.clear();
  auto [it, fresh] = budgets_.try_emplace(writer, Budget{kBudgetBurst, now});
  Budget& b = it->second;
  if (!fresh) {
    b.tokens = std::min(kBudgetBurst,
                        b.tokens + static_cast<double>(now - b.last_ns) * 1e-9 * kBudgetPerSecond);
    b.last_ns = now;
  }
  if (b.tokens < cost) return false;
  b.tokens -= cost;
  return true;
}

Origin SimServer::origin_of(std::size_t service, dds_instance_handle_t writer) {
  Origin origin;
  origin.session = writer;
  if (!setup_.secure) return origin;
  // With DDS Security only identities permitted to write this request topic reach it; the
  // sender is named by its participant.
  auto it = identities_.find(writer);
  if (it == identities_.end()) {
    if (identities_.size() >= kMaxWriters) identities_.clear();
    std::string id;
    if (dds_builtintopic_endpoint_t* ep =
            dds_get_matched_publication_data(services_[service].reader.get(), writer)) {
      id = "ros:" + hex(ep->participant_key.v, 12);
      dds_builtintopic_free_endpoint(ep);
    }
    it = identities_.emplace(writer, id).first;
  }
  if (it->second.empty()) return origin;
  origin.identity = it->second;
  origin.authenticated = true;
  return origin;
}

}  // namespace rigid::transport::ros
