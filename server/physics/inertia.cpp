// Principal axes of an inertia tensor, its physical-validity check, and the inertia of uniform
// solids.
#include "physics/inertia.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <numbers>

namespace rigid::physics {
namespace {

// Shortest text that reads back to the same double, so a message shows exactly the offending value.
std::string num(double x) {
  std::array<char, 32> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), x);
  return std::string(buf.data(), r.ptr);
}

// Computed moments carry eigen-solver round-off in their last digits; 15 significant digits show
// every violation the 1e-12 tolerances can flag without printing -0.9999999999999998 for -1.
std::string computed(double x) {
  std::array<char, 32> buf{};
  const auto r =
      std::to_chars(buf.data(), buf.data() + buf.size(), x, std::chars_format::general, 15);
  return std::string(buf.data(), r.ptr);
}

std::string moments_text(const Vec3& m) {
  return "(" + computed(m.x()) + ", " + computed(m.y()) + ", " + computed(m.z()) + ")";
}

// Makes the largest-magnitude component of an eigenvector positive. An eigenvector's sign is
// arbitrary; fixing it this way means a tensor that is already principal gets R_BP = identity
// instead of a 180-degree turn about some axis.
Vec3 canonical_sign(const Vec3& v) {
  Eigen::Index i = 0;
  v.cwiseAbs().maxCoeff(&i);
  return v(i) < 0.0 ? Vec3(-v) : v;
}

bool is_diagonal(const Mat3& m) {
  return m(0, 1) == 0.0 && m(0, 2) == 0.0 && m(1, 0) == 0.0 && m(1, 2) == 0.0 && m(2, 0) == 0.0 &&
         m(2, 1) == 0.0;
}

}  // namespace

PrincipalInertia principal_inertia(const Mat3& I_B) {
  Mat3 R_BP;  // columns: the principal axes, expressed in B
  Vec3 moments;
  if (is_diagonal(I_B)) {
    // Already principal: sort the axes by moment exactly, with no eigen-solver round-off.
    std::array<int, 3> order{0, 1, 2};
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return I_B(a, a) < I_B(b, b); });
    R_BP.setZero();
    for (int k = 0; k < 3; ++k) {
      moments(k) = I_B(order[k], order[k]);
      R_BP(order[k], k) = 1.0;
    }
  } else {
    // Symmetrise first: the solver reads only one triangle, so an asymmetry within tolerance
    // would otherwise be resolved arbitrarily. The iterative (QR) solver is used rather than
    // computeDirect(): the closed-form 3x3 path loses accuracy for nearly repeated moments.
    const Mat3 sym = 0.5 * (I_B + I_B.transpose());
    const Eigen::SelfAdjointEigenSolver<Mat3> solver(sym);
    moments = solver.eigenvalues();  // ascending, as Eigen documents
    R_BP = solver.eigenvectors();
    R_BP.col(0) = canonical_sign(R_BP.col(0));
    R_BP.col(1) = canonical_sign(R_BP.col(1));
  }
  // A right-handed frame: the third axis is the cross product of the first two, which also turns a
  // reflection (det = -1, a sign flip of one eigenvector) into a proper rotation.
  R_BP.col(2) = R_BP.col(0).cross(R_BP.col(1));
  PrincipalInertia out;
  out.moments = moments;
  out.q_BP = Quat(R_BP).normalized();
  return out;
}

// Each reason is a predicate phrase ("is not positive definite: ...") so that callers can prefix
// the subject: World reports "body 'b': inertia is not positive definite: ...".
std::string inertia_problem(const Mat3& I_B) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(I_B(r, c))) {
        return "has a non-finite entry (" + std::to_string(r) + ", " + std::to_string(c) +
               "): " + num(I_B(r, c));
      }
    }
  }
  const double scale = I_B.cwiseAbs().maxCoeff();
  for (int r = 0; r < 3; ++r) {
    for (int c = r + 1; c < 3; ++c) {
      if (std::abs(I_B(r, c) - I_B(c, r)) > 1e-12 * scale) {
        return "is not symmetric: entry (" + std::to_string(r) + ", " + std::to_string(c) +
               ") = " + num(I_B(r, c)) + " but (" + std::to_string(c) + ", " + std::to_string(r) +
               ") = " + num(I_B(c, r));
      }
    }
  }
  const Vec3 m = principal_inertia(I_B).moments;
  if (!(m(0) > 0.0)) {
    return "is not positive definite: principal moments " + moments_text(m);
  }
  // A rigid body's principal moments satisfy I_a + I_b >= I_c: with s_i = integral of x_i^2 dm,
  // I_a = s_b + s_c etc., so I_a + I_b - I_c = 2 s_c >= 0. Moments are ascending, so only the
  // largest can break it.
  if (m(0) + m(1) - m(2) < -1e-12 * m(2)) {
    return "violates the triangle inequality I1 + I2 >= I3: principal moments " + moments_text(m) +
           ", " + computed(m(0)) + " + " + computed(m(1)) + " < " + computed(m(2));
  }
  return "";
}

