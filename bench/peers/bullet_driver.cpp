// Bullet 3.24 (double precision) driven on the hard cases (see README.md for what each mode does
// and why). One btDiscreteDynamicsWorld holds every copy, as a Bullet user would write it;
// collisions between the copies are filtered out in the broadphase (mask 0), so no contact is
// ever made and each body moves as a free body.
#include <btBulletDynamicsCommon.h>

#include <limits>
#include <memory>
#include <stdexcept>

#include "peer_body.hpp"
#include "peer_engine.hpp"

namespace rigid::bench::peers {

namespace {

static_assert(sizeof(btScalar) == sizeof(double),
              "link Bullet's -float64 libraries and define BT_USE_DOUBLE_PRECISION");

struct Mode {
  int flags = 0;           // btRigidBodyFlags: which gyroscopic force, if any
  bool unclamped = false;  // lift the solver's clamp of the explicit gyroscopic force
};

Mode parse_mode(const std::string& name) {
  if (name == "nogyro") return {0, false};
  if (name == "gyro_explicit") return {BT_ENABLE_GYROSCOPIC_FORCE_EXPLICIT, false};
  if (name == "gyro_explicit_unclamped") return {BT_ENABLE_GYROSCOPIC_FORCE_EXPLICIT, true};
  if (name == "gyro_implicit") return {BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY, false};
  if (name == "gyro_implicit_world") return {BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_WORLD, false};
  throw std::runtime_error("bullet: unknown mode '" + name + "'");
}

btVector3 bt(const Vec3& v) {
  return btVector3(v.x(), v.y(), v.z());
}
Vec3 ours(const btVector3& v) {
  return Vec3(v.x(), v.y(), v.z());
}

class BulletWorld final : public PeerWorld {
 public:
  BulletWorld(const Case& c, const Mode& mode, double dt, int copies)
      : dt_(dt), loads_(c.loads), c_(c.body.linear_drag), k_(c.body.angular_drag) {
    world_.setGravity(bt(gravity_of(c)));
    if (mode.unclamped) {
      world_.getSolverInfo().m_maxGyroscopicForce = std::numeric_limits<double>::infinity();
    }
    const Vec3 I = principal_moments(c);
    const Quat q = c.body.q_WB.normalized();
    btRigidBody::btRigidBodyConstructionInfo info(c.body.mass, nullptr, &shape_, bt(I));
    info.m_startWorldTransform =
        btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), bt(c.body.p_WBo));
    info.m_linearDamping = 0;
    info.m_angularDamping = 0;
    info.m_linearSleepingThreshold = 0;
    info.m_angularSleepingThreshold = 0;
    for (int k = 0; k < copies; ++k) {
      auto b = std::make_unique<btRigidBody>(info);
      b->setLinearVelocity(bt(c.body.v_WBo));
      b->setAngularVelocity(bt(c.body.w_WB));
      b->setActivationState(DISABLE_DEACTIVATION);
      b->setFlags(mode.flags);  // replaces the default, BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY
      // Group 1, mask 0: the broadphase never pairs this body with anything.
      world_.addRigidBody(b.get(), 1, 0);
      bodies_.push_back(std::move(b));
    }
  }

  ~BulletWorld() override {
    for (const auto& b : bodies_)
      world_.removeRigidBody(b.get());
  }
  BulletWorld(const BulletWorld&) = delete;
  BulletWorld& operator=(const BulletWorld&) = delete;

  void step() override {
    for (const auto& b : bodies_) {
      const btMatrix3x3& R = b->getCenterOfMassTransform().getBasis();
      // applyForce takes a world-frame force and its point as a world-frame arm from the centre
      // of mass; Bullet clears applied forces after every stepSimulation.
      for (const LoadSpec& l : loads_) {
        const btVector3 f_B = bt(l.force);
        const btVector3 f_W = l.frame == Frame::kWorld ? f_B : R * f_B;
        if (!l.force.isZero()) b->applyForce(f_W, R * bt(l.p_BoQ_B));
        if (!l.torque.isZero()) {
          b->applyTorque(l.torque_frame == Frame::kWorld ? bt(l.torque) : R * bt(l.torque));
        }
      }
      if (c_ > 0) b->applyCentralForce(-c_ * b->getLinearVelocity());
      if (k_ > 0) b->applyTorque(-k_ * b->getAngularVelocity());
    }
    // maxSubSteps = 0: exactly one step of dt, no fixed-step accumulator, no interpolation.
    world_.stepSimulation(dt_, 0);
  }

  BodyState state(int i) const override {
    const btRigidBody& b = *bodies_[i];
    const btQuaternion q = b.getOrientation();
    BodyState s;
    s.p_WBo = ours(b.getCenterOfMassPosition());
    s.q_WB = Quat(q.w(), q.x(), q.y(), q.z()).normalized();
    s.v_WBo = ours(b.getLinearVelocity());
    s.w_WB = ours(b.getAngularVelocity());
    return s;
  }

 private:
  double dt_;
  std::vector<LoadSpec> loads_;
  double c_, k_;  // drag, applied as user forces
  // Declared in construction order; the bodies are removed from the world before it dies.
  btDefaultCollisionConfiguration config_;
  btCollisionDispatcher dispatcher_{&config_};
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  btDiscreteDynamicsWorld world_{&dispatcher_, &broadphase_, &solver_, &config_};
  btSphereShape shape_{0.1};  // needed by Bullet, never collides, carries no inertia
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
};

class BulletEngine final : public PeerEngine {
 public:
  std::string name() const override { return "bullet"; }

  std::string version() const override {
    const int v = btGetVersion();
    return "Bullet " + std::to_string(v / 100) + "." + std::to_string(v % 100) +
           " (btScalar double, BT_USE_DOUBLE_PRECISION)";
  }

  std::vector<std::string> modes(const Case&) const override {
    return {"nogyro", "gyro_explicit", "gyro_explicit_unclamped", "gyro_implicit",
            "gyro_implicit_world"};
  }

  std::unique_ptr<PeerWorld> make_world(const Case& c, const std::string& mode, double dt,
                                        int copies) const override {
    return std::make_unique<BulletWorld>(c, parse_mode(mode), dt, copies);
  }
};

}  // namespace

std::unique_ptr<PeerEngine> make_bullet_engine() {
  return std::make_unique<BulletEngine>();
}

}  // namespace rigid::bench::peers
