// The course notes' scheme shown for what it is. Its rotation update w += dt I^-1 tau has no
// gyroscopic term: torque-free, it keeps the world-frame w constant, which for a body whose moments
// differ is not the physics (the angular momentum must be kept, and w must move). For a sphere w
// and L are the same thing, and the scheme is exact in both.
#include <gtest/gtest.h>

#include "test_util.hpp"

namespace rigid::test {
namespace {

TEST(NotesScheme, KeepsAngularVelocityInsteadOfMomentumForAnAsymmetricBody) {
  const Vec3 w0(1e-3, 5.0, 1e-3);
  World w(one_body(body("racket", {1, 2, 3}, w0), 1e-3, "games103"));
  const Vec3 L0 = w.angular_momentum_W(0);
  double max_dw = 0, max_dL = 0;
  for (int i = 0; i < 20000; ++i) {
    w.step();
    max_dw = std::max(max_dw, (w.state(0).w_WB - w0).norm());
    max_dL = std::max(max_dL, (w.angular_momentum_W(0) - L0).norm() / L0.norm());
  }
  EXPECT_LT(max_dw, 1e-12);  // w frozen in the world frame...
  EXPECT_GT(max_dL, 1e-4);   // ...so L, which physics conserves, wanders
  // and it never flips: the true motion turns w_y over within 20 s (see the hard cases).
  const Vec3 w_B = w.state(0).q_WB.conjugate() * w.state(0).w_WB;
  EXPECT_GT(std::abs(w_B.y()), 4.0);
}

// For a sphere the scheme conserves w = L / I exactly, and its orientation after n steps is the
// predicted discrete result: each step turns by 2 atan(h |w| / 2) instead of h |w|.
TEST(NotesScheme, IsExactInAngularVelocityForASphereAndTurnsByItsPredictedAngle) {
  const Vec3 w0(0.3, -1.2, 2.0);
  const double h = 0.01;
  for (const std::string name : {"games103", "notes_explicit_euler"}) {
    World w(one_body(body("ball", {0.4, 0.4, 0.4}, w0), h, name));
    const Vec3 L0 = w.angular_momentum_W(0);
    w.step(500);
    EXPECT_LT((w.state(0).w_WB - w0).norm(), 1e-14) << name;
    EXPECT_LT((w.angular_momentum_W(0) - L0).norm(), 1e-14) << name;
    const double per_step = 2.0 * std::atan(0.5 * h * w0.norm());
    const Quat expect(Eigen::AngleAxisd(500 * per_step, w0.normalized()));
    EXPECT_LT(angle_between(w.state(0).q_WB, expect), 1e-12) << name;
  }
}

}  // namespace
}  // namespace rigid::test
