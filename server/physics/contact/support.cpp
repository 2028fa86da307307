#include "physics/contact/support.hpp"

#include <cmath>
#include <numbers>

namespace rigid::physics::contact {

namespace {

double sign_of(double x) {
  return x < 0.0 ? -1.0 : 1.0;
}

}  // namespace

Convex Convex::of(const std::optional<Shape>& shape) {
  Convex c;
  if (!shape) return c;
  const Vec3& s = shape->size;
  switch (shape->kind) {
    case ShapeKind::kBox:
      c.kind = Kind::kBox;
      c.half = 0.5 * s;
      break;
    case ShapeKind::kSphere:
      c.kind = Kind::kSphere;
      c.radius = s.x();
      break;
    case ShapeKind::kCapsule:
      c.kind = Kind::kCapsule;
      c.half = Vec3(0.0, 0.0, 0.5 * s.z());
      c.radius = s.x();
      break;
    case ShapeKind::kCylinder:
      c.kind = Kind::kCylinder;
      c.half = Vec3(s.x(), s.x(), 0.5 * s.z());
      break;
    case ShapeKind::kEllipsoid:
      c.kind = Kind::kEllipsoid;
      c.half = s;
      break;
  }
  return c;
}

Vec3 Convex::core_support(const Vec3& u) const {
  switch (kind) {
    case Kind::kPoint:
    case Kind::kSphere:
      return Vec3::Zero();
    case Kind::kBox:
      return Vec3(sign_of(u.x()) * half.x(), sign_of(u.y()) * half.y(), sign_of(u.z()) * half.z());
    case Kind::kCapsule:
      return Vec3(0.0, 0.0, sign_of(u.z()) * half.z());
    case Kind::kCylinder: {
      // The rim point along u's transverse part; with none (u along the axis), the disk's centre
      // (every point of the disk is a support point: the centre is the symmetric choice).
      const double t = std::hypot(u.x(), u.y());
      const double z = sign_of(u.z()) * half.z();
      if (t == 0.0) return Vec3(0.0, 0.0, z);
      return Vec3(half.x() * u.x() / t, half.x() * u.y() / t, z);
    }
    case Kind::kEllipsoid: {
      // x = A^2 u / |A u| for the semi-axes A = diag(a): the point where the normal is u.
      const Vec3 au = half.cwiseProduct(u);
      const double n = au.norm();
      if (n == 0.0) return Vec3::Zero();
      return half.cwiseProduct(au) / n;
    }
  }
  return Vec3::Zero();
}

double Convex::core_height(const Vec3& u) const {
  switch (kind) {
    case Kind::kPoint:
    case Kind::kSphere:
      return 0.0;
    case Kind::kBox:
      return half.x() * std::abs(u.x()) + half.y() * std::abs(u.y()) + half.z() * std::abs(u.z());
    case Kind::kCapsule:
      return half.z() * std::abs(u.z());
    case Kind::kCylinder:
      return half.x() * std::hypot(u.x(), u.y()) + half.z() * std::abs(u.z());
    case Kind::kEllipsoid:
      return half.cwiseProduct(u).norm();
  }
  return 0.0;
}

double Convex::bounding_radius() const {
  switch (kind) {
    case Kind::kPoint:
      return 0.0;
    case Kind::kSphere:
      return radius;
    case Kind::kBox:
      return half.norm();
    case Kind::kCapsule:
      return half.z() + radius;
    case Kind::kCylinder:
      return std::hypot(half.x(), half.z());
    case Kind::kEllipsoid:
      return half.maxCoeff();
  }
  return 0.0;
}

int touching_points(const Convex& c, const Vec3& u, double tol,
                    std::array<Vec3, kMaxFeature>& out) {
  const Vec3 rim = c.radius * u;  // a rounded shape touches one radius beyond its core
  switch (c.kind) {
    case Convex::Kind::kPoint:
    case Convex::Kind::kSphere:
    case Convex::Kind::kEllipsoid:
      // Strictly convex: one point.
      out[0] = c.core_support(u) + rim;
      return 1;
    case Convex::Kind::kBox: {
      // The corners within tol of the support plane: 1, 2 or 4 of the 8.
      const double h = c.core_height(u);
      int n = 0;
      for (int k = 0; k < 8; ++k) {
        const Vec3 p((k & 1 ? -1.0 : 1.0) * c.half.x(), (k & 2 ? -1.0 : 1.0) * c.half.y(),
                     (k & 4 ? -1.0 : 1.0) * c.half.z());
        if (u.dot(p) >= h - tol) out[n++] = p;
      }
      return n;
    }
    case Convex::Kind::kCapsule: {
      // Lying along the plane: both ends of its core touch.
      const double l = c.half.z();
      if (2.0 * l * std::abs(u.z()) <= tol) {
        out[0] = Vec3(0.0, 0.0, l) + rim;
        out[1] = Vec3(0.0, 0.0, -l) + rim;
        return 2;
      }
      out[0] = c.core_support(u) + rim;
      return 1;
    }
    case Convex::Kind::kCylinder: {
      const double r = c.half.x(), l = c.half.z();
      const double t = std::hypot(u.x(), u.y());
      if (r * t <= tol) {
        // Standing on an end: the disk, as points of its rim.
        const double z = sign_of(u.z()) * l;
        for (int k = 0; k < kDiskPoints; ++k) {
          const double a = 2.0 * std::numbers::pi * k / kDiskPoints;
          out[k] = Vec3(r * std::cos(a), r * std::sin(a), z);
        }
        return kDiskPoints;
      }
      const Vec3 side(r * u.x() / t, r * u.y() / t, 0.0);
      if (2.0 * l * std::abs(u.z()) <= tol) {
        // Lying on its side: the line along it.
        out[0] = side + Vec3(0.0, 0.0, l);
        out[1] = side - Vec3(0.0, 0.0, l);
        return 2;
      }
      out[0] = side + Vec3(0.0, 0.0, sign_of(u.z()) * l);
      return 1;
    }
  }
  return 0;
}

}  // namespace rigid::physics::contact
