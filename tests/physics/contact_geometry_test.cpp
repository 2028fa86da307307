// The contact code's geometry and laws, against closed forms: support mappings, gaps, closest
// points, times of impact on known trajectories, and the impulses at one or several points.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "physics/contact/gap.hpp"
#include "physics/contact/gjk.hpp"
#include "physics/contact/point_solver.hpp"
#include "physics/contact/reach.hpp"
#include "physics/contact/support.hpp"
#include "physics/contact/time_of_impact.hpp"
#include "physics/contact/wake_schedule.hpp"

namespace rigid::physics::contact {
namespace {

Convex shape(ShapeKind kind, const Vec3& size) {
  return Convex::of(Shape{kind, size});
}

StaticPart ground(double offset = 0.0, const Vec3& n = Vec3::UnitZ()) {
  StaticPart p;
  p.kind = StaticPart::Kind::kPlane;
  p.n_W = n.normalized();
  p.offset = offset;
  return p;
}

// Points on each shape's surface, to hold the support mapping to: h(u) is their largest u . x,
// and the support point is one of them (dense sampling of the parametrised surfaces).
std::vector<Vec3> surface_samples(const Convex& c) {
  std::vector<Vec3> out;
  for (int k = 0; c.kind == Convex::Kind::kBox && k < 8; ++k)  // corners: missed below
    out.push_back(c.half.cwiseProduct(Vec3(k & 1 ? -1 : 1, k & 2 ? -1 : 1, k & 4 ? -1 : 1)));
  const int n = 64;
  for (int i = 0; i <= n; ++i) {
    const double th = M_PI * i / n;
    for (int j = 0; j < 2 * n; ++j) {
      const double ph = M_PI * j / n;
      const Vec3 s(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
      switch (c.kind) {
        case Convex::Kind::kPoint:
          out.push_back(Vec3::Zero());
          break;
        case Convex::Kind::kSphere:
          out.push_back(c.radius * s);
          break;
        case Convex::Kind::kEllipsoid:
          out.push_back(c.half.cwiseProduct(s));
          break;
        case Convex::Kind::kCapsule:
          out.push_back(c.radius * s + Vec3(0, 0, s.z() >= 0 ? c.half.z() : -c.half.z()));
          break;
        case Convex::Kind::kBox:
          out.push_back(c.half.cwiseProduct(s / s.cwiseAbs().maxCoeff()));
          break;
        case Convex::Kind::kCylinder:
          out.push_back(Vec3(c.half.x() * std::cos(ph), c.half.x() * std::sin(ph),
                             c.half.z() * std::cos(th)));
          break;
      }
    }
  }
  return out;
}

TEST(ContactSupport, HeightIsTheLargestProjectionOfTheSurfaceForEveryShape) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  const std::vector<Convex> shapes = {shape(ShapeKind::kBox, Vec3(0.2, 0.4, 0.6)),
                                      shape(ShapeKind::kSphere, Vec3(0.3, 0, 0)),
                                      shape(ShapeKind::kCapsule, Vec3(0.1, 0, 0.5)),
                                      shape(ShapeKind::kCylinder, Vec3(0.2, 0, 0.3)),
                                      shape(ShapeKind::kEllipsoid, Vec3(0.1, 0.2, 0.3)),
                                      Convex{}};
  for (const Convex& c : shapes) {
    const auto samples = surface_samples(c);
    for (int k = 0; k < 50; ++k) {
      const Vec3 u = Vec3(g(rng), g(rng), g(rng)).normalized();
      double best = -INFINITY;
      for (const Vec3& x : samples)
        best = std::max(best, u.dot(x));
      const double h = c.height(u);
      // Never below a surface point; above the sampled maximum by no more than the sampling.
      EXPECT_GE(h, best - 1e-12) << static_cast<int>(c.kind);
      EXPECT_LE(h, best + 2e-3) << static_cast<int>(c.kind);
      const Vec3 s = c.core_support(u) + c.radius * u;
      EXPECT_NEAR(u.dot(s), h, 1e-14) << static_cast<int>(c.kind);
    }
  }
}

TEST(ContactGap, PlaneGapOfATiltedBoxIsItsLowestCorner) {
  const Convex box = shape(ShapeKind::kBox, Vec3(0.2, 0.3, 0.4));
  const Pose pose{Vec3(0.1, -0.2, 1.0), Quat(Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()))};
  const StaticPart plane = ground(0.25, Vec3(0.1, 0.2, 1.0));
  double lowest = INFINITY;
  for (int k = 0; k < 8; ++k) {
    const Vec3 c((k & 1 ? -0.1 : 0.1), (k & 2 ? -0.15 : 0.15), (k & 4 ? -0.2 : 0.2));
    lowest = std::min(lowest, plane.n_W.dot(pose.p_WBo + pose.q_WB * c) - plane.offset);
  }
  const Gap g = plane_gap(box, pose, plane);
  EXPECT_NEAR(g.distance, lowest, 1e-15);
  EXPECT_NEAR(plane.n_W.dot(g.p_W) - plane.offset, lowest, 1e-15);
}

TEST(ContactGap, SphereToStaticBoxIsTheClampedPointsDistance) {
  StaticPart box;
  box.kind = StaticPart::Kind::kShape;
  box.convex = shape(ShapeKind::kBox, Vec3(2.0, 1.0, 0.5));
  box.p_WS = Vec3(0.5, 0.0, -1.0);
  const Convex ball = shape(ShapeKind::kSphere, Vec3(0.1, 0, 0));
  for (const Vec3& c : {Vec3(0.5, 0.0, 0.0), Vec3(2.0, 1.0, 0.0), Vec3(-1.0, -0.8, -1.2)}) {
    const Vec3 local = c - box.p_WS;
    const Vec3 clamped = local.cwiseMax(-box.convex.half).cwiseMin(box.convex.half);
    const double expect = (local - clamped).norm() - 0.1;
    const Gap g = shape_gap(ball, Pose{c, Quat::Identity()}, box);
    EXPECT_NEAR(g.distance, expect, 1e-13) << c.transpose();
    EXPECT_NEAR(g.n_W.dot((local - clamped).normalized()), 1.0, 1e-12);
  }
}

TEST(ContactGap, BoxesFaceToFaceAreApartByTheirGapWithTheFaceNormal) {
  StaticPart slab;
  slab.kind = StaticPart::Kind::kShape;
  slab.convex = shape(ShapeKind::kBox, Vec3(4.0, 4.0, 0.01));
  slab.p_WS = Vec3(0.0, 0.0, -0.005);
  const Convex box = shape(ShapeKind::kBox, Vec3(0.2, 0.2, 0.2));
  for (const double gap : {0.5, 1e-6, 1e-12, 0.0}) {
    const Gap g = shape_gap(box, Pose{Vec3(0.3, -0.2, 0.1 + gap), Quat::Identity()}, slab);
    EXPECT_NEAR(g.distance, gap, 1e-15) << gap;
    EXPECT_NEAR(g.n_W.z(), 1.0, 1e-9) << gap;
  }
}

// A body falling from rest at height z0 (gap z0 - r) with gravity g: touches after
// sqrt(2 (z0 - r) / g), exactly.
struct Ballistic : Trajectory {
  Pose start;
  Vec3 v0 = Vec3::Zero(), a = Vec3(0, 0, -9.81), w = Vec3::Zero();
  MotionSample at(double s) const override {
    MotionSample m;
    m.pose.p_WBo = start.p_WBo + s * v0 + 0.5 * s * s * a;
    m.pose.q_WB = (start.q_WB * Quat(Eigen::AngleAxisd(
                                    s * w.norm(), w.norm() > 0 ? w.normalized() : Vec3::UnitZ())))
                      .normalized();
    m.v_W = v0 + s * a;
    m.w_W = m.pose.q_WB * w;  // w given in B: a spin about a fixed body axis (isotropic body)
    return m;
  }
};

TEST(ContactTimeOfImpact, AFallingSphereTouchesAtTheClosedFormTime) {
  const Convex ball = shape(ShapeKind::kSphere, Vec3(0.1, 0, 0));
  Ballistic t;
  t.start.p_WBo = Vec3(0, 0, 1.0);
  t.length = 1.0;
  t.a_max = 9.81;
  const Touch touch = first_touch(ball, ground(), t, 0.0);
  ASSERT_TRUE(touch.found);
  EXPECT_NEAR(touch.s, std::sqrt(2 * 0.9 / 9.81), 1e-15);
  EXPECT_GE(touch.gap.distance, 0.0);
  EXPECT_LE(touch.gap.distance, 1e-14);
  EXPECT_LE(touch.iterations, 12);
}

TEST(ContactTimeOfImpact, NoTouchWhenTheTrajectoryEndsAbove) {
  const Convex ball = shape(ShapeKind::kSphere, Vec3(0.1, 0, 0));
  Ballistic t;
  t.start.p_WBo = Vec3(0, 0, 1.0);
  t.length = 0.4;  // falls 0.78 m: 0.12 m short of touching
  t.a_max = 9.81;
  EXPECT_FALSE(first_touch(ball, ground(), t, 0.0).found);
}

TEST(ContactTimeOfImpact, ABounceLeavesAndIsFoundAgainOnItsReturn) {
  // Touching and moving up at 2 m/s: back after 2 v / g.
  const Convex ball = shape(ShapeKind::kSphere, Vec3(0.1, 0, 0));
  Ballistic t;
  t.start.p_WBo = Vec3(0, 0, 0.1);
  t.v0 = Vec3(0.3, 0, 2.0);
  t.length = 1.0;
  t.a_max = 9.81;
  const Touch touch = first_touch(ball, ground(), t, 0.0);
  ASSERT_TRUE(touch.found);
  EXPECT_NEAR(touch.s, 4.0 / 9.81, 1e-15);
}

TEST(ContactTimeOfImpact, ASpinningBoxTouchesAtItsLowestCornersFirstRoot) {
  const Convex box = shape(ShapeKind::kBox, Vec3(0.4, 0.2, 0.3));
  Ballistic t;
  t.start.p_WBo = Vec3(0, 0, 0.6);
  t.start.q_WB = Quat(Eigen::AngleAxisd(0.4, Vec3(1, 1, 0).normalized()));
  t.v0 = Vec3(0.5, 0, -1.0);
  t.w = Vec3(7.0, 0.0, 0.0);
  t.length = 0.5;
  t.a_max = 9.81;
  t.w_max = 7.0;
  const Touch touch = first_touch(box, ground(), t, 0.0);
  ASSERT_TRUE(touch.found);
  // Brute force: the first sign change of the exact gap on a fine grid, then bisection.
  const auto gap_at = [&](double s) { return plane_gap(box, t.at(s).pose, ground()).distance; };
  double lo = 0.0, hi = -1.0;
  for (int k = 1; k <= 200000; ++k) {
    const double s = t.length * k / 200000;
    if (gap_at(s) <= 0.0) {
      hi = s;
      break;
    }
    lo = s;
  }
  ASSERT_GT(hi, 0.0);
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (gap_at(mid) > 0.0 ? lo : hi) = mid;
  }
  EXPECT_NEAR(touch.s, lo, 1e-14);
  EXPECT_GE(touch.gap.distance, 0.0);
  EXPECT_LE(touch.gap.distance, 1e-13);
}

