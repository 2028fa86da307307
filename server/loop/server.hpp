// The daemon's parts wired together: the loop and its thread, one intake per bus (the transports'
// receivers), one publisher per transport, the journal (its thread publishes each accepted command
// on rigid/accepted and, with --journal, writes the journal file), and a housekeeping thread that
// publishes Stats when the loop closes a one-second window, republishes SceneInfo on LCM every
// second (DDS keeps it for late joiners: transient-local), and writes deferred log lines (first
// refusals, overruns, bodies frozen by the physics guard).
//
// Order of use: construct; create each transport with receiver(bus) and give it to
// add_transport; start(); ... stop() (or the destructor). Threads: the loop, one per publisher,
// the journal, housekeeping, and each transport's receive thread.
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "loop/bounded_queue.hpp"
#include "loop/command.hpp"
#include "loop/command_validation.hpp"
#include "loop/doorbell.hpp"
#include "loop/intake.hpp"
#include "loop/journal.hpp"
#include "loop/log.hpp"
#include "loop/loop.hpp"
#include "loop/outbox.hpp"
#include "loop/publisher.hpp"
#include "loop/reject_counters.hpp"
#include "scene/scene.hpp"
#include "transport/transport.hpp"

namespace rigid::loop {

struct ServerOptions {
  rigid::Mode mode = rigid::Mode::kRealtime;
  std::size_t command_capacity = 1024;  // queued commands between the transports and the loop
  std::size_t wrench_capacity = 4096;   // live wrenches
  // Realtime mode: ask for SCHED_FIFO for the loop thread at fifo_priority and the publishers one
  // below (needs CAP_SYS_NICE; logged either way), all on one CPU (the last one this process may
  // use), so that whatever rate a client asks for, rigidd's real-time threads take at most that
  // CPU: the loop then falls behind (overruns, rtf in Stats) instead of starving the host.
  bool realtime_priority = true;
  int fifo_priority = 10;
  // With realtime_priority, the physics pool's workers (World::worker_threads) at SCHED_FIFO too,
  // at fifo_priority - 2, on the CPUs other than the loop's (rigidd --rt-workers). Off: they run
  // at normal priority there, and rigidd's real-time threads never take more than the loop's CPU.
  bool realtime_workers = false;
  std::int64_t spin_ns = 100'000;  // LoopConfig::spin_ns
  // rigidd --journal: the journal file (created; an existing file is refused), and the scene
  // file's text, kept in it so that a replay can check it runs the same scene. Empty: no file.
  std::string journal_path;
  std::string scene_text;
  // Control requests (pause, resume, step, reset, rate) accepted at all (rigidd --controls).
  bool controls = true;
  // DDS Security is on: only authenticated identities' commands count (intake.hpp).
  bool secure = false;
};

class Server final : private LoopOutput {
 public:
  // Throws LogFileError when the journal file cannot be created.
  Server(const scene::Scene& scene, const ServerOptions& options, Log& log);
  ~Server() override;
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  // The receiver to create `bus`'s transport with. It may be called as soon as the transport
  // exists: commands wait in the queue until start().
  transport::Receiver& receiver(rigid::Bus bus);
  // Before start().
  void add_transport(std::unique_ptr<transport::Transport> transport);

  // Publishes SceneInfo and starts every thread.
  void start();
  // Stops the loop, then the journal (it writes what it holds), housekeeping, and the publishers
  // (each sends what it holds). Idempotent.
  void stop();

  bool first_state_sent() const;
  std::uint64_t heartbeat() const { return loop_.heartbeat(); }
  const Loop& loop() const { return loop_; }
  const Journal& journal() const { return *journal_; }
  // One line summing up the run (after stop): ticks, lateness and step cost percentiles,
  // overruns, states sent and skipped per bus, commands accepted and refused.
  std::string closing_line() const;
  // The same in short, for the log at exit: ticks, rtf, overruns, lateness p99, commands.
  std::string short_closing_line() const;
  // The whole run's tick lateness distribution (after stop), for benchmarks that plot it:
  // "lateness_histogram_ns LOW:COUNT ...", one pair per non-empty bucket, LOW its lower bound.
  std::string lateness_histogram_line() const;

 private:
  void offer_state(const rigid::StateFrame& frame, std::int64_t command_arrival_ns) override;
  // The loop writes each state straight into a free slot of states_ (LoopConfig::
  // output_lends_frames), which hand_over_lent then offers to every bus.
  rigid::StateFrame* lend_frame() override;
  void hand_over_lent(std::int64_t command_arrival_ns) override;
  bool wait_states_taken(std::int64_t deadline_ns) override;
  void offer_contacts(const rigid::ContactEvents& events) override;
  bool wait_contacts_room(std::size_t events, std::int64_t deadline_ns) override;
  void reply(const Reply& reply) override;
  void journal(const common::JournalEntry& entry) override { journal_->push(entry); }
  void publish_accepted(const rigid::AcceptedCommand& accepted);
  void housekeeping();
  // Logs each body the loop found frozen for the first time (housekeeping and stop).
  void log_frozen_bodies();
  rigid::StatsReport make_stats(const LoopSummary& summary) const;
  void set_priorities();
  int loop_cpu_ = -1;  // the CPU the real-time threads are pinned to, or -1

  Log& log_;
  const ServerOptions options_;
  rigid::SceneDescription scene_info_;  // until start() has given it to the transports
  BodyDirectory bodies_;
  CommandValidator validator_;
  BoundedQueue<Command> commands_;
  Doorbell doorbell_;
  RejectCounters rejects_;
  Intake dds_intake_;
  Intake lcm_intake_;
  Loop loop_;
  // The states the publishers read (before them: they hold a reference to it).
  std::unique_ptr<SharedStates> states_;
  // Publishers by bus, for replies (set before start, read from any thread).
  std::array<std::atomic<Publisher*>, 2> by_bus_{};
  std::vector<std::unique_ptr<Publisher>> publishers_;
  // After the publishers and intakes: destroyed first, so their receive threads end before what
  // they call into goes away.
  std::vector<std::unique_ptr<transport::Transport>> transports_;
  // Calls into the transports from its thread: declared after them, so destroyed before.
  std::unique_ptr<Journal> journal_;

  std::mutex mutex_;  // guards stopping_ for the housekeeping wait
  std::condition_variable wake_;
  bool stopping_ = false;
  bool started_ = false;
  bool stopped_ = false;
  std::optional<RunTotals> totals_;
  std::thread loop_thread_;
  std::thread housekeeping_thread_;
};

}  // namespace rigid::loop
