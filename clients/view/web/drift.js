// Energy and angular momentum of each free rigid body from the published state, and how far they
// drifted since a reference state: what the accuracy claims are about (README "Integrators").
//
// Frames (msgs/rigid.idl): p_WBo in W, q_WB (w, x, y, z), v_WBo in W, w_WB in W; the inertia I_B
// (Ixx, Iyy, Izz, Ixy, Ixz, Iyz) is about the centre of mass, in B (SceneInfo). With w_B = R_WB^T w_WB:
//   E   = 1/2 m v.v + 1/2 w_B . I_B w_B - m g.p_WBo   (the last term: gravity's potential, g in W)
//   L_W = R_WB I_B w_B                                  (about the centre of mass, in W)
// For a body without applied wrenches both are constant along the exact solution (L_W about the
// CoM even under uniform gravity, which has no moment about it), so their change is integration
// error. A push from the page changes them: that is work done, not drift.

// v rotated by q (w, x, y, z), or by its inverse when sign = -1; written to out[0..2].
function rotate(qw, qx, qy, qz, sign, vx, vy, vz, out) {
  const x = sign * qx, y = sign * qy, z = sign * qz;
  // t = 2 q_v x v;  v' = v + w t + q_v x t  (Rodrigues with a unit quaternion)
  const tx = 2 * (y * vz - z * vy), ty = 2 * (z * vx - x * vz), tz = 2 * (x * vy - y * vx);
  out[0] = vx + qw * tx + (y * tz - z * ty);
  out[1] = vy + qw * ty + (z * tx - x * tz);
  out[2] = vz + qw * tz + (x * ty - y * tx);
}

// The energy of the body in state slot i, and its angular momentum L_W (into L at 3 o).
const wB = new Float64Array(3), LB = new Float64Array(3), LW = new Float64Array(3);
export function invariants(mass, I, gravity, pos, ori, vel, omega, i, L, o) {
  const qw = ori[4 * i], qx = ori[4 * i + 1], qy = ori[4 * i + 2], qz = ori[4 * i + 3];
  const n = Math.hypot(qw, qx, qy, qz) || 1;
  rotate(qw / n, qx / n, qy / n, qz / n, -1, omega[3 * i], omega[3 * i + 1], omega[3 * i + 2], wB);
  LB[0] = I[0] * wB[0] + I[3] * wB[1] + I[4] * wB[2];
  LB[1] = I[3] * wB[0] + I[1] * wB[1] + I[5] * wB[2];
  LB[2] = I[4] * wB[0] + I[5] * wB[1] + I[2] * wB[2];
  rotate(qw / n, qx / n, qy / n, qz / n, 1, LB[0], LB[1], LB[2], LW);
  L[3 * o] = LW[0];
  L[3 * o + 1] = LW[1];
  L[3 * o + 2] = LW[2];
  const vx = vel[3 * i], vy = vel[3 * i + 1], vz = vel[3 * i + 2];
  const kinetic = 0.5 * mass * (vx * vx + vy * vy + vz * vz) +
                  0.5 * (wB[0] * LB[0] + wB[1] * LB[1] + wB[2] * LB[2]);
  const potential = -mass * (gravity[0] * pos[3 * i] + gravity[1] * pos[3 * i + 1] +
                             gravity[2] * pos[3 * i + 2]);
  return kinetic + potential;
}

// Each body's relative drift since its reference state: |E - E0| / |E0| and |L_W - L0| / |L0|
// (a quantity that starts at zero is compared to 1 instead: its absolute change). The reference
// is the first state after the scene arrives, a reset (the tick goes back), rebase(), or for one
// body rebaseBody() (the page calls it while a wrench acts on the body).
export class Drift {
  constructor() { this.setBodies([], [0, 0, 0]); }

  // bodies: [{ mass, inertia: [6] }] in the order of the ids given to update().
  setBodies(bodies, gravity) {
    const n = bodies.length;
    this.mass = Float64Array.from(bodies, (b) => b.mass || 0);
    this.inertia = bodies.map((b) => (b.inertia && b.inertia.length === 6 ? b.inertia : [0, 0, 0, 0, 0, 0]));
    this.gravity = gravity && gravity.length === 3 ? gravity : [0, 0, 0];
    this.e0 = new Float64Array(n);
    this.L0 = new Float64Array(3 * n);
    this.e = new Float64Array(n);
    this.L = new Float64Array(3 * n);
    this.energy = new Float64Array(n);    // relative drifts, per body
    this.momentum = new Float64Array(n);
    this.have = new Uint8Array(n);
    this.lastTick = -1;
  }

  rebase() { this.have.fill(0); }
  rebaseBody(k) { if (k >= 0 && k < this.have.length) this.have[k] = 0; }

  // index[i]: the body's place in setBodies' order for state slot i (or -1 to skip).
  update(tick, n, index, pos, ori, vel, omega) {
    if (tick < this.lastTick) this.rebase();
    this.lastTick = tick;
    for (let i = 0; i < n; ++i) {
      const k = index[i];
      if (k < 0 || k >= this.mass.length) continue;
      const e = invariants(this.mass[k], this.inertia[k], this.gravity, pos, ori, vel, omega, i,
                           this.L, k);
      const lx = this.L[3 * k], ly = this.L[3 * k + 1], lz = this.L[3 * k + 2];
      if (!this.have[k]) {
        this.have[k] = 1;
        this.e0[k] = e;
        this.L0[3 * k] = lx;
        this.L0[3 * k + 1] = ly;
        this.L0[3 * k + 2] = lz;
      }
      this.e[k] = e;
      const e0 = this.e0[k], a = this.L0[3 * k], b = this.L0[3 * k + 1], c = this.L0[3 * k + 2];
      this.energy[k] = Math.abs(e - e0) / (Math.abs(e0) || 1);
      this.momentum[k] = Math.hypot(lx - a, ly - b, lz - c) / (Math.hypot(a, b, c) || 1);
    }
  }

  // The largest drift over all bodies (or body k's when k >= 0), and which bodies have it
  // (energyAt, momentumAt: indices in setBodies' order, -1 when every drift is 0). A body under a
  // load of the scene file (a thruster, drag) is not free: its change is work, not error, and the
  // page names the worst body so that such a body is not taken for the integrator's error.
  worst(k = -1) {
    if (k >= 0) return { energy: this.energy[k], momentum: this.momentum[k], energyAt: k, momentumAt: k };
    let energy = 0, momentum = 0, energyAt = -1, momentumAt = -1;
    for (let i = 0; i < this.energy.length; ++i) {
      if (this.energy[i] > energy) { energy = this.energy[i]; energyAt = i; }
      if (this.momentum[i] > momentum) { momentum = this.momentum[i]; momentumAt = i; }
    }
    return { energy, momentum, energyAt, momentumAt };
  }
}
