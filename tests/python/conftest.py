"""Shared fixtures of the rigid Python package's tests: paths from ctest's environment, and
rigidd as a subprocess with a unique prefix, bounded in time and stopped by PID."""

from __future__ import annotations

import itertools
import os
import signal
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterator, Optional

import pytest

HERE = Path(__file__).resolve().parent
SOURCE_DIR = Path(os.environ.get("RIGID_SOURCE_DIR", HERE.parent.parent))
SCENES = HERE / "scenes"


def program(var: str) -> str:
    """A program ctest names in the environment (RIGIDD, RIGID_SIM, RIGID_WORLD_DUMP)."""
    path = os.environ.get(var)
    if not path or not os.access(path, os.X_OK):
        pytest.fail(f"{var} is not set to an executable (run through ctest, or set it)")
    return path


_counter = itertools.count()


def unique_prefix(tag: str) -> str:
    """A prefix no other test (or concurrent ctest run) uses: rigidd's topics and channels."""
    return f"py{tag}{os.getpid()}x{next(_counter)}"


@dataclass
class Daemon:
    proc: subprocess.Popen[bytes]
    prefix: str
    transport: str
    log: Path

    def stderr(self) -> str:
        return self.log.read_text(errors="replace")

    def stop(self, patience: float = 3.0) -> Optional[int]:
        """SIGTERM by PID, then SIGKILL if it has not exited within `patience` seconds."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(patience)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait(5)
        return self.proc.returncode


StartDaemon = Callable[..., Daemon]


@pytest.fixture
def rigidd(tmp_path: Path) -> Iterator[StartDaemon]:
    """start(scene, transport, mode="realtime", *extra) -> Daemon; every daemon started is
    stopped by PID when the test ends (exit status 0 expected after SIGTERM)."""
    started: list[Daemon] = []

    def start(scene: Path, transport: str, mode: str = "realtime", *extra: str) -> Daemon:
        prefix = unique_prefix(transport)
        log = tmp_path / f"rigidd-{prefix}.log"
        with open(log, "wb") as err:
            proc = subprocess.Popen(
                [program("RIGIDD"), "--scene", str(scene), "--transport", transport,
                 "--mode", mode, "--prefix", prefix, *extra],
                stdout=subprocess.DEVNULL, stderr=err, stdin=subprocess.DEVNULL)
        d = Daemon(proc, prefix, transport, log)
        started.append(d)
        return d

    yield start
    for d in started:
        d.stop()


@pytest.fixture(params=["dds", "lcm"])
def bus(request: pytest.FixtureRequest) -> str:
    return str(request.param)
