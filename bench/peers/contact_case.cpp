#include "contact_case.hpp"

#include <algorithm>
#include <cmath>

namespace rigid::bench::peers {

namespace {

ContactCase sphere(std::string name, ContactKind kind, double e, double duration) {
  ContactCase c;
  c.name = std::move(name);
  c.kind = kind;
  c.shape = ContactShape::kSphere;
  c.size = 0.1;
  c.restitution = e;
  c.friction = 0.5;
  c.start.p_WBo = Vec3(0, 0, 1);
  c.duration = duration;
  return c;
}

ContactCase cube(std::string name, ContactKind kind, double e, double duration) {
  ContactCase c;
  c.name = std::move(name);
  c.kind = kind;
  c.shape = ContactShape::kCube;
  c.size = 0.2;
  c.restitution = e;
  c.friction = 0.5;
  c.duration = duration;
  return c;
}

}  // namespace

std::vector<ContactCase> contact_cases() {
  std::vector<ContactCase> cases;
  // 10.5 s rather than 10: the apex after the 12th impact (at 9.85 s) comes at 10.28 s.
  ContactCase elastic = sphere("elastic_sphere", ContactKind::kElastic, 1.0, 10.5);
  elastic.description =
      "sphere r 0.1 m, m 1 kg, e 1, mu 0.5, dropped from rest with its centre at 1 m, 10.5 s";
  cases.push_back(elastic);

  ContactCase bouncing = sphere("bouncing_sphere", ContactKind::kBouncing, 0.5, 3.0);
  bouncing.description =
      "sphere r 0.1 m, m 1 kg, e 0.5, mu 0.5, dropped from rest with its centre at 1 m, 3 s";
  cases.push_back(bouncing);

  ContactCase resting = cube("resting_cube", ContactKind::kResting, 0.0, 10.0);
  resting.start.p_WBo = Vec3(0, 0, 0.1 + 1e-6);
  resting.description =
      "cube 0.2 m, m 1 kg, e 0, mu 0.5, put down flat 1 um above the plane, at rest, 10 s";
  cases.push_back(resting);

  ContactCase sliding = cube("sliding_cube", ContactKind::kSliding, 0.0, 2.0);
  sliding.start.p_WBo = Vec3(0, 0, 0.1);
  sliding.start.v_WBo = Vec3(2, 0, 0);
  sliding.description =
      "cube 0.2 m, m 1 kg, e 0, mu 0.5, flat on the plane, sliding at 2 m/s along x, 2 s";
  cases.push_back(sliding);

  ContactCase tumbling = cube("tumbling_cube", ContactKind::kTumbling, 0.5, 5.0);
  tumbling.start.p_WBo = Vec3(0, 0, 1);
  tumbling.start.q_WB = Quat(Eigen::AngleAxisd(0.4, Vec3(1, 1, 0).normalized()));
  tumbling.start.w_WB = Vec3(2, -1, 3);
  tumbling.description =
      "cube 0.2 m, m 1 kg, e 0.5, mu 0.5, centre at 1 m, tilted 0.4 rad about (1, 1, 0), "
      "w (2, -1, 3) rad/s, 5 s";
  cases.push_back(tumbling);
  return cases;
}

ContactCase without_plane(const ContactCase& c) {
  ContactCase f = c;
  f.plane = false;
  return f;
}

physics::Shape shape_of(const ContactCase& c) {
  physics::Shape s;
  if (c.shape == ContactShape::kSphere) {
    s.kind = physics::ShapeKind::kSphere;
    s.size = Vec3(c.size, c.size, c.size);
  } else {
    s.kind = physics::ShapeKind::kBox;
    s.size = Vec3::Constant(c.size);
  }
  return s;
}

Vec3 principal_moments(const ContactCase& c) {
  return physics::shape_inertia(shape_of(c), c.mass).diagonal();
}

double rest_height(const ContactCase& c) {
  return c.shape == ContactShape::kSphere ? c.size : 0.5 * c.size;
}

double bounding_radius(const ContactCase& c) {
  return c.shape == ContactShape::kSphere ? c.size : 0.5 * std::sqrt(3.0) * c.size;
}

std::vector<Vec3> corners(const ContactCase& c, const BodyState& s) {
  std::vector<Vec3> out;
  const double h = 0.5 * c.size;
  for (int i = 0; i < 8; ++i) {
    const Vec3 p_B((i & 1) ? h : -h, (i & 2) ? h : -h, (i & 4) ? h : -h);
    out.push_back(s.p_WBo + s.q_WB * p_B);
  }
  return out;
}

double lowest_point(const ContactCase& c, const BodyState& s) {
  if (c.shape == ContactShape::kSphere) return s.p_WBo.z() - c.size;
  // The lowest corner: the centre minus the half-edges' projections on z.
  const physics::Mat3 R = s.q_WB.toRotationMatrix();
  const double h = 0.5 * c.size;
  return s.p_WBo.z() - h * R.row(2).cwiseAbs().sum();
}

double energy(const ContactCase& c, const BodyState& s) {
  const Vec3 I = principal_moments(c);  // isotropic for both shapes, so any frame will do
  const Vec3 w_B = s.q_WB.conjugate() * s.w_WB;
  return c.mass * c.g * (s.p_WBo.z() - rest_height(c)) + 0.5 * c.mass * s.v_WBo.squaredNorm() +
         0.5 * w_B.dot(I.cwiseProduct(w_B));
}

double speed_bound(const ContactCase& c, const BodyState& s) {
  return s.v_WBo.norm() + s.w_WB.norm() * bounding_radius(c);
}

double tilt(const BodyState& s) {
  const physics::Mat3 R = s.q_WB.toRotationMatrix();
  const double nearest = std::min(1.0, R.row(2).cwiseAbs().maxCoeff());
  return std::acos(nearest);
}

ClosedForm closed_form(const ContactCase& c) {
  ClosedForm f;
  if (!c.plane) return f;
  const double g = c.g, e = c.restitution;
  switch (c.kind) {
    case ContactKind::kElastic:
    case ContactKind::kBouncing: {
      // Free fall from rest to the first touch, then each bounce leaves at e times the speed it
      // arrived with and returns after 2 u / g.
      const double t1 = std::sqrt(2.0 * (c.start.p_WBo.z() - c.size) / g);
      double u = g * t1, t = t1;  // approach speed and time of the next impact
      while (u >= kRestSpeed && t <= c.duration &&
             static_cast<int>(f.impacts.size()) < 10 * kImpactsScored) {
        f.impacts.push_back(t);
        u *= e;
        f.apexes.push_back(c.size + u * u / (2.0 * g));
        t += 2.0 * u / g;
      }
      if (c.kind == ContactKind::kBouncing) {
        f.rest_time = t1 * (1.0 + e) / (1.0 - e);
        // After the last impact approached at kRestSpeed or more, every speed is below it.
        f.rest_threshold_time = f.impacts.back();
      }
      break;
    }
    case ContactKind::kSliding: {
      const double v0 = c.start.v_WBo.norm(), a = c.friction * g;
      f.rest_time = v0 / a;
      f.rest_threshold_time = (v0 - kRestSpeed) / a;
      f.stop_distance = v0 * v0 / (2.0 * a);
      break;
    }
    case ContactKind::kResting:
    case ContactKind::kTumbling:
      break;
  }
  return f;
}

bool has_exact_motion(const ContactCase& c) {
  return c.kind != ContactKind::kTumbling;
}

BodyState exact_state(const ContactCase& c, double t) {
  BodyState s = c.start;
  const double g = c.g;
  if (!c.plane) {
    s.p_WBo = c.start.p_WBo + c.start.v_WBo * t - Vec3(0, 0, 0.5 * g * t * t);
    s.v_WBo = c.start.v_WBo - Vec3(0, 0, g * t);
    s.q_WB =
        Quat(Eigen::AngleAxisd(c.start.w_WB.norm() * t, c.start.w_WB.normalized())) * c.start.q_WB;
    if (c.start.w_WB.isZero()) s.q_WB = c.start.q_WB;
    return s;
  }
  switch (c.kind) {
    case ContactKind::kSliding: {
      const double v0 = c.start.v_WBo.norm(), a = c.friction * g;
      const double ts = std::min(t, v0 / a);
      const Vec3 along = c.start.v_WBo / v0;
      s.p_WBo = c.start.p_WBo + along * (v0 * ts - 0.5 * a * ts * ts);
      s.v_WBo = along * (v0 - a * ts);
      return s;
    }
    case ContactKind::kResting: {
      // Falls its gap and stays (e = 0).
      const double gap = lowest_point(c, c.start), tl = std::sqrt(2.0 * gap / g);
      const double tf = std::min(t, tl);
      s.p_WBo.z() = c.start.p_WBo.z() - 0.5 * g * tf * tf;
      s.v_WBo.z() = t < tl ? -g * t : 0.0;
      return s;
    }
    case ContactKind::kElastic:
    case ContactKind::kBouncing: {
      const double h = c.start.p_WBo.z(), r = c.size, e = c.restitution;
      double ti = std::sqrt(2.0 * (h - r) / g), u = g * ti;
      if (t < ti) {
        s.p_WBo.z() = h - 0.5 * g * t * t;
        s.v_WBo.z() = -g * t;
        return s;
      }
      // Bounce after bounce until t falls in a flight; the series ends at the rest time.
      while (u > 0) {
        u *= e;
        const double T = 2.0 * u / g;
        if (t < ti + T) {
          const double tau = t - ti;
          s.p_WBo.z() = r + u * tau - 0.5 * g * tau * tau;
          s.v_WBo.z() = u - g * tau;
          return s;
        }
        if (T == 0.0 || ti + T == ti) break;
        ti += T;
      }
      s.p_WBo.z() = r;
      s.v_WBo.z() = 0;
      return s;
    }
    case ContactKind::kTumbling:
      break;
  }
  BodyState nan;
  nan.p_WBo.setConstant(kNaN);
  return nan;
}

double exact_speed_rule_rest(const ContactCase& c, double dt) {
  const long n = std::lround(c.duration / dt);
  double last_fast = speed_bound(c, c.start) >= kRestSpeed ? 0.0 : -dt;
  for (long i = 1; i <= n; ++i) {
    const double t = static_cast<double>(i) * dt;
    if (speed_bound(c, exact_state(c, t)) >= kRestSpeed) last_fast = t;
  }
  return last_fast + dt;
}

}  // namespace rigid::bench::peers
