#include "drift.hpp"

#include <cmath>
#include <limits>

#include "common/wrench_table.hpp"

namespace rigid::view {

namespace {

// v turned by the unit quaternion (w, x, y, z), or by its inverse when sign = -1: with
// t = 2 q_v x v, v' = v + w t + q_v x t (Rodrigues).
std::array<double, 3> rotate(const double q[4], double sign, const std::array<double, 3>& v) {
  const double w = q[0], x = sign * q[1], y = sign * q[2], z = sign * q[3];
  const double tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]),
               tz = 2 * (x * v[1] - y * v[0]);
  return {v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz),
          v[2] + w * tz + (x * ty - y * tx)};
}

// |now - ref| / |ref|, or |now - ref| when ref is 0, as float (the page plots it on a log scale).
float relative(double change, double ref) {
  const double r = change / (ref != 0 ? std::abs(ref) : 1.0);
  return std::isfinite(r) ? static_cast<float>(std::min(r, 1e30))
                          : std::numeric_limits<float>::infinity();
}

}  // namespace

Invariants invariants(double m, const double* I, const Vec3& g_W, const double* p_WBo,
                      const double* q_WB, const double* v_WBo, const double* w_WB) {
  double n =
      std::sqrt(q_WB[0] * q_WB[0] + q_WB[1] * q_WB[1] + q_WB[2] * q_WB[2] + q_WB[3] * q_WB[3]);
  if (!(n > 0)) n = 1;
  const double q[4] = {q_WB[0] / n, q_WB[1] / n, q_WB[2] / n, q_WB[3] / n};
  const std::array<double, 3> w_B = rotate(q, -1, {w_WB[0], w_WB[1], w_WB[2]});
  const std::array<double, 3> L_B = {I[0] * w_B[0] + I[3] * w_B[1] + I[4] * w_B[2],
                                     I[3] * w_B[0] + I[1] * w_B[1] + I[5] * w_B[2],
                                     I[4] * w_B[0] + I[5] * w_B[1] + I[2] * w_B[2]};
  Invariants out;
  out.L_W = rotate(q, 1, L_B);
  const double kinetic =
      0.5 * m * (v_WBo[0] * v_WBo[0] + v_WBo[1] * v_WBo[1] + v_WBo[2] * v_WBo[2]) +
      0.5 * (w_B[0] * L_B[0] + w_B[1] * L_B[1] + w_B[2] * L_B[2]);
  const double potential = -m * (g_W[0] * p_WBo[0] + g_W[1] * p_WBo[1] + g_W[2] * p_WBo[2]);
  out.energy = kinetic + potential;
  return out;
}

void DriftTracker::set_scene(const SceneDescription& scene) {
  bodies_.clear();
  index_.clear();
  gravity_ = scene.gravity;
  dt_ = scene.dt > 0 && std::isfinite(scene.dt) ? scene.dt : 0;
  last_tick_ = -1;
  if (!scene.lengths_agree()) return;  // (a decoder guarantees it does)
  bodies_.resize(scene.body_count());
  index_.reserve(scene.body_count());
  for (std::size_t k = 0; k < scene.body_count(); ++k) {
    bodies_[k].mass = scene.masses[k];
    for (int j = 0; j < 6; ++j)
      bodies_[k].inertia[j] = scene.inertia[6 * k + j];
    index_.emplace(scene.ids[k], k);
  }
}

void DriftTracker::drive(std::int32_t body, std::int64_t tick, double ttl) {
  const auto it = index_.find(body);
  if (it == index_.end()) return;
  const std::int64_t ticks =
      dt_ > 0 && ttl >= 0 && ttl / dt_ <= 1e12 ? common::ticks_to_live(ttl, dt_) : 0;
  const double margin = dt_ > 0 ? std::ceil(kDrivenMargin / dt_) : 0;
  // Saturating: a ttl of "until replaced" (ticks_to_live's 0 for too long) or a huge one.
  const double until = static_cast<double>(tick) + static_cast<double>(ticks > 0 ? ticks : 0) +
                       (ticks > 0 ? margin : 1e15);
  const std::int64_t u =
      until >= 9e15 ? std::int64_t{9'000'000'000'000'000} : static_cast<std::int64_t>(until);
  Body& b = bodies_[it->second];
  if (u > b.driven_until) b.driven_until = u;
}

void DriftTracker::update(const StateFrame& s) {
  const std::size_t n = s.body_count();
  energy_.assign(n, 0.0f);
  momentum_.assign(n, 0.0f);
  if (!s.lengths_agree()) return;
  if (s.tick < last_tick_) {  // a reset, or a restarted rigidd: every reference again
    for (Body& b : bodies_) {
      b.have = false;
      b.driven_until = -1;
    }
  }
  last_tick_ = s.tick;
  for (std::size_t i = 0; i < n; ++i) {
    const auto it = index_.find(s.ids[i]);
    if (it == index_.end()) continue;
    Body& b = bodies_[it->second];
    const Invariants now =
        invariants(b.mass, b.inertia.data(), gravity_, &s.position[3 * i], &s.orientation[4 * i],
                   &s.linear_velocity[3 * i], &s.angular_velocity[3 * i]);
    if (!b.have || s.tick <= b.driven_until) {
      b.have = true;
      b.e0 = now.energy;
      b.L0 = now.L_W;
    }
    energy_[i] = relative(std::abs(now.energy - b.e0), b.e0);
    const double dL = std::hypot(now.L_W[0] - b.L0[0], now.L_W[1] - b.L0[1], now.L_W[2] - b.L0[2]);
    momentum_[i] = relative(dL, std::hypot(b.L0[0], b.L0[1], b.L0[2]));
  }
}

}  // namespace rigid::view
