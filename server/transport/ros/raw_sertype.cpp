#include "transport/ros/raw_sertype.hpp"

#include <dds/ddsi/ddsi_serdata.h>
#include <dds/ddsi/ddsi_sertype.h>
#include <dds/ddsi/q_radmin.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <memory>
#include <new>
#include <vector>

namespace rigid::transport::ros {
namespace {

// A sample: its serialized bytes, padded with zeros to a multiple of 4 (Cyclone sends whole
// 4-byte units of a sample and reads that far; DDSI-RTPS 2.5, 9.4.2.11).
struct RawSerdata : ddsi_serdata {
  std::unique_ptr<std::uint8_t[]> bytes;  // not value-initialised: every byte is written
  std::uint32_t size = 0;                 // padding included
};

struct RawSertype : ddsi_sertype {};

RawSerdata* make(const ddsi_sertype* type, ddsi_serdata_kind kind, std::size_t size) {
  auto* d = new (std::nothrow) RawSerdata;
  if (d == nullptr) return nullptr;
  ddsi_serdata_init(d, type, kind);
  const std::size_t padded = (size + 3) / 4 * 4;
  d->bytes.reset(new (std::nothrow) std::uint8_t[padded == 0 ? 1 : padded]);
  if (!d->bytes) {
    delete d;
    return nullptr;
  }
  std::memset(d->bytes.get() + size, 0, padded - size);
  d->size = static_cast<std::uint32_t>(padded);
  return d;
}

// --- serdata operations (ddsi_serdata.h describes each) ---

bool eqkey(const ddsi_serdata*, const ddsi_serdata*) {
  return true;  // keyless: every sample is the one instance
}

std::uint32_t get_size(const ddsi_serdata* d) {
  return static_cast<const RawSerdata*>(d)->size;
}

ddsi_serdata* from_ser(const ddsi_sertype* type, ddsi_serdata_kind kind, const nn_rdata* fragchain,
                       std::size_t size) {
  RawSerdata* d = nullptr;
  try {
    d = make(type, kind, size);
  } catch (const std::bad_alloc&) {
    delete d;
    return nullptr;
  }
  if (d == nullptr) return nullptr;
  // Fragments may overlap: copy from each only what extends the bytes already copied.
  // Bytes no fragment covers (never, from a conforming writer) stay zero rather than undefined.
  std::memset(d->bytes.get(), 0, size);
  std::uint32_t off = 0;
  for (; fragchain != nullptr; fragchain = fragchain->nextfrag) {
    if (fragchain->maxp1 <= off) continue;
    if (fragchain->min > off || fragchain->maxp1 > size) break;  // a gap or excess: never seen
    const unsigned char* payload =
        NN_RMSG_PAYLOADOFF(fragchain->rmsg, NN_RDATA_PAYLOAD_OFF(fragchain));
    std::memcpy(d->bytes.get() + off, payload + (off - fragchain->min), fragchain->maxp1 - off);
    off = fragchain->maxp1;
  }
  return d;
}

ddsi_serdata* from_ser_iov(const ddsi_sertype* type, ddsi_serdata_kind kind,
                           ddsrt_msg_iovlen_t niov, const ddsrt_iovec_t* iov, std::size_t size) {
  RawSerdata* d = nullptr;
  try {
    d = make(type, kind, size);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
  if (d == nullptr) return nullptr;
  std::size_t off = 0;
  for (ddsrt_msg_iovlen_t i = 0; i < niov && off < size; ++i) {
    const std::size_t n = std::min<std::size_t>(iov[i].iov_len, size - off);
    std::memcpy(d->bytes.get() + off, iov[i].iov_base, n);
    off += n;
  }
  std::memset(d->bytes.get() + off, 0, size - off);
  return d;
}

ddsi_serdata* from_keyhash(const ddsi_sertype* type, const ddsi_keyhash*) {
  try {
    return make(type, SDK_KEY, 0);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}

// dds_write's path: a sample is a std::span<const std::uint8_t> of serialized bytes.
ddsi_serdata* from_sample(const ddsi_sertype* type, ddsi_serdata_kind kind, const void* sample) {
  const auto& bytes = *static_cast<const std::span<const std::uint8_t>*>(sample);
  if (kind != SDK_DATA) return from_keyhash(type, nullptr);
  ddsrt_iovec_t iov;
  iov.iov_base = const_cast<std::uint8_t*>(bytes.data());
  iov.iov_len = static_cast<ddsrt_iov_len_t>(bytes.size());
  return from_ser_iov(type, kind, 1, &iov, bytes.size());
}

void to_ser(const ddsi_serdata* d, std::size_t off, std::size_t sz, void* buf) {
  std::memcpy(buf, static_cast<const RawSerdata*>(d)->bytes.get() + off, sz);
}

ddsi_serdata* to_ser_ref(const ddsi_serdata* d, std::size_t off, std::size_t sz,
                         ddsrt_iovec_t* ref) {
  ref->iov_base = const_cast<std::uint8_t*>(static_cast<const RawSerdata*>(d)->bytes.get() + off);
  ref->iov_len = static_cast<ddsrt_iov_len_t>(sz);
  return ddsi_serdata_ref(d);
}

void to_ser_unref(ddsi_serdata* d, const ddsrt_iovec_t*) {
  ddsi_serdata_unref(d);
}

// rigid reads samples with dds_takecdr only: there is no deserialized form.
bool to_sample(const ddsi_serdata*, void*, void**, void*) {
  return false;
}

ddsi_serdata* to_untyped(const ddsi_serdata* d) {
  RawSerdata* u = nullptr;
  try {
    u = make(d->type, SDK_KEY, 0);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
  if (u != nullptr) u->type = nullptr;
  return u;
}

bool untyped_to_sample(const ddsi_sertype*, const ddsi_serdata*, void*, void**, void*) {
  return true;
}

void free_serdata(ddsi_serdata* d) {
  delete static_cast<RawSerdata*>(d);
}

std::size_t print(const ddsi_sertype*, const ddsi_serdata* d, char* buf, std::size_t size) {
  const int n = std::snprintf(buf, size, "(%u bytes)", static_cast<const RawSerdata*>(d)->size);
  return n < 0 ? 0 : static_cast<std::size_t>(n);
}

void get_keyhash(const ddsi_serdata*, ddsi_keyhash* buf, bool) {
  std::memset(buf, 0, sizeof *buf);
}

const ddsi_serdata_ops& serdata_ops() {
  static const ddsi_serdata_ops ops = [] {
    ddsi_serdata_ops o{};
    o.eqkey = eqkey;
    o.get_size = get_size;
    o.from_ser = from_ser;
    o.from_ser_iov = from_ser_iov;
    o.from_keyhash = from_keyhash;
    o.from_sample = from_sample;
    o.to_ser = to_ser;
    o.to_ser_ref = to_ser_ref;
    o.to_ser_unref = to_ser_unref;
    o.to_sample = to_sample;
    o.to_untyped = to_untyped;
    o.untyped_to_sample = untyped_to_sample;
    o.free = free_serdata;
    o.print = print;
    o.get_keyhash = get_keyhash;
    return o;
  }();
  return ops;
}

// --- sertype operations ---

void free_sertype(ddsi_sertype* t) {
  ddsi_sertype_fini(t);
  delete static_cast<RawSertype*>(t);
}

// Samples are spans (from_sample) that rigid owns: nothing to zero, grow or free.
void zero_samples(const ddsi_sertype*, void*, std::size_t) {}
void realloc_samples(void** ptrs, const ddsi_sertype*, void* old, std::size_t, std::size_t count) {
  auto* base = static_cast<std::span<const std::uint8_t>*>(old);
  for (std::size_t i = 0; i < count; ++i)
    ptrs[i] = base == nullptr ? nullptr : base + i;
}
void free_samples(const ddsi_sertype*, void**, std::size_t, dds_free_op_t) {}

// Cyclone compares the type name, the operations and the flags itself; nothing else to compare.
bool equal(const ddsi_sertype*, const ddsi_sertype*) {
  return true;
}
std::uint32_t hash(const ddsi_sertype*) {
  return 0;
}

std::size_t serialized_size(const ddsi_sertype*, const void* sample) {
  return static_cast<const std::span<const std::uint8_t>*>(sample)->size();
}
bool serialize_into(const ddsi_sertype*, const void* sample, void* dst, std::size_t dst_size) {
  const auto& bytes = *static_cast<const std::span<const std::uint8_t>*>(sample);
  if (bytes.size() > dst_size) return false;
  std::memcpy(dst, bytes.data(), bytes.size());
  return true;
}

const ddsi_sertype_ops& sertype_ops() {
  static const ddsi_sertype_ops ops = [] {
    ddsi_sertype_ops o{};
    o.version = ddsi_sertype_v0;
    o.free = free_sertype;
    o.zero_samples = zero_samples;
    o.realloc_samples = realloc_samples;
    o.free_samples = free_samples;
    o.equal = equal;
    o.hash = hash;
    // No type_id / type_map / type_info: like ROS 2's own middleware, no XTypes type information,
    // so peers match on the type name alone.
    o.get_serialized_size = serialized_size;
    o.serialize_into = serialize_into;
    return o;
  }();
  return ops;
}

}  // namespace

RawTopic::RawTopic(dds_entity_t participant, const std::string& name, const std::string& type_name,
                   const dds_qos_t* qos)
    : name_(name) {
  auto* type = new RawSertype;
  ddsi_sertype_init_flags(type, type_name.c_str(), &sertype_ops(), &serdata_ops(),
                          DDSI_SERTYPE_FLAG_TOPICKIND_NO_KEY);
  type->allowed_data_representation = DDS_DATA_REPRESENTATION_FLAG_XCDR1;
  ddsi_sertype* actual = type;
  // On success Cyclone owns `type` (or drops it for an equal one it has) and returns the one in
  // use; on failure it is still ours.
  const dds_entity_t topic =
      dds_create_topic_sertype(participant, name.c_str(), &actual, qos, nullptr, nullptr);
  if (topic < 0) ddsi_sertype_unref(type);
  topic_ = dds::Entity(topic, "topic " + name + " (" + type_name + ")");
  sertype_ = actual;
}

dds_return_t RawTopic::write(dds_entity_t writer, std::span<const std::uint8_t> bytes) const {
  ddsrt_iovec_t iov;
  iov.iov_base = const_cast<std::uint8_t*>(bytes.data());
  iov.iov_len = static_cast<ddsrt_iov_len_t>(bytes.size());
  ddsi_serdata* d = from_ser_iov(sertype_, SDK_DATA, 1, &iov, bytes.size());
  if (d == nullptr) return DDS_RETCODE_OUT_OF_RESOURCES;
  // dds_writecdr takes the reference, whatever it returns.
  return dds_writecdr(writer, d);
}

std::span<const std::uint8_t> raw_bytes(const ddsi_serdata* sample) {
  const auto* d = static_cast<const RawSerdata*>(sample);
  return {d->bytes.get(), d->size};
}

void release_raw(ddsi_serdata* sample) {
  ddsi_serdata_unref(sample);
}

}  // namespace rigid::transport::ros
