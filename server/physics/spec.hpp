// What a world is made of, as a scene describes it, before it is compiled for stepping.
//
// Frames (Drake-style monogram notation, so that frame mistakes show in names):
//   W  world frame.
//   B  a body's own frame, the one the scene file uses: origin at the centre of mass.
//   P  the body's principal frame: origin at the centre of mass, axes along the principal axes of
//      inertia. The integrators work in P; B only appears at the edges (scene, wire, output).
// Names: p_WBo = position of B's origin in W; q_WB = orientation of B in W (maps B vectors to W);
// v_WBo = velocity of B's origin in W; w_WB = angular velocity of B in W, expressed in W
// (a suffix _B means "expressed in B"); f_W = a force expressed in W.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "physics/inertia.hpp"
#include "physics/math.hpp"

namespace rigid::physics {

// The frame a force or torque vector is expressed in. A BODY-frame force turns with the body.
enum class Frame { kWorld, kBody };

// What a surface does in contact: the coefficient of restitution e in [0, 1] (the normal speed
// after an impact over the speed before: Newton's law) and the Coulomb friction coefficient
// mu >= 0 (the tangential force at most mu times the normal force). A pair takes the larger e and
// the geometric mean of mu (contact/static_part.hpp: combine).
struct Surface {
  double restitution = 0.0;
  double friction = 0.5;
};

struct BodySpec {
  std::string name;
  // Mass in kg, > 0. Ignored for kinematic bodies.
  double mass = 1.0;
  // Inertia tensor about the centre of mass, expressed in B (kg m^2). Symmetric positive definite
  // and physically realisable (principal moments satisfy the triangle inequality).
  // A body with has_inertia == false is a point mass: it translates but never rotates.
  Mat3 I_B = Mat3::Identity();
  bool has_inertia = true;

  Vec3 p_WBo = Vec3::Zero();
  Quat q_WB = Quat::Identity();  // unit quaternion
  Vec3 v_WBo = Vec3::Zero();     // expressed in W
  Vec3 w_WB = Vec3::Zero();      // expressed in W

  double linear_drag = 0.0;   // c in F = -c v (N s / m), >= 0
  double angular_drag = 0.0;  // k in tau = -k w (N m s), >= 0
  bool use_gravity = true;
  // A kinematic body moves with its set velocities forever and ignores every force.
  bool kinematic = false;
  // Frozen axes, along the world axes x, y, z. Frozen translation: that velocity component is held
  // at zero and forces along it are ignored. Frozen rotation: 0, 2 or 3 axes (2 frozen axes leave a
  // hinge about the third world axis; freezing exactly one is rejected, because the constrained
  // motion is no longer that of a free body).
  std::array<bool, 3> freeze_translation{false, false, false};
  std::array<bool, 3> freeze_rotation{false, false, false};

  // Its collision shape, centred on the centre of mass with its axes along B; none: it collides as
  // a point (with static parts and with bodies that have a shape; two points never meet).
  std::optional<Shape> shape;
  Surface surface;
  // Which bodies it meets: two bodies collide when each one's group shares a bit with the other's
  // mask (the convention of Bullet, ODE and Box2D). By default every body meets every other.
  std::uint32_t collision_group = 1;
  std::uint32_t collision_mask = ~std::uint32_t{0};
};

// Static geometry: it never moves and has no mass.
// An infinite plane whose solid side is the half-space n_W . x <= offset (n_W unit).
struct PlaneSpec {
  std::string name;
  Vec3 n_W = Vec3::UnitZ();
  double offset = 0.0;
  Surface surface;
};
// A placed shape (box, sphere, capsule, cylinder): its centre at p_WS, its axes turned by q_WS.
struct StaticSpec {
  std::string name;
  Shape shape;
  Vec3 p_WS = Vec3::Zero();
  Quat q_WS = Quat::Identity();
  Surface surface;
};

// A constant load on one body: a force applied at a point plus an optional pure torque.
struct LoadSpec {
  int body = 0;                 // index into WorldSpec::bodies
  Vec3 force = Vec3::Zero();    // expressed in `frame`
  Vec3 p_BoQ_B = Vec3::Zero();  // application point Q, from the centre of mass, in B
  Frame frame = Frame::kWorld;
  Vec3 torque = Vec3::Zero();  // pure torque, expressed in `torque_frame`
  Frame torque_frame = Frame::kWorld;
};

struct WorldSpec {
  Vec3 g_W{0.0, 0.0, -9.81};
  double dt = 1e-3;        // physics step (s), > 0
  std::string integrator;  // empty: the default integrator
  // Threads that step the world (World::set_threads): >= 1; 0 takes the machine's hardware
  // concurrency. States are bit-identical for any count.
  int threads = 1;
  std::vector<BodySpec> bodies;
  std::vector<LoadSpec> loads;
  // Static parts: the planes, then the shapes (a part's index counts planes first).
  std::vector<PlaneSpec> planes;
  std::vector<StaticSpec> statics;
};

}  // namespace rigid::physics
