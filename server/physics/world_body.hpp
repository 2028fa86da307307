// One World body as the contact stage sees it (contact/moving_body.hpp), over the body's entry in
// its group: its motion over part of a step as the integrators' exact family takes it, and how it
// answers impulses. world_contact.cpp (a body among static parts) and world_pairs.cpp (bodies
// among each other) step bodies through it.
#pragma once

#include <algorithm>
#include <cmath>

#include "physics/contact/moving_body.hpp"
#include "physics/free_rotor.hpp"
#include "physics/groups.hpp"
#include "physics/kernels.hpp"
#include "physics/model.hpp"
#include "physics/translation.hpp"

namespace rigid::physics::detail {

// --- one body's motion over part of a step ---

// The body's motion as the integrators' exact family takes it over a sub-step s from its state at
// the sub-step's start: a body nothing turns (its loads quiet) in free flight exactly (the drag
// flow under its constant acceleration, and the exact free rotor); a loaded one by Yoshida's
// triple jump of kick-drift-kick with exact drifts (fourth order, model.hpp: TripleJump).
template <BodyMotion K>
class BodyPath final : public contact::Trajectory {
 public:
  using Traits = GroupTraits<K>;
  using Rot = typename Traits::Rot;

  void plan(const Motion& start, const Linear& lin, const Rot& rot, const RotorInertia* rotor,
            const Quat& q_BP, const Loads& loads, double len) {
    start_ = start;
    lin_ = lin;
    rot_ = rot;
    rotor_ = rotor;
    q_BP_ = q_BP;
    loads_ = loads;
    quiet_ = loads.quiet();
    length = len;
    // Bounds over the sub-step. Force: its largest size at any orientation; acceleration: with
    // drag, the speed it can reach.
    const double f = loads.f_W.norm() + loads.f_P.norm();
    const double inv_m = lin.inv_m.maxCoeff();
    const double a = lin.g.norm() + inv_m * f;
    const double v = start.v.norm() + a * len;
    a_max = a + lin.gamma * v;
    if constexpr (Traits::kTurns) {
      // The torque's largest size at any orientation (loads.hpp: the lever term is fr's
      // antisymmetric part turned, at most its Frobenius norm).
      const double tau = loads.tau_P.norm() + loads.tau_W.norm() + loads.fr.norm();
      const Vec3 w0 = rot.omega(start.spin);
      double inv_I_max, inv_I_min;
      if constexpr (K == BodyMotion::kSteadySpin) {
        inv_I_max = inv_I_min = rot.inv_I;
      } else {
        inv_I_max = rot.inv_I.maxCoeff();
        inv_I_min = rot.inv_I.minCoeff();
      }
      // |w| grows at most by |I^-1 tau| over the sub-step; the gyroscopic term turns w but, for
      // the momentum's size, does not grow it: |w| <= |h| / I_min with |h| <= |h0| + tau t.
      double h0;
      if constexpr (K == BodyMotion::kSteadySpin) {
        h0 = rot.inv_I > 0.0 ? start.spin.norm() / rot.inv_I : 0.0;
      } else {
        h0 = start.spin.norm();
      }
      w_max = std::max(w0.norm() + inv_I_max * tau * len, inv_I_max * (h0 + tau * len));
      alpha_max = inv_I_max * (tau + rot.k * w_max) + inv_I_max * w_max * (h0 + tau * len);
      (void)inv_I_min;
    } else {
      w_max = alpha_max = 0.0;
    }
  }

