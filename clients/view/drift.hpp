// Each body's drift of energy and angular momentum since a reference state: what the accuracy
// claims are about (docs/physics.md, "Integrators"), computed by rigid-view from the exact
// published state and sent to the page with every state frame (protocol.hpp), so that the page
// needs neither the doubles nor the arithmetic: a large scene's frame carries its poses as float32
// (what the GPU draws), and a large scene's invariants would take the page's main thread
// milliseconds per state (bench/notes/view.md).
//
// Frames (msgs/rigid.idl): p_WBo in W, q_WB (w, x, y, z), v_WBo in W, w_WB in W; the inertia I_B
// (Ixx, Iyy, Izz, Ixy, Ixz, Iyz) is about the centre of mass, in B (SceneInfo). With
// w_B = R_WB^T w_WB:
//   E   = 1/2 m v.v + 1/2 w_B . I_B w_B - m g.p_WBo   (the last term: gravity's potential)
//   L_W = R_WB I_B w_B                                  (about the centre of mass, in W)
// For a body without applied wrenches both are constant along the exact solution (L_W about the
// CoM even under uniform gravity, which has no moment about it), so their change is integration
// error. A wrench changes them by its work: that is not drift, so a driven body's reference is
// taken again with each state until kDrivenMargin after the wrench's last tick.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "rigid/messages.hpp"

namespace rigid::view {

struct Invariants {
  double energy = 0;
  std::array<double, 3> L_W{};  // angular momentum about the CoM, in W
};

// Of one body: mass m, inertia6 = I_B as above, g_W, and the state's p_WBo, q_WB (w, x, y, z;
// normalised here), v_WBo, w_WB.
Invariants invariants(double m, const double* inertia6, const Vec3& g_W, const double* p_WBo,
                      const double* q_WB, const double* v_WBo, const double* w_WB);

class DriftTracker {
 public:
  // How long after a wrench's last tick its body's reference is still retaken (s): a wrench
  // learnt of after the states it acted on (the accepted stream and the states are two topics).
  static constexpr double kDrivenMargin = 0.25;

  // The bodies (mass, inertia by id) and gravity of `scene`; every reference is dropped.
  void set_scene(const SceneDescription& scene);
  // A wrench accepted at `tick` with time to live `ttl` (s) on `body`: its reference is retaken
  // with every state up to tick + ticks_to_live(ttl, dt) + kDrivenMargin / dt (rigidd's ticks,
  // common/wrench_table.hpp); until the next reset when dt or ttl gives no sensible count.
  void drive(std::int32_t body, std::int64_t tick, double ttl);
  // Takes a state: each body's relative drift |E - E0| / |E0| and |L_W - L0| / |L0| (a quantity
  // that starts at zero is compared to 1 instead), in the state's order (0 for an id the scene
  // does not have). The reference is a body's first state, or the first after a reset (the tick
  // goes back), a new scene, or a wrench on it.
  void update(const StateFrame& s);
  const std::vector<float>& energy() const { return energy_; }
  const std::vector<float>& momentum() const { return momentum_; }

 private:
  struct Body {
    double mass = 0;
    std::array<double, 6> inertia{};
    bool have = false;  // a reference
    double e0 = 0;
    std::array<double, 3> L0{};
    std::int64_t driven_until = -1;  // tick
  };
  std::vector<Body> bodies_;
  std::unordered_map<std::int32_t, std::size_t> index_;  // id -> bodies_
  Vec3 gravity_{};
  double dt_ = 0;
  std::int64_t last_tick_ = -1;
  std::vector<float> energy_, momentum_;
};

}  // namespace rigid::view