TEST(ContactTimeOfImpact, AFastSphereDoesNotTunnelThroughAThinPlate) {
  StaticPart plate;
  plate.kind = StaticPart::Kind::kShape;
  plate.convex = shape(ShapeKind::kBox, Vec3(1.0, 1.0, 0.01));
  plate.p_WS = Vec3(0, 0, 0);
  const Convex ball = shape(ShapeKind::kSphere, Vec3(0.01, 0, 0));
  Ballistic t;
  t.start.p_WBo = Vec3(0, 0, 0.5);
  t.v0 = Vec3(0, 0, -1000.0);
  t.a = Vec3::Zero();
  t.length = 1e-3;  // one step: 1 m, past the plate
  const Touch touch = first_touch(ball, plate, t, 0.0);
  ASSERT_TRUE(touch.found);
  EXPECT_NEAR(touch.s, (0.5 - 0.005 - 0.01) / 1000.0, 1e-15);
  EXPECT_GE(touch.gap.distance, -1e-12);
}

Response sphere_response(double m, double r) {
  Response b;
  b.inv_m = Vec3::Constant(1.0 / m);
  b.inv_I_W = Mat3::Identity() / (0.4 * m * r * r);
  return b;
}

TEST(ContactPointSolver, AVerticalImpactReversesTheNormalSpeedTimesRestitution) {
  PointRow row;
  row.r_W = Vec3(0, 0, -0.1);
  row.u_W = Vec3(0, 0, -3.0);
  row.target = 0.5 * 3.0;
  row.mu = 0.4;
  const PointSolution s = solve_points(sphere_response(2.0, 0.1), &row, 1);
  ASSERT_TRUE(s.converged);
  EXPECT_NEAR(s.dv.z(), 4.5, 1e-14);
  EXPECT_NEAR(s.dw.norm(), 0.0, 1e-14);
}

