// Inertia: principal axes of a full tensor, and the tensors of simple solid shapes.
#pragma once

#include <string>

#include "physics/math.hpp"

namespace rigid::physics {

// The principal decomposition I_B = R_BP diag(moments) R_BP^T, moments ascending, R_BP a proper
// rotation (right-handed), returned as the unit quaternion q_BP.
struct PrincipalInertia {
  Vec3 moments = Vec3::Ones();
  Quat q_BP = Quat::Identity();
};
PrincipalInertia principal_inertia(const Mat3& I_B);

// Why I_B is not the inertia of a rigid body about its centre of mass, or "" when it is: it must be
// finite, symmetric (to 1e-12 relative), positive definite, and its principal moments must satisfy
// the triangle inequality I_a + I_b >= I_c (to 1e-12 relative).
std::string inertia_problem(const Mat3& I_B);

enum class ShapeKind { kBox, kSphere, kCylinder, kCapsule, kEllipsoid };
// Solid, uniform-density shapes centred on the centre of mass, axes along B.
//   box:       size = full edge lengths (x, y, z)
//   sphere:    size.x() = radius
//   cylinder:  size.x() = radius, size.z() = length, axis along z
//   capsule:   size.x() = radius, size.z() = length of the cylindrical part, axis along z
//   ellipsoid: size = semi-axes (a, b, c)
struct Shape {
  ShapeKind kind = ShapeKind::kSphere;
  Vec3 size = Vec3::Ones();
};
double shape_volume(const Shape& s);
// Inertia about the centre of mass, in B, of the shape with the given mass.
Mat3 shape_inertia(const Shape& s, double mass);

}  // namespace rigid::physics
