#include "loop/server.hpp"

#include <pthread.h>
#include <sched.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <span>

#include "common/log_records.hpp"
#include "common/state_conversion.hpp"
#include "loop/clock.hpp"
#include "loop/overrun_log.hpp"
#include "rigid/names.hpp"
#include "util/cpu_affinity.hpp"
#include "util/thread_name.hpp"

namespace rigid::loop {
namespace {

std::vector<std::string> body_names(const scene::Scene& scene) {
  std::vector<std::string> names;
  names.reserve(scene.world.bodies.size());
  for (const physics::BodySpec& b : scene.world.bodies)
    names.push_back(b.name);
  return names;
}

LoopConfig loop_config(const scene::Scene& scene, const ServerOptions& options) {
  LoopConfig c;
  c.mode = options.mode;
  c.tick_dt = 1.0 / scene.rate_hz;
  c.substeps = scene.substeps;
  c.publish_every = scene.publish_every;
  c.wrench_capacity = options.wrench_capacity;
  c.wrench_share = static_cast<std::size_t>(scene.limits.max_wrenches_per_source);
  c.spin_ns = options.spin_ns;
  c.hash_states = !options.journal_path.empty();
  c.output_lends_frames = true;  // Server::lend_frame
  return c;
}

// What a replay needs besides the journal's entries: the scene (its text and as SceneInfo), the
// tick rate, the integrator and the wrench table's capacity.
msgs::LogHeader journal_header(const scene::Scene& scene, const ServerOptions& options,
                               const rigid::SceneDescription& info) {
  msgs::LogHeader h;
  h.set_kind(msgs::LogHeader::JOURNAL);
  h.set_schema_version(common::kLogSchemaVersion);
  h.set_software_version(common::software_version());
  h.set_writer("rigidd");
  h.set_start_unix_ns(realtime_ns());
  common::to_record(info, 0, *h.mutable_scene());
  h.set_integrator(info.integrator);
  h.set_rate_hz(scene.rate_hz);
  h.set_scene_text(options.scene_text);
  h.set_mode(std::string(rigid::mode_name(options.mode)));
  h.set_wrench_capacity(options.wrench_capacity);
  return h;
}

IntakePolicy intake_policy(const scene::Scene& scene, const ServerOptions& options) {
  IntakePolicy p;
  p.controls = options.controls;
  p.secure = options.secure;
  p.commands_per_second = scene.limits.max_commands_per_second;
  return p;
}

// Every CPU this process may use but `cpu`, for the physics pool's workers (World::set_threads).
// The loop thread is the pool's first thread and runs at SCHED_FIFO on `cpu`: a worker there
// would only get that CPU once the loop blocks at the pool's closing barrier, so its share would
// run after the loop's instead of beside it (and behind the FIFO publishers too). Elsewhere the
// workers leave the loop's CPU to the loop and its publishers, as with one thread. Leaves them
// where they are when `cpu` is the only CPU. The number of CPUs the workers got.
int keep_off(std::span<const std::thread::native_handle_type> workers, int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 0;
  CPU_CLR(cpu, &set);
  const int others = CPU_COUNT(&set);
  if (others == 0) return 0;
  for (const std::thread::native_handle_type w : workers)
    (void)pthread_setaffinity_np(w, sizeof set, &set);
  return others;
}

std::size_t bus_index(rigid::Bus bus) {
  return bus == rigid::Bus::kDds ? 0 : 1;
}

std::string fixed(double v, int decimals) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

std::string us(std::int64_t ns) {
  return fixed(static_cast<double>(ns) * 1e-3, 1);
}

}  // namespace

Server::Server(const scene::Scene& scene, const ServerOptions& options, Log& log)
    : log_(log),
      options_(options),
      bodies_(body_names(scene)),
      validator_(bodies_, scene.limits),
      commands_(options.command_capacity),
      dds_intake_(rigid::Bus::kDds, validator_, intake_policy(scene, options), commands_, doorbell_,
                  rejects_, *this),
      lcm_intake_(rigid::Bus::kLcm, validator_, intake_policy(scene, options), commands_, doorbell_,
                  rejects_, *this),
      loop_(scene.world, loop_config(scene, options), commands_, doorbell_, rejects_, *this) {
  scene_info_ = common::describe_scene(scene, loop_.world());
  rigid::StateFrame shape;
  common::shape_state_frame(loop_.world(), shape);
  states_ = std::make_unique<SharedStates>(shape);
  Journal::Options journal;
  journal.path = options.journal_path;
  // The header (the scene's text and a record of every body) is built only for a journal file:
  // without one, it was a copy of the whole scene, built at start and thrown away.
  journal_ = std::make_unique<Journal>(
      journal,
      journal.path.empty() ? msgs::LogHeader{} : journal_header(scene, options, scene_info_), log_,
      [this](const rigid::AcceptedCommand& a) { publish_accepted(a); });
}

Server::~Server() {
  stop();
}

transport::Receiver& Server::receiver(rigid::Bus bus) {
  return bus == rigid::Bus::kDds ? static_cast<transport::Receiver&>(dds_intake_)
                                 : static_cast<transport::Receiver&>(lcm_intake_);
}

void Server::add_transport(std::unique_ptr<transport::Transport> transport) {
  // Contact events only where there can be any: a scene without static parts has no outbox.
  publishers_.push_back(std::make_unique<Publisher>(*transport, *states_, log_, 256,
                                                    loop_.world().static_part_count() > 0));
  by_bus_[bus_index(transport->bus())].store(publishers_.back().get(), std::memory_order_release);
  transports_.push_back(std::move(transport));
}

void Server::start() {
  if (started_) return;
  started_ = true;
  for (auto& t : transports_) {
    if (t->publish(scene_info_) != transport::PublishResult::kOk) {
      log_.line("cannot publish SceneInfo on " + std::string(to_string(t->bus())));
    }
  }
  // Each transport keeps what late joiners get (DDS its durable history, LCM the encoded bytes it
  // sends again every second): this copy (~150 B a body) is no longer needed.
  scene_info_ = rigid::SceneDescription{};
  for (auto& p : publishers_)
    p->start();
  journal_->start();
  housekeeping_thread_ = std::thread([this] { housekeeping(); });
  util::name_thread(housekeeping_thread_, "rigid-house");
  loop_thread_ = std::thread([this] { loop_.run(); });
  util::name_thread(loop_thread_, "rigid-loop");
  if (options_.mode == rigid::Mode::kRealtime && options_.realtime_priority) {
    set_priorities();
  }
}

void Server::set_priorities() {
  // First the CPU, then the priority: a real-time thread never runs unpinned.
  loop_cpu_ = util::last_allowed_cpu();
  if (loop_cpu_ >= 0 && !util::pin_to_cpu(loop_thread_.native_handle(), loop_cpu_)) loop_cpu_ = -1;
  if (loop_cpu_ < 0) {
    log_.line(
        "loop thread: cannot pin it to one CPU: running at normal priority so that it can "
        "never take more than one CPU from this host");
    return;
  }
  for (auto& p : publishers_)
    (void)util::pin_to_cpu(p->native_handle(), loop_cpu_);
  // The step's other threads run at normal priority on the other CPUs: between steps they sleep
  // on the pool's barrier, and the loop's CPU keeps no more than the loop and its publishers.
  const auto workers = loop_.world().worker_threads();
  const int worker_cpus = workers.empty() ? 0 : keep_off(workers, loop_cpu_);
  sched_param param{};
  param.sched_priority = options_.fifo_priority;
  const int error = pthread_setschedparam(loop_thread_.native_handle(), SCHED_FIFO, &param);
  if (error != 0) {
    log_.line(std::string("loop thread: no real-time priority (") + std::strerror(error) +
              "): running at normal priority; tick lateness may suffer under load");
    return;
  }
  // The publishers just below the loop: a state (or a command's effect) then leaves within
  // ~100 us of its tick even when other processes keep the CPUs busy, instead of waiting for
  // the scheduler's next slice. They sleep between states and use a few percent of a core each in a
  // small world; one that takes more than a quarter of the CPU (a large world's states) steps down
  // to normal priority while it does (Publisher::watch_realtime_share).
  param.sched_priority = options_.fifo_priority - 1;
  bool publishers = true;
  for (auto& p : publishers_) {
    const bool ok = pthread_setschedparam(p->native_handle(), SCHED_FIFO, &param) == 0;
    if (ok) p->watch_realtime_share(param.sched_priority);
    publishers = ok && publishers;
  }
  // --rt-workers: a worker of normal priority preempted in the middle of its chunk holds the
  // step until the scheduler gives it its CPU back (the loop cannot take a chunk already begun),
  // so a busy host's other processes stretch the step. At SCHED_FIFO they cannot; the worker
  // still sleeps between ticks (it polls from just before the tick to the end of the step,
  // pool.hpp), so it takes its CPUs only for the step's length. Only on CPUs of their own: on
  // the loop's they would only run behind it anyway.
  bool rt_workers = false;
  if (options_.realtime_workers && worker_cpus > 0) {
    param.sched_priority = options_.fifo_priority - 2;
    rt_workers = true;
    for (const std::thread::native_handle_type w : workers)
      rt_workers = pthread_setschedparam(w, SCHED_FIFO, &param) == 0 && rt_workers;
    if (!rt_workers) {  // all or none
      param.sched_priority = 0;
      for (const std::thread::native_handle_type w : workers)
        (void)pthread_setschedparam(w, SCHED_OTHER, &param);
    }
  }
  std::string line = "loop thread: SCHED_FIFO priority " + std::to_string(options_.fifo_priority);
  if (publishers) line += ", publishers " + std::to_string(options_.fifo_priority - 1);
  line += ", on CPU " + std::to_string(loop_cpu_);
  if (!rt_workers) line += " (the real-time threads never take more than this CPU)";
  if (!workers.empty()) {
    line += "; " + std::to_string(workers.size()) + " physics worker(s) at " +
            (rt_workers ? "SCHED_FIFO priority " + std::to_string(options_.fifo_priority - 2)
                        : std::string("normal priority")) +
            " on the " + std::to_string(worker_cpus) + " other CPU(s)";
  }
  if (options_.realtime_workers && !rt_workers) {
    line += std::string(" (--rt-workers: ") +
            (workers.empty()    ? "no other step thread"
             : worker_cpus == 0 ? "no other CPU"
                                : "refused") +
            ")";
  }
  log_.line(line);
}

void Server::stop() {
  if (stopped_) return;
  stopped_ = true;
  if (!started_) return;
  loop_.request_stop();
  if (loop_thread_.joinable()) loop_thread_.join();
  totals_ = loop_.totals();
  journal_->stop();
  {
    const std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (housekeeping_thread_.joinable()) housekeeping_thread_.join();
  for (auto& p : publishers_)
    p->stop();
  rejects_.flush(log_, INT64_MAX);
  log_frozen_bodies();
}

void Server::log_frozen_bodies() {
  FrozenBody f;
  while (loop_.take_frozen(f)) {
    const std::string name = f.body >= 0 && f.body < bodies_.size() ? bodies_.name(f.body) : "?";
    log_.line("body '" + name + "' (id " + std::to_string(f.body) + ") frozen at tick " +
              std::to_string(f.tick) +
              ": its state went non-finite or beyond 1e100 (the integrator diverged under its "
              "loads); held at its last good state, at rest, ignoring loads until a reset; the "
              "rest of the world goes on (Stats counts frozen bodies)");
  }
}

bool Server::first_state_sent() const {
  for (const auto& p : publishers_)
    if (p->states_sent() > 0) return true;
  return false;
}

void Server::offer_state(const rigid::StateFrame& frame, std::int64_t command_arrival_ns) {
  if (publishers_.empty()) return;
  const int slot = states_->put_copied(frame, static_cast<int>(publishers_.size()));
  for (auto& p : publishers_)
    p->offer_slot(slot, command_arrival_ns);
}

rigid::StateFrame* Server::lend_frame() {
  return &states_->lend();
}

void Server::hand_over_lent(std::int64_t command_arrival_ns) {
  // Without a bus the lent slot stays lent, and the next lend_frame gives it again.
  if (publishers_.empty()) return;
  const int slot = states_->put_lent(static_cast<int>(publishers_.size()));
  for (auto& p : publishers_)
    p->offer_slot(slot, command_arrival_ns);
}

bool Server::wait_states_taken(std::int64_t deadline_ns) {
  for (auto& p : publishers_)
    if (!p->wait_taken(deadline_ns)) return false;
  return true;
}

void Server::offer_contacts(const rigid::ContactEvents& events) {
  // One stamp for every bus, as a state's.
  const std::int64_t stamp = realtime_ns();
  for (auto& p : publishers_)
    (void)p->offer_contacts(events, stamp);  // a bus without room counts its loss
}

bool Server::wait_contacts_room(std::size_t events, std::int64_t deadline_ns) {
  for (auto& p : publishers_)
    if (!p->wait_contacts_room(events, deadline_ns)) return false;
  return true;
}

void Server::reply(const Reply& reply) {
  Publisher* p = by_bus_[bus_index(reply.bus)].load(std::memory_order_acquire);
  if (p != nullptr) p->reply(reply);
}

void Server::publish_accepted(const rigid::AcceptedCommand& accepted) {
  for (auto& t : transports_)
    (void)t->publish(accepted);  // failures are counted by the transport
}

rigid::StatsReport Server::make_stats(const LoopSummary& s) const {
  rigid::StatsReport r;
  r.tick = s.tick;
  r.sim_time = s.sim_time;
  r.mode = s.mode;
  r.paused = s.paused;
  r.rtf_last_second = s.rtf_last_second;
  r.rtf_since_start = s.rtf_since_start;
  r.lateness_p50_us = s.lateness_p50_us;
  r.lateness_p99_us = s.lateness_p99_us;
  r.lateness_max_us = s.lateness_max_us;
  r.overruns = s.overruns;
  r.step_cost_p50_us = s.step_cost_p50_us;
  r.step_cost_max_us = s.step_cost_max_us;
  r.bodies_frozen = s.bodies_frozen;
  r.large_rotation_steps = s.large_rotation_steps;
  for (const auto& p : publishers_)
    r.states_skipped += p->states_skipped();
  r.commands_accepted = loop_.commands_accepted();
  r.rejected = rejects_.counts();
  r.refused_by_source = rejects_.top_senders();
  for (const auto& t : transports_) {
    (t->bus() == rigid::Bus::kDds ? r.dds : r.lcm) = t->counts();
  }
  return r;
}

void Server::housekeeping() {
  constexpr auto kPeriod = std::chrono::milliseconds(100);
  std::int64_t next_scene_ns = monotonic_ns() + 1'000'000'000;
  OverrunLog overrun_log;
  LoopSummary summary;
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    wake_.wait_for(lock, kPeriod, [this] { return stopping_; });
    if (stopping_) break;
    lock.unlock();
    const std::int64_t now = monotonic_ns();
    rejects_.flush(log_, now);
    log_frozen_bodies();
    if (loop_.take_summary(summary)) {
      const rigid::StatsReport stats = make_stats(summary);
      for (auto& t : transports_)
        (void)t->publish(stats);  // failures are counted by the transport
    }
    if (now >= next_scene_ns) {
      // LCM has no durability: late joiners get the scene within a second.
      for (auto& t : transports_)
        (void)t->republish_scene();  // failures are counted by the transport
      next_scene_ns = now + 1'000'000'000;
    }
    if (auto line = overrun_log.update(loop_.overruns(), now)) log_.line(*line);
    lock.lock();
  }
}

std::string Server::closing_line() const {
  if (!totals_) return "stopped before starting";
  const RunTotals& t = *totals_;
  std::string line = "stopped: ticks=" + std::to_string(t.ticks_stepped) +
                     " wall_s=" + fixed(t.wall_s, 3) + " sim_s=" + fixed(t.sim_s_stepped, 3) +
                     " rtf=" + fixed(t.wall_s > 0 ? t.sim_s_stepped / t.wall_s : 0.0, 4) +
                     " overruns=" + std::to_string(t.overruns);
  line += " lateness_us p50=" + us(t.lateness.percentile(0.5)) +
          " p99=" + us(t.lateness.percentile(0.99)) + " max=" + us(t.lateness.max());
  line += " step_cost_us p50=" + us(t.step_cost.percentile(0.5)) +
          " p99=" + us(t.step_cost.percentile(0.99)) + " max=" + us(t.step_cost.max());
  for (const auto& p : publishers_) {
    const std::string bus(to_string(p->bus()));
    line += " " + bus + "_states_sent=" + std::to_string(p->states_sent()) + " " + bus +
            "_states_skipped=" + std::to_string(p->states_skipped()) + " " + bus +
            "_priority_step_downs=" + std::to_string(p->priority_step_downs());
    if (loop_.world().static_part_count() > 0) {
      line += " " + bus + "_contact_messages_sent=" + std::to_string(p->contacts_sent()) + " " +
              bus + "_contact_events_lost=" + std::to_string(p->contact_events_lost());
    }
    const Histogram& h = p->command_to_state();
    line += " " + bus + "_command_to_state_us p50=" + us(h.percentile(0.5)) +
            " p99=" + us(h.percentile(0.99)) + " max=" + us(h.max()) +
            " n=" + std::to_string(h.count());
  }
  line += " commands_accepted=" + std::to_string(loop_.commands_accepted()) +
          " commands_rejected=" + std::to_string(rejects_.total());
  line += " bodies_frozen=" + std::to_string(loop_.world().frozen_bodies().size());
  if (loop_.world().static_part_count() > 0) {
    line += " contact_events_dropped_by_physics=" +
            std::to_string(loop_.world().contact_events_dropped());
  }
  return line;
}

std::string Server::short_closing_line() const {
  if (!totals_) return "stopped before starting";
  const RunTotals& t = *totals_;
  return "stopped after " + std::to_string(t.ticks_stepped) + " ticks (" + fixed(t.wall_s, 1) +
         " s, rtf " + fixed(t.wall_s > 0 ? t.sim_s_stepped / t.wall_s : 0.0, 3) + "), " +
         std::to_string(t.overruns) + " overruns, lateness p99 " + us(t.lateness.percentile(0.99)) +
         " us; commands accepted " + std::to_string(loop_.commands_accepted()) + ", refused " +
         std::to_string(rejects_.total()) +
         "; bodies_frozen=" + std::to_string(loop_.world().frozen_bodies().size()) +
         " (--verbose: the full summary)";
}

std::string Server::lateness_histogram_line() const {
  std::string line = "lateness_histogram_ns";
  if (!totals_) return line;
  const Histogram& h = totals_->lateness;
  for (int b = 0; b < Histogram::kBuckets; ++b)
    if (const std::int64_t n = h.count_in(b); n > 0)
      line += " " + std::to_string(Histogram::bucket_low(b)) + ":" + std::to_string(n);
  return line;
}

}  // namespace rigid::loop
