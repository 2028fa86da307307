// World's edges: states in and out (about the centre of mass, in W and B, where the groups keep
// them in P), applied loads and impulses, reset, and every other accessor.
#include <algorithm>

#include "physics/inertia.hpp"
#include "physics/world_impl.hpp"

namespace rigid::physics {

using detail::Loads;
using detail::Motion;

// --- frames and momenta of one body ---

Quat World::Impl::rot_BP(int id) const {
  return with_body(id, [](auto g, int i) -> Quat {
    if constexpr (decltype(g)::Traits::kPrincipalFrame) {
      return g.q_BP(i);
    } else {
      (void)g, (void)i;
      return Quat::Identity();
    }
  });
}

Vec3 World::Impl::omega_P(int id) const {
  return with_body(id, [](auto g, int i) -> Vec3 {
    if constexpr (decltype(g)::Traits::kTurns) {
      return g.rot(i).omega(g.motion(i).spin);
    } else {
      (void)g, (void)i;
      return Vec3::Zero();
    }
  });
}

Vec3 World::Impl::angular_momentum_P(int id) const {
  return with_body(id, [&](auto g, int i) -> Vec3 {
    using G = decltype(g);
    const Motion& m = g.motion(i);
    if constexpr (G::kKind == BodyMotion::kSteadySpin) {
      const detail::SpinRot& r = g.rot(i);
      // A kinematic body has no inertia to speak of: report what its spec's tensor would give.
      if (r.inv_I == 0.0) return model().specs.params(id).I_B * m.spin;
      return m.spin / r.inv_I;
    } else if constexpr (G::Traits::kTurns) {
      return m.spin;  // the angular momentum itself
    } else {
      (void)m;
      return Vec3::Zero();
    }
  });
}

// --- states ---

void World::Impl::set_state(int id, const BodyState& st) {
  const detail::SpecStore::Params& b = model().specs.params(id);
  with_body(id, [&](auto g, int i) {
    using G = decltype(g);
    Motion& m = g.motion(i);
    m.x = st.p_WBo;
    m.v = st.v_WBo;
    for (int a = 0; a < 3; ++a) {
      if (!allows(b.allowed_dofs, translation_dof(a)) && !b.kinematic()) m.v[a] = 0.0;
    }
    if constexpr (!G::Traits::kTurns) {
      // A body that never turns keeps its orientation.
      m.q = st.q_WB.normalized();
      m.spin.setZero();
    } else {
      Quat q_BP = Quat::Identity();
      if constexpr (G::Traits::kPrincipalFrame) q_BP = g.q_BP(i);
      m.q = (st.q_WB.normalized() * q_BP).normalized();
      const Vec3 w_P = m.q.conjugate() * st.w_WB;
      if constexpr (G::kKind == BodyMotion::kSteadySpin) {
        const detail::SpinRot& r = g.rot(i);
        m.spin = r.hinge != 0.0 ? Vec3(r.axis * r.axis.dot(w_P)) : w_P;
      } else {
        m.spin = g.rot(i).spin_of(w_P);
      }
    }
  });
  invalidate_cache(id);
  contact_state_set(id);
}

BodyState World::state(int id) const {
  impl_->check_id(id);
  const Motion& m = impl_->motion(id);
  BodyState s;
  s.p_WBo = m.x;
  s.v_WBo = m.v;
  if (impl_->model().motion[id] == BodyMotion::kTranslation) {
    s.q_WB = m.q;
    s.w_WB.setZero();
  } else {
    s.q_WB = m.q * impl_->rot_BP(id).conjugate();
    s.w_WB = rotate(m.q, impl_->omega_P(id));
  }
  return s;
}

namespace {

// Entries [begin, end) of the groups in write order (each group's entries in turn) into rows, at
// their body ids.
struct StateWriter {
  const detail::Model& model;
  const detail::Data& data;
  StateRows rows;

  void put(int id, const Motion& m, const Quat& q_WB, const Vec3& w_WB) const {
    const auto k = static_cast<std::size_t>(id);
    double* p = rows.p_WBo + 3 * k;
    double* q = rows.q_WB_wxyz + 4 * k;
    double* v = rows.v_WBo + 3 * k;
    double* o = rows.w_WB + 3 * k;
    p[0] = m.x.x(), p[1] = m.x.y(), p[2] = m.x.z();
    q[0] = q_WB.w(), q[1] = q_WB.x(), q[2] = q_WB.y(), q[3] = q_WB.z();
    v[0] = m.v.x(), v[1] = m.v.y(), v[2] = m.v.z();
    o[0] = w_WB.x(), o[1] = w_WB.y(), o[2] = w_WB.z();
  }

