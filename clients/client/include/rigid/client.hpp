// rigid's client SDK in one include: the messages (rigid/messages.hpp), the bus options and the
// session with rigidd. Link rigid::client (CMake: find_package(rigid)) or `pkg-config rigid`.
#pragma once

#include "rigid/client/bus.hpp"
#include "rigid/client/names.hpp"
#include "rigid/client/session.hpp"
#include "rigid/messages.hpp"
