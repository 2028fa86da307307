// The control for security_process_test's oversized samples: a plain participant reading
// rigid/wrench with attacker.idl's type (no bound on the body name) and Cyclone's default
// MaxSampleSize, so that it reassembles every sample however large, as rigidd would without its
// cap. What its peak memory does under the attacker's samples is what rigidd's must not.
//
//   raw_dds_reader COUNT
//
// Prints "ready" once its reader exists, then "received N largest B" (B: the longest body name)
// once COUNT samples came, and stays until SIGTERM so that its memory can be read from /proc.
// Exit: 0 on SIGTERM after COUNT samples; 1 if they did not come within 60 s; 2 bad arguments.
#include <dds/dds.h>
#include <pthread.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "attacker.h"

int main(int argc, char** argv) {
  const int wanted = argc == 2 ? std::atoi(argv[1]) : 0;
  if (wanted <= 0) {
    std::fprintf(stderr, "usage: raw_dds_reader COUNT\n");
    return 2;
  }
  sigset_t term;
  sigemptyset(&term);
  sigaddset(&term, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &term, nullptr);  // before Cyclone's threads: they inherit it
  const dds_entity_t participant = dds_create_participant(DDS_DOMAIN_DEFAULT, nullptr, nullptr);
  if (participant < 0) return 1;
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 8);
  const dds_entity_t topic =
      dds_create_topic(participant, &rigid_Wrench_desc, "rigid/wrench", qos, nullptr);
  const dds_entity_t reader = dds_create_reader(participant, topic, qos, nullptr);
  dds_delete_qos(qos);
  if (reader < 0) return 1;
  std::printf("ready\n");
  std::fflush(stdout);
  int received = 0;
  std::size_t largest = 0;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (received < wanted && std::chrono::steady_clock::now() < end) {
    void* samples[4] = {};
    dds_sample_info_t infos[4];
    const dds_return_t got = dds_take(reader, samples, infos, 4, 4);
    for (dds_return_t i = 0; i < got; ++i) {
      if (!infos[i].valid_data) continue;
      ++received;
      const auto* w = static_cast<const rigid_Wrench*>(samples[i]);
      if (w->body_name != nullptr) largest = std::max(largest, std::strlen(w->body_name));
    }
    if (got > 0) dds_return_loan(reader, samples, got);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (received < wanted) {
    dds_delete(participant);
    return 1;
  }
  std::printf("received %d largest %zu\n", received, largest);
  std::fflush(stdout);
  const timespec patience{60, 0};
  (void)sigtimedwait(&term, nullptr, &patience);
  dds_delete(participant);
  return 0;
}