  // The same expressions as World::state(id), per group, so that both give the same bits.
  void write(int begin, int end) const {
    int base = 0;
    detail::for_each_group([&](auto kind) {
      const auto g = detail::group(model, data, kind);
      using G = decltype(g);
      const int lo = std::max(begin - base, 0), hi = std::min(end - base, g.size());
      base += g.size();
      for (int k = lo; k < hi; ++k) {
        const Motion& m = g.motion(k);
        if constexpr (!G::Traits::kTurns) {
          put(g.entries.id[k], m, m.q, Vec3::Zero());
        } else {
          Quat q_BP = Quat::Identity();
          if constexpr (G::Traits::kPrincipalFrame) q_BP = g.q_BP(k);
          put(g.entries.id[k], m, m.q * q_BP.conjugate(), rotate(m.q, g.rot(k).omega(m.spin)));
        }
      }
    });
  }
};

}  // namespace

void World::write_states(const StateRows& rows) const {
  const Impl& w = *impl_;
  const StateWriter writer{w.model(), w.data, rows};
  const int bodies = w.body_count();
  // A large world's states are written on the step's threads too, in chunks they claim: what
  // each body's rows hold does not depend on which thread wrote them. (rigidd writes every state
  // it publishes on its loop thread: what that costs at 10^5 bodies is in bench/notes/
  // loop-latency.md, "Writing the state".)
  const int chunks = std::min(bodies / kBodiesPerWriteChunk, detail::Pool::kMaxChunks);
  if (!w.pool.pool || w.threads < 2 || chunks < 2) {
    writer.write(0, bodies);
    return;
  }
  struct Job {
    const StateWriter& writer;
    int bodies, chunks;
  } job{writer, bodies, chunks};
  w.pool.pool->run(
      [](void* ctx, int c) {
        const Job& j = *static_cast<const Job*>(ctx);
        const auto at = [&](int k) {
          return static_cast<int>(std::int64_t{j.bodies} * k / j.chunks);
        };
        j.writer.write(at(c), at(c + 1));
      },
      &job, chunks);
}

void World::set_state(int id, const BodyState& s) {
  impl_->check_id(id);
  if (!s.p_WBo.allFinite() || !s.v_WBo.allFinite() || !s.w_WB.allFinite() ||
      !s.q_WB.coeffs().allFinite() || s.q_WB.norm() < 1e-6) {
    throw std::invalid_argument("set_state: body '" + std::string(impl_->model().specs.name(id)) +
                                "': the state must be finite, with a non-zero quaternion");
  }
  impl_->set_state(id, s);
}

void World::reset() {
  Impl& w = *impl_;
  detail::Data& d = w.data;
  d.steps = 0;
  d.large_rotations = 0;
  w.thaw_all();
  const detail::SpecStore& b = w.model().specs;
  for (int i = 0; i < body_count(); ++i)
    w.set_state(i, BodyState{b.p_WBo(i), b.q_WB(i), b.v_WBo(i), b.w_WB(i)});
  for (const detail::PendingImpulse& p : d.pending)
    d.pending_slot[p.id] = -1;
  d.pending.clear();
  clear_applied();
  w.reset_contacts();
  for (int i = 0; i < body_count(); ++i)
    d.last_good[i] = detail::GuardPose(w.motion(i).q, w.motion(i).x);
}

// --- loads and impulses ---

void World::clear_applied() {
  Impl& w = *impl_;
  const detail::SceneLoads& scene = w.model().scene_loads;
  std::size_t k = 0;  // walks scene.ids, ascending like i
  for (int i = 0; i < body_count(); ++i) {
    const bool has_scene = k < scene.ids.size() && scene.ids[k] == i;
    const int b = has_scene ? scene.of[k++] : -1;
    const bool was_quiet = w.load(i).quiet();
    w.set_scene_loads(i, w.data.frozen[i] ? -1 : b);
    w.loads_changed(i, was_quiet);
  }
}

void World::clear_applied(int id) {
  Impl& w = *impl_;
  w.check_id(id);
  const bool was_quiet = w.load(id).quiet();
  w.set_scene_loads(id, w.data.frozen[id] ? -1 : w.model().scene_loads.index(id));
  w.loads_changed(id, was_quiet);
}

void World::add_force(int id, const Vec3& f, const Vec3& p_BoQ_B, Frame frame) {
  Impl& w = *impl_;
  w.check_id(id);
  if (w.model().specs.params(id).kinematic() || w.data.frozen[id]) return;
  const Quat q_PB = w.rot_BP(id).conjugate();
  const bool body = frame == Frame::kBody;
  const bool was_quiet = w.load(id).quiet();
  Loads v = w.load_value(id);
  v.add_force(body ? Vec3(q_PB * f) : f, q_PB * p_BoQ_B, body);
  w.set_loads(id, v);
  w.loads_changed(id, was_quiet);
}

void World::add_torque(int id, const Vec3& tau, Frame frame) {
  Impl& w = *impl_;
  w.check_id(id);
  if (w.model().specs.params(id).kinematic() || w.data.frozen[id]) return;
  const bool body = frame == Frame::kBody;
  const bool was_quiet = w.load(id).quiet();
  Loads v = w.load_value(id);
  v.add_torque(body ? Vec3(w.rot_BP(id).conjugate() * tau) : tau, body);
  w.set_loads(id, v);
  w.loads_changed(id, was_quiet);
}

void World::apply_impulse(int id, const Vec3& J, const Vec3& p_BoQ_B, Frame frame) {
  Impl& w = *impl_;
  w.check_id(id);
  if (w.model().specs.params(id).kinematic() || w.data.frozen[id]) return;
  const BodyState s = state(id);
  const Vec3 J_W = frame == Frame::kBody ? Vec3(s.q_WB * J) : J;
  const Vec3 r_W = s.q_WB * p_BoQ_B;
  detail::Data& d = w.data;
  if (d.pending_slot[id] < 0) {
    d.pending_slot[id] = static_cast<int>(d.pending.size());
    d.pending.push_back(detail::PendingImpulse{id, Vec3::Zero(), Vec3::Zero()});  // reserved
  }
  detail::PendingImpulse& p = d.pending[d.pending_slot[id]];
  p.J += J_W;
  p.L += r_W.cross(J_W);
}

// --- the rest ---

double World::dt() const {
  return impl_->model().dt;
}
std::int64_t World::large_rotation_steps() const {
  return impl_->data.large_rotations;
}
double World::time() const {
  return static_cast<double>(impl_->data.steps) * impl_->model().dt;
}
std::int64_t World::step_count() const {
  return impl_->data.steps;
}
const IntegratorInfo& World::integrator() const {
  return *impl_->model().integrator;
}
int World::body_count() const {
  return impl_->body_count();
}

int World::find_body(std::string_view name) const {
  const detail::Model& m = impl_->model();
  const auto it =
      std::lower_bound(m.by_name.begin(), m.by_name.end(), name,
                       [&](int id, std::string_view n) { return m.specs.name(id) < n; });
  return it != m.by_name.end() && m.specs.name(*it) == name ? *it : -1;
}

BodySpec World::body_spec(int id) const {
  impl_->check_id(id);
  return impl_->model().specs.get(id);
}
std::string_view World::body_name(int id) const {
  impl_->check_id(id);
  return impl_->model().specs.name(id);
}
BodyMotion World::body_motion(int id) const {
  impl_->check_id(id);
  return impl_->model().motion[id];
}
MotionType World::motion_type(int id) const {
  impl_->check_id(id);
  return impl_->model().specs.params(id).motion_type;
}
AllowedDofs World::allowed_dofs(int id) const {
  impl_->check_id(id);
  return impl_->model().specs.params(id).allowed_dofs;
}

Vec3 World::principal_moments(int id) const {
  impl_->check_id(id);
  // Not stored: the group's own moments, or the spec's for a kinematic body (no inertia in use).
  const Impl& w = *impl_;
  return w.with_body(id, [&](auto g, int i) -> Vec3 {
    using G = decltype(g);
    if constexpr (G::kKind == BodyMotion::kSteadySpin) {
      const double inv_I = g.rot(i).inv_I;
      return inv_I > 0 ? Vec3::Constant(1.0 / inv_I)
                       : principal_inertia(w.model().specs.params(id).I_B).moments;
    } else if constexpr (G::Traits::kTurns) {
      return g.rot(i).I;
    } else {
      (void)g, (void)i;
      return Vec3::Zero();
    }
  });
}
Quat World::q_BP(int id) const {
  impl_->check_id(id);
  return impl_->rot_BP(id);
}

double World::kinetic_energy(int id) const {
  impl_->check_id(id);
  const Motion& m = impl_->motion(id);
  const double mass = impl_->model().specs.params(id).mass;
  return 0.5 * mass * m.v.squaredNorm() +
         0.5 * impl_->omega_P(id).dot(impl_->angular_momentum_P(id));
}

double World::total_energy() const {
  double e = 0.0;
  for (int i = 0; i < body_count(); ++i) {
    e += kinetic_energy(i);
    // A body the contact stage holds at rest points at the still row; its gravity is its own.
    const detail::ContactData& c = impl_->data.contact;
    const detail::Linear& lin = !c.held_linear.empty() && c.held_linear[i] >= 0
                                    ? impl_->with_body(i,
                                                       [&](auto g, int) -> const detail::Linear& {
                                                         return g.params.linear[c.held_linear[i]];
                                                       })
                                    : impl_->linear(i);
    e -= impl_->model().specs.params(i).mass * lin.g.dot(impl_->motion(i).x);
  }
  return e;
}

Vec3 World::angular_momentum_W(int id) const {
  impl_->check_id(id);
  return impl_->motion(id).q * impl_->angular_momentum_P(id);
}

}  // namespace rigid::physics
