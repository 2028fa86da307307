"""rigid.Client against a live rigidd on each bus (DDS and LCM over loopback): the scene, states in
order, a push's effect per tick, controls answered, refusals raised with rigidd's reason.

rigidd runs as a subprocess with a unique --prefix per test and is stopped by PID (conftest.py).
Needs scripts/net-setup (LCM's multicast route on lo) and CYCLONEDDS_URI (ctest sets both up)."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import threading
import time
from typing import Callable

import numpy as np
import pytest

import rigid
from conftest import SCENES, SOURCE_DIR, Daemon, StartDaemon

pytestmark = pytest.mark.network

PROBE = SCENES / "probe.pbtxt"
LOCKSTEP = SCENES / "lockstep.pbtxt"
PUCK = 1
DV_PER_TICK = 4.0 * 1e-3 / 2.0  # 4 N on the 2 kg puck for one 1 ms tick


def client_for(d: Daemon) -> rigid.Client:
    try:
        c = rigid.Client(d.transport, prefix=d.prefix, timeout=10.0)
    except rigid.TransportError as e:
        pytest.fail(f"{e} (run scripts/net-setup as root; ctest sets CYCLONEDDS_URI)")
    try:
        c.scene()  # rigidd is up and seen on this bus
    except TimeoutError:
        pytest.fail(f"rigidd did not show up; its stderr:\n{d.stderr()}")
    return c


def wait_for(pred: Callable[[], bool], timeout: float = 10.0) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if pred():
            return True
        time.sleep(0.005)
    return pred()


def test_the_scene_matches_the_file(rigidd: StartDaemon, bus: str) -> None:
    d = rigidd(PROBE, bus)
    w = rigid.World.load(str(PROBE))
    with client_for(d) as c:
        s = c.scene()
        assert [b.name for b in s.bodies] == w.body_names == ["brick", "puck"]
        assert [b.id for b in s.bodies] == [0, 1]
        assert [b.mass for b in s.bodies] == list(w.masses)
        assert np.array_equal(np.array(s.bodies[0].inertia), w.inertia("brick"))
        assert (s.dt, s.rate_hz, s.substeps, s.publish_every) == (1e-3, 1000.0, 1, 1)
        assert (s.max_force, s.max_torque, s.max_ttl) == (100.0, 50.0, 5.0)
        assert s.gravity == (0.0, 0.0, 0.0)
        assert s.integrator == w.integrator
        assert c.bodies() == list(s.bodies)
        assert c.body("puck") == PUCK and c.body(0) == 0
        with pytest.raises(rigid.UnknownBodyError,
                           match=r"^no body 'nope' in the scene \(bodies: brick, puck\)$"):
            c.body("nope")
        with pytest.raises(rigid.UnknownBodyError):
            c.push("nope", [1, 0, 0])
    assert d.stop() == 0, d.stderr()


def test_states_arrive_in_order_with_numpy_arrays(rigidd: StartDaemon, bus: str) -> None:
    d = rigidd(PROBE, bus)
    with client_for(d) as c, c.states(timeout=10.0) as stream:
        got = [next(stream) for _ in range(100)]
        assert stream.dropped == 0
        ticks = [s.tick for s in got]
        assert all(b > a for a, b in zip(ticks, ticks[1:])), ticks
        if bus == "lcm":
            # LCM on loopback loses nothing at this rate: every tick missing here is one rigidd
            # itself skipped (its publisher had no time for it on a loaded machine: Stats count
            # those), none lost on the way. Best-effort DDS may also drop.
            missing = ticks[-1] - ticks[0] + 1 - len(ticks)
            assert wait_for(lambda: c.stats()["tick"] > ticks[-1]), "no Stats after the states"
            assert missing <= c.stats()["states_skipped"], (missing, c.stats(), ticks)
    for s in got:
        assert s.time == pytest.approx(s.tick * 1e-3, rel=1e-12)
        assert list(s.ids) == [0, 1] and len(s) == 2
        assert s.positions.shape == (2, 3) and s.orientations.shape == (2, 4)
        assert s.velocities.shape == (2, 3) and s.angular_velocities.shape == (2, 3)
        assert not s.positions.flags.writeable
        assert s.positions[PUCK].tolist() == [1.0, 0.0, 0.0]
    assert d.stop() == 0, d.stderr()


def test_a_push_changes_velocity_by_f_dt_over_m_per_tick(rigidd: StartDaemon, bus: str) -> None:
    d = rigidd(PROBE, bus)
    with client_for(d) as c, c.states(timeout=10.0) as stream:
        next(stream)
        accepted = c.push("puck", [4, 0, 0], ttl=0.1)  # 100 ticks
        assert (accepted.body, accepted.force, accepted.ttl) == (PUCK, (4.0, 0.0, 0.0), 0.1)
        states = []
        while not states or states[-1].tick < accepted.tick + 200:
            states.append(next(stream))
    v = [(s.tick, float(s.velocities[PUCK, 0])) for s in states]
    moving = [(t, x) for t, x in v if x > 0]
    assert moving, v[:5]
    # The tick the push began, read off the first moving state (k ticks pushed: k * F dt / m).
    onset = moving[0][0] + 1 - round(moving[0][1] / DV_PER_TICK)
    assert onset in (accepted.tick, accepted.tick + 1), (onset, accepted.tick)
    for t, x in v:
        pushed = min(max(t - onset + 1, 0), 100)
        assert x == pytest.approx(DV_PER_TICK * pushed, abs=1e-12), (t, onset)
    assert sum(1 for t, _ in v if t >= onset + 100) > 50  # well after expiry: 100 ticks' worth
    # The brick was not touched.
    assert np.all(states[-1].velocities[0] == 0) and np.all(states[-1].angular_velocities[0] == 0)
    assert d.stop() == 0, d.stderr()


def test_on_state_calls_fn_with_each_state_on_the_receive_thread(rigidd: StartDaemon,
                                                                  bus: str) -> None:
    d = rigidd(PROBE, bus)
    got: list[tuple[int, int]] = []
    with client_for(d) as c:
        with c.on_state(lambda s: got.append((s.tick, threading.get_ident()))) as cb:
            assert wait_for(lambda: len(got) >= 100)
            assert cb.active and cb.error is None
        n = len(got)  # close() has returned: fn is not running and will not run again
        time.sleep(0.1)
        assert len(got) == n and not cb.active
        assert cb.calls == n
        # A callback may add another one: it joins after the state being delivered.
        inner: list[int] = []
        added: dict[str, rigid.StateCallback] = {}
        added_at: list[int] = []

        def outer(s: rigid.State) -> None:
            if not added:
                added["cb"] = c.on_state(lambda s2: inner.append(s2.tick))
                added_at.append(s.tick)

        with c.on_state(outer):
            assert wait_for(lambda: len(inner) >= 10)
        added["cb"].close()
        assert inner[0] > added_at[0] and inner == sorted(inner), (added_at, inner[:5])
    ticks = [t for t, _ in got]
    assert all(b > a for a, b in zip(ticks, ticks[1:])), ticks
    threads = {t for _, t in got}
    assert len(threads) == 1 and threading.get_ident() not in threads
    assert d.stop() == 0, d.stderr()


def test_inside_on_state_send_works_and_waiting_calls_are_refused(rigidd: StartDaemon,
                                                                  bus: str) -> None:
    d = rigidd(PROBE, bus)
    errors: dict[str, str] = {}
    sent: list[int] = []

    def fn(s: rigid.State) -> None:
        if sent:
            return
        for name, call in (("push", lambda: c.push(PUCK, [1, 0, 0])),
                           ("pause", c.pause),
                           ("close", c.close)):
            try:
                call()
            except RuntimeError as e:
                errors[name] = str(e)
        assert c.scene().bodies[PUCK].name == "puck" and c.body("puck") == PUCK
        assert c.latest() is not None
        sent.append(s.tick)
        c.send(PUCK, [4, 0, 0], ttl=0.0)  # one tick: the puck's velocity becomes DV_PER_TICK

    with client_for(d) as c, c.states(timeout=10.0) as stream:
        with c.on_state(fn) as cb:
            assert wait_for(lambda: bool(sent))
            v = 0.0
            deadline = time.monotonic() + 10.0
            while v == 0.0 and time.monotonic() < deadline:
                v = float(next(stream).velocities[PUCK, 0])
            assert v == pytest.approx(DV_PER_TICK, abs=1e-12)
            assert cb.error is None, cb.error
        assert c.take_refusal() is None
    assert set(errors) == {"push", "pause", "close"}, errors
    assert errors["push"].startswith("Client.push() inside an on_state callback would wait")
    assert errors["pause"].startswith("Client.pause() inside an on_state callback")
    assert errors["close"].startswith("Client.close() inside an on_state callback")
    assert d.stop() == 0, d.stderr()


def test_an_exception_in_on_state_ends_that_callback_only(rigidd: StartDaemon, bus: str,
                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    d = rigidd(PROBE, bus)
    reported: list[BaseException] = []
    monkeypatch.setattr(sys, "unraisablehook", lambda u: reported.append(u.exc_value))
    calls = [0]

    def bad(s: rigid.State) -> None:
        calls[0] += 1
        raise ValueError(f"bad state {s.tick}")

    with client_for(d) as c:
        good = c.on_state(lambda s: None)
        failing = c.on_state(bad)
        assert wait_for(lambda: not failing.active)
        n = good.calls
        assert wait_for(lambda: good.calls > n + 10), "the other callback stopped too"
        assert good.active
        assert isinstance(failing.error, ValueError) and calls[0] == 1
        assert failing.calls == 0
        assert reported == [failing.error]
        c.close()
        assert not good.active  # closing the client ends its callbacks
        n = good.calls
        time.sleep(0.05)
        assert good.calls == n
        with pytest.raises(RuntimeError, match="the client is closed"):
            c.on_state(lambda s: None)
    with pytest.raises(TypeError, match="on_state needs a callable, got int"):
        rigid.Client(bus, prefix="pynobody").on_state(3)  # type: ignore[arg-type]
    assert d.stop() == 0, d.stderr()


def test_exiting_with_a_callback_running_ends_cleanly(rigidd: StartDaemon, bus: str) -> None:
    d = rigidd(PROBE, bus)
    # A script that leaves its client and a busy callback open at exit: the atexit hook closes
    # them before the interpreter finalizes, so the receive thread never runs Python after it.
    script = (
        "import rigid, sys, time\n"
        f"c = rigid.Client({bus!r}, prefix={d.prefix!r}, timeout=10.0)\n"
        "c.scene()\n"
        "n = [0]\n"
        "def fn(s):\n"
        "    n[0] += 1\n"
        "    sum(range(20000))\n"
        "c.on_state(fn)\n"
        "while n[0] < 50: time.sleep(0.01)\n"
        "print('calls', n[0])\n"
    )
    for _ in range(3):
        r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                           timeout=60)
        assert r.returncode == 0, r.stderr
        assert r.stdout.startswith("calls "), r.stdout
        assert r.stderr == "", r.stderr
    assert d.stop() == 0, d.stderr()


def test_pause_step_reset_resume_are_answered(rigidd: StartDaemon, bus: str) -> None:
    d = rigidd(PROBE, bus)
    with client_for(d) as c:
        paused = c.pause()
        assert paused.command == "pause"
        assert wait_for(lambda: (s := c.latest()) is not None and s.tick >= paused.tick)
        time.sleep(0.05)
        t0 = c.latest().tick
        time.sleep(0.1)
        assert c.latest().tick == t0, "ticks went on while paused"

        # One tick of 4 N on the puck while paused: exactly F dt / m after the next step.
        c.push("puck", [4, 0, 0], ttl=0.0)
        stepped = c.step(5)
        assert stepped.command == "step"
        assert wait_for(lambda: c.latest().tick == t0 + 5), (c.latest().tick, t0)
        s = c.latest()
        assert s.velocities[PUCK].tolist() == [DV_PER_TICK, 0.0, 0.0]

        reset = c.reset()
        assert reset.command == "reset"
        c.step(1)
        assert wait_for(lambda: c.latest().tick == 1), c.latest().tick
        s = c.latest()
        assert s.velocities[PUCK].tolist() == [0.0, 0.0, 0.0]
        assert s.positions[PUCK].tolist() == [1.0, 0.0, 0.0]

        resumed = c.resume()
        assert resumed.command == "resume"
        assert wait_for(lambda: c.latest().tick > 50)
        assert c.set_rate(2.0).command == "rate"
        # Stats go out once a second: the newest may predate the first accepted command.
        assert wait_for(lambda: c.stats()["commands_accepted"] >= 1), c.stats()
        assert c.stats()["mode"] == "realtime"
    assert d.stop() == 0, d.stderr()


def test_refused_commands_raise_with_rigidds_reason(rigidd: StartDaemon, bus: str) -> None:
    d = rigidd(PROBE, bus)
    with client_for(d) as c:
        with pytest.raises(rigid.Refused) as e:
            c.push("puck", [1, 0, 0], ttl=10.0)
        assert "ttl 10 s > max_ttl 5" in e.value.reason
        assert str(e.value).startswith("push: refused by rigidd: ")
        with pytest.raises(rigid.Refused, match=r"\|force\| 1000 N > max_force 100"):
            c.push("puck", [1000, 0, 0])
        with pytest.raises(rigid.Refused, match=r"max_torque 50"):
            c.push("brick", torque=[0, 0, 60])
        with pytest.raises(rigid.Refused, match=r"force \(nan, 0, 0\)"):
            c.push("puck", [math.nan, 0, 0])
        with pytest.raises(rigid.Refused, match=r"^rate: invalid: "):
            c.set_rate(0.0)
        with pytest.raises(ValueError, match="frame must be 'world' or 'body'"):
            c.push("puck", [1, 0, 0], frame="local")
        # None of them moved anything: judged on a state published after the last refusal
        # (the first state may not have arrived yet on a loaded machine).
        before = c.latest()
        after = -1 if before is None else before.tick
        assert wait_for(lambda: getattr(c.latest(), "tick", -1) > after), \
            "no state from rigidd within 10 s of the refusals"
        s = c.latest()
        assert np.all(s.velocities == 0), s.velocities
        stats = c.stats()
        assert stats["rejected"]["over_limit"] >= 3 or wait_for(
            lambda: c.stats()["rejected"]["over_limit"] >= 3)
    assert d.stop() == 0, d.stderr()


def test_set_state_lands_on_the_next_tick_and_reset_puts_one_body_back(rigidd: StartDaemon,
                                                                        bus: str) -> None:
    d = rigidd(PROBE, bus)
    with client_for(d) as c:
        t = c.pause().tick
        r = c.set_state("puck", position=[0, 2, 0], velocity=np.array([0.0, 0.5, 0.0]))
        assert r.command == "set_state" and r.tick == t, r
        # Paused: the edited state is published at once, as the same tick.
        assert wait_for(lambda: c.latest().positions[PUCK].tolist() == [0.0, 2.0, 0.0])
        assert c.latest().tick == t
        # The next tick steps from it: 0.5 m/s for 1 ms, no force, no gravity.
        c.step(1)
        assert wait_for(lambda: c.latest().tick == t + 1)
        assert c.latest().positions[PUCK].tolist() == [0.0, 2.0 + 0.5e-3, 0.0]
        # Body-frame velocities turn with the orientation after the edit (90 degrees about z).
        h = math.sqrt(0.5)
        c.set_state("brick", orientation=[h, 0, 0, h], angular_velocity=[1, 0, 0],
                    angular_velocity_frame="body")
        assert wait_for(lambda: abs(c.latest().angular_velocities[0][1] - 1.0) < 1e-12), \
            c.latest().angular_velocities[0]
        # reset(body): that body back to its scene state; the tick goes on.
        r = c.reset("puck")
        assert r.command == "reset_body" and r.tick == t + 1, r
        assert wait_for(lambda: c.latest().positions[PUCK].tolist() == [1.0, 0.0, 0.0])
        assert c.latest().velocities[PUCK].tolist() == [0.0, 0.0, 0.0]
        assert c.latest().tick == t + 1

        # Checked before sending: each error names the argument and its value.
        with pytest.raises(ValueError, match=r"orientation \(1, 1, 0, 0\) must be a unit"):
            c.set_state("puck", orientation=[1, 1, 0, 0])
        with pytest.raises(ValueError, match=r"position \(nan, 0, 0\) is not finite"):
            c.set_state("puck", position=[math.nan, 0, 0])
        with pytest.raises(ValueError, match="velocity_frame must be 'world' or 'body'"):
            c.set_state("puck", velocity=[1, 0, 0], velocity_frame="local")
        with pytest.raises(ValueError, match="orientation must have 4 components"):
            c.set_state("puck", orientation=[1, 0, 0])
        with pytest.raises(ValueError, match="nothing to set"):
            c.set_state("puck")
        with pytest.raises(rigid.UnknownBodyError):
            c.set_state("comet", position=[0, 0, 0])
    assert d.stop() == 0, d.stderr()


def test_edits_are_refused_with_controls_off(rigidd: StartDaemon, bus: str) -> None:
    d = rigidd(PROBE, bus, "realtime", "--controls", "off")
    with client_for(d) as c:
        with pytest.raises(rigid.Refused, match=r"^set_state: not allowed: .*--controls off"):
            c.set_state("puck", position=[0, 0, 9])
        with pytest.raises(rigid.Refused, match=r"^reset_body: not allowed: "):
            c.reset("puck")
        assert c.latest().positions[PUCK].tolist() == [1.0, 0.0, 0.0]
    assert d.stop() == 0, d.stderr()


def test_no_rigidd_times_out_with_the_bus_named(bus: str) -> None:
    with rigid.Client(bus, prefix="pynobody", timeout=0.3) as c:
        with pytest.raises(TimeoutError, match="no SceneInfo from rigidd within 0.3 s"):
            c.scene()
        with pytest.raises(TimeoutError, match="reply to pause"):
            c.pause()
        with c.states(timeout=0.2) as stream, pytest.raises(TimeoutError, match="no state"):
            next(stream)
    with pytest.raises(ValueError, match="transport must be 'dds' or 'lcm'"):
        rigid.Client("udp")


@pytest.mark.lockstep
def test_lockstep_step_500_yields_500_over_publish_every_states(rigidd: StartDaemon,
                                                                bus: str) -> None:
    # As the C++ lockstep test does: the state best-effort (the subscriber keeps 256 unread; a
    # reliable keep-last-1 writer would replace a state not yet acknowledged), and on LCM a group
    # port of the test's own, so that no other traffic shares this client's receive buffers.
    url = f"udpm://239.255.76.67:{7900 + os.getpid() % 90}?ttl=0&recv_buf_size=4194304"
    extra = ("--lcm-url", url) if bus == "lcm" else ()
    d = rigidd(LOCKSTEP, bus, "lockstep", *extra)
    try:
        c = rigid.Client(bus, prefix=d.prefix, url=url if bus == "lcm" else None, timeout=10.0)
        c.scene()
    except (rigid.TransportError, TimeoutError) as e:
        pytest.fail(f"{e}; rigidd's stderr:\n{d.stderr()}")
    with c, c.states(timeout=10.0) as stream:
        reply = c.step(500)
        ticks: list[int] = []
        deadline = time.monotonic() + 10.0  # rigidd may repeat its last state while idle
        while time.monotonic() < deadline:
            try:
                s = next(stream)
            except TimeoutError:
                break
            if 0 < s.tick <= 500 and s.tick not in ticks:
                ticks.append(s.tick)
            if s.tick >= 500:
                break
        assert reply.command == "step"
        assert ticks == list(range(10, 501, 10)), ticks
    assert d.stop() == 0, d.stderr()


DROP = SOURCE_DIR / "tests" / "rigidd" / "scenes" / "drop.pbtxt"  # a ball dropped 1 m, e = 1/2


@pytest.mark.lockstep
def test_on_contact_gets_every_contact_event_as_the_world_has_it(rigidd: StartDaemon,
                                                                  bus: str) -> None:
    # A lockstep rigidd on a ball dropped onto a plane: on_contact gets each event once, in order,
    # named by the scene, the same values as rigid.World's contacts() for the same steps.
    d = rigidd(DROP, bus, "lockstep")
    got: list[rigid.Contact] = []
    with client_for(d) as c:
        c.scene()
        c.on_contact(got.append)
        c.step(1500, timeout=20.0)
        assert wait_for(lambda: bool(got) and got[-1].kind == "resting"), [x.kind for x in got]
    w = rigid.World.load(str(DROP))
    w.step(1500)
    want = w.contacts()
    assert [(x.kind, x.body, x.part, x.time, x.point, x.normal, x.impulse) for x in got] == \
        [(x.kind, x.body, x.part, x.time, x.point, x.normal, x.impulse) for x in want]
    assert got[0].kind == "impact" and got[0].body == "ball" and got[0].part == "ground"
