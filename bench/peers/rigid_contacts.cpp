// Ours behind the contact interface: a physics::World built from the case's WorldSpec (the body's
// collision shape and surface, the plane as a static part), timed and scored by the same code as
// the peers. Its impacts and rests are the World's contact events: located inside the step, at the
// world's time they happen. contact(): the step's events (points) and the sum of their impulses
// along their normals.
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "contact_engine.hpp"

namespace rigid::bench::peers {

physics::WorldSpec contact_world_spec(const ContactCase& c, const std::string& integrator,
                                      double dt, int copies) {
  physics::WorldSpec spec;
  spec.g_W = Vec3(0, 0, -c.g);
  spec.dt = dt;
  spec.integrator = integrator;
  // A pair takes the larger restitution and the geometric mean of the frictions
  // (contact/static_part.hpp): the plane with the body's surface gives the pair exactly it.
  const physics::Surface surface{c.restitution, c.friction};
  for (int k = 0; k < copies; ++k) {
    physics::BodySpec b;
    b.name = "b" + std::to_string(k);
    b.mass = c.mass;
    b.I_B = principal_moments(c).asDiagonal();
    // Copies overlap: each one meets the static parts only (no group in another's mask).
    b.p_WBo = c.start.p_WBo;
    b.collision_group = 0;
    b.q_WB = c.start.q_WB;
    b.v_WBo = c.start.v_WBo;
    b.w_WB = c.start.w_WB;
    b.shape = shape_of(c);
    b.surface = surface;
    spec.bodies.push_back(b);
  }
  if (c.plane) {
    spec.planes.push_back(physics::PlaneSpec{"ground", Vec3::UnitZ(), 0.0, surface});
  }
  return spec;
}

namespace {

LocatedEvent::Kind kind_of(physics::ContactEventKind k) {
  switch (k) {
    case physics::ContactEventKind::kImpact:
      return LocatedEvent::Kind::kImpact;
    case physics::ContactEventKind::kResting:
      return LocatedEvent::Kind::kResting;
    default:
      return LocatedEvent::Kind::kOther;
  }
}

class RigidContactWorld final : public ContactWorld {
 public:
  RigidContactWorld(const physics::WorldSpec& spec, bool record)
      : world_(spec), record_(record), events_(spec.bodies.size()), contacts_(spec.bodies.size()) {}

  void step() override {
    world_.step();
    if (!record_) return;
    for (auto& e : events_)
      e.clear();
    for (StepContact& c : contacts_)
      c = {};
    // The World's events of the step, each at the world's time it happened.
    for (const physics::ContactEvent& e : world_.contact_events()) {
      const double normal = e.impulse_W.dot(e.n_W);
      events_[e.body].push_back({kind_of(e.kind), e.time, normal});
      ++contacts_[e.body].points;
      contacts_[e.body].normal_impulse += normal;
    }
  }

  // A body the World's guard froze (it diverged) reads as NaN, as for the peers.
  BodyState state(int i) const override {
    return world_.is_frozen(i) ? nan_state() : world_.state(i);
  }
  StepContact contact(int i) const override { return contacts_[i]; }
  std::span<const LocatedEvent> events(int i) const override { return events_[i]; }

 private:
  physics::World world_;
  bool record_;
  std::vector<std::vector<LocatedEvent>> events_;  // per copy, of the last step
  std::vector<StepContact> contacts_;
};

class RigidContactEngine final : public ContactEngine {
 public:
  std::string name() const override { return "rigid"; }
  std::string version() const override { return "rigid (this tree)"; }
  std::vector<std::string> modes() const override {
    return {std::string(physics::default_integrator().name)};
  }
  std::string settings(const std::string& mode) const override {
    return "physics::World from the case's WorldSpec (the body's shape and surface, the plane as "
           "a static part with the same surface), integrator " +
           mode + "; impacts and rest from its contact events";
  }
  // The World locates impacts and the start of rest inside its step (contact_events()).
  bool locates_events() const override { return true; }
  std::unique_ptr<ContactWorld> make_world(const ContactCase& c, const std::string& mode, double dt,
                                           int copies, bool record) const override {
    if (!physics::find_integrator(mode)) throw std::runtime_error("rigid: unknown mode " + mode);
    return std::make_unique<RigidContactWorld>(contact_world_spec(c, mode, dt, copies), record);
  }
};

}  // namespace

std::unique_ptr<ContactEngine> make_rigid_contact_engine() {
  return std::make_unique<RigidContactEngine>();
}

}  // namespace rigid::bench::peers
