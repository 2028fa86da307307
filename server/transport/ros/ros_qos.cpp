#include "transport/ros/ros_qos.hpp"

#include <cstring>

namespace rigid::transport::ros {

dds::Qos ros_qos(Durability durability, std::int32_t depth, std::string_view user_data) {
  dds::Qos qos(dds_create_qos());
  dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, DDS_MSECS(10));
  dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, depth);
  dds_qset_writer_data_lifecycle(qos.get(), false);
  if (durability == Durability::kTransientLocal) {
    dds_qset_durability(qos.get(), DDS_DURABILITY_TRANSIENT_LOCAL);
    // Cyclone keeps what the durability service QoS says for late joiners (rmw sets it so).
    dds_qset_durability_service(qos.get(), 0, DDS_HISTORY_KEEP_LAST, depth, DDS_LENGTH_UNLIMITED,
                                DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
  } else {
    dds_qset_durability(qos.get(), DDS_DURABILITY_VOLATILE);
  }
  if (!user_data.empty()) dds_qset_userdata(qos.get(), user_data.data(), user_data.size());
  return qos;
}

std::optional<std::string> user_data_value(const dds_qos_t* qos, std::string_view key) {
  void* raw = nullptr;
  std::size_t size = 0;
  if (qos == nullptr || !dds_qget_userdata(qos, &raw, &size) || raw == nullptr) return std::nullopt;
  const std::string text(static_cast<const char*>(raw), size);
  dds_free(raw);
  // "k1=v1;k2=v2;": a key starts the text or follows a ';'.
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t end = std::min(text.find(';', at), text.size());
    const std::string_view item(text.data() + at, end - at);
    if (item.size() > key.size() && item.substr(0, key.size()) == key && item[key.size()] == '=') {
      return std::string(item.substr(key.size() + 1));
    }
    at = end + 1;
  }
  return std::nullopt;
}

Guid guid_of(dds_entity_t entity) {
  Guid g{};
  dds_guid_t guid;
  if (dds_get_guid(entity, &guid) == DDS_RETCODE_OK) std::memcpy(g.data(), guid.v, g.size());
  return g;
}

}  // namespace rigid::transport::ros
