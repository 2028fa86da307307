// hybrid4's loaded bodies in batches (hybrid_lanes.hpp): gathers W bodies of a group into a
// LaneBatch, runs the kernel of width W that the CPU supports, scatters the states back.
#include "physics/hybrid_lanes.hpp"

#include <cstdlib>
#include <cstring>

#include "physics/kernels.hpp"
#include "physics/math.hpp"

namespace rigid::physics::detail {

static_assert(kSmallAngle == 1.0 / 16.0, "hybrid_lanes_kernel.cpp restates kSmallAngle");

int pick_lane_width() {
  int widest = 2;
#if defined(__x86_64__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) {
    widest = 8;
  } else if (__builtin_cpu_supports("avx2")) {
    widest = 4;
  }
#endif
  // A test knob, not a tuning one: every width gives the same bits, so only tests need to choose.
  if (const char* e = std::getenv("RIGID_LANES")) {
    const int want = std::strcmp(e, "1") == 0   ? 1
                     : std::strcmp(e, "2") == 0 ? 2
                     : std::strcmp(e, "4") == 0 ? 4
                                                : 0;
    if (want != 0 && want <= widest) return want;
  }
  return widest;
}

namespace {

void put(LaneBatch::L* d, int l, const Vec3& s) {
  d[0][l] = s.x();
  d[1][l] = s.y();
  d[2][l] = s.z();
}

// `linear`, `coefs`, `rot`: copy the translation parameters (g, 1/m), the translation
// coefficients, the rotational parameters (false: b holds this lane's already).
template <class G>
void gather(const G& g, const Model& m, int i, int l, std::uint32_t flags, bool linear, bool coefs,
            bool rot, LaneBatch& b) {
  const Motion& mo = g.motion(i);
  b.qw[l] = mo.q.w();
  b.qx[l] = mo.q.x();
  b.qy[l] = mo.q.y();
  b.qz[l] = mo.q.z();
  put(b.x, l, mo.x);
  put(b.v, l, mo.v);
  put(b.m, l, mo.spin);
  const Linear& lin = g.linear(i);
  if (linear) {
    put(b.g, l, lin.g);
    put(b.inv_m, l, lin.inv_m);
  }
  for (int k = 0; coefs && k < 2; ++k) {
    const TransCoef& c = m.tc(lin, k == 0 ? kForced0 : kForced1);
    b.E[k][l] = c.E;
    b.p1[k][l] = c.p1;
    b.p2[k][l] = c.p2;
    b.q2[k][l] = c.q2;
    b.q3[k][l] = c.q3;
  }
  if (rot) {
    const DiagRot& r = g.rot(i);
    put(b.inv_I, l, r.inv_I);
    put(b.decay, l, r.drag_rates());
  }
  const LoadsRef L = g.load(i);
  b.body_force[l] = (L.flags & Loads::kBodyForce) ? -1 : 0;
  b.world_torque[l] = (L.flags & Loads::kWorldTorque) ? -1 : 0;
  b.lever[l] = (L.flags & Loads::kLever) ? -1 : 0;
  put(b.f_W, l, L.f_W);
  put(b.tau_P, l, L.tau_P);
  // The terms the kernel reads only when some lane has their flag (its any_*): copied for the
  // batches that have it (`flags`: the batch's flags together).
  if (flags & Loads::kBodyForce) put(b.f_P, l, L.f_P);
  if (flags & Loads::kWorldTorque) put(b.tau_W, l, L.tau_W);
  if (flags & Loads::kLever) {
    for (int r0 = 0; r0 < 3; ++r0)
      for (int c0 = 0; c0 < 3; ++c0)
        b.fr[r0][c0][l] = L.fr(r0, c0);
  }
}

template <class G>
void scatter(const LaneBatch& b, int l, const G& g, int i) {
  Motion& mo = g.motion(i);
  mo.q = Quat(b.qw[l], b.qx[l], b.qy[l], b.qz[l]);
  mo.x = Vec3(b.x[0][l], b.x[1][l], b.x[2][l]);
  mo.v = Vec3(b.v[0][l], b.v[1][l], b.v[2][l]);
  mo.spin = Vec3(b.m[0][l], b.m[1][l], b.m[2][l]);
}

template <class G>
void run(const G& g, const Model& m, Range r, bool general) {
  using C = TripleJump;
  static_assert(C::kStages == LaneStages::kStages);
  LaneStages st{};
  for (int k = 0; k < C::kStages; ++k) {
    st.s[k] = C::kStage[k] * m.dt;
    st.size[k] = C::kSize[k] == kForced0 ? 0 : 1;
  }
  st.general = general;
  const int W = m.lanes;
  // Zero-initialised: the terms a batch does not copy (gather) hold defined values, never read.
  LaneBatch b{};
  // The drag row (TransTable) whose coefficients every lane of b holds, and the shared entries
  // (GroupParams) whose parameters every lane holds, -1 if none: most worlds have one drag
  // rate and a few kinds of body, so the batches after the first need not copy them again.
  int coef_row = -1, lin_entry = -1, rot_entry = -1;
  for (int i = r.begin; i < r.end; i += W) {
    const int n = r.end - i < W ? r.end - i : W;
    std::uint32_t flags = 0;
    const GroupEntries<G::kKind>& e = g.entries;
    int row = g.linear(i).drag, entry = e.linear[i], rentry = e.rot[i];
    for (int l = 0; l < n; ++l) {
      flags |= e.loads[i + l].flags;
      if (g.linear(i + l).drag != row) row = -1;
      if (e.linear[i + l] != entry) entry = -1;
      if (e.rot[i + l] != rentry) rentry = -1;
    }
    const bool coefs = row < 0 || row != coef_row;
    const bool linear = entry < 0 || entry != lin_entry;
    const bool rot = rentry < 0 || rentry != rot_entry;
    coef_row = row;
    lin_entry = entry;
    rot_entry = rentry;
    // Lanes past the run's end repeat its first body of this batch and are never written back.
    for (int l = 0; l < W; ++l)
      gather(g, m, l < n ? i + l : i, l, flags, linear, coefs, rot, b);
    switch (W) {
      case 8:
        lanes8::step(b, st);
        break;
      case 4:
        lanes4::step(b, st);
        break;
      default:
        lanes2::step(b, st);
        break;
    }
    for (int l = 0; l < n; ++l) {
      scatter(b, l, g, i + l);
      g.entries.plan_ok[i + l] = 0;  // the momentum changed: the cached free-rotor plan is stale
    }
  }
}

}  // namespace

void hybrid_loaded_lanes(TumblingGroup g, const Model& m, Range r) {
  run(g, m, r, true);
}
void hybrid_loaded_lanes(PrecessionGroup g, const Model& m, Range r) {
  run(g, m, r, false);
}

}  // namespace rigid::physics::detail
