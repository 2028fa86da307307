// DDS Security for one participant: the identity directory that `rigid-keys add` makes, turned
// into the QoS properties of Cyclone's security plugins (authentication PKI-DH, access control
// with signed governance and permissions, AES-GCM cryptography), and the partitions that bind a
// command to the identity that wrote it.
//
// Why partitions: the server must know which authenticated identity wrote each command, and
// Cyclone does not hand the application the remote certificate. The permissions rigid-keys
// signs let identity NAME write wrenches only in partition push/NAME/BODY (for each BODY it may
// push) and controls only in control/NAME; access control checks a writer's partitions against
// its signed permissions when it is created and when the server matches it, so the partition of
// the writer a sample came from names its sender and what it may do.
#pragma once

#include <string>
#include <string_view>

#include "transport/dds/dds_entity.hpp"

namespace rigid::transport::dds {

inline constexpr std::string_view kPushPartition = "push";
inline constexpr std::string_view kControlPartition = "control";

// The files of an identity directory (rigid-keys add DIR NAME makes DIR/identities/NAME).
struct Identity {
  std::string directory;  // absolute, without a trailing '/'
  std::string name;       // the certificate's common name (CN)
};

// Checks that every file is there and readable and reads the name from cert.pem. Throws
// TransportError, one line naming the file and what to do.
Identity load_identity(const std::string& directory);

// Participant QoS with the security plugins' properties for `identity`.
Qos participant_security_qos(const Identity& identity);

// "push/NAME/BODY", "control/NAME"; the server's readers use "push/*", "control/*".
std::string push_partition(std::string_view identity, std::string_view body);
std::string control_partition(std::string_view identity);

}  // namespace rigid::transport::dds
