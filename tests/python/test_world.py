"""rigid.World: the physics through Python is the C++ World's bit for bit; state views; errors that
name what is wrong and change nothing. No network."""

from __future__ import annotations

import csv
import math
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import rigid
from conftest import SCENES, SOURCE_DIR, program

DEFAULT = SOURCE_DIR / "config" / "scenes" / "mixed.pbtxt"  # every body model, under gravity
RACKET = SOURCE_DIR / "config" / "scenes" / "racket.pbtxt"


def state_matrix(w: rigid.World) -> np.ndarray:
    """(N, 13): x, y, z, qw, qx, qy, qz, vx, vy, vz, wx, wy, wz, as the CSV rows order them."""
    return np.hstack([w.positions, w.orientations, w.velocities, w.angular_velocities])


def rows_by_step(text: str) -> dict[int, np.ndarray]:
    """python_world_dump's output: {step: (N, 13)}."""
    out: dict[int, list[list[float]]] = {}
    for line in text.splitlines():
        f = line.split(",")
        out.setdefault(int(f[0]), []).append([float(x) for x in f[2:]])
    return {k: np.array(v) for k, v in out.items()}


def assert_bits_equal(a: np.ndarray, b: np.ndarray, what: str) -> None:
    # Exact equality of every double (the text carries 17 significant digits: exact round trip).
    assert a.shape == b.shape, what
    diff = np.argwhere(a != b)
    assert diff.size == 0, f"{what}: first difference at {diff[0]}: {a[tuple(diff[0])]!r} vs {b[tuple(diff[0])]!r}"


# -- the same numbers as C++ ----------------------------------------------------------------------


