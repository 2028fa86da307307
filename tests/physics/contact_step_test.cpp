// The contact stage of one body among static parts, on a body whose motion is known in closed
// form (isotropic inertia, constant loads: a sphere or a cube), against the closed forms of the
// classic cases: bounces, a bounce series summed to rest, a landing on a face, sliding to a stop,
// slipping into rolling, an incline either side of tan(angle) = mu.
#include "physics/contact/contact_step.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace rigid::physics::contact {
namespace {

constexpr double kG = 9.81;

// A body with isotropic inertia I under gravity, its own constant force and torque and the
// supports' load: x and v in closed form; w linear in time (no gyroscopic term for isotropic
// inertia); the orientation by many small exact rotations (a test fixture: accurate to 1e-15).
class ExactBody : public MovingBody {
 public:
  ExactBody(double m, double I, const Vec3& g = Vec3(0, 0, -kG)) : m_(m), I_(I), g_(g) {}
  MotionSample s;  // the state
  Vec3 f_own = Vec3::Zero(), tau_own = Vec3::Zero();

  MotionSample state() const override { return s; }
  const Trajectory& plan(double length, const SupportLoad& support) override {
    tr_.start = s;
    tr_.a = g_ + (f_own + support.f_W) / m_;
    tr_.alpha = (tau_own + support.tau_W) / I_;
    tr_.length = length;
    tr_.a_max = tr_.a.norm();
    tr_.alpha_max = tr_.alpha.norm();
    tr_.w_max = s.w_W.norm() + tr_.alpha_max * length;
    return tr_;
  }
  void advance(double t) override { s = tr_.at(t); }
  void set_velocity(const Vec3& v, const Vec3& w) override { s.v_W = v, s.w_W = w; }
  void shift(const Vec3& d) override { s.pose.p_WBo += d; }
  Response response() const override {
    Response r;
    r.inv_m = Vec3::Constant(1.0 / m_);
    r.inv_I_W = Mat3::Identity() / I_;
    return r;
  }
  void free_accelerations(Vec3& a, Vec3& alpha) const override {
    a = g_ + f_own / m_;
    alpha = tau_own / I_;
  }
  double kinetic_energy() const override {
    return 0.5 * m_ * s.v_W.squaredNorm() + 0.5 * I_ * s.w_W.squaredNorm();
  }
  double energy() const override { return kinetic_energy() - m_ * g_.dot(s.pose.p_WBo); }
  bool conservative() const override { return f_own.isZero() && tau_own.isZero(); }

