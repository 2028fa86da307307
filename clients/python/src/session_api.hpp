// The one place the Python module includes the C++ client session (the rigid_client SDK:
// rigid::client::Session, its bus options and names, and the messages). If the SDK's headers or
// namespace move again, only these lines change.
#pragma once

#include "rigid/client.hpp"

namespace rigid::python {

namespace sdk = rigid::client;
using rigid::AcceptedCommand;
using rigid::ControlKind;
using rigid::ControlReply;
using rigid::Outcome;
using rigid::SceneDescription;
using rigid::StateFrame;
using rigid::StatsReport;
using rigid::WrenchCommand;

}  // namespace rigid::python