TEST(ContactPointSolver, AnObliqueImpactOfASphereSlidesOrSticksAsTheClosedFormSays) {
  // Ball of radius r, no spin, hitting at normal speed vn with tangential speed vt. The contact
  // point's tangential velocity changes by (1 + m r^2 / I) = 7/2 times the friction impulse / m:
  // it sticks when vt <= 7/2 mu (1 + e) vn, and slides (friction mu times the normal impulse)
  // otherwise.
  const double m = 1.5, r = 0.1, e = 0.5, vn = 2.0;
  for (const double mu : {0.05, 0.4}) {
    const double vt = 1.0;
    PointRow row;
    row.r_W = Vec3(0, 0, -r);
    row.u_W = Vec3(vt, 0, -vn);
    row.target = e * vn;
    row.mu = mu;
    const PointSolution s = solve_points(sphere_response(m, r), &row, 1);
    ASSERT_TRUE(s.converged);
    const double Pn = m * (1 + e) * vn;
    const bool sticks = vt <= 3.5 * mu * (1 + e) * vn;
    const double Pt = sticks ? m * vt / 3.5 : mu * Pn;
    EXPECT_NEAR(s.P[0].z(), Pn, 1e-13) << mu;
    EXPECT_NEAR(-s.P[0].x(), Pt, 1e-13) << mu;
    const Vec3 u = row.u_W + s.dv + s.dw.cross(row.r_W);
    if (sticks) {
      EXPECT_NEAR(u.x(), 0.0, 1e-13);
    }
  }
}

