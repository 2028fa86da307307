#!/usr/bin/env python3
"""The rigid Python package against C++, in one run, medians side by side.

  step     World.step(n) from Python on 10^4 bodies against the same World stepped by C++:
           rigid-sim on the same scene file, whose "ns per body-step" times World::step alone.
           Interleaved rounds, so that both see the same machine. Also step(1) in a loop with
           state views held (each call then refreshes the views: the cost of reading every step).
  read     Reading the state of 10^3 bodies into NumPy after a step: the four arrays (positions,
           orientations, velocities, angular_velocities), refreshed from the physics on read.
  latency  A Python controller's push to the state that shows it, per bus and per way the states
           reach Python (--delivery: Client.on_state's callback, Client.states' stream), against the C++
           client's, both at once on one rigidd: bench/loop_bench realtime starts rigidd (1 kHz,
           1000 racket bodies, a state every 10 ticks) and its C++ controller pushes body 0 (DDS)
           or 1 (LCM); the Python controller joins that rigidd and pushes body 2 in the same
           seconds, so that the machine's stalls hit both alike. Each pushes one tick every 5 ms
           plus a random fraction of a millisecond, timed from the send call to the arrival of the
           first state in which its body's velocity changed.

  PYTHONPATH=build/clients/python /usr/bin/python3 bench/physics/python_bench.py --build build
      [--parts step,read,latency] [--rounds 7] [--latency-seconds 20]
"""

from __future__ import annotations

import argparse
import csv
import os
import random
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


def racket_scene(n: int, publish_every: int = 10) -> str:
    """step_bench's and loop_bench's racket case: I = diag(1, 2, 3),
    w0 = (1e-3 + 1e-6 i, 5, 1e-3), no gravity, dt = 1 ms, the default integrator."""
    head = (f"world {{ rate_hz: 1000 publish_every: {publish_every} gravity {{ z: 0 }} "
            f"limits {{ max_commands_per_second: 100000 }} }}\n")
    bodies = "".join(
        f'body {{ name: "b{i}" mass: 1 inertia {{ x: 1 y: 2 z: 3 }} '
        f'angular_velocity {{ x: {1e-3 + 1e-6 * i!r} y: 5 z: 1e-3 }} use_gravity: false }}\n'
        for i in range(n))
    return head + bodies


def ns_per_body_step_cpp(sim: str, scene: Path, steps: int) -> float:
    out = subprocess.run([sim, str(scene), "--duration", str(steps * 1e-3)], check=True,
                         capture_output=True, text=True, timeout=600).stdout
    # "wall time ... s, stepping X s: Y ns per body-step"
    line = next(l for l in out.splitlines() if "ns per body-step" in l)
    return float(line.split(": ")[-1].split()[0])