double shape_volume(const Shape& s) {
  constexpr double pi = std::numbers::pi;
  const double r = s.size.x();
  switch (s.kind) {
    case ShapeKind::kBox:
      return s.size.x() * s.size.y() * s.size.z();
    case ShapeKind::kSphere:
      return 4.0 / 3.0 * pi * r * r * r;
    case ShapeKind::kCylinder:
      return pi * r * r * s.size.z();
    case ShapeKind::kCapsule:
      return pi * r * r * s.size.z() + 4.0 / 3.0 * pi * r * r * r;
    case ShapeKind::kEllipsoid:
      return 4.0 / 3.0 * pi * s.size.x() * s.size.y() * s.size.z();
  }
  return 0.0;
}

Mat3 shape_inertia(const Shape& s, double mass) {
  const double r = s.size.x();
  Vec3 d = Vec3::Zero();  // diagonal of the tensor; every shape here is principal in B
  switch (s.kind) {
    case ShapeKind::kBox: {
      // Solid cuboid with edges (a, b, c): I_xx = m (b^2 + c^2) / 12, and cyclically.
      const Vec3 e2 = s.size.cwiseAbs2();
      d = mass / 12.0 * Vec3(e2.y() + e2.z(), e2.x() + e2.z(), e2.x() + e2.y());
      break;
    }
    case ShapeKind::kSphere:
      // Solid ball: I = 2/5 m r^2 about every axis.
      d = Vec3::Constant(0.4 * mass * r * r);
      break;
    case ShapeKind::kCylinder: {
      // Solid cylinder, axis z, length L: I_zz = m r^2 / 2, I_xx = I_yy = m (3 r^2 + L^2) / 12.
      const double L = s.size.z();
      const double t = mass * (3.0 * r * r + L * L) / 12.0;
      d = Vec3(t, t, 0.5 * mass * r * r);
      break;
    }
    case ShapeKind::kCapsule: {
      // A cylinder of length L plus two solid hemispheres of radius r, mass split by volume.
      const double L = s.size.z();
      const double v_cyl = std::numbers::pi * r * r * L;
      const double v_ball = 4.0 / 3.0 * std::numbers::pi * r * r * r;
      const double m_cyl = mass * v_cyl / (v_cyl + v_ball);
      const double m_hemi = 0.5 * (mass - m_cyl);  // each hemisphere
      // Hemisphere about its flat face's centre: half a ball, so 2/5 m_hemi r^2 about every axis
      // through that point. Its centre of mass sits 3r/8 from the face, so about its own centre
      // of mass (parallel-axis theorem, backwards) the transverse moment is
      // 2/5 m r^2 - m (3r/8)^2 = 83/320 m r^2, and about the capsule's centre, at distance
      // L/2 + 3r/8, it is that plus m (L/2 + 3r/8)^2.
      const double offset = 0.5 * L + 0.375 * r;
      const double hemi_cm = 0.4 * m_hemi * r * r - m_hemi * (0.375 * r) * (0.375 * r);
      const double hemi_transverse = hemi_cm + m_hemi * offset * offset;
      const double t = m_cyl * (3.0 * r * r + L * L) / 12.0 + 2.0 * hemi_transverse;
      // About the axis, each hemisphere is half a ball: 2/5 m_hemi r^2.
      const double axial = 0.5 * m_cyl * r * r + 2.0 * 0.4 * m_hemi * r * r;
      d = Vec3(t, t, axial);
      break;
    }
    case ShapeKind::kEllipsoid: {
      // Solid ellipsoid with semi-axes (a, b, c): I_xx = m (b^2 + c^2) / 5, and cyclically.
      const Vec3 e2 = s.size.cwiseAbs2();
      d = mass / 5.0 * Vec3(e2.y() + e2.z(), e2.x() + e2.z(), e2.x() + e2.y());
      break;
    }
  }
  return d.asDiagonal();
}

}  // namespace rigid::physics
