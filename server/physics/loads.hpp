// The loads on one body, kept in the frames in which they are constant during a step, so that an
// integrator can re-evaluate them cheaply at every stage with that stage's orientation.
//
// For a body with orientation R = R_WP:
//   force   F_W = f_W + R f_P
//   torque  tau_P = tau_P + R^T tau_W + sum_i r_i x (R^T f_i)          (r_i in P, f_i in W)
// The last sum, the torque of world-frame forces at body points, is (R r_i) x f_i = tau_W of the
// course notes, rotated into P. It is kept as one matrix fr = sum_i f_i r_i^T, so that any number
// of such forces costs one 3x3 product: with N = R^T fr, (r x g)_x = N(2,1) - N(1,2), etc.
#pragma once

#include <cstdint>

#include "physics/math.hpp"

namespace rigid::physics::detail {

// The flags that say which terms a body's loads have (refresh_flags), and the terms' effect at an
// orientation, shared by the value (Loads) and the view of a body's stored loads (LoadsRef): D has
// members flags, f_W, f_P, tau_P, tau_W and fr.
struct LoadFlags {
  enum : std::uint32_t {
    kBodyForce = 1u << 0,    // f_P != 0
    kBodyTorque = 1u << 1,   // tau_P != 0
    kWorldTorque = 1u << 2,  // tau_W != 0
    kLever = 1u << 3,        // fr != 0
    kAngularDrag = 1u << 4,  // the body has angular drag (set once, at compile time)
  };
  // The flags of the terms kept apart from f_W (LoadTerms).
  static constexpr std::uint32_t kTerms = kBodyForce | kBodyTorque | kWorldTorque | kLever;
};

template <class D>
struct LoadMath : LoadFlags {
  bool torque_free() const { return (self().flags & (kBodyTorque | kWorldTorque | kLever)) == 0; }
  bool orientation_free_force() const { return (self().flags & kBodyForce) == 0; }
  // Nothing turns the body and nothing it carries depends on its orientation: its rotation is
  // free and its translation sees a constant acceleration.
  bool quiet() const {
    return (self().flags & (kBodyForce | kBodyTorque | kWorldTorque | kLever | kAngularDrag)) == 0;
  }
  // Force in W at orientation q = q_WP.
  [[gnu::always_inline]] Vec3 force_W(const Quat& q) const {
    const D& d = self();
    Vec3 f = d.f_W;
    if (d.flags & kBodyForce) f += q * d.f_P;
    return f;
  }
  // Torque in P at orientation q = q_WP.
  [[gnu::always_inline]] Vec3 torque_P(const Quat& q) const {
    const D& d = self();
    Vec3 t = d.tau_P;
    if (d.flags & kWorldTorque) t += q.conjugate() * d.tau_W;
    if (d.flags & kLever) {
      const Mat3 n = q.conjugate().toRotationMatrix() * d.fr;
      t += Vec3(n(2, 1) - n(1, 2), n(0, 2) - n(2, 0), n(1, 0) - n(0, 1));
    }
    return t;
  }

 private:
  const D& self() const { return static_cast<const D&>(*this); }
};

// The loads of one body as a value: what World builds from the spec and edits (add_force, ...).
struct Loads : LoadMath<Loads> {
  // flags and f_W first: the integrators' fast path for a body with nothing turning it reads only
  // these (LoadHead keeps them, and only them, per body).
  std::uint32_t flags = 0;
  Vec3 f_W = Vec3::Zero();
  Vec3 f_P = Vec3::Zero();
  Vec3 tau_P = Vec3::Zero();
  Vec3 tau_W = Vec3::Zero();
  Mat3 fr = Mat3::Zero();

  void add_force(const Vec3& f, const Vec3& r_P, bool body_frame) {
    if (body_frame) {
      f_P += f;
      tau_P += r_P.cross(f);
    } else {
      f_W += f;
      fr += f * r_P.transpose();
    }
    refresh_flags();
  }
  void add_torque(const Vec3& t, bool body_frame) {
    (body_frame ? tau_P : tau_W) += t;
    refresh_flags();
  }
  void refresh_flags() {
    flags = (flags & kAngularDrag) | (f_P.isZero(0) ? 0u : kBodyForce) |
            (tau_P.isZero(0) ? 0u : kBodyTorque) | (tau_W.isZero(0) ? 0u : kWorldTorque) |
            (fr.isZero(0) ? 0u : kLever);
  }
};

// How a group stores its bodies' loads (groups.hpp: Entries): per body a LoadHead of 32 B, which is
// all that the many bodies with no torque and no body-fixed force have; the terms of those that do
// (144 B) in a pool of LoadTerms, whose entry 0 is all zero and shared by every body without terms.
// A dense Loads per body cost 176 B, most of it zeros (issue 13's memory budget).
struct LoadHead {
  std::uint32_t flags = 0;
  std::int32_t terms = 0;  // the entry of the group's LoadTerms pool; 0: none
  Vec3 f_W = Vec3::Zero();
};
struct LoadTerms {
  Vec3 f_P = Vec3::Zero();
  Vec3 tau_P = Vec3::Zero();
  Vec3 tau_W = Vec3::Zero();
  Mat3 fr = Mat3::Zero();
};

// A body's stored loads seen as one: what the integrators read.
struct LoadsRef : LoadMath<LoadsRef> {
  LoadsRef(const LoadHead& h, const LoadTerms& t)
      : flags(h.flags), f_W(h.f_W), f_P(t.f_P), tau_P(t.tau_P), tau_W(t.tau_W), fr(t.fr) {}
  std::uint32_t flags;
  const Vec3& f_W;
  const Vec3& f_P;
  const Vec3& tau_P;
  const Vec3& tau_W;
  const Mat3& fr;
};

}  // namespace rigid::physics::detail
