"""rigid: rigid-body simulation from Python.

- ``rigid.World``: the physics core (C++ ``rigid::physics::World``) on a scene file, stepped
  from Python with its state as NumPy arrays. Same numbers as ``rigid-sim``, bit for bit.
- ``rigid.Client``: a conversation with a running ``rigidd`` over Cyclone DDS or LCM: its scene,
  a stream of states, pushes (forces at body points) and control requests, each answered by
  rigidd or raising with its reason.
- ``rigid.integrators()``: the integrators a scene (or ``World.load(..., integrator=)``) can name.

Errors are exceptions carrying the C++ tools' one-line messages: ``SceneError``
("FILE:LINE:COL: message"), ``SpecError``, ``UnknownBodyError``, ``TransportError``,
``Refused`` (rigidd's reason), ``TimeoutError`` (no answer in time) and ``ValueError`` for
non-finite or malformed numbers.
"""

from __future__ import annotations

import atexit
import math
import weakref
from dataclasses import dataclass
from typing import Any, Callable, Optional, Sequence, Union

from ._rigid import (
    Contact,
    SceneError,
    SpecError,
    State,
    StateCallback,
    StateStream,
    TransportError,
    UnknownBodyError,
    World,
)
from ._rigid import _integrators, _Session

__all__ = [
    "World",
    "Contact",
    "Client",
    "State",
    "StateStream",
    "StateCallback",
    "Integrator",
    "SceneInfo",
    "BodyInfo",
    "Reply",
    "Accepted",
    "integrators",
    "SceneError",
    "SpecError",
    "UnknownBodyError",
    "TransportError",
    "Refused",
]

Body = Union[str, int]
Vector = Sequence[float]


class Refused(RuntimeError):
    """rigidd refused a command: ``str()`` is the command and rigidd's reason, as rigidctl prints
    it; ``reason`` is rigidd's message alone."""

    def __init__(self, message: str, reason: str) -> None:
        super().__init__(message)
        self.reason = reason


@dataclass(frozen=True)
class Integrator:
    """An integrator a scene can name (rigid-sim --list-integrators)."""

    name: str
    order: int
    symplectic: bool
    gyroscopic: bool
    summary: str
    default: bool


def integrators() -> list[Integrator]:
    """Every integrator, the default one marked, in rigid-sim --list-integrators order."""
    return [Integrator(**d) for d in _integrators()]


@dataclass(frozen=True)
class BodyInfo:
    """A body as rigidd's SceneInfo describes it (inertia about the centre of mass, in B)."""

    id: int
    name: str
    mass: float
    inertia: tuple[tuple[float, float, float], ...]
    shape: str  # "sphere", "box", "cylinder", "ellipsoid", "capsule", or "" (inertia given)
    dims: tuple[float, float, float]


@dataclass(frozen=True)
class SceneInfo:
    """rigidd's scene: tick period dt (s), substeps, publish_every, gravity, integrator, the
    limits it enforces on commands, and the bodies."""

    name: str
    dt: float
    substeps: int
    publish_every: int
    gravity: tuple[float, float, float]
    integrator: str
    max_force: float
    max_torque: float
    max_ttl: float
    max_wrenches_per_source: int
    max_commands_per_second: float
    bodies: tuple[BodyInfo, ...]

    @property
    def rate_hz(self) -> float:
        """Ticks per second."""
        return 1.0 / self.dt

    def body(self, name: str) -> BodyInfo:
        """The body of that name; UnknownBodyError names it and lists the scene's."""
        for b in self.bodies:
            if b.name == name:
                return b
        names = ", ".join(b.name for b in self.bodies) or "none"
        raise UnknownBodyError(f"no body '{name}' in the scene (bodies: {names})")


@dataclass(frozen=True)
class Reply:
    """rigidd's answer to a control request that it carried out (a refusal raises Refused)."""

    command: str  # "pause", "resume", "step", "reset", "rate", "set_state", "reset_body"
    tick: int  # the tick at which it took effect
    message: str


