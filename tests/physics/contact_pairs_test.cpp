// Bodies against bodies: the pair's gap and touching features, the first touch of two moving
// bodies, and the island solver's impulses, against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "physics/contact/island_solver.hpp"
#include "physics/contact/pair_gap.hpp"
#include "physics/contact/time_of_impact.hpp"

namespace rigid::physics::contact {
namespace {

Convex sphere(double r) {
  return Convex::of(Shape{ShapeKind::kSphere, Vec3(r, 0, 0)});
}
Convex box(const Vec3& size) {
  return Convex::of(Shape{ShapeKind::kBox, size});
}

TEST(ContactPairs, SpheresAreApartByTheirCentresLessTheirRadii) {
  const PairGap g = pair_gap(sphere(0.1), Pose{Vec3(1, 2, 3), Quat::Identity()}, sphere(0.2),
                             Pose{Vec3(1, 2, 2), Quat::Identity()});
  EXPECT_DOUBLE_EQ(g.distance, 0.7);
  EXPECT_EQ(g.n_W, Vec3(0, 0, 1));
  EXPECT_EQ(g.p_a_W, Vec3(1, 2, 2.9));
  EXPECT_EQ(g.p_b_W, Vec3(1, 2, 2.2));
}

TEST(ContactPairs, ABoxOnABoxTouchesOverTheirFacesOverlap) {
  // A 0.2 cube resting on a 1 x 1 x 0.2 slab, its centre 0.45 off the slab's in x: the four
  // corners of the overlap, the cube's face cut at the slab's edge x = 0.5.
  const Convex cube = box(Vec3(0.2, 0.2, 0.2)), slab = box(Vec3(1.0, 1.0, 0.2));
  const Pose pc{Vec3(0.45, 0.0, 0.2), Quat::Identity()}, ps{Vec3::Zero(), Quat::Identity()};
  const PairGap g = pair_gap(cube, pc, slab, ps);
  EXPECT_NEAR(g.distance, 0.0, 1e-15);
  EXPECT_NEAR(g.n_W.z(), 1.0, 1e-9);
  std::array<Vec3, kMaxFeature> pts;
  const int n = pair_manifold(cube, pc, slab, ps, g, 1e-9, pts);
  ASSERT_EQ(n, 4);
  double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
  for (int i = 0; i < n; ++i) {
    xmin = std::min(xmin, pts[i].x()), xmax = std::max(xmax, pts[i].x());
    ymin = std::min(ymin, pts[i].y()), ymax = std::max(ymax, pts[i].y());
    EXPECT_NEAR(pts[i].z(), 0.1, 1e-9);  // the normal of touching boxes: to ~1e-11
  }
  EXPECT_NEAR(xmin, 0.35, 1e-12);
  EXPECT_NEAR(xmax, 0.5, 1e-12);
  EXPECT_NEAR(ymin, -0.1, 1e-12);
  EXPECT_NEAR(ymax, 0.1, 1e-12);
}

TEST(ContactPairs, AnEdgeOnAFaceTouchesAlongTheEdge) {
  const Convex cube = box(Vec3(0.2, 0.2, 0.2)), slab = box(Vec3(1.0, 1.0, 0.2));
  // The cube turned 45 degrees about y: its lowest edge along y, at height 0.1 sqrt(2) below it.
  const Pose pc{Vec3(0.0, 0.0, 0.1 + 0.1 * std::sqrt(2.0)),
                Quat(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitY()))};
  const Pose ps{Vec3::Zero(), Quat::Identity()};
  const PairGap g = pair_gap(cube, pc, slab, ps);
  EXPECT_NEAR(g.distance, 0.0, 1e-15);
  std::array<Vec3, kMaxFeature> pts;
  const int n = pair_manifold(cube, pc, slab, ps, g, 1e-9, pts);
  ASSERT_EQ(n, 2);
  EXPECT_NEAR(std::abs(pts[0].y() - pts[1].y()), 0.2, 1e-12);
  EXPECT_NEAR(pts[0].x(), 0.0, 1e-12);
}

struct Linear : Trajectory {
  Vec3 p0, v;
  Vec3 a = Vec3::Zero();
  MotionSample at(double s) const override {
    MotionSample m;
    m.pose.p_WBo = p0 + s * v + 0.5 * s * s * a;
    m.v_W = v + s * a;
    return m;
  }
};

TEST(ContactPairs, TwoSpheresHeadOnTouchAtTheClosedFormTime) {
  Linear ta, tb;
  ta.p0 = Vec3(0, 0, 1), ta.v = Vec3(3, 0, 0);
  tb.p0 = Vec3(2, 0.05, 1), tb.v = Vec3(-1, 0, 0);
  for (Linear* t : {&ta, &tb}) {
    t->a = Vec3(0, 0, -9.81);  // both falling: the same relative motion
    t->a_max = 9.81;
    t->length = 1.0;
  }
  const PairTouch touch = first_touch_pair(sphere(0.1), ta, sphere(0.1), tb, 0.0);
  ASSERT_TRUE(touch.found);
  // |(2 - 4 s, 0.05)| = 0.2: s = (2 - sqrt(0.04 - 0.0025)) / 4.
  EXPECT_NEAR(touch.s, (2.0 - std::sqrt(0.0375)) / 4.0, 1e-15);
}

Response ball(double m, double r) {
  Response b;
  b.inv_m = Vec3::Constant(1.0 / m);
  b.inv_I_W = Mat3::Identity() / (0.4 * m * r * r);
  return b;
}

TEST(ContactPairs, EqualSpheresExchangeVelocitiesHeadOnAndLeaveAtRightAnglesObliquely) {
  // Head on, e = 1: the velocities swap. Obliquely (frictionless), equal masses with one at
  // rest leave at right angles, momentum and energy kept.
  for (const double offset : {0.0, 0.12}) {
    std::vector<IslandBody> bodies(2);
    bodies[0].resp = ball(1.0, 0.1);
    bodies[1].resp = ball(1.0, 0.1);
    bodies[0].v = Vec3(2.0, 0, 0);
    const Vec3 n = Vec3(-std::sqrt(0.04 - offset * offset), -offset, 0).normalized();  // b to a
    std::vector<IslandRow> rows(1);
    rows[0].a = 0, rows[0].b = 1;
    rows[0].n = n;
    rows[0].r_a = -0.1 * n, rows[0].r_b = 0.1 * n;
    const double un = n.dot(bodies[0].v - bodies[1].v);
    rows[0].target = -1.0 * un;
    const IslandResult r = solve_island(bodies, rows, 100, 1e-14);
    ASSERT_TRUE(r.converged);
    const Vec3 p = bodies[0].v + bodies[1].v;
    EXPECT_NEAR((p - Vec3(2, 0, 0)).norm(), 0.0, 1e-14);
    EXPECT_NEAR(bodies[0].v.squaredNorm() + bodies[1].v.squaredNorm(), 4.0, 1e-13);
    EXPECT_NEAR(bodies[0].v.dot(bodies[1].v), 0.0, 1e-13);
    if (offset == 0.0) {
      EXPECT_NEAR(bodies[0].v.norm(), 0.0, 1e-14);
      EXPECT_NEAR(bodies[1].v.x(), 2.0, 1e-14);
    }
  }
}

}  // namespace
}  // namespace rigid::physics::contact
