// Each body's relative drift of energy and angular momentum, as rigid-view computes it from the
// exact published state and sends it with every state frame (clients/view/drift.hpp: the
// formulas, the reference state, and why a body a wrench acts on takes its reference again).
export class DriftTable {
  constructor() { this.setBodies(0); }

  setBodies(n) {
    this.energy = new Float64Array(n);  // per body, in the scene's order
    this.momentum = new Float64Array(n);
    this.reported = null;
  }

  // index[i]: the body's place in the scene's order for state slot i (or -1 to skip); energy
  // and momentum: the frame's drifts, by slot.
  update(n, index, energy, momentum) {
    this.reported = null;  // a whole frame: worst() finds the worst itself
    for (let i = 0; i < n; ++i) {
      const k = index[i];
      if (k < 0 || k >= this.energy.length) continue;
      this.energy[k] = energy[i];
      this.momentum[k] = momentum[i];
    }
  }

  // A decoded state frame (protocol.js): a whole frame's drifts, or a pose frame's worst drifts and
  // its watched bodies' own. slots[i]: state slot i's index in the scene's order (-1: none).
  apply(state, slots) {
    const n = state.n;
    if (!state.poses) {
      this.update(n, slots, state.energyDrift, state.momentumDrift);
      return;
    }
    const indexOf = (slot) => (slot >= 0 && slot < n ? slots[slot] : -1);
    const w = state.worst;
    this.report({ energy: w.energy, energyAt: indexOf(w.energySlot), momentum: w.momentum,
                  momentumAt: indexOf(w.momentumSlot) });
    for (const r of state.watched) this.set(indexOf(r.slot), r.energy, r.momentum);
  }

  // A pose frame (protocol.hpp): the worst drifts as rigid-view found them ({ energy, energyAt,
  // momentum, momentumAt }, indices in the scene's order), and the watched bodies' own (set).
  report(worst) { this.reported = worst; }
  set(k, energy, momentum) {
    if (k < 0 || k >= this.energy.length) return;
    this.energy[k] = energy;
    this.momentum[k] = momentum;
  }

  // The largest drift over all bodies (or body k's when k >= 0), and which bodies have it
  // (energyAt, momentumAt: indices in the scene's order, -1 when every drift is 0). A body under
  // a load of the scene file (a thruster, drag) is not free: its change is work, not error, and
  // the page names the worst body so that such a body is not taken for the integrator's error.
  worst(k = -1) {
    if (k >= 0) return { energy: this.energy[k], momentum: this.momentum[k], energyAt: k, momentumAt: k };
    if (this.reported) return { ...this.reported };
    let energy = 0, momentum = 0, energyAt = -1, momentumAt = -1;
    for (let i = 0; i < this.energy.length; ++i) {
      if (this.energy[i] > energy) { energy = this.energy[i]; energyAt = i; }
      if (this.momentum[i] > momentum) { momentum = this.momentum[i]; momentumAt = i; }
    }
    return { energy, momentum, energyAt, momentumAt };
  }
}