@pytest.mark.parametrize("integrator", [i.name for i in rigid.integrators()])
def test_every_integrator_matches_rigid_sim_csv_bit_for_bit(tmp_path: Path, integrator: str) -> None:
    csv_path = tmp_path / "out.csv"
    subprocess.run(
        [program("RIGID_SIM"), str(DEFAULT), "--duration", "0.3", "--every", "50",
         "--integrator", integrator, "--csv", str(csv_path)],
        check=True, capture_output=True, timeout=120)
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    w = rigid.World.load(str(DEFAULT), integrator=integrator)
    assert w.integrator == integrator or integrator == "games103"  # an alias
    n = w.body_count
    assert len(rows) == n * 7  # t = 0, 0.05, ..., 0.3
    cols = ["x", "y", "z", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy", "wz"]
    for k in range(7):
        block = rows[k * n:(k + 1) * n]
        assert [r["body"] for r in block] == w.body_names
        expected = np.array([[float(r[c]) for c in cols] for r in block])
        assert_bits_equal(state_matrix(w), expected, f"{integrator} at t = {block[0]['t']}")
        assert float(block[0]["t"]) == w.time
        w.step(50)


def test_forces_torques_and_impulses_match_the_cpp_world_bit_for_bit() -> None:
    ops = [
        "force:tumbler:0.3,-0.2,0.1:0.05,0.1,-0.2:body",
        "force:ball:1e-3,2,-0.5:0,0,0:world",
        "torque:top:0.01,0.02,-0.5:world",
        "torque:rocket:0.1,0,0:body",
        "impulse:pebble:0.01,0,0.02:0,0,0:world",
        "impulse:tumbler:0,0.001,0:0.05,0,0:body",
        "step:37", "print", "clear", "step:20", "print",
        "force:top:0,0,3:0.2,0,0:body", "step:1", "print", "step:100", "print",
    ]
    out = subprocess.run([program("RIGID_WORLD_DUMP"), str(DEFAULT), *ops],
                         check=True, capture_output=True, text=True, timeout=60).stdout
    expected = rows_by_step(out)

    w = rigid.World.load(str(DEFAULT))
    w.add_force("tumbler", [0.3, -0.2, 0.1], at=[0.05, 0.1, -0.2], frame="body")
    w.add_force(w.body("ball"), np.array([1e-3, 2, -0.5]))
    w.add_torque("top", (0.01, 0.02, -0.5), frame="world")
    w.add_torque("rocket", [0.1, 0, 0], frame="body")
    w.apply_impulse("pebble", [0.01, 0, 0.02])
    w.apply_impulse("tumbler", [0, 0.001, 0], at=[0.05, 0, 0], frame="body")
    got = {}
    w.step(37)
    got[w.step_count] = state_matrix(w).copy()
    w.clear_applied()
    w.step(20)
    got[w.step_count] = state_matrix(w).copy()
    w.add_force("top", [0, 0, 3], at=[0.2, 0, 0], frame="body")
    w.step()
    got[w.step_count] = state_matrix(w).copy()
    w.step(100)
    got[w.step_count] = state_matrix(w).copy()
    assert sorted(got) == sorted(expected) == [37, 57, 58, 158]
    for k in got:
        assert_bits_equal(got[k], expected[k], f"step {k}")


def test_step_n_equals_n_single_steps_and_reset_restarts() -> None:
    a = rigid.World.load(str(RACKET))
    b = rigid.World.load(str(RACKET))
    a.step(2500)
    for _ in range(2500):
        b.step()
    assert_bits_equal(state_matrix(a), state_matrix(b), "step(2500) vs 2500 x step()")
    assert a.time == b.time == 2500 * a.dt
    a.reset()
    assert a.step_count == 0 and a.time == 0.0
    fresh = rigid.World.load(str(RACKET))
    assert_bits_equal(state_matrix(a), state_matrix(fresh), "after reset")


# -- state views ----------------------------------------------------------------------------------


def test_state_views_are_read_only_and_follow_the_world() -> None:
    w = rigid.World.load(str(DEFAULT))
    n = w.body_count
    views = {"positions": w.positions, "orientations": w.orientations,
             "velocities": w.velocities, "angular_velocities": w.angular_velocities}
    shapes = {"positions": (n, 3), "orientations": (n, 4), "velocities": (n, 3),
              "angular_velocities": (n, 3)}
    before = {k: v.copy() for k, v in views.items()}
    for k, v in views.items():
        assert v.shape == shapes[k] and v.dtype == np.float64
        assert not v.flags.writeable
        with pytest.raises(ValueError, match="read-only"):
            v[0, 0] = 1.0
        with pytest.raises(ValueError):
            v.flags.writeable = True
        with pytest.raises(ValueError, match="read-only"):
            v += 1.0
    assert_bits_equal(state_matrix(w), np.hstack(list(before.values())), "writes changed nothing")
    # The same buffers, refreshed by step(): a kept view shows the current state.
    w.step(10)
    expected = rows_by_step(subprocess.run(
        [program("RIGID_WORLD_DUMP"), str(DEFAULT), "step:10", "print"],
        check=True, capture_output=True, text=True, timeout=60).stdout)[10]
    assert_bits_equal(np.hstack(list(views.values())), expected, "kept views after step(10)")
    assert w.positions is views["positions"]
    w.reset()
    assert_bits_equal(np.hstack(list(views.values())), np.hstack(list(before.values())),
                      "kept views after reset")
    # A view outlives its world (it keeps the buffers, with their last contents).
    w.step(10)
    del w
    assert_bits_equal(np.hstack(list(views.values())), expected, "views after the world is gone")
    # Unit quaternions, w first.
    assert np.allclose(np.linalg.norm(views["orientations"], axis=1), 1.0)


def test_a_view_not_held_is_refreshed_when_read() -> None:
    w = rigid.World.load(str(RACKET))
    w.step(5)  # nobody holds a view: the buffers are filled when read
    p = w.angular_velocities.copy()
    v = rigid.World.load(str(RACKET))
    v.step(5)
    assert_bits_equal(p, v.angular_velocities, "lazy refresh")


# -- errors ---------------------------------------------------------------------------------------


def test_a_bad_scene_raises_rigid_sims_message() -> None:
    bad = SCENES / "bad.pbtxt"
    sim = subprocess.run([program("RIGID_SIM"), str(bad)], capture_output=True, text=True,
                         timeout=60)
    assert sim.returncode == 2
    with pytest.raises(rigid.SceneError) as e:
        rigid.World.load(str(bad))
    assert str(e.value) == sim.stderr.strip().splitlines()[0]
    assert str(e.value).startswith(f"{bad}:9:3: ")
    assert "mass" in str(e.value) and "-2" in str(e.value)
    assert (e.value.file, e.value.line, e.value.column) == (str(bad), 9, 3)
    assert isinstance(e.value, ValueError)

    with pytest.raises(rigid.SceneError, match=r"^inline:2:[0-9]+: .*bogus"):
        rigid.World.from_string("world { rate_hz: 100 }\n  bogus: 1\n", "inline")
    with pytest.raises(rigid.SceneError, match="cannot open"):
        rigid.World.load("/nonexistent/scene.pbtxt")


def test_overrides_the_scene_refuses_raise_spec_error() -> None:
    with pytest.raises(rigid.SpecError, match="unknown integrator 'nope'"):
        rigid.World.load(str(RACKET), integrator="nope")
    with pytest.raises(rigid.SpecError, match="dt"):
        rigid.World.load(str(RACKET), dt=-1.0)
    w = rigid.World.load(str(RACKET), integrator="rk4", dt=1e-4)
    assert (w.integrator, w.dt) == ("rk4", 1e-4)


def test_integrators_lists_one_default() -> None:
    ints = rigid.integrators()
    assert sum(i.default for i in ints) == 1
    assert {"rk4", "exact_rotor4", "exact_rotor", "dlm"} <= {i.name for i in ints}
    default = next(i for i in ints if i.default)
    assert rigid.World.load(str(RACKET)).integrator == default.name


def test_bad_arguments_raise_clear_errors_and_change_nothing() -> None:
    w = rigid.World.load(str(DEFAULT))
    twin = rigid.World.load(str(DEFAULT))
    nan, inf = math.nan, math.inf
    cases = [
        (lambda: w.body("nope"), rigid.UnknownBodyError,
         "no body 'nope' in the scene (bodies: tumbler, top, ball, pebble, rocket)"),
        (lambda: w.add_force("nope", [1, 0, 0]), rigid.UnknownBodyError, "no body 'nope'"),
        (lambda: w.add_force(99, [1, 0, 0]), rigid.UnknownBodyError, "no body with index 99"),
        (lambda: w.add_force(-1, [1, 0, 0]), rigid.UnknownBodyError, "no body with index -1"),
        (lambda: w.add_force("ball", [nan, 1, 0]), ValueError,
         "add_force: body 'ball': force (nan, 1, 0) is not finite"),
        (lambda: w.add_force("ball", [1, 0, 0], at=[0, inf, 0]), ValueError,
         "add_force: body 'ball': at (0, inf, 0) is not finite"),
        (lambda: w.add_torque("top", [0, 0, -inf]), ValueError,
         "add_torque: body 'top': torque (0, 0, -inf) is not finite"),
        (lambda: w.apply_impulse("pebble", [nan, nan, nan]), ValueError,
         "apply_impulse: body 'pebble': impulse (nan, nan, nan) is not finite"),
        (lambda: w.add_force("ball", [1, 2]), ValueError, "force must have 3 components"),
        (lambda: w.add_force("ball", "xyz"), TypeError, "force must be 3 numbers"),
        (lambda: w.add_force("ball", [1, 2, 3], frame="local"), ValueError,
         "frame must be 'world' or 'body', got 'local'"),
        (lambda: w.add_force(1.5, [1, 2, 3]), TypeError, "a body is a name"),
        (lambda: w.step(-1), ValueError, "n must be >= 0"),
        (lambda: w.set_state("ball", position=[nan, 0, 0]), ValueError, "finite"),
        (lambda: w.set_state("ball", orientation=[0, 0, 0, 0]), ValueError, "quaternion"),
    ]
    for call, exc, message in cases:
        with pytest.raises(exc) as e:
            call()
        assert message in str(e.value), str(e.value)
    # Nothing reached the world: it steps exactly as its twin that saw none of it.
    w.step(200)
    twin.step(200)
    assert_bits_equal(state_matrix(w), state_matrix(twin), "after the refused calls")


# -- energy, momentum, impulses -------------------------------------------------------------------


def test_energy_and_momenta_agree_with_the_state() -> None:
    w = rigid.World.load(str(DEFAULT))
    w.step(100)
    m = w.masses
    v = w.velocities
    assert np.allclose(w.linear_momentum(), (m[:, None] * v).sum(axis=0), rtol=1e-14, atol=0)
    for i, name in enumerate(w.body_names):
        assert np.array_equal(w.linear_momentum(name), m[i] * v[i])
        if w.body_motion(name) == "translation":
            continue
        # T = m v.v / 2 + w.L / 2, with L in W.
        L = w.angular_momentum(name)
        t = 0.5 * m[i] * v[i] @ v[i] + 0.5 * w.angular_velocities[i] @ L
        assert w.kinetic_energy(name) == pytest.approx(t, rel=1e-12)
    assert w.kinetic_energy() == pytest.approx(sum(w.kinetic_energy(n) for n in w.body_names))
    total_L = sum(w.angular_momentum(n) + np.cross(w.positions[i], m[i] * v[i])
                  for i, n in enumerate(w.body_names))
    assert np.allclose(w.angular_momentum(), total_L, rtol=1e-13, atol=1e-15)


def test_a_free_body_keeps_its_angular_momentum_and_energy() -> None:
    w = rigid.World.load(str(RACKET))
    L0, T0 = w.angular_momentum("racket"), w.kinetic_energy("racket")
    w.step(5000)  # through the first flip
    assert np.allclose(w.angular_momentum("racket"), L0, rtol=1e-9, atol=1e-12)
    assert w.kinetic_energy("racket") == pytest.approx(T0, rel=1e-9)
    assert w.total_energy() == pytest.approx(T0, rel=1e-9)


def test_an_impulse_changes_momentum_by_j_at_the_next_step() -> None:
    w = rigid.World.load(str(DEFAULT))
    v0 = w.velocities[w.body("pebble")].copy()
    w.apply_impulse("pebble", [0.05, 0, 0])
    w.step()
    # The pebble (0.05 kg) gains 1 m/s along x, beyond what gravity did in the step.
    twin = rigid.World.load(str(DEFAULT))
    twin.step()
    dv = w.velocities[w.body("pebble")] - twin.velocities[twin.body("pebble")]
    assert dv == pytest.approx([1.0, 0, 0], abs=1e-12)
    assert v0[0] == 3.0


# -- the GIL --------------------------------------------------------------------------------------


def test_stepping_releases_the_gil() -> None:
    text = "world { rate_hz: 1000 gravity { z: 0 } }\n" + "".join(
        f'body {{ name: "b{i}" mass: 1 inertia {{ x: 1 y: 2 z: 3 }} '
        f'angular_velocity {{ x: 1 y: 2 z: 0.5 }} }}\n' for i in range(2000))
    w = rigid.World.from_string(text, "many")
    ticks = 0
    done = threading.Event()

    def count() -> None:
        nonlocal ticks
        while not done.is_set():
            ticks += 1
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    start = time.perf_counter()
    w.step(1000)  # ~25 ns per body-step: ~50 ms
    elapsed = time.perf_counter() - start
    done.set()
    t.join()
    # While step() ran (tens of ms or more) the other thread kept running.
    assert elapsed > 0.02
    assert ticks >= 0.3 * elapsed / 0.002, (ticks, elapsed)


def test_help_is_useful() -> None:
    doc = rigid.World.__doc__ or ""
    assert "read-only" in doc and "copies of the physics state" in doc
    for name in ["load", "from_string", "step", "add_force", "add_torque", "apply_impulse",
                 "positions", "orientations", "kinetic_energy", "angular_momentum"]:
        assert getattr(rigid.World, name).__doc__, name


DROP = SOURCE_DIR / "tests" / "rigidd" / "scenes" / "drop.pbtxt"  # a ball dropped 1 m, e = 1/2


def test_contacts_are_the_closed_form_bounces_and_rigid_sims_contact_csv_bit_for_bit(
    tmp_path: Path,
) -> None:
    # The ball falls 1 m to its first impact at t1 = sqrt(2 / g), takes the impulse m (1 + e) g t1,
    # bounces with e = 1/2 and rests at 3 t1 (the bounce series summed).
    w = rigid.World.load(str(DROP))
    assert w.static_parts == ["ground"]
    assert w.contacts() == []
    w.step(1500)
    c = w.contacts()
    g, m, e = 9.81, 2.0, 0.5
    t1 = math.sqrt(2.0 / g)
    assert c[0].kind == "impact" and c[0].body == "ball" and c[0].part == "ground"
    assert (c[0].body_index, c[0].part_index) == (0, 0)
    assert abs(c[0].time - t1) < 1e-14
    assert c[0].point == (0.25, -0.5, 0.0) and c[0].normal == (0.0, 0.0, 1.0)
    assert abs(c[0].impulse[2] - m * (1 + e) * g * t1) < 1e-13
    assert c[-1].kind == "resting" and abs(c[-1].time - 3 * t1) < 1e-13
    assert [x.time for x in c] == sorted(x.time for x in c)
    assert w.contacts_dropped == 0
    assert "impact of 'ball' on 'ground'" in repr(c[0])
    # The same events as rigid-sim --contacts-csv writes for the same run, to the last bit.
    out = tmp_path / "contacts.csv"
    sim = subprocess.run(
        [program("RIGID_SIM"), str(DROP), "--duration", "1.5", "--contacts-csv", str(out)],
        capture_output=True, text=True, timeout=60)
    assert sim.returncode == 0, sim.stderr
    assert f"contacts csv: {out}, {len(c)} events" in sim.stdout
    with out.open() as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(c)
    for r, x in zip(rows, c):
        assert int(r["tick"]) == math.ceil(x.time / 1e-3 - 1e-9)
        assert (r["kind"], r["body"], r["part"]) == (x.kind, x.body, x.part)
        assert float(r["t"]) == x.time
        assert tuple(float(r[k]) for k in ("px", "py", "pz")) == x.point
        assert tuple(float(r[k]) for k in ("nx", "ny", "nz")) == x.normal
        assert tuple(float(r[k]) for k in ("jx", "jy", "jz")) == x.impulse
    # A separate event (the body leaves all its supports) names no part.
    toss = rigid.World.load(str(SOURCE_DIR / "config" / "scenes" / "contacts.pbtxt"))
    toss.step(3000)
    kinds = {(x.kind, x.part == "", x.part_index == -1) for x in toss.contacts()}
    assert ("separate", True, True) in kinds
    assert all(p == (k == "separate") for k, p, _ in kinds), kinds
    # A step without events empties the list; a scene without static parts has none.
    w.step(10)
    assert w.contacts() == []
    free = rigid.World.load(str(DEFAULT))
    free.step(100)
    assert free.contacts() == [] and free.static_parts == []
