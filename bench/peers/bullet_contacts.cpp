// Bullet 3.24 (double precision) on the contact cases (README.md, "Contacts": the settings and
// why). One btDiscreteDynamicsWorld holds a static plane and every copy, the copies 10 m apart
// along y and filtered so that they only ever pair with the plane.
#include <btBulletDynamicsCommon.h>

#include <memory>
#include <stdexcept>
#include <vector>

#include "contact_engine.hpp"

namespace rigid::bench::peers {

namespace {

static_assert(sizeof(btScalar) == sizeof(double),
              "link Bullet's -float64 libraries and define BT_USE_DOUBLE_PRECISION");

constexpr double kSpacing = 10;  // m between copies along y
// Collision groups: the copies collide with the plane only.
constexpr int kGroundGroup = 1, kBodyGroup = 2;

btVector3 bt(const Vec3& v) {
  return btVector3(v.x(), v.y(), v.z());
}

class BulletContactWorld final : public ContactWorld {
 public:
  BulletContactWorld(const ContactCase& c, bool tuned, double dt, int copies, bool record)
      : dt_(dt), record_(record) {
    if (tuned) {
      // A box on a plane gets its full manifold (up to 4 points) from the first touching step
      // instead of one point a step: the plane-convex algorithm perturbs the body to find more.
      // Set before the dispatcher reads the algorithms.
      config_.setPlaneConvexMultipointIterations();
    }
    dispatcher_ = std::make_unique<btCollisionDispatcher>(&config_);
    world_ = std::make_unique<btDiscreteDynamicsWorld>(dispatcher_.get(), &broadphase_, &solver_,
                                                       &config_);
    world_->setGravity(btVector3(0, 0, -c.g));
    if (tuned) {
      btContactSolverInfo& info = world_->getSolverInfo();
      info.m_numIterations = 100;
      info.m_restitutionVelocityThreshold = 0;      // restitution at any approach speed
      info.m_splitImpulsePenetrationThreshold = 0;  // every penetration resolved apart
    }
    if (c.plane) {
      // Bullet multiplies the two sides' restitution and friction: the ground's 1 leaves the
      // body's.
      btRigidBody::btRigidBodyConstructionInfo ground(0, nullptr, &plane_);
      ground.m_restitution = 1;
      ground.m_friction = 1;
      ground_ = std::make_unique<btRigidBody>(ground);
      world_->addRigidBody(ground_.get(), kGroundGroup, kBodyGroup);
    }
    if (c.shape == ContactShape::kSphere) {
      shape_ = std::make_unique<btSphereShape>(c.size);
    } else {
      // Bullet's default margin (0.04 m) is inside the half extents: the box keeps its size
      // and has rounded edges.
      const double h = 0.5 * c.size;
      shape_ = std::make_unique<btBoxShape>(btVector3(h, h, h));
    }
    const Quat q = c.start.q_WB.normalized();
    btRigidBody::btRigidBodyConstructionInfo info(c.mass, nullptr, shape_.get(),
                                                  bt(principal_moments(c)));
    info.m_linearDamping = 0;
    info.m_angularDamping = 0;
    info.m_linearSleepingThreshold = 0;
    info.m_angularSleepingThreshold = 0;
    info.m_restitution = c.restitution;
    info.m_friction = c.friction;
    for (int k = 0; k < copies; ++k) {
      info.m_startWorldTransform = btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()),
                                               bt(c.start.p_WBo + Vec3(0, kSpacing * k, 0)));
      auto b = std::make_unique<btRigidBody>(info);
      b->setLinearVelocity(bt(c.start.v_WBo));
      b->setAngularVelocity(bt(c.start.w_WB));
      b->setActivationState(DISABLE_DEACTIVATION);
      b->setUserIndex(k);
      world_->addRigidBody(b.get(), kBodyGroup, kGroundGroup);
      bodies_.push_back(std::move(b));
    }
    contacts_.resize(copies);
  }