  Motion motion_at(double s) const {
    Motion b = start_;
    if (s == 0.0) return b;
    if constexpr (!Traits::kTurns) {
      translate(trans_coef(lin_.gamma, s), lin_.accel(loads_.force_W(b.q)), b.x, b.v);
      return b;
    } else {
      if (quiet_) {
        translate(trans_coef(lin_.gamma, s), lin_.accel(loads_.f_W), b.x, b.v);
        drift(b, s);
        return b;
      }
      using J = TripleJump;
      const Vec3 rates = rot_.drag_rates();
      Vec3 a0 = lin_.accel(loads_.force_W(b.q));
      kick_angular(rot_.spin_rate(loads_.torque_P(b.q)), rates, 0.5 * J::kStage[0] * s, b.spin);
      for (int k = 0; k < J::kStages; ++k) {
        const double sk = J::kStage[k] * s;
        drift(b, sk);
        const Vec3 a1 = lin_.accel(loads_.force_W(b.q));
        translate(trans_coef(lin_.gamma, sk), a0, a1, b.x, b.v);
        const double next = k + 1 < J::kStages ? J::kStage[k + 1] * s : 0.0;
        kick_angular(rot_.spin_rate(loads_.torque_P(b.q)), rates, 0.5 * (sk + next), b.spin);
        a0 = a1;
      }
      return b;
    }
  }

  contact::MotionSample at(double s) const override { return sample(motion_at(s), rot_, q_BP_); }

  // A body's state b as the contact stage sees it, from its own rotational parameters.
  static contact::MotionSample sample(const Motion& b, const Rot& rot, const Quat& q_BP) {
    contact::MotionSample m;
    m.pose.p_WBo = b.x;
    m.v_W = b.v;
    if constexpr (Traits::kTurns) {
      m.pose.q_WB = b.q * q_BP.conjugate();
      m.w_W = rotate(b.q, rot.omega(b.spin));
    } else {
      (void)rot, (void)q_BP;
      m.pose.q_WB = b.q;
    }
    return m;
  }

 private:
  // The exact torque-free rotation over s.
  void drift(Motion& b, double s) const {
    if constexpr (K == BodyMotion::kSteadySpin) {
      b.q = b.q * quat_exp(s * b.spin);
    } else if constexpr (K == BodyMotion::kPrecession) {
      AxisymPlan p;
      make_axisym_plan(rot_.I.x(), rot_.I.z(), b.spin, s, p);
      Quat dq;
      advance_axisym(p, b.spin, dq);
      b.q = b.q * dq;
    } else if constexpr (K == BodyMotion::kTumbling) {
      Quat dq;
      free_rotor_step(*rotor_, b.spin, s, dq);
      b.q = b.q * dq;
    }
    renormalize(b.q);
  }

  Motion start_;
  Linear lin_;
  Rot rot_{};
  const RotorInertia* rotor_ = nullptr;
  Quat q_BP_ = Quat::Identity();
  Loads loads_;
  bool quiet_ = true;
};

template <BodyMotion K>
class WorldBody final : public contact::MovingBody {
 public:
  using Traits = GroupTraits<K>;

  WorldBody(Group<K> g, int i) : g_(g), i_(i) {}

  // Not through path_: its parameters are those of the last plan(), none before the first.
  contact::MotionSample state() const override {
    return BodyPath<K>::sample(g_.motion(i_), rot(), q_BP());
  }

  const contact::Trajectory& plan(double length, const contact::SupportLoad& support) override {
    Loads loads = g_.entries.load_value(i_);
    if (!support.f_W.isZero(0)) loads.add_force(support.f_W, Vec3::Zero(), false);
    if (!support.tau_W.isZero(0)) loads.add_torque(support.tau_W, false);
    path_.plan(g_.motion(i_), g_.linear(i_), rot(), rotor(), q_BP(), loads, length);
    return path_;
  }

  void advance(double s) override {
    g_.motion(i_) = path_.motion_at(s);
    stale();
  }

  void set_velocity(const Vec3& v_W, const Vec3& w_W) override {
    Motion& b = g_.motion(i_);
    const Linear& lin = g_.linear(i_);
    for (int a = 0; a < 3; ++a)
      b.v[a] = lin.inv_m[a] > 0.0 ? v_W[a] : 0.0;
    if constexpr (Traits::kTurns) {
      const Vec3 w_P = b.q.conjugate() * w_W;
      if constexpr (K == BodyMotion::kSteadySpin) {
        const SpinRot& r = rot();
        b.spin = r.hinge != 0.0 ? Vec3(r.axis * r.axis.dot(w_P)) : w_P;
      } else {
        b.spin = rot().spin_of(w_P);
      }
    } else {
      (void)w_W;
    }
    stale();
  }

