"""The examples in clients/python/examples run and do what they say: the PD controller settles a
live rigidd's body within 1 degree on each bus; the integrator study writes its plot."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import SOURCE_DIR, StartDaemon

EXAMPLES = SOURCE_DIR / "clients" / "python" / "examples"
ATTITUDE = SOURCE_DIR / "config" / "scenes" / "attitude.pbtxt"


@pytest.mark.network
def test_pd_attitude_settles_within_one_degree(rigidd: StartDaemon, bus: str) -> None:
    d = rigidd(ATTITUDE, bus)
    # Bounded: the example gives up after --timeout 30 s; the subprocess is killed after 60 s.
    run = subprocess.run(
        [sys.executable, str(EXAMPLES / "pd_attitude.py"), "--transport", bus,
         "--prefix", d.prefix, "--timeout", "30"],
        capture_output=True, text=True, timeout=60, env=dict(os.environ))
    assert run.returncode == 0, f"{run.stdout}\n{run.stderr}\nrigidd:\n{d.stderr()}"
    last = run.stdout.strip().splitlines()[-1]
    assert last.startswith("settled: error ")
    assert float(last.split()[2]) < 1.0
    assert d.stop() == 0, d.stderr()


def test_integrator_study_writes_its_plot(tmp_path: Path) -> None:
    out = tmp_path / "study.png"
    run = subprocess.run(
        [sys.executable, str(EXAMPLES / "integrator_study.py"), "--quick", "--out", str(out)],
        capture_output=True, text=True, timeout=120, env=dict(os.environ, MPLBACKEND="Agg"))
    assert run.returncode == 0, run.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # The reference is exact to round-off on this free body: its coarse run agrees with it.
    ref_line = run.stdout.splitlines()[0]
    assert float(ref_line.split("differs by ")[1].split()[0]) < 1e-9, ref_line
    assert "rk4" in run.stdout and "exact_rotor4" in run.stdout