def bench_step(rigid, sim: str, tmp: Path, rounds: int) -> None:
    n, steps = 10_000, 1000
    scene = tmp / "racket10k.pbtxt"
    scene.write_text(racket_scene(n))
    w = rigid.World.load(str(scene))
    w.step(steps)  # warm up (caches, page faults)
    ns_cpp, ns_py, ns_py1 = [], [], []
    for _ in range(rounds):
        ns_cpp.append(ns_per_body_step_cpp(sim, scene, steps))
        # rigid-sim times a world it has just built, so in cache; the child's run has evicted
        # this one: one untimed step brings it back, so that both are timed warm.
        w.step(1)
        t0 = time.perf_counter_ns()
        w.step(steps)
        ns_py.append((time.perf_counter_ns() - t0) / (steps * n))
        views = (w.positions, w.orientations, w.velocities, w.angular_velocities)  # held
        t0 = time.perf_counter_ns()
        for _ in range(steps // 4):
            w.step(1)
        ns_py1.append((time.perf_counter_ns() - t0) / (steps // 4 * n))
        del views
    c, p, p1 = (statistics.median(x) for x in (ns_cpp, ns_py, ns_py1))
    print(f"step, {n} racket bodies, {w.integrator}, {rounds} interleaved rounds (median ns per "
          f"body-step):")
    print(f"  C++ rigid-sim World::step(n)          {c:8.2f}")
    print(f"  Python World.step({steps})               {p:8.2f}   {100 * (p / c - 1):+.1f}% vs C++")
    print(f"  Python World.step(1), views held      {p1:8.2f}   {100 * (p1 / c - 1):+.1f}% vs C++ "
          f"(refreshes the views every call)")


def bench_read(rigid, tmp: Path) -> None:
    n = 1000
    w = rigid.World.from_string(racket_scene(n), "racket1k")
    samples, copies = [], []
    for _ in range(2000):
        w.step(1)  # no view held: the state is stale until read
        t0 = time.perf_counter_ns()
        p, q, v, om = w.positions, w.orientations, w.velocities, w.angular_velocities
        t1 = time.perf_counter_ns()
        snap = [p.copy(), q.copy(), v.copy(), om.copy()]
        t2 = time.perf_counter_ns()
        samples.append(t1 - t0)
        copies.append(t2 - t1)
        del p, q, v, om, snap
    s = np.array(samples) / 1e3
    c = np.array(copies) / 1e3
    print(f"read, {n} bodies, 2000 samples (us): the four state arrays after a step "
          f"p50 {np.median(s):.1f} / p99 {np.percentile(s, 99):.1f}; "
          f"copying them as well (.copy()) p50 {np.median(c):.1f} more")


# Each controller pushes every kPushPeriodS plus a random fraction of a millisecond: often enough
# that a run's p99 rests on tens of samples, not a handful.
kPushPeriodS = 0.005


def python_latency(rigid, prefix: str, transport: str, body: int, seconds: float,
                   delivery: str) -> list[float]:
    """Push `body` from Python for `seconds` on a rigidd already running under `prefix`; the
    states reach Python through Client.states() ("stream": a thread woken per state) or
    Client.on_state() ("callback": run on the bus's receive thread)."""
    lat: list[float] = []
    with rigid.Client(transport, prefix=prefix, timeout=10.0) as c:
        c.scene()
        if delivery == "callback":
            # (velocity before the push, send time) of the push in flight, set in one assignment
            pending: list = [None]

            def on_state(s) -> None:
                t = time.perf_counter_ns()
                p = pending[0]
                if p is not None and s.velocities[body, 0] != p[0]:
                    lat.append((t - p[1]) / 1e3)
                    pending[0] = None

            with c.on_state(on_state) as cb:
                while c.latest() is None:
                    time.sleep(0.01)
                end = time.monotonic() + seconds
                sign = 1.0
                while time.monotonic() < end and cb.active:
                    time.sleep(kPushPeriodS + random.random() * 1e-3)
                    pending[0] = (c.latest().velocities[body, 0], time.perf_counter_ns())
                    c.send(body, [sign * 1.0, 0, 0], ttl=0.0)
                    sign = -sign
                if cb.error is not None:
                    raise cb.error
            return lat
        with c.states(timeout=2.0) as states:
            next(states)
            end = time.monotonic() + seconds
            sign = 1.0
            while time.monotonic() < end:
                time.sleep(kPushPeriodS + random.random() * 1e-3)
                before = c.latest().velocities[body, 0]
                while states.pending:  # only states that arrive after the send count
                    next(states)
                t0 = time.perf_counter_ns()
                c.send(body, [sign * 1.0, 0, 0], ttl=0.0)
                deadline = time.monotonic() + 0.5
                while time.monotonic() < deadline:
                    s = next(states)
                    if s.velocities[body, 0] != before:
                        lat.append((time.perf_counter_ns() - t0) / 1e3)
                        break
                sign = -sign
    return lat


def latency_side_by_side(rigid, loop_bench: str, rigidd: str, transport: str, delivery: str,
                         seconds: float, tmp: Path) -> tuple[list[float], dict[str, float]]:
    """The Python and the C++ controller on one rigidd at once (see the module's docstring)."""
    out = tmp / f"loop_{transport}.csv"
    # loop_bench's own window is longer than Python's by the seconds Python needs to join it.
    margin = 8.0
    lb = subprocess.Popen([loop_bench, "realtime", "--bodies", "1000",
                           "--duration", str(seconds + margin), "--transport", transport,
                           "--push-every-ms", str(round(kPushPeriodS * 1e3)),
                           "--rigidd", rigidd, "--csv", str(out)],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        time.sleep(2.0)  # rigidd up and loop_bench's controllers started
        py = python_latency(rigid, f"bench{lb.pid}", transport, 2, seconds, delivery)
        text, _ = lb.communicate(timeout=seconds + margin + 120)
    finally:
        if lb.poll() is None:
            lb.kill()
            lb.wait(5)
    if lb.returncode != 0:
        raise RuntimeError(f"loop_bench realtime failed ({lb.returncode}):\n{text}")
    with open(out) as f:
        row = list(csv.DictReader(f))[-1]
    cpp = {k: float(row[k]) for k in ("latency_p50_us", "latency_p99_us", "latency_max_us")}
    return py, cpp


def bench_latency(rigid, build: Path, tmp: Path, seconds: float, deliveries: list[str]) -> None:
    rigidd = str(build / "server" / "rigidd" / "rigidd")
    loop_bench = str(build / "bench" / "loop_bench")
    if not os.access(loop_bench, os.X_OK):
        print(f"latency: no {loop_bench}: build the loop_bench target")
        return
    print(f"latency, push to the state that shows it, 1000 bodies at 1 kHz, Python and C++ "
          f"controllers on one rigidd at once, {seconds:g} s per bus (us):")
    for transport, delivery in ((t, d) for t in ("dds", "lcm") for d in deliveries):
        lat, cpp = latency_side_by_side(rigid, loop_bench, rigidd, transport, delivery, seconds,
                                        tmp)
        py = np.array(lat)
        print(f"  {transport} {delivery:8}: Python p50 {np.median(py):7.0f} "
              f"p99 {np.percentile(py, 99):7.0f} max {py.max():7.0f} (n {len(py)});  "
              f"C++ p50 {cpp['latency_p50_us']:7.0f} p99 {cpp['latency_p99_us']:7.0f} "
              f"max {cpp['latency_max_us']:7.0f}  "
              f"p50 {np.median(py) - cpp['latency_p50_us']:+.0f}, "
              f"p99 {np.percentile(py, 99) - cpp['latency_p99_us']:+.0f} vs C++")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", type=Path, default=Path("build"), help="the CMake build directory")
    ap.add_argument("--parts", default="step,read,latency")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--latency-seconds", type=float, default=20.0)
    ap.add_argument("--delivery", default="callback,stream",
                    help="how the Python controller gets its states: Client.on_state() "
                         "(callback), Client.states() (stream), or both in turn")
    args = ap.parse_args()
    sys.path.insert(0, str(args.build / "clients" / "python"))
    import rigid  # the build tree's

    parts = set(args.parts.split(","))
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        if "step" in parts:
            bench_step(rigid, str(args.build / "server" / "sim" / "rigid-sim"), tmp, args.rounds)
        if "read" in parts:
            bench_read(rigid, tmp)
        if "latency" in parts:
            deliveries = args.delivery.split(",")
            for d in deliveries:
                if d not in ("callback", "stream"):
                    ap.error(f"--delivery: unknown '{d}' (callback, stream)")
            bench_latency(rigid, args.build, tmp, args.latency_seconds, deliveries)
    return 0


if __name__ == "__main__":
    sys.exit(main())