  void shift(const Vec3& d_W) override {
    Motion& b = g_.motion(i_);
    const Linear& lin = g_.linear(i_);
    for (int a = 0; a < 3; ++a)
      if (lin.inv_m[a] > 0.0) b.x[a] += d_W[a];
  }

  contact::Response response() const override {
    contact::Response r;
    r.inv_m = g_.linear(i_).inv_m;
    if constexpr (Traits::kTurns) {
      const Mat3 R = g_.motion(i_).q.toRotationMatrix();
      Mat3 inv_I_P;
      if constexpr (K == BodyMotion::kSteadySpin) {
        const SpinRot& s = rot();
        inv_I_P = s.hinge != 0.0 ? Mat3(s.inv_I * s.axis * s.axis.transpose())
                                 : Mat3(s.inv_I * Mat3::Identity());
      } else {
        inv_I_P = rot().inv_I.asDiagonal();
      }
      r.inv_I_W = R * inv_I_P * R.transpose();
    }
    return r;
  }

  void free_accelerations(Vec3& a_W, Vec3& alpha_W) const override {
    const Motion& b = g_.motion(i_);
    const Linear& lin = g_.linear(i_);
    const Loads L = g_.entries.load_value(i_);
    a_W = lin.accel(L.force_W(b.q)) - lin.gamma * b.v;
    alpha_W.setZero();
    if constexpr (Traits::kTurns) {
      const auto& r = rot();
      const Vec3 w_P = r.omega(b.spin);
      Vec3 alpha_P;
      if constexpr (K == BodyMotion::kSteadySpin) {
        alpha_P = r.alpha(L.torque_P(b.q) - r.k * w_P);
      } else {
        alpha_P = r.inv_I.cwiseProduct(L.torque_P(b.q) - w_P.cross(b.spin) - r.k * w_P);
      }
      alpha_W = rotate(b.q, alpha_P);
    }
  }

  double kinetic_energy() const override {
    const Motion& b = g_.motion(i_);
    const Linear& lin = g_.linear(i_);
    double e = 0.0;
    for (int a = 0; a < 3; ++a)
      if (lin.inv_m[a] > 0.0) e += 0.5 * b.v[a] * b.v[a] / lin.inv_m[a];
    if constexpr (K == BodyMotion::kSteadySpin) {
      if (rot().inv_I > 0.0) e += 0.5 * b.spin.squaredNorm() / rot().inv_I;
    } else if constexpr (Traits::kTurns) {
      e += 0.5 * rot().omega(b.spin).dot(b.spin);
    }
    return e;
  }

  double energy() const override {
    const Motion& b = g_.motion(i_);
    const Linear& lin = g_.linear(i_);
    double e = kinetic_energy();
    for (int a = 0; a < 3; ++a)
      if (lin.inv_m[a] > 0.0) e -= lin.g[a] * b.x[a] / lin.inv_m[a];
    return e;
  }

  bool conservative() const override {
    const auto& h = g_.entries.loads[i_];
    return h.flags == 0 && h.f_W.isZero(0);
  }

 private:
  const typename Traits::Rot& rot() const {
    if constexpr (Traits::kTurns) {
      return g_.rot(i_);
    } else {
      static constexpr None kNone{};
      return kNone;
    }
  }
  const RotorInertia* rotor() const {
    if constexpr (K == BodyMotion::kTumbling) {
      return &g_.rotor(i_);
    } else {
      return nullptr;
    }
  }
  Quat q_BP() const {
    if constexpr (Traits::kPrincipalFrame) {
      return g_.q_BP(i_);
    } else {
      return Quat::Identity();
    }
  }
  void stale() {
    if constexpr (Traits::kTurns) g_.entries.plan_ok[i_] = 0;
  }

  Group<K> g_;
  int i_;
  BodyPath<K> path_;
};

}  // namespace rigid::physics::detail
