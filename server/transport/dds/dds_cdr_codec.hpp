// rigid's messages as Cyclone DDS serializes them (XCDR1, native byte order, without the 4-byte
// encapsulation header a DDS sample carries on the wire): what dds_write puts in a datagram, for
// tests and measurements that want the bytes without a network. The transport itself lets Cyclone
// serialize; it does not use this. Decoding validates the bytes the way Cyclone validates a
// received sample, then deserializes into the idlc type and copies into the plain message.
//
// The interface is transport/codec.hpp's, shared with LCM.
#pragma once

#include "transport/codec.hpp"

namespace rigid::transport::dds {

using CdrCodec = Codec<Bus::kDds>;

}  // namespace rigid::transport::dds