  ~BulletContactWorld() override {
    for (const auto& b : bodies_)
      world_->removeRigidBody(b.get());
    if (ground_) world_->removeRigidBody(ground_.get());
  }
  BulletContactWorld(const BulletContactWorld&) = delete;
  BulletContactWorld& operator=(const BulletContactWorld&) = delete;

  void step() override {
    // maxSubSteps = 0: exactly one step of dt, no fixed-step accumulator, no interpolation.
    world_->stepSimulation(dt_, 0);
    if (!record_) return;
    for (StepContact& s : contacts_)
      s = {};
    // The manifolds the solver used this step: their points' applied impulses (N s, along each
    // point's normal, which points from the plane to the body).
    for (int m = 0; m < dispatcher_->getNumManifolds(); ++m) {
      const btPersistentManifold* pm = dispatcher_->getManifoldByIndexInternal(m);
      const btCollisionObject* body =
          pm->getBody0() == ground_.get() ? pm->getBody1() : pm->getBody0();
      StepContact& s = contacts_[body->getUserIndex()];
      for (int p = 0; p < pm->getNumContacts(); ++p) {
        ++s.points;
        s.normal_impulse += pm->getContactPoint(p).getAppliedImpulse();
      }
    }
  }

  BodyState state(int i) const override {
    const btRigidBody& b = *bodies_[i];
    const btQuaternion q = b.getOrientation();
    const btVector3 p = b.getCenterOfMassPosition(), v = b.getLinearVelocity(),
                    w = b.getAngularVelocity();
    BodyState s;
    s.p_WBo = Vec3(p.x(), p.y() - kSpacing * i, p.z());
    s.q_WB = Quat(q.w(), q.x(), q.y(), q.z()).normalized();
    s.v_WBo = Vec3(v.x(), v.y(), v.z());
    s.w_WB = Vec3(w.x(), w.y(), w.z());
    return s;
  }

  StepContact contact(int i) const override { return contacts_[i]; }

 private:
  double dt_;
  bool record_;
  // Declared in construction order; the bodies are removed from the world before it dies.
  btDefaultCollisionConfiguration config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  btDbvtBroadphase broadphase_;
  btSequentialImpulseConstraintSolver solver_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  btStaticPlaneShape plane_{btVector3(0, 0, 1), 0};
  std::unique_ptr<btConvexShape> shape_;
  std::unique_ptr<btRigidBody> ground_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::vector<StepContact> contacts_;
};

class BulletContactEngine final : public ContactEngine {
 public:
  std::string name() const override { return "bullet"; }
  std::string version() const override {
    const int v = btGetVersion();
    return "Bullet " + std::to_string(v / 100) + "." + std::to_string(v % 100) +
           " (btScalar double, BT_USE_DOUBLE_PRECISION)";
  }
  std::vector<std::string> modes() const override { return {"default", "tuned"}; }
  std::string settings(const std::string& mode) const override {
    const std::string common =
        "stepSimulation(dt, 0); ground restitution and friction 1 (Bullet multiplies them), "
        "body e and mu; deactivation off, damping 0; box margin 0.04 m (default)";
    if (mode == "tuned") {
      return common +
             "; 100 iterations, restitution threshold 0, split-impulse threshold 0, "
             "setPlaneConvexMultipointIterations() (a full box-plane manifold at once)";
    }
    return common +
           "; solver defaults (10 iterations, restitution above 0.2 m/s, split "
           "impulses past 0.04 m)";
  }
  std::unique_ptr<ContactWorld> make_world(const ContactCase& c, const std::string& mode, double dt,
                                           int copies, bool record) const override {
    if (mode != "default" && mode != "tuned") {
      throw std::runtime_error("bullet: unknown mode " + mode);
    }
    return std::make_unique<BulletContactWorld>(c, mode == "tuned", dt, copies, record);
  }
};

}  // namespace

std::unique_ptr<ContactEngine> make_bullet_contact_engine() {
  return std::make_unique<BulletContactEngine>();
}

}  // namespace rigid::bench::peers
