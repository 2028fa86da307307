#include "physics/spec_store.hpp"

#include <bit>

#include "physics/intern.hpp"

namespace rigid::physics::detail {

namespace {

// Params compared by their bits: two bodies share an entry only if get() gives each back exactly
// (-0.0 and 0.0 stay apart).
struct ParamsKey {
  std::array<std::uint64_t, 12> bits{};
  unsigned flags = 0;
  auto operator<=>(const ParamsKey&) const = default;
};

// An initial orientation and velocities compared by their bits, as ParamsKey.
struct StartKey {
  std::array<std::uint64_t, 10> bits{};
  auto operator<=>(const StartKey&) const = default;
};

ParamsKey key_of(const SpecStore::Params& p) {
  ParamsKey k;
  k.bits[0] = std::bit_cast<std::uint64_t>(p.mass);
  for (int i = 0; i < 9; ++i)
    k.bits[1 + i] = std::bit_cast<std::uint64_t>(p.I_B.data()[i]);
  k.bits[10] = std::bit_cast<std::uint64_t>(p.linear_drag);
  k.bits[11] = std::bit_cast<std::uint64_t>(p.angular_drag);
  k.flags = static_cast<unsigned>(p.has_inertia) | static_cast<unsigned>(p.use_gravity) << 1 |
            static_cast<unsigned>(p.motion_type) << 2 | static_cast<unsigned>(p.allowed_dofs) << 3;
  return k;
}

}  // namespace

SpecStore::SpecStore(const std::vector<BodySpec>& bodies) {
  const std::size_t n = bodies.size();
  std::size_t chars = 0;
  for (const BodySpec& b : bodies)
    chars += b.name.size();
  names_.reserve(chars);
  name_end_.reserve(n);
  p_.reserve(n);
  const auto start_of = [](const BodySpec& b) {
    Start s;
    const Quat q = b.q_WB.normalized();
    s.q[0] = q.w(), s.q[1] = q.x(), s.q[2] = q.y(), s.q[3] = q.z();
    for (int a = 0; a < 3; ++a) {
      s.v[a] = b.v_WBo[a];
      s.w[a] = b.w_WB[a];
    }
    return s;
  };
  // Interned one after the other, so that only one key array is alive at a time.
  {
    std::vector<StartKey> keys;
    keys.reserve(n);
    for (const BodySpec& b : bodies) {
      names_ += b.name;
      name_end_.push_back(static_cast<std::uint32_t>(names_.size()));  // World bounds the total
      p_.push_back({b.p_WBo.x(), b.p_WBo.y(), b.p_WBo.z()});
      const Start s = start_of(b);
      StartKey k;
      for (int a = 0; a < 4; ++a)
        k.bits[a] = std::bit_cast<std::uint64_t>(s.q[a]);
      for (int a = 0; a < 3; ++a) {
        k.bits[4 + a] = std::bit_cast<std::uint64_t>(s.v[a]);
        k.bits[7 + a] = std::bit_cast<std::uint64_t>(s.w[a]);
      }
      keys.push_back(k);
    }
    std::vector<std::int32_t> first;
    intern(keys, start_of_, first);
    starts_.reserve(first.size());
    for (const std::int32_t f : first)
      starts_.push_back(start_of(bodies[f]));
  }
  const auto params_of = [](const BodySpec& b) {
    AllowedDofs dofs = AllowedDofs::kNone;
    for (int a = 0; a < 3; ++a) {
      if (!b.freeze_translation[a]) dofs = dofs | translation_dof(a);
      if (!b.freeze_rotation[a]) dofs = dofs | rotation_dof(a);
    }
    return Params{b.mass,
                  b.I_B,
                  b.linear_drag,
                  b.angular_drag,
                  b.has_inertia,
                  b.use_gravity,
                  b.kinematic ? MotionType::kKinematic : MotionType::kDynamic,
                  dofs};
  };
  std::vector<ParamsKey> keys;
  keys.reserve(n);
  for (const BodySpec& b : bodies)
    keys.push_back(key_of(params_of(b)));
  std::vector<std::int32_t> first;
  intern(keys, params_of_, first);
  params_.reserve(first.size());
  for (const std::int32_t f : first)
    params_.push_back(params_of(bodies[f]));
}

BodySpec SpecStore::get(int id) const {
  const Params& p = params(id);
  BodySpec b;
  b.name = name(id);
  b.mass = p.mass;
  b.I_B = p.I_B;
  b.has_inertia = p.has_inertia;
  b.p_WBo = p_WBo(id);
  b.q_WB = q_WB(id);
  b.v_WBo = v_WBo(id);
  b.w_WB = w_WB(id);
  b.linear_drag = p.linear_drag;
  b.angular_drag = p.angular_drag;
  b.use_gravity = p.use_gravity;
  b.kinematic = p.kinematic();
  for (int a = 0; a < 3; ++a) {
    b.freeze_translation[a] = !allows(p.allowed_dofs, translation_dof(a));
    b.freeze_rotation[a] = !allows(p.allowed_dofs, rotation_dof(a));
  }
  return b;
}

}  // namespace rigid::physics::detail
