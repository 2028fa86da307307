// ODE 0.16 (double precision) driven on the hard cases (see README.md for what each mode does
// and why). One dWorld holds every copy; without geoms there is no collision at all.
#include <ode/ode.h>

#include <memory>
#include <stdexcept>
#include <type_traits>

#include "peer_body.hpp"
#include "peer_engine.hpp"

namespace rigid::bench::peers {

namespace {

static_assert(std::is_same_v<dReal, double>, "ODE must be a dDOUBLE build");

struct Mode {
  bool gyroscopic = false;  // dBodySetGyroscopicMode
  bool finite = false;      // dBodySetFiniteRotationMode: exact rotation of the orientation
};

Mode parse_mode(const std::string& name) {
  if (name == "nogyro") return {false, false};
  if (name == "gyro") return {true, false};
  if (name == "gyro_finite") return {true, true};
  throw std::runtime_error("ode: unknown mode '" + name + "'");
}

Vec3 ours(const dReal* v) {
  return Vec3(v[0], v[1], v[2]);
}

void init_ode_once() {
  static const bool ok = dInitODE2(0) != 0;
  if (!ok) throw std::runtime_error("ode: dInitODE2 failed");
}

class OdeWorld final : public PeerWorld {
 public:
  OdeWorld(const Case& c, const Mode& mode, double dt, int copies)
      : world_(dWorldCreate()),
        dt_(dt),
        loads_(c.loads),
        c_(c.body.linear_drag),
        k_(c.body.angular_drag) {
    const Vec3 g = gravity_of(c);
    dWorldSetGravity(world_, g.x(), g.y(), g.z());
    dWorldSetAutoDisableFlag(world_, 0);
    dWorldSetLinearDamping(world_, 0);
    dWorldSetAngularDamping(world_, 0);
    const Vec3 I = principal_moments(c);
    dMass m;
    // Centre of mass at the body origin, inertia about it in the body frame.
    dMassSetParameters(&m, c.body.mass, 0, 0, 0, I.x(), I.y(), I.z(), 0, 0, 0);
    const Quat q = c.body.q_WB.normalized();
    const dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};
    for (int k = 0; k < copies; ++k) {
      const dBodyID b = dBodyCreate(world_);
      dBodySetMass(b, &m);
      dBodySetPosition(b, c.body.p_WBo.x(), c.body.p_WBo.y(), c.body.p_WBo.z());
      dBodySetQuaternion(b, dq);
      dBodySetLinearVel(b, c.body.v_WBo.x(), c.body.v_WBo.y(), c.body.v_WBo.z());
      dBodySetAngularVel(b, c.body.w_WB.x(), c.body.w_WB.y(), c.body.w_WB.z());
      dBodySetAutoDisableFlag(b, 0);
      dBodySetLinearDamping(b, 0);
      dBodySetAngularDamping(b, 0);
      dBodySetGyroscopicMode(b, mode.gyroscopic ? 1 : 0);
      dBodySetFiniteRotationMode(b, mode.finite ? 1 : 0);
      bodies_.push_back(b);
    }
  }

  ~OdeWorld() override { dWorldDestroy(world_); }  // destroys the bodies too
  OdeWorld(const OdeWorld&) = delete;
  OdeWorld& operator=(const OdeWorld&) = delete;

  void step() override {
    for (const dBodyID b : bodies_) {
      // ODE takes a force at a body-relative point directly, in either frame; its accumulators
      // are cleared by every dWorldStep.
      for (const LoadSpec& l : loads_) {
        const Vec3& f = l.force;
        const Vec3& p = l.p_BoQ_B;
        if (!f.isZero()) {
          if (l.frame == Frame::kWorld) {
            dBodyAddForceAtRelPos(b, f.x(), f.y(), f.z(), p.x(), p.y(), p.z());
          } else {
            dBodyAddRelForceAtRelPos(b, f.x(), f.y(), f.z(), p.x(), p.y(), p.z());
          }
        }
        const Vec3& t = l.torque;
        if (!t.isZero()) {
          if (l.torque_frame == Frame::kWorld) {
            dBodyAddTorque(b, t.x(), t.y(), t.z());
          } else {
            dBodyAddRelTorque(b, t.x(), t.y(), t.z());
          }
        }
      }
      if (c_ > 0) {
        const dReal* v = dBodyGetLinearVel(b);
        dBodyAddForce(b, -c_ * v[0], -c_ * v[1], -c_ * v[2]);
      }
      if (k_ > 0) {
        const dReal* w = dBodyGetAngularVel(b);
        dBodyAddTorque(b, -k_ * w[0], -k_ * w[1], -k_ * w[2]);
      }
    }
    dWorldStep(world_, dt_);
  }

  BodyState state(int i) const override {
    const dBodyID b = bodies_[i];
    const dReal* q = dBodyGetQuaternion(b);  // w, x, y, z
    BodyState s;
    s.p_WBo = ours(dBodyGetPosition(b));
    s.q_WB = Quat(q[0], q[1], q[2], q[3]).normalized();
    s.v_WBo = ours(dBodyGetLinearVel(b));
    s.w_WB = ours(dBodyGetAngularVel(b));
    return s;
  }

 private:
  dWorldID world_;
  double dt_;
  std::vector<LoadSpec> loads_;
  double c_, k_;  // drag, applied as user forces
  std::vector<dBodyID> bodies_;
};

class OdeEngine final : public PeerEngine {
 public:
  OdeEngine() { init_ode_once(); }

  std::string name() const override { return "ode"; }

  std::string version() const override {
    return std::string("ODE ") + RIGID_ODE_VERSION + " (" + dGetConfiguration() + ")";
  }

  std::vector<std::string> modes(const Case&) const override {
    return {"nogyro", "gyro", "gyro_finite"};
  }

  std::unique_ptr<PeerWorld> make_world(const Case& c, const std::string& mode, double dt,
                                        int copies) const override {
    return std::make_unique<OdeWorld>(c, parse_mode(mode), dt, copies);
  }
};

}  // namespace

std::unique_ptr<PeerEngine> make_ode_engine() {
  return std::make_unique<OdeEngine>();
}

}  // namespace rigid::bench::peers