@dataclass(frozen=True)
class Accepted:
    """rigidd's acceptance of a push: the wrench as it applies it, from `tick` on."""

    tick: int
    seq: int
    body: int
    force: tuple[float, float, float]
    at: tuple[float, float, float]
    frame: str
    torque: tuple[float, float, float]
    torque_frame: str
    ttl: float


def _scene_info(d: dict[str, Any]) -> SceneInfo:
    bodies = tuple(BodyInfo(**b) for b in d.pop("bodies"))
    return SceneInfo(bodies=bodies, **d)


# Clients still open at exit are closed before the interpreter finalizes, so that no receive
# thread tries to run an on_state callback in an interpreter that is going away.
_open_clients: "weakref.WeakSet[Client]" = weakref.WeakSet()


@atexit.register
def _close_open_clients() -> None:
    for c in list(_open_clients):
        c.close()


class Client:
    """A client of a running rigidd on one bus (the C++ rigid::client::Session).

    ``transport``: "dds" or "lcm"; ``prefix``: rigidd's --prefix; ``domain``: its DDS domain;
    ``url``: its LCM URL (None: rigid's default, loopback multicast); ``security``: a DDS Security
    identity directory (scripts/rigid-keys add). ``timeout`` (s) is the default wait for every
    answer. Requests are sent exactly once even across DDS discovery: the session waits to see
    rigidd, then resends with the same sequence number until answered.

    Every control (pause, resume, step, reset, set_rate) and push returns rigidd's answer, or
    raises ``Refused`` with rigidd's reason, or ``TimeoutError`` when no answer came in time.
    The GIL is released while waiting. Use as a context manager, or call close().
    """

    def __init__(
        self,
        transport: str = "dds",
        prefix: str = "",
        domain: int = 0,
        url: Optional[str] = None,
        security: Optional[str] = None,
        timeout: float = 5.0,
    ) -> None:
        self._session = _Session(transport, prefix, domain, url, security)
        self.transport = transport
        self.timeout = timeout
        _open_clients.add(self)

    # -- lifetime --------------------------------------------------------------------------

    def close(self) -> None:
        """Leave the bus (open state streams end)."""
        self._session.close()

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"<rigid.Client on {self._session.describe}>"

    @property
    def bus(self) -> str:
        """The bus as messages name it: "dds domain 0, prefix P" or "lcm udpm://..."."""
        return str(self._session.describe)

    def _wait(self, timeout: Optional[float]) -> float:
        return self.timeout if timeout is None else timeout

    def _no_answer(self, what: str, timeout: float) -> TimeoutError:
        return TimeoutError(
            f"no {what} from rigidd within {timeout:.3g} s on {self.bus} "
            "(is rigidd running, with the same transport, prefix and domain?)"
        )

    # -- what rigidd runs -------------------------------------------------------------------

    def scene(self, timeout: Optional[float] = None) -> SceneInfo:
        """rigidd's SceneInfo (DDS: at once after discovery; LCM: within a second)."""
        t = self._wait(timeout)
        d = self._session.scene(t)
        if d is None:
            raise self._no_answer("SceneInfo", t)
        return _scene_info(d)

    def bodies(self, timeout: Optional[float] = None) -> list[BodyInfo]:
        """The scene's bodies: id, name, mass, inertia, shape and dims."""
        return list(self.scene(timeout).bodies)

    def body(self, body: Body, timeout: Optional[float] = None) -> int:
        """The id of a body given by name (or id); UnknownBodyError lists the scene's bodies."""
        return int(self._session.resolve(body, self._wait(timeout)))

    def stats(self, timeout: Optional[float] = None) -> dict[str, Any]:
        """rigidd's newest Stats (once a second): tick, mode, paused, rtf, lateness, overruns,
        commands accepted and refused by reason, per-bus traffic."""
        t = self._wait(timeout)
        d = self._session.stats(t)
        if d is None:
            raise self._no_answer("Stats", t)
        return dict(d)

    # -- states -----------------------------------------------------------------------------

    def states(self, timeout: Optional[float] = None, max_queue: int = 1024) -> StateStream:
        """An iterator over the states published from now on, in order of arrival; next()
        raises TimeoutError after `timeout` s without one. Best-effort DDS (rigidd's default)
        may skip states; their ticks still increase. Close it (or use ``with``) when done."""
        return self._session.states(self._wait(timeout), max_queue)

    def latest(self) -> Optional[State]:
        """The newest state received so far, or None."""
        return self._session.latest()

    def on_state(self, fn: Callable[[State], None]) -> StateCallback:
        """Call ``fn(state)`` for every state from now on, as it arrives: on the bus's receive
        thread, holding the GIL, so that no thread has to be woken for it (the lowest latency
        from rigidd's publish to your code; ``states()`` hands each state to a waiting thread).

        Keep ``fn`` short: while it runs, this client receives nothing, and while another
        thread of yours runs Python code the call waits for the GIL. Inside ``fn``, ``send()``,
        ``latest()``, ``scene()`` and ``body()`` work; calls that would wait for the bus
        (``push()``, controls, a stream's ``next()``, ``close()``) raise RuntimeError, since the
        answer would have to come through this very thread. An exception from ``fn`` ends the
        callback: it is reported through ``sys.unraisablehook`` and kept in ``.error``.
        Returns a handle: ``close()`` it (or use ``with``) to stop; closing the client stops it.
        """
        if not callable(fn):
            raise TypeError(f"on_state needs a callable, got {type(fn).__name__}")
        return self._session.on_state(fn)

    def on_contact(self, fn: Callable[[Contact], None]) -> None:
        """Call ``fn(contact)`` for every contact event rigidd publishes from now on (a scene with
        static parts: each impact, and each time a body starts resting, sliding or rolling on
        them or leaves them), in order, on the bus's receive thread holding the GIL, as
        ``on_state``'s callbacks. ``contact`` is a ``rigid.Contact`` named by rigidd's scene. An
        exception from ``fn`` ends it (reported through ``sys.unraisablehook``); closing the
        client ends them all.
        """
        if not callable(fn):
            raise TypeError(f"on_contact needs a callable, got {type(fn).__name__}")
        self._session.on_contact(fn)

    # -- pushes -----------------------------------------------------------------------------

    def _wrench(
        self,
        body: Body,
        force: Optional[Vector],
        at: Optional[Vector],
        frame: str,
        torque: Optional[Vector],
        torque_frame: str,
        ttl: float,
        timeout: float,
    ) -> Any:
        if not math.isfinite(ttl):
            raise ValueError(f"ttl {ttl} is not finite")
        return self._session.wrench(
            self._session.resolve(body, timeout), force, at, frame, torque, torque_frame, ttl
        )

    def push(
        self,
        body: Body,
        force: Optional[Vector] = None,
        at: Optional[Vector] = None,
        frame: str = "world",
        ttl: float = 0.0,
        *,
        torque: Optional[Vector] = None,
        torque_frame: str = "world",
        timeout: Optional[float] = None,
    ) -> Accepted:
        """Push a body and wait until rigidd accepts it.

        force (N) at `at` (from the centre of mass, in the body frame; None: the centre of
        mass), expressed in `frame` ("world", or "body": it turns with the body); optionally a
        pure torque (N m) in `torque_frame`. It acts for `ttl` simulated seconds (0: the next
        tick only; at most the scene's max_ttl). The same client replaces its previous push on
        the same body. Returns rigidd's acceptance (the tick it takes effect); raises Refused
        with rigidd's reason (a limit, a non-finite number), UnknownBodyError, TimeoutError.
        """
        t = self._wait(timeout)
        w = self._wrench(body, force, at, frame, torque, torque_frame, ttl, t)
        accepted, refused = self._session.push(w, t)
        if accepted is not None:
            return Accepted(**accepted)
        if refused is not None:
            raise Refused(f"push: refused by rigidd: {refused}", refused)
        raise self._no_answer("acceptance of the push", t)

    def send(
        self,
        body: Body,
        force: Optional[Vector] = None,
        at: Optional[Vector] = None,
        frame: str = "world",
        ttl: float = 0.0,
        *,
        torque: Optional[Vector] = None,
        torque_frame: str = "world",
    ) -> int:
        """Send a push without waiting (a controller's stream); returns its sequence number.
        rigidd's refusals come back later: take_refusal()."""
        w = self._wrench(body, force, at, frame, torque, torque_frame, ttl, self.timeout)
        return int(self._session.send(w))

    def take_refusal(self) -> Optional[str]:
        """rigidd's reason for the newest refused send() since the last call, or None."""
        r = self._session.take_refusal()
        return None if r is None else str(r)

    # -- controls ---------------------------------------------------------------------------

    def _control(self, kind: str, steps: int, rate: float, timeout: Optional[float]) -> Reply:
        t = self._wait(timeout)
        r = self._session.request(kind, steps, rate, t)
        if r is None:
            raise self._no_answer(f"reply to {kind}", t)
        if not r["ok"]:
            raise Refused(f"{kind}: {r['outcome']}: {r['message']}", r["message"])
        return Reply(command=r["command"], tick=r["tick"], message=r["message"])

    def pause(self, timeout: Optional[float] = None) -> Reply:
        """Pause the loop (answered with the tick it stopped at)."""
        return self._control("pause", 0, 0.0, timeout)

    def resume(self, timeout: Optional[float] = None) -> Reply:
        """Resume a paused loop."""
        return self._control("resume", 0, 0.0, timeout)

    def step(self, n: int = 1, timeout: Optional[float] = None) -> Reply:
        """Run n ticks while paused (or in lockstep); answered when they are done."""
        return self._control("step", n, 0.0, timeout)

    def reset(self, body: Optional[Body] = None, timeout: Optional[float] = None) -> Reply:
        """Back to the initial state, tick 0, wrenches cleared.

        With `body` (a name or an id), that body alone goes back to its scene state and the
        wrenches acting on it are dropped; the world's tick goes on (an edit: see set_state).
        """
        if body is None:
            return self._control("reset", 0, 0.0, timeout)
        return self._edit("reset_body", body, None, None, None, "world", None, "world", timeout)

    # -- edits ------------------------------------------------------------------------------

    def _edit(
        self,
        kind: str,
        body: Body,
        position: Optional[Vector],
        orientation: Optional[Vector],
        velocity: Optional[Vector],
        velocity_frame: str,
        angular_velocity: Optional[Vector],
        angular_velocity_frame: str,
        timeout: Optional[float],
    ) -> Reply:
        t = self._wait(timeout)
        r = self._session.edit(
            kind,
            self._session.resolve(body, t),
            position,
            orientation,
            velocity,
            velocity_frame,
            angular_velocity,
            angular_velocity_frame,
            t,
        )
        if r is None:
            raise self._no_answer(f"reply to {kind}", t)
        if not r["ok"]:
            raise Refused(f"{kind}: {r['outcome']}: {r['message']}", r["message"])
        return Reply(command=r["command"], tick=r["tick"], message=r["message"])

    def set_state(
        self,
        body: Body,
        position: Optional[Vector] = None,
        orientation: Optional[Vector] = None,
        velocity: Optional[Vector] = None,
        angular_velocity: Optional[Vector] = None,
        *,
        velocity_frame: str = "world",
        angular_velocity_frame: str = "world",
        timeout: Optional[float] = None,
    ) -> Reply:
        """Set parts of a body's state between two ticks; the parts left None keep their values.

        position: p_WBo (m, world frame); orientation: q_WB as w, x, y, z (a unit quaternion,
        normalised by rigidd); velocity (m/s) and angular_velocity (rad/s) in the world frame, or
        with velocity_frame / angular_velocity_frame "body" in the body's frame as it is
        oriented after this edit. Returns rigidd's answer: its tick T is the tick the edit was
        made at, and the state of tick T + 1 is the first stepped from it (a paused rigidd
        publishes the edited state at once, as tick T). Raises Refused (--controls off, an
        identity that may not control), UnknownBodyError, ValueError, TimeoutError.
        """
        return self._edit(
            "set_state",
            body,
            position,
            orientation,
            velocity,
            velocity_frame,
            angular_velocity,
            angular_velocity_frame,
            timeout,
        )

    def set_rate(self, x: float, timeout: Optional[float] = None) -> Reply:
        """The real-time factor (realtime mode; 0 < x <= 1000)."""
        return self._control("rate", 0, x, timeout)
