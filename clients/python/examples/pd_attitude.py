#!/usr/bin/env python3
"""A PD attitude controller for a live rigidd, over DDS or LCM.

It turns one body to a target orientation and holds it there with body-frame torques, sent as
wrenches (the Wrench message carries a pure torque and its frame) at every state rigidd
publishes. The law, with the body's inertia I from rigidd's SceneInfo:

    tau_B = I (kp phi_B - kd w_B) + w_B x I w_B

phi_B is the rotation from the body to the target (axis times angle, body frame, the short way
round), w_B the body's angular velocity in its own frame; kd = 2 sqrt(kp) makes each axis a
critically damped second-order system once the gyroscopic term is cancelled. The torque is
clipped to --max-torque (and the scene's max_torque). Each wrench lives 3 state periods, so the
body coasts free within milliseconds if the controller stops.

    rigidd --scene config/scenes/attitude.pbtxt &
    clients/python/examples/pd_attitude.py --transport dds          # or lcm

Prints its error five times a second; exit status 0 once settled within --settle degrees (for
--hold seconds), 1 when not settled within --timeout or rigidd refuses its torques, 3 when no
rigidd answers.
"""

from __future__ import annotations

import argparse
import math
import sys
import time

import numpy as np

import rigid


def quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product of (w, x, y, z) quaternions."""
    aw, av = a[0], a[1:]
    bw, bv = b[0], b[1:]
    return np.concatenate(([aw * bw - av @ bv], aw * bv + bw * av + np.cross(av, bv)))


def quat_conj(q: np.ndarray) -> np.ndarray:
    return np.array([q[0], -q[1], -q[2], -q[3]])


def rotate_inverse(q: np.ndarray, v_W: np.ndarray) -> np.ndarray:
    """A world-frame vector in the body frame of orientation q (q maps B to W)."""
    return quat_mul(quat_mul(quat_conj(q), np.concatenate(([0.0], v_W))), q)[1:]


def rotation_vector(q: np.ndarray) -> np.ndarray:
    """Axis times angle of the unit quaternion q, the short way round (angle <= pi)."""
    if q[0] < 0:
        q = -q
    s = np.linalg.norm(q[1:])
    if s < 1e-12:
        return 2.0 * q[1:]  # small angle: sin(a/2) ~ a/2
    return 2.0 * math.atan2(s, q[0]) * q[1:] / s


def from_rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """Roll about x, then pitch about y, then yaw about z (fixed axes), degrees."""
    r, p, y = (math.radians(a) / 2 for a in (roll, pitch, yaw))
    qx = np.array([math.cos(r), math.sin(r), 0, 0])
    qy = np.array([math.cos(p), 0, math.sin(p), 0])
    qz = np.array([math.cos(y), 0, 0, math.sin(y)])
    return quat_mul(qz, quat_mul(qy, qx))


def parse_args(argv: list[str]) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("body", nargs="?", default="craft", help="the body to turn (default craft)")
    ap.add_argument("--transport", choices=["dds", "lcm"], default="dds")
    ap.add_argument("--prefix", default="", help="rigidd's --prefix")
    ap.add_argument("--dds-domain", type=int, default=0)
    ap.add_argument("--lcm-url", default=None)
    ap.add_argument("--target-rpy", default="0,0,0", help="roll,pitch,yaw in degrees")
    ap.add_argument("--kp", type=float, default=4.0, help="stiffness, 1/s^2 (default 4)")
    ap.add_argument("--max-torque", type=float, default=10.0, help="N m (default 10)")
    ap.add_argument("--settle", type=float, default=1.0, help="degrees (default 1)")
    ap.add_argument("--hold", type=float, default=0.5, help="seconds within --settle (0.5)")
    ap.add_argument("--timeout", type=float, default=30.0, help="seconds to settle (30)")
    args = ap.parse_args(argv)
    try:
        rpy = [float(x) for x in args.target_rpy.split(",")]
        if len(rpy) != 3 or not all(math.isfinite(a) for a in rpy):
            raise ValueError
    except ValueError:
        ap.error(f"--target-rpy: expected R,P,Y in degrees, got '{args.target_rpy}'")
    args.target = from_rpy(*rpy)
    if not (args.kp > 0 and args.max_torque > 0 and args.settle > 0):
        ap.error("--kp, --max-torque and --settle must be > 0")
    return args


def run(args: argparse.Namespace) -> int:
    with rigid.Client(args.transport, prefix=args.prefix, domain=args.dds_domain,
                      url=args.lcm_url, timeout=5.0) as client:
        try:
            scene = client.scene()
            body = scene.body(args.body)
        except TimeoutError as e:
            print(f"pd_attitude: {e}", file=sys.stderr)
            return 3
        except rigid.UnknownBodyError as e:
            print(f"pd_attitude: {e}", file=sys.stderr)
            return 2
        I = np.array(body.inertia)
        kp, kd = args.kp, 2.0 * math.sqrt(args.kp)
        limit = args.max_torque if scene.max_torque <= 0 else min(args.max_torque,
                                                                    0.99 * scene.max_torque)
        period = scene.dt * scene.publish_every  # between states
        print(f"pd_attitude: {args.body} on {client.bus}: kp {kp:g}, kd {kd:g}, "
              f"|tau| <= {limit:g} N m, a state every {period * 1e3:g} ms")

        start = time.monotonic()
        settled_since: float | None = None
        last_print = 0.0
        refused_since: float | None = None
        row = None
        with client.states(timeout=5.0) as states:
            for s in states:
                now = time.monotonic()
                if row is None:
                    row = int(np.nonzero(s.ids == body.id)[0][0])
                q = s.orientations[row]
                w_B = rotate_inverse(q, s.angular_velocities[row])
                # The error rotation, body frame: q_err = conj(q_WB) q_target.
                phi = rotation_vector(quat_mul(quat_conj(q), args.target))
                angle = math.degrees(np.linalg.norm(phi))
                tau = I @ (kp * phi - kd * w_B) + np.cross(w_B, I @ w_B)
                n = np.linalg.norm(tau)
                if n > limit:
                    tau *= limit / n  # keep its direction
                client.send(body.id, torque=tau, torque_frame="body", ttl=3 * period)

                reason = client.take_refusal()
                if reason is not None:
                    refused_since = refused_since or now
                    print(f"pd_attitude: refused by rigidd: {reason}", file=sys.stderr)
                    if now - refused_since > 2.0:
                        return 1
                else:
                    refused_since = None
                if now - last_print >= 0.2:
                    last_print = now
                    print(f"t {s.time:8.3f} s  error {angle:8.3f} deg  "
                          f"|w| {np.linalg.norm(w_B):7.4f} rad/s  |tau| {np.linalg.norm(tau):6.3f} N m",
                          flush=True)
                if angle < args.settle:
                    settled_since = settled_since if settled_since is not None else s.time
                    if s.time - settled_since >= args.hold:
                        # Stop pushing: the same (source, body) replaces the previous wrench.
                        client.send(body.id, torque=[0, 0, 0], torque_frame="body")
                        print(f"settled: error {angle:.3f} deg < {args.settle:g} deg for "
                              f"{args.hold:g} s, at t {s.time:.3f} s "
                              f"({now - start:.2f} s after start)", flush=True)
                        return 0
                else:
                    settled_since = None
                if now - start > args.timeout:
                    print(f"pd_attitude: not settled within {args.timeout:g} s "
                          f"(error {angle:.3f} deg)", file=sys.stderr)
                    return 1
    return 1


def main() -> int:
    args = parse_args(sys.argv[1:])
    try:
        return run(args)
    except TimeoutError as e:
        print(f"pd_attitude: {e}", file=sys.stderr)
        return 3
    except rigid.TransportError as e:
        print(f"pd_attitude: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
