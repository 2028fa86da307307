// How a compiled body moves: the motion group whose kernel steps it (named by the motion it
// computes), whether forces drive it or its set velocities do (as Jolt's EMotionType), and which
// of its six degrees of freedom are free (as Jolt's EAllowedDOFs).
#pragma once

#include <cstdint>
#include <string_view>

namespace rigid::physics {

// The group a body is compiled into: the cheapest exact motion for it.
//   kTranslation: never turns. Point masses, bodies with every rotation locked, kinematic bodies
//                 without spin.
//   kSteadySpin:  turns about an axis fixed in the body at a rate that only torque changes, the
//                 rotation over a step exp(h w) exactly: isotropic bodies, hinges (two rotations
//                 locked: the free world axis is fixed in the body too), kinematic spinning bodies.
//   kPrecession:  axisymmetric bodies (two equal principal moments): regular precession in closed
//                 form (Landau & Lifshitz section 33).
//   kTumbling:    general bodies (three distinct principal moments): the Euler-Poinsot motion by
//                 Jacobi elliptic functions (free_rotor.hpp).
enum class BodyMotion : std::uint8_t { kTranslation, kSteadySpin, kPrecession, kTumbling };
inline constexpr int kBodyMotions = 4;
std::string_view to_string(BodyMotion m);

// A dynamic body moves under its loads; a kinematic one keeps its set velocities and ignores every
// load and impulse.
enum class MotionType : std::uint8_t { kDynamic, kKinematic };
std::string_view to_string(MotionType t);

// The degrees of freedom a body's spec leaves free, about the world axes: a bit per axis, the
// translations' then the rotations'. A dynamic body's locked translation keeps that velocity
// component at zero and ignores forces along it; its rotations are locked none, two (a hinge about
// the third world axis) or all three (it never turns). A kinematic body keeps every set velocity
// and honours only a lock of all three rotations.
enum class AllowedDofs : std::uint8_t {
  kNone = 0,
  kTranslationX = 1u << 0,
  kTranslationY = 1u << 1,
  kTranslationZ = 1u << 2,
  kRotationX = 1u << 3,
  kRotationY = 1u << 4,
  kRotationZ = 1u << 5,
  kAllTranslation = 7u,
  kAllRotation = 7u << 3,
  kAll = 63u,
};
constexpr AllowedDofs operator|(AllowedDofs a, AllowedDofs b) {
  return static_cast<AllowedDofs>(static_cast<unsigned>(a) | static_cast<unsigned>(b));
}
constexpr AllowedDofs operator&(AllowedDofs a, AllowedDofs b) {
  return static_cast<AllowedDofs>(static_cast<unsigned>(a) & static_cast<unsigned>(b));
}
// The translation along, and the rotation about, world axis `axis` (0, 1, 2).
constexpr AllowedDofs translation_dof(int axis) {
  return static_cast<AllowedDofs>(1u << axis);
}
constexpr AllowedDofs rotation_dof(int axis) {
  return static_cast<AllowedDofs>(8u << axis);
}
// Whether every degree of freedom of `dofs` is free in `set`.
constexpr bool allows(AllowedDofs set, AllowedDofs dofs) {
  return (set & dofs) == dofs;
}
// How many rotations `set` locks (0 to 3).
constexpr int locked_rotations(AllowedDofs set) {
  int n = 0;
  for (int a = 0; a < 3; ++a)
    n += allows(set, rotation_dof(a)) ? 0 : 1;
  return n;
}

}  // namespace rigid::physics
