// rigid's messages as LCM payloads (msgs/rigid.lcm, fingerprint first), both ways, for the LCM
// transport and for tools that read LCM logs. A scene refused by encode leaves the previous
// scene's payload valid (the LCM transport republishes it).
//
// The interface is transport/codec.hpp's, shared with DDS.
#pragma once

#include "transport/codec.hpp"

namespace rigid::transport::lcm {

using Codec = transport::Codec<Bus::kLcm>;

}  // namespace rigid::transport::lcm
