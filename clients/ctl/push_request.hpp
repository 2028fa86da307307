// rigidctl push: the wrench it sends, from the command line and the running scene. It checks the
// wrench against the scene's limits as rigidd would (so that a refusal is told before anything is
// sent, with exit status 1 as rigidd's own refusal), picks the duration when --for is not given,
// and says what the push amounts to, so that a push too short to see is not a silent one.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "ctl/ctl_options.hpp"
#include "rigid/messages.hpp"

namespace rigid::ctl {

// Without --for a push lasts this long (or the scene's max_ttl, if shorter): long enough to see.
inline constexpr double kDefaultPushSeconds = 1.0;

struct PushRequest {
  rigid::WrenchCommand wrench;  // body, force, point, torque, frames and ttl filled in
  std::string refusal;          // non-empty: what rigidd would refuse it for (not sent)
};

// The wrench for `o` on body `body` (an index into `scene`), checked against the scene's limits.
PushRequest make_push(const CtlOptions& o, const rigid::SceneDescription& scene, std::int32_t body);

// What the accepted push amounts to, for rigidctl's answer: its duration and impulse, and the
// change of velocity that impulse gives the body's mass (a free body's, without other forces),
// e.g. "for 1 s (default; --for S): impulse 5 N s, |dv| 0.33 m/s on its 15 kg".
std::string push_summary(const PushRequest& push, const CtlOptions& o,
                         const rigid::SceneDescription& scene);

}  // namespace rigid::ctl
