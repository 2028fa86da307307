#include "connect.hpp"

#include "transport/dds/dds_transport.hpp"
#include "transport/lcm/lcm_transport.hpp"

namespace rigid::client {

static_assert(kDefaultLcmUrl == transport::lcm::kDefaultUrl);

std::unique_ptr<transport::Transport> connect(const BusOptions& o, transport::Role role,
                                              transport::Receiver& receiver) {
  try {
    if (o.bus == Bus::kDds) {
      transport::dds::Options d;
      d.role = role;
      d.domain = o.dds_domain;
      d.prefix = o.prefix;
      d.security = o.security;
      // DDS stays on loopback unless the user configured a network (CYCLONEDDS_URI).
      (void)transport::dds::ensure_dds_config();
      return transport::dds::make_transport(d, receiver);
    }
    transport::lcm::Options l;
    l.role = role;
    l.prefix = o.prefix;
    // liblcm's default socket receive buffer silently loses messages over ~200 KB (a state of a
    // few thousand bodies): ask for 4 MiB (the kernel caps it at net.core.rmem_max).
    l.url = o.lcm_url.empty() ? std::string(kDefaultLcmUrl) + "&recv_buf_size=4194304" : o.lcm_url;
    return transport::lcm::make_transport(l, receiver);
  } catch (const transport::TransportError& e) {
    throw BusError(e.what());
  }
}

}  // namespace rigid::client
