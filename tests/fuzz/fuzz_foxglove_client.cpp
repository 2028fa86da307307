// libFuzzer target: what a Foxglove client sends rigid-view (clients/view/foxglove_protocol.hpp),
// the whole input read as a text message, as a binary message and as a push on /rigid/push,
// through the bounded JSON reader (json_value.hpp). Besides memory errors and undefined behaviour
// (ASan, UBSan), each accepted result must keep the promises the server relies on: ids are
// uint32, a push's numbers finite and within their limits, a binary message's payload inside the
// input; and the reader's bounds hold (at most kMaxJsonValues values, nesting at most
// kMaxJsonDepth).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "foxglove_protocol.hpp"
#include "fuzz_require.hpp"
#include "json_value.hpp"
#include "protocol.hpp"

namespace {

using namespace rigid::view;

// Values and depth of a parsed value, to check the reader's bounds.
void measure(const Json& j, std::size_t depth, std::size_t& values, std::size_t& deepest) {
  ++values;
  if (depth > deepest) deepest = depth;
  for (const Json& item : j.items)
    measure(item, depth + 1, values, deepest);
  for (const JsonField& f : j.fields)
    measure(f.value, depth + 1, values, deepest);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view in(reinterpret_cast<const char*>(data), size);

  auto json = parse_json(in);
  if (const Json* j = std::get_if<Json>(&json)) {
    std::size_t values = 0, deepest = 0;
    measure(*j, 0, values, deepest);
    rigid::fuzz::require(values <= kMaxJsonValues, "values <= kMaxJsonValues");
    rigid::fuzz::require(deepest <= kMaxJsonDepth, "deepest <= kMaxJsonDepth");
  }

  auto text = foxglove::parse_client_text(in);
  if (auto* t = std::get_if<foxglove::ClientText>(&text)) {
    if (auto* s = std::get_if<foxglove::Subscribe>(t))
      rigid::fuzz::require(s->subscriptions.size() <= foxglove::kChannelCount,
                           "s->subscriptions.size() <= foxglove::kChannelCount");
    if (auto* a = std::get_if<foxglove::ClientAdvertise>(t)) {
      rigid::fuzz::require(a->channels.size() <= foxglove::kMaxClientChannels,
                           "a->channels.size() <= foxglove::kMaxClientChannels");
      for (const auto& c : a->channels)
        rigid::fuzz::require(
            c.topic.size() <= 256 && c.encoding.size() <= 256 && c.schema_name.size() <= 256,
            "c.topic.size() <= 256 && c.encoding.size() <= 256 && c.schema_name.size() <= 256");
    }
  }

  auto binary = foxglove::parse_client_binary(in);
  if (auto* d = std::get_if<foxglove::ClientData>(&binary)) {
    rigid::fuzz::require(
        size >= 5 && d->payload.data() == in.data() + 5 && d->payload.size() == size - 5,
        "size >= 5 && d->payload.data() == in.data() + 5 && d->payload.size() == size - 5");
  }

  auto push = foxglove::parse_push(in);
  if (auto* p = std::get_if<foxglove::PushRequest>(&push)) {
    rigid::fuzz::require(p->duration > 0 && p->duration <= foxglove::kMaxPushDuration,
                         "p->duration > 0 && p->duration <= foxglove::kMaxPushDuration");
    rigid::fuzz::require(p->body_name.empty() != (p->body < 0),
                         "p->body_name.empty() != (p->body < 0)");
    rigid::fuzz::require(p->body_name.size() <= 256, "p->body_name.size() <= 256");
    for (int k = 0; k < 3; ++k) {
      rigid::fuzz::require(std::isfinite(p->force[k]) && std::abs(p->force[k]) <= kMaxPushForce,
                           "std::isfinite(p->force[k]) && std::abs(p->force[k]) <= kMaxPushForce");
      rigid::fuzz::require(std::isfinite(p->point[k]) && std::abs(p->point[k]) <= kMaxPushPoint,
                           "std::isfinite(p->point[k]) && std::abs(p->point[k]) <= kMaxPushPoint");
    }
  }
  return 0;
}
