// An attacker process for security_process_test.cpp, built from the message definitions only:
// writes wrenches on rigid/wrench with attacker.idl's type (msgs/rigid.idl's fields, but an
// unbounded body name), as a plain participant or with Cyclone's security plugins for an
// identity directory, in a partition of its choice.
//
//   raw_dds_writer [--security DIR] [--partition P] [--source S] [--seq Q] [--count N]
//                  [--force FX] [--ttl T] [--name-bytes B] [--readers R]
//
// Exit: 0 written once R readers (default 1) matched (then it lingers 0.5 s); 1 they did not
// match within 5 s; 2 bad arguments; 3 the participant or the writer was refused (security).
#include <dds/dds.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "attacker.h"

int main(int argc, char** argv) {
  std::string security, partition, body = "zebracraft";
  long long source = 5, seq = 1;
  int count = 1, readers = 1;
  double force = 0.0, ttl = 0.0;
  std::size_t name_bytes = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--security")
      security = v;
    else if (k == "--partition")
      partition = v;
    else if (k == "--source")
      source = std::atoll(v.c_str());
    else if (k == "--seq")
      seq = std::strtoll(v.c_str(), nullptr, 10);
    else if (k == "--count")
      count = std::atoi(v.c_str());
    else if (k == "--force")
      force = std::atof(v.c_str());
    else if (k == "--ttl")
      ttl = std::atof(v.c_str());
    else if (k == "--name-bytes")
      name_bytes = std::strtoull(v.c_str(), nullptr, 10);
    else if (k == "--readers")
      readers = std::atoi(v.c_str());
    else {
      std::fprintf(stderr, "raw_dds_writer: unknown option %s\n", k.c_str());
      return 2;
    }
  }
  dds_qos_t* pqos = dds_create_qos();
  if (!security.empty()) {
    const std::string lib = RIGID_DDS_SECURITY_DIR;
    const auto file = [&](const char* f) { return "file:" + security + "/" + f; };
    const std::vector<std::pair<std::string, std::string>> props{
        {"dds.sec.auth.library.path", lib + "/libdds_security_auth.so"},
        {"dds.sec.auth.library.init", "init_authentication"},
        {"dds.sec.auth.library.finalize", "finalize_authentication"},
        {"dds.sec.crypto.library.path", lib + "/libdds_security_crypto.so"},
        {"dds.sec.crypto.library.init", "init_crypto"},
        {"dds.sec.crypto.library.finalize", "finalize_crypto"},
        {"dds.sec.access.library.path", lib + "/libdds_security_ac.so"},
        {"dds.sec.access.library.init", "init_access_control"},
        {"dds.sec.access.library.finalize", "finalize_access_control"},
        {"dds.sec.auth.identity_ca", file("identity_ca.pem")},
        {"dds.sec.auth.identity_certificate", file("cert.pem")},
        {"dds.sec.auth.private_key", file("key.pem")},
        {"dds.sec.access.permissions_ca", file("permissions_ca.pem")},
        {"dds.sec.access.governance", file("governance.p7s")},
        {"dds.sec.access.permissions", file("permissions.p7s")}};
    for (const auto& [k, v] : props)
      dds_qset_prop(pqos, k.c_str(), v.c_str());
  }
  const dds_entity_t participant = dds_create_participant(0, pqos, nullptr);
  dds_delete_qos(pqos);
  if (participant < 0) return 3;
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 256);
  const dds_entity_t topic =
      dds_create_topic(participant, &rigid_Wrench_desc, "rigid/wrench", qos, nullptr);
  if (topic < 0) return 3;
  if (!partition.empty()) {
    const char* ps[] = {partition.c_str()};
    dds_qset_partition(qos, 1, ps);
  }
  const dds_entity_t writer = dds_create_writer(participant, topic, qos, nullptr);
  dds_delete_qos(qos);
  if (writer < 0) {
    dds_delete(participant);
    return 3;
  }
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  dds_publication_matched_status_t matched{};
  while (dds_get_publication_matched_status(writer, &matched) == DDS_RETCODE_OK &&
         matched.current_count < static_cast<std::uint32_t>(readers)) {
    if (std::chrono::steady_clock::now() > end) {
      dds_delete(participant);
      return 1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  std::string name = name_bytes > 0 ? std::string(name_bytes, 'n') : body;
  for (int i = 0; i < count; ++i) {
    rigid_Wrench w{};
    w.source = source;
    w.seq = seq + i;
    w.body_id = -1;
    w.body_name = name.data();
    w.force[0] = force;
    w.ttl = ttl;
    if (dds_write(writer, &w) != DDS_RETCODE_OK) std::fprintf(stderr, "write %d failed\n", i);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  dds_delete(participant);
  return 0;
}
