#!/usr/bin/env python3
"""Error against cost of every integrator, on a hard case: the tennis racket.

A free body with principal moments 1:2:3 spins at 5 rad/s about its middle axis, perturbed by
1e-3 rad/s: the spin is unstable and the body flips over every 6.6 s (the Dzhanibekov effect).
Small errors in the spin grow exponentially between flips, so the time of the flip, and the
orientation after it, expose an integrator's error.

Each integrator runs the case to --duration at each step size; its error is the rotation angle
between its final orientation and the reference's, and its cost the CPU time of World.step per
simulated second (the best of --repeat runs). The reference is exact_rotor4 at the finest step:
it integrates torque-free motion exactly (up to round-off), which the script checks by comparing
its finest and coarsest runs.

    PYTHONPATH=build/clients/python /usr/bin/python3 clients/python/examples/integrator_study.py
    # writes integrator_study.png (and prints the table); --quick for a short run
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from dataclasses import dataclass

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import rigid  # noqa: E402

RACKET = """
world {{ rate_hz: {rate} substeps: 1 gravity {{ z: 0 }} }}
body {{
  name: "racket"
  mass: 1
  inertia {{ x: 1 y: 2 z: 3 }}
  angular_velocity {{ x: 1e-3 y: 5 z: 1e-3 }}
  use_gravity: false
}}
"""

REFERENCE = "exact_rotor4"


@dataclass
class Run:
    integrator: str
    dt: float
    q: np.ndarray  # final orientation (w, x, y, z)
    w: np.ndarray  # final angular velocity, W
    seconds_per_sim_second: float
    finite: bool


def angle_between(q1: np.ndarray, q2: np.ndarray) -> float:
    """The rotation angle (rad) from orientation q1 to q2, from their relative rotation
    conj(q1) q2: 2 atan2(|v|, |w|) stays accurate near 0, where acos(q1 . q2) would not."""
    w = float(q1 @ q2)
    v = q1[0] * q2[1:] - q2[0] * q1[1:] - np.cross(q1[1:], q2[1:])
    return 2.0 * math.atan2(float(np.linalg.norm(v)), abs(w))


def simulate(integrator: str, dt: float, duration: float, repeat: int) -> Run:
    steps = round(duration / dt)
    best = math.inf
    w = None
    for _ in range(repeat):
        w = rigid.World.from_string(RACKET.format(rate=1.0 / dt), "racket", integrator=integrator,
                                    dt=dt)
        t0 = time.process_time()
        w.step(steps)
        best = min(best, time.process_time() - t0)
    assert w is not None
    q = w.orientations[0].copy()
    om = w.angular_velocities[0].copy()
    finite = bool(np.all(np.isfinite(q)) and np.all(np.isfinite(om)) and not w.frozen_bodies)
    return Run(integrator, dt, q, om, best / duration, finite)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--duration", type=float, default=8.0, help="simulated seconds (8: past "
                    "the first flip at 3.5 s)")
    ap.add_argument("--out", default="integrator_study.png", help="the PNG to write")
    ap.add_argument("--repeat", type=int, default=3, help="timing runs per point (best kept)")
    ap.add_argument("--quick", action="store_true", help="fewer steps sizes, 4 s: a smoke test")
    args = ap.parse_args()

    dts = [1e-2, 5e-3, 2e-3, 1e-3, 5e-4, 2e-4, 1e-4]
    if args.quick:
        dts, args.duration, args.repeat = [1e-2, 3e-3, 1e-3], 4.0, 1
    names = [i.name for i in rigid.integrators()]
    default = next(i.name for i in rigid.integrators() if i.default)

    ref = simulate(REFERENCE, min(dts), args.duration, 1)
    coarse = simulate(REFERENCE, max(dts), args.duration, 1)
    ref_check = angle_between(ref.q, coarse.q)
    print(f"reference: {REFERENCE} at dt = {min(dts):g} s; the same at dt = {max(dts):g} s "
          f"differs by {ref_check:.2e} rad (exact for a free body: round-off only)")

    runs = {n: [simulate(n, dt, args.duration, args.repeat) for dt in dts] for n in names}
    print(f"\n{'integrator':<22}{'dt (s)':>10}{'error (rad)':>14}{'|dw|/|w|':>12}"
          f"{'CPU s per sim s':>18}")
    for n, rs in runs.items():
        for r in rs:
            err = angle_between(r.q, ref.q) if r.finite else math.nan
            dw = np.linalg.norm(r.w - ref.w) / np.linalg.norm(ref.w) if r.finite else math.nan
            tag = "" if r.finite else "  blew up"
            print(f"{n:<22}{r.dt:>10.0e}{err:>14.3e}{dw:>12.3e}{r.seconds_per_sim_second:>18.3e}"
                  f"{tag}")

    fig, ax = plt.subplots(figsize=(8, 5.5))
    # Errors below this are round-off: drawn on it rather than vanishing off a log axis. The
    # reference's own run (error 0 by definition) is left out.
    floor = 1e-15
    for n, rs in runs.items():
        shown = [r for r in rs if r.finite and not (n == REFERENCE and r.dt == ref.dt)]
        cost = [r.seconds_per_sim_second for r in shown]
        err = [max(angle_between(r.q, ref.q), floor) for r in shown]
        label = n + (" (default)" if n == default else "")
        style = "-o" if n in (REFERENCE, default) else "-."
        ax.loglog(cost, err, style, label=label, markersize=4)
        blown = [r.seconds_per_sim_second for r in rs if not r.finite]
        if blown:
            ax.loglog(blown, [math.pi] * len(blown), "x", color="k")
    ax.axhline(math.pi, color="grey", lw=0.5)
    ax.axhline(floor, color="grey", lw=0.5, ls=":")
    ax.set_xlabel("CPU time of World.step per simulated second (s)")
    ax.set_ylabel(f"orientation error at t = {args.duration:g} s (rad)")
    ax.set_title(f"Tennis racket (moments 1:2:3, 5 rad/s about the middle axis), dt "
                 f"{max(dts):g} to {min(dts):g} s\nreference: {REFERENCE} at dt = {min(dts):g} s; "
                 f"x: blew up; pi: the orientation is lost; dotted: round-off", fontsize=9)
    ax.grid(True, which="both", lw=0.3)
    ax.legend(fontsize=8, loc="center left")
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"\nwrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