TEST(ContactPointSolver, ABoxLandingFlatOnFourCornersGetsNoSpin) {
  const double m = 2.0, a = 0.1;  // cube of half size a
  Response b;
  b.inv_m = Vec3::Constant(1.0 / m);
  b.inv_I_W = Mat3::Identity() / (m * (2 * a) * (2 * a) / 6.0);
  PointRow rows[4];
  for (int k = 0; k < 4; ++k) {
    rows[k].r_W = Vec3(k & 1 ? a : -a, k & 2 ? a : -a, -a);
    rows[k].u_W = Vec3(0.3, -0.1, -1.0);  // sliding while it lands
    rows[k].target = 0.25;
    rows[k].mu = 0.5;
  }
  const PointSolution s = solve_points(b, rows, 4);
  ASSERT_TRUE(s.converged);
  EXPECT_NEAR(s.dv.z(), 1.25, 1e-13);
  EXPECT_LE(s.dw.norm(), 1e-12);
}

TEST(ContactReach, NoTouchBeforeTheTimeToReach) {
  // A body falling from rest onto a plane: D = h, v = 0, a = g: t = sqrt(2 h / g) exactly.
  EXPECT_NEAR(time_to_reach(0.9, 0.0, 9.81), std::sqrt(2 * 0.9 / 9.81), 1e-15);
  EXPECT_NEAR(time_to_reach(2.0, 4.0, 0.0), 0.5, 1e-15);
  EXPECT_EQ(time_to_reach(0.0, 1.0, 1.0), 0.0);
  EXPECT_TRUE(std::isinf(time_to_reach(1.0, 0.0, 0.0)));
  // Clearance: the nearest part less the bounding radius.
  StaticPart ball;
  ball.kind = StaticPart::Kind::kShape;
  ball.convex = shape(ShapeKind::kSphere, Vec3(0.5, 0, 0));
  ball.p_WS = Vec3(3, 0, 5);
  const std::vector<StaticPart> parts = {ground(0.0), ball};
  EXPECT_NEAR(clearance(parts, Vec3(0, 0, 4), 0.2), std::sqrt(10.0) - 0.7, 1e-15);
  EXPECT_NEAR(clearance(parts, Vec3(3, 0, 6.5), 0.2), 0.8, 1e-15);
}

TEST(ContactWakeSchedule, BodiesComeDueInOrderOnceAndReschedulingReplaces) {
  WakeSchedule w;
  w.reset(4);
  w.at(2, 10);
  w.at(0, 5);
  w.at(1, 5);
  w.at(3, 7);
  w.at(3, 20);  // replaces 7
  std::vector<int> due;
  w.take_due(9, [&](int id) { due.push_back(id); });
  EXPECT_EQ(due, (std::vector<int>{0, 1}));
  due.clear();
  w.take_due(9, [&](int id) { due.push_back(id); });
  EXPECT_TRUE(due.empty());
  EXPECT_EQ(w.when(0), WakeSchedule::kNever);
  w.take_due(100, [&](int id) { due.push_back(id); });
  EXPECT_EQ(due, (std::vector<int>{2, 3}));
  // Many reschedules of one body stay within the reserved capacity (compaction) and keep the last.
  for (int k = 0; k < 1000; ++k)
    w.at(1, 1000 - k);
  due.clear();
  w.take_due(0, [&](int id) { due.push_back(id); });
  EXPECT_TRUE(due.empty());
  w.take_due(1, [&](int id) { due.push_back(id); });
  EXPECT_EQ(due, (std::vector<int>{1}));
}

}  // namespace
}  // namespace rigid::physics::contact
