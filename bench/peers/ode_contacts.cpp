// ODE 0.16 (double precision) on the contact cases (README.md, "Contacts": the settings and why).
// One dWorld and one hash space hold the plane and every copy, the copies 10 m apart along y so
// that the space never pairs two of them; each step collides the space, joins a contact joint per
// point (at most 8 per pair), steps, and empties the contact group, as ODE's demos do.
#include <ode/ode.h>

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "contact_engine.hpp"

namespace rigid::bench::peers {

namespace {

static_assert(std::is_same_v<dReal, double>, "ODE must be a dDOUBLE build");

constexpr int kMaxContacts = 8;  // per body-plane pair
constexpr double kSpacing = 10;  // m between copies along y

void init_ode_once() {
  static const bool ok = dInitODE2(0) != 0;
  if (!ok) throw std::runtime_error("ode: dInitODE2 failed");
}

class OdeContactWorld final : public ContactWorld {
 public:
  OdeContactWorld(const ContactCase& c, bool quick, double dt, int copies, bool record)
      : dt_(dt), quick_(quick), record_(record), mu_(c.friction), bounce_(c.restitution) {
    // QuickStep orders its constraints with ODE's global random generator: the same seed for every
    // world makes runs repeatable.
    if (quick) dRandSetSeed(0);
    world_ = dWorldCreate();
    space_ = dHashSpaceCreate(nullptr);
    group_ = dJointGroupCreate(0);
    dWorldSetGravity(world_, 0, 0, -c.g);
    dWorldSetERP(world_, 0.2);
    dWorldSetCFM(world_, 1e-10);
    dWorldSetAutoDisableFlag(world_, 0);
    dWorldSetLinearDamping(world_, 0);
    dWorldSetAngularDamping(world_, 0);
    if (c.plane) dCreatePlane(space_, 0, 0, 1, 0);
    const Vec3 I = principal_moments(c);
    dMass m;
    dMassSetParameters(&m, c.mass, 0, 0, 0, I.x(), I.y(), I.z(), 0, 0, 0);
    const Quat q = c.start.q_WB.normalized();
    const dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};
    for (int k = 0; k < copies; ++k) {
      const dBodyID b = dBodyCreate(world_);
      dBodySetMass(b, &m);
      const Vec3 p = c.start.p_WBo + Vec3(0, kSpacing * k, 0);
      dBodySetPosition(b, p.x(), p.y(), p.z());
      dBodySetQuaternion(b, dq);
      dBodySetLinearVel(b, c.start.v_WBo.x(), c.start.v_WBo.y(), c.start.v_WBo.z());
      dBodySetAngularVel(b, c.start.w_WB.x(), c.start.w_WB.y(), c.start.w_WB.z());
      dBodySetAutoDisableFlag(b, 0);
      dBodySetLinearDamping(b, 0);
      dBodySetAngularDamping(b, 0);
      const dGeomID g = c.shape == ContactShape::kSphere
                            ? dCreateSphere(space_, c.size)
                            : dCreateBox(space_, c.size, c.size, c.size);
      dGeomSetBody(g, b);
      dGeomSetData(g, reinterpret_cast<void*>(static_cast<std::intptr_t>(k)));
      bodies_.push_back(b);
    }
    feedback_.resize(static_cast<std::size_t>(copies) * kMaxContacts);
    contacts_.resize(copies);
  }

  ~OdeContactWorld() override {
    dJointGroupDestroy(group_);
    dSpaceDestroy(space_);  // destroys its geoms
    dWorldDestroy(world_);  // and its bodies
  }
  OdeContactWorld(const OdeContactWorld&) = delete;
  OdeContactWorld& operator=(const OdeContactWorld&) = delete;

  void step() override {
    if (record_) {
      for (StepContact& s : contacts_)
        s = {};
    }
    dSpaceCollide(space_, this, &OdeContactWorld::near);
    if (quick_) {
      dWorldQuickStep(world_, dt_);
    } else {
      dWorldStep(world_, dt_);
    }
    if (record_) {
      // Each joint's feedback holds the force it applied to its body 1 (the copy) over the step;
      // the plane's normal is z.
      for (std::size_t copy = 0; copy < contacts_.size(); ++copy) {
        for (int i = 0; i < contacts_[copy].points; ++i) {
          contacts_[copy].normal_impulse += dt_ * feedback_[copy * kMaxContacts + i].f1[2];
        }
      }
    }
    dJointGroupEmpty(group_);
  }

