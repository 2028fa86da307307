// A ROS 2 peer of rigidd --ros on Cyclone DDS with the security plugins of an identity directory
// (rigid-keys), built from ros_msgs.idl alone: writes a WrenchStamped on a topic, or reads /tf.
//
//   ros_secure_peer write [--security DIR] TOPIC FX     (frame "world", ten samples)
//   ros_secure_peer read [--security DIR] BODY          (prints BODY's x from /tf, newest first)
//
// Exit: 0 done; 1 nothing matched or read in 5 s; 2 bad arguments; 3 the participant, the topic,
// the writer or the reader was refused (security).
#include <dds/dds.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "ros_msgs.h"

namespace {

dds_entity_t participant(const std::string& dir) {
  dds_qos_t* qos = dds_create_qos();
  if (!dir.empty()) {
    const std::string lib = RIGID_DDS_SECURITY_DIR;
    const auto file = [&](const char* f) { return "file:" + dir + "/" + f; };
    // SROS2's file names (identity_ca.cert.pem, permissions_ca.cert.pem): what a ROS 2 node
    // pointed at the keystore reads.
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
        {"dds.sec.auth.identity_ca", file("identity_ca.cert.pem")},
        {"dds.sec.auth.identity_certificate", file("cert.pem")},
        {"dds.sec.auth.private_key", file("key.pem")},
        {"dds.sec.access.permissions_ca", file("permissions_ca.cert.pem")},
        {"dds.sec.access.governance", file("governance.p7s")},
        {"dds.sec.access.permissions", file("permissions.p7s")}};
    for (const auto& [k, v] : props)
      dds_qset_prop(qos, k.c_str(), v.c_str());
  }
  // rmw_cyclonedds's participant USER_DATA.
  dds_qset_userdata(qos, "enclave=/;", 10);
  const dds_entity_t p = dds_create_participant(0, qos, nullptr);
  dds_delete_qos(qos);
  return p;
}

dds_qos_t* ros_qos() {
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 10);
  return qos;
}

int write(dds_entity_t p, const std::string& topic_name, double fx) {
  dds_qos_t* qos = ros_qos();
  const dds_entity_t topic = dds_create_topic(p, &geometry_msgs_msg_dds__WrenchStamped__desc,
                                              topic_name.c_str(), qos, nullptr);
  const dds_entity_t writer = topic < 0 ? topic : dds_create_writer(p, topic, qos, nullptr);
  dds_delete_qos(qos);
  if (writer < 0) return 3;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  dds_publication_matched_status_t matched{};
  while (dds_get_publication_matched_status(writer, &matched) == DDS_RETCODE_OK &&
         matched.current_count == 0) {
    if (std::chrono::steady_clock::now() > end) return 1;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  for (int i = 0; i < 10; ++i) {
    geometry_msgs_msg_dds__WrenchStamped_ m{};
    m.header.frame_id = const_cast<char*>("world");
    m.wrench.force.x = fx;
    dds_write(writer, &m);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return 0;
}

int read(dds_entity_t p, const std::string& body) {
  dds_qos_t* qos = ros_qos();
  const dds_entity_t topic =
      dds_create_topic(p, &tf2_msgs_msg_dds__TFMessage__desc, "rt/tf", qos, nullptr);
  const dds_entity_t reader = topic < 0 ? topic : dds_create_reader(p, topic, qos, nullptr);
  dds_delete_qos(qos);
  if (reader < 0) return 3;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (std::chrono::steady_clock::now() < end) {
    void* samples[1] = {nullptr};
    dds_sample_info_t info;
    if (dds_take(reader, samples, &info, 1, 1) > 0) {
      const auto* m = static_cast<const tf2_msgs_msg_dds__TFMessage_*>(samples[0]);
      bool found = false;
      for (std::uint32_t i = 0; info.valid_data && i < m->transforms._length; ++i) {
        const auto& t = m->transforms._buffer[i];
        if (body == t.child_frame_id) {
          std::printf("%.17g\n", t.transform.translation.x);
          found = true;
        }
      }
      dds_return_loan(reader, samples, 1);
      if (found) return 0;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  std::string security;
  if (args.size() >= 3 && args[1] == "--security") {
    security = args[2];
    args.erase(args.begin() + 1, args.begin() + 3);
  }
  const bool writing = args.size() == 3 && args[0] == "write";
  const bool reading = args.size() == 2 && args[0] == "read";
  if (!writing && !reading) {
    std::fprintf(stderr, "usage: ros_secure_peer write|read [--security DIR] ...\n");
    return 2;
  }
  const dds_entity_t p = participant(security);
  if (p < 0) return 3;
  const int status = writing ? write(p, args[1], std::atof(args[2].c_str())) : read(p, args[1]);
  dds_delete(p);
  return status;
}