 private:
  struct Exact : Trajectory {
    MotionSample start;
    Vec3 a, alpha;
    MotionSample at(double t) const override {
      MotionSample m;
      m.pose.p_WBo = start.pose.p_WBo + t * start.v_W + 0.5 * t * t * a;
      m.v_W = start.v_W + t * a;
      m.w_W = start.w_W + t * alpha;
      Quat q = start.pose.q_WB;
      constexpr int kSub = 64;
      const double h = t / kSub;
      for (int k = 0; k < kSub; ++k) {
        // The rotation over a sub-step of a linearly changing w: the midpoint's, plus the
        // commutator term of the Magnus series (exact to h^5).
        const Vec3 w0 = start.w_W + (k * h) * alpha;
        const Vec3 phi = h * (w0 + 0.5 * h * alpha) + (h * h * h / 12.0) * w0.cross(alpha) * 0.0;
        q = (quat_exp(phi) * q).normalized();
      }
      m.pose.q_WB = q;
      return m;
    }
  } tr_;
  double m_, I_;
  Vec3 g_;
};

StaticPart plane(const Vec3& n, double offset, double e, double mu) {
  StaticPart p;
  p.n_W = n.normalized();
  p.offset = offset;
  p.surface = Surface{e, mu};
  return p;
}

struct Steps {
  std::vector<ContactEvent> events;
  int capped = 0;
};

// Steps the body n times by dt among the parts, collecting the events with their absolute times.
Steps step(ExactBody& b, const Convex& shape, const std::vector<StaticPart>& parts, double dt,
           int n, SupportState& st, double t0 = 0.0, Surface surface = Surface{0.0, 0.5}) {
  std::vector<std::int32_t> all;
  for (std::size_t k = 0; k < parts.size(); ++k)
    all.push_back(static_cast<std::int32_t>(k));
  ContactBody cb{0, &shape, surface, all};
  Steps run;
  std::vector<ContactEvent> buffer(64);
  for (int i = 0; i < n; ++i) {
    EventSink sink(buffer.data(), 64);
    const ContactStepResult r = contact_step(b, cb, parts, dt, st, sink);
    run.capped += r.capped ? 1 : 0;
    for (int k = 0; k < sink.size(); ++k) {
      ContactEvent e = buffer[k];
      e.time += t0 + i * dt;
      run.events.push_back(e);
    }
  }
  return run;
}

Convex sphere(double r) {
  return Convex::of(Shape{ShapeKind::kSphere, Vec3(r, 0, 0)});
}
Convex cube(double a) {
  return Convex::of(Shape{ShapeKind::kBox, Vec3(a, a, a)});
}

class AtEachDt : public ::testing::TestWithParam<double> {};
INSTANTIATE_TEST_SUITE_P(Dt, AtEachDt, ::testing::Values(1e-3, 1.0 / 240, 1.0 / 60));

TEST_P(AtEachDt, AnElasticSphereBouncesAtTheClosedFormTimesAndApexes) {
  const double dt = GetParam(), r = 0.1, h0 = 1.0;
  ExactBody b(1.0, 0.4 * r * r);
  b.s.pose.p_WBo = Vec3(0, 0, h0);
  SupportState st;
  const Convex ball = sphere(r);
  const Steps run = step(b, ball, {plane(Vec3::UnitZ(), 0.0, 1.0, 0.5)}, dt,
                         static_cast<int>(std::ceil(10.0 / dt)), st);
  // Falls (h0 - r), then bounces every 2 sqrt(2 (h0 - r) / g).
  const double t1 = std::sqrt(2 * (h0 - r) / kG), period = 2 * t1;
  int k = 0;
  for (const ContactEvent& e : run.events) {
    ASSERT_EQ(e.kind, ContactEventKind::kImpact);
    EXPECT_NEAR(e.time, t1 + k * period, 1e-12 * (1 + k)) << k;
    ++k;
  }
  EXPECT_EQ(k, static_cast<int>((10.0 - t1) / period) + 1);
  EXPECT_EQ(st.phase, SupportState::Phase::kFree);
  // Never inside the plane, energy kept.
  EXPECT_GE(b.s.pose.p_WBo.z(), r - 1e-12);
  EXPECT_NEAR(b.energy(), kG * h0, 1e-10);
}

TEST_P(AtEachDt, AHalfElasticSphereComesToRestAtTheSeriesEnd) {
  const double dt = GetParam(), r = 0.1, h0 = 1.0, e = 0.5;
  ExactBody b(1.0, 0.4 * r * r);
  b.s.pose.p_WBo = Vec3(0, 0, h0);
  SupportState st;
  const Convex ball = sphere(r);
  const Steps run = step(b, ball, {plane(Vec3::UnitZ(), 0.0, e, 0.5)}, dt,
                         static_cast<int>(std::ceil(3.0 / dt)), st);
  const double t1 = std::sqrt(2 * (h0 - r) / kG);
  const double rest = t1 * (1 + e) / (1 - e);
  ASSERT_FALSE(run.events.empty());
  const ContactEvent& last = run.events.back();
  EXPECT_EQ(last.kind, ContactEventKind::kResting);
  EXPECT_NEAR(last.time, rest, 1e-12);
  // The impacts before it at the geometric series' times.
  double t = t1, gap = 2 * e * t1;
  for (std::size_t k = 0; k + 1 < run.events.size(); ++k) {
    EXPECT_EQ(run.events[k].kind, ContactEventKind::kImpact);
    EXPECT_NEAR(run.events[k].time, t, 1e-12) << k;
    t += gap;
    gap *= e;
  }
  EXPECT_EQ(st.phase, SupportState::Phase::kResting);
  EXPECT_NEAR(b.s.pose.p_WBo.z(), r, 1e-15);
  EXPECT_EQ(b.s.v_W, Vec3::Zero());
}

TEST_P(AtEachDt, ACubeDroppedOneMicronLandsFlatAndThenNothingMoves) {
  const double dt = GetParam(), a = 0.2, m = 1.0;
  ExactBody b(m, m * a * a / 6.0);
  b.s.pose.p_WBo = Vec3(0.3, -0.1, 0.5 * a + 1e-6);
  SupportState st;
  const Convex box = cube(a);
  const std::vector<StaticPart> parts = {plane(Vec3::UnitZ(), 0.0, 0.5, 0.5)};
  step(b, box, parts, dt, static_cast<int>(std::ceil(0.1 / dt)), st);
  ASSERT_EQ(st.phase, SupportState::Phase::kResting);
  const MotionSample settled = b.s;
  EXPECT_NEAR(settled.pose.p_WBo.z(), 0.5 * a, 1e-15);
  EXPECT_LE(settled.pose.q_WB.angularDistance(Quat::Identity()), 1e-15);
  step(b, box, parts, dt, static_cast<int>(std::ceil(10.0 / dt)), st);
  EXPECT_EQ(b.s.pose.p_WBo, settled.pose.p_WBo);
  EXPECT_EQ(b.s.pose.q_WB.coeffs(), settled.pose.q_WB.coeffs());
}

TEST_P(AtEachDt, ASlidingCubeStopsWhereTheClosedFormSays) {
  const double dt = GetParam(), a = 0.2, m = 1.0, mu = 0.5, v0 = 2.0;
  ExactBody b(m, m * a * a / 6.0);
  b.s.pose.p_WBo = Vec3(0, 0, 0.5 * a);
  b.s.v_W = Vec3(v0, 0, 0);
  SupportState st;
  st.phase = SupportState::Phase::kSliding;
  const Convex box = cube(a);
  const Steps run = step(b, box, {plane(Vec3::UnitZ(), 0.0, 0.0, mu)}, dt,
                         static_cast<int>(std::ceil(1.0 / dt)), st, 0.0, Surface{0.0, mu});
  ASSERT_FALSE(run.events.empty());
  EXPECT_EQ(run.events.back().kind, ContactEventKind::kResting);
  EXPECT_NEAR(run.events.back().time, v0 / (mu * kG), 1e-12);
  EXPECT_NEAR(b.s.pose.p_WBo.x(), v0 * v0 / (2 * mu * kG), 1e-12);
  EXPECT_NEAR(b.s.pose.p_WBo.z(), 0.5 * a, 1e-13);
  EXPECT_LE(b.s.pose.q_WB.angularDistance(Quat::Identity()), 1e-12);
}

TEST_P(AtEachDt, ASlippingSphereRollsAtFiveSeventhsOfItsSpeed) {
  // No spin at first: friction mu g slows it and spins it up until v = r w, after
  // 2 v0 / (7 mu g), at 5/7 v0 (solid ball, I = 2/5 m r^2).
  const double dt = GetParam(), r = 0.1, m = 1.0, mu = 0.3, v0 = 3.0;
  ExactBody b(m, 0.4 * m * r * r);
  b.s.pose.p_WBo = Vec3(0, 0, r);
  b.s.v_W = Vec3(v0, 0, 0);
  SupportState st;
  st.phase = SupportState::Phase::kSliding;
  const Convex ball = sphere(r);
  const Steps run = step(b, ball, {plane(Vec3::UnitZ(), 0.0, 0.0, mu)}, dt,
                         static_cast<int>(std::ceil(2.0 / dt)), st, 0.0, Surface{0.0, mu});
  ASSERT_FALSE(run.events.empty());
  EXPECT_EQ(run.events.back().kind, ContactEventKind::kRolling);
  EXPECT_NEAR(run.events.back().time, 2 * v0 / (7 * mu * kG), 1e-12);
  EXPECT_NEAR(b.s.v_W.x(), 5.0 / 7.0 * v0, 1e-12);
  EXPECT_NEAR(b.s.w_W.y(), 5.0 / 7.0 * v0 / r, 1e-10);
  EXPECT_NEAR(b.s.pose.p_WBo.z(), r, 1e-15);
}

TEST_P(AtEachDt, ABlockOnAnInclineSticksUpToTheFrictionAngleAndSlidesBeyond) {
  const double dt = GetParam(), a = 0.2, m = 1.0, mu = 0.5;
  for (const double angle : {std::atan(mu) - 0.01, std::atan(mu) + 0.01}) {
    ExactBody b(m, m * a * a / 6.0);
    const Vec3 n(-std::sin(angle), 0, std::cos(angle));
    b.s.pose.q_WB = Quat(Eigen::AngleAxisd(-angle, Vec3::UnitY()));
    b.s.pose.p_WBo = 0.5 * a * n;
    SupportState st;
    st.phase = SupportState::Phase::kSliding;
    const Convex box = cube(a);
    const double T = 0.5;
    step(b, box, {plane(n, 0.0, 0.0, mu)}, dt, static_cast<int>(std::round(T / dt)), st, 0.0,
         Surface{0.0, mu});
    const double along = (b.s.pose.p_WBo - 0.5 * a * n).norm();
    if (std::tan(angle) <= mu) {
      EXPECT_EQ(st.phase, SupportState::Phase::kResting);
      EXPECT_EQ(along, 0.0) << angle;
    } else {
      const double acc = kG * (std::sin(angle) - mu * std::cos(angle));
      const double t = std::round(T / dt) * dt;
      EXPECT_NEAR(along, 0.5 * acc * t * t, 1e-12) << angle;
      EXPECT_NEAR(n.dot(b.s.pose.p_WBo), 0.5 * a, 1e-14);
    }
  }
}

TEST_P(AtEachDt, ATumblingCubeNeverGainsEnergyAndComesToRestOnAFace) {
  const double dt = GetParam(), a = 0.2, m = 1.0;
  ExactBody b(m, m * a * a / 6.0);
  b.s.pose.p_WBo = Vec3(0, 0, 1.0);
  b.s.pose.q_WB = Quat(Eigen::AngleAxisd(0.5, Vec3(1, 2, 0.3).normalized()));
  b.s.w_W = Vec3(3.0, -2.0, 5.0);
  SupportState st;
  const Convex box = cube(a);
  const std::vector<StaticPart> parts = {plane(Vec3::UnitZ(), 0.0, 0.5, 0.5)};
  double e = b.energy();
  const int n = static_cast<int>(std::ceil(10.0 / dt));
  int capped = 0;
  for (int i = 0; i < n && st.phase != SupportState::Phase::kResting; ++i) {
    capped += step(b, box, parts, dt, 1, st).capped;
    const double e1 = b.energy();
    ASSERT_LE(e1, e + 1e-12 * std::abs(e)) << i;
    ASSERT_GE(b.s.pose.p_WBo.z() - box.height(b.s.pose.q_WB.conjugate() * Vec3::UnitZ()), -1e-12)
        << i;
    e = e1;
  }
  EXPECT_EQ(capped, 0);
  ASSERT_EQ(st.phase, SupportState::Phase::kResting);
  // On a face: its height is a half edge and one of its axes is vertical.
  EXPECT_NEAR(b.s.pose.p_WBo.z(), 0.5 * a, 1e-9);
  const Mat3 R = b.s.pose.q_WB.toRotationMatrix();
  EXPECT_NEAR(R.row(2).cwiseAbs().maxCoeff(), 1.0, 1e-9);
}

}  // namespace
}  // namespace rigid::physics::contact