  BodyState state(int i) const override {
    const dBodyID b = bodies_[i];
    const dReal* q = dBodyGetQuaternion(b);  // w, x, y, z
    const dReal* p = dBodyGetPosition(b);
    const dReal* v = dBodyGetLinearVel(b);
    const dReal* w = dBodyGetAngularVel(b);
    BodyState s;
    s.p_WBo = Vec3(p[0], p[1] - kSpacing * i, p[2]);
    s.q_WB = Quat(q[0], q[1], q[2], q[3]).normalized();
    s.v_WBo = Vec3(v[0], v[1], v[2]);
    s.w_WB = Vec3(w[0], w[1], w[2]);
    return s;
  }

  StepContact contact(int i) const override { return contacts_[i]; }

 private:
  static void near(void* self, dGeomID a, dGeomID b) {
    static_cast<OdeContactWorld*>(self)->collide(a, b);
  }

  void collide(dGeomID a, dGeomID b) {
    if (dGeomGetBody(a) && dGeomGetBody(b)) return;  // two copies: kept apart, never in contact
    if (!dGeomGetBody(a)) std::swap(a, b);  // the body's geom first: the joint's body 1 is it
    const dBodyID body = dGeomGetBody(a);
    if (!body) return;
    dContact contact[kMaxContacts];
    const int n = dCollide(a, b, kMaxContacts, &contact[0].geom, sizeof(dContact));
    const auto copy = static_cast<std::size_t>(reinterpret_cast<std::intptr_t>(dGeomGetData(a)));
    for (int i = 0; i < n; ++i) {
      dSurfaceParameters& s = contact[i].surface;
      s.mode = dContactBounce | dContactApprox1;
      s.mu = mu_;
      s.bounce = bounce_;
      s.bounce_vel = 0;  // restitution at any approach speed
      const dJointID j = dJointCreateContact(world_, group_, &contact[i]);
      dJointAttach(j, body, nullptr);
      if (record_) dJointSetFeedback(j, &feedback_[copy * kMaxContacts + i]);
    }
    if (record_) contacts_[copy].points = n;
  }

  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  dJointGroupID group_ = nullptr;
  double dt_;
  bool quick_, record_;
  // The pair's surface: ODE takes it per contact, as given (it combines no materials).
  double mu_, bounce_;
  std::vector<dBodyID> bodies_;
  std::vector<dJointFeedback> feedback_;
  std::vector<StepContact> contacts_;
};

class OdeContactEngine final : public ContactEngine {
 public:
  OdeContactEngine() { init_ode_once(); }
  std::string name() const override { return "ode"; }
  std::string version() const override {
    return std::string("ODE ") + RIGID_ODE_VERSION + " (" + dGetConfiguration() + ")";
  }
  std::vector<std::string> modes() const override { return {"step", "quick"}; }
  std::string settings(const std::string& mode) const override {
    return std::string(mode == "quick" ? "dWorldQuickStep (20 iterations, dRandSetSeed(0))"
                                       : "dWorldStep") +
           "; dContactBounce (bounce e, bounce_vel 0) | dContactApprox1 (mu), ERP 0.2, CFM "
           "1e-10, up to 8 contacts per pair, dHashSpace, auto-disable off, damping 0";
  }
  std::unique_ptr<ContactWorld> make_world(const ContactCase& c, const std::string& mode, double dt,
                                           int copies, bool record) const override {
    if (mode != "step" && mode != "quick") throw std::runtime_error("ode: unknown mode " + mode);
    return std::make_unique<OdeContactWorld>(c, mode == "quick", dt, copies, record);
  }
};

}  // namespace

std::unique_ptr<ContactEngine> make_ode_contact_engine() {
  return std::make_unique<OdeContactEngine>();
}

}  // namespace rigid::bench::peers
