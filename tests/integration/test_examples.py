"""Every script in ``examples/`` runs top to bottom and exits with status 0.

The examples are the chapter made executable (worked examples, code blocks,
exercises, errata); each stops with ``SystemExit(1)`` on a failed comparison,
so a wrong number anywhere fails its test here.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
SCRIPTS = sorted(p for p in EXAMPLES.glob("[0-9]*.py"))
TIMEOUT_S = 120  # each runs in seconds; the budget is generous for slow CI machines


def test_examples_found() -> None:
    assert len(SCRIPTS) >= 20, f"expected the chapter's example scripts in {EXAMPLES}"


@pytest.mark.parametrize("script", SCRIPTS, ids=[p.stem for p in SCRIPTS])
def test_example_runs(script: Path) -> None:
    pytest.importorskip("pinocchio")
    pytest.importorskip("sympy")
    env = dict(os.environ, PYTHONIOENCODING="utf-8", MPLBACKEND="Agg")
    proc = subprocess.run(
        [sys.executable, str(script)], cwd=EXAMPLES, capture_output=True, text=True, timeout=TIMEOUT_S, env=env,
        check=False,
    )
    assert proc.returncode == 0, (
        f"{script.name} exited with {proc.returncode}\n--- stdout (tail) ---\n{proc.stdout[-3000:]}"
        f"\n--- stderr (tail) ---\n{proc.stderr[-3000:]}"
    )


def test_speed_claims_label_the_backend_they_measure() -> None:
    # the reference (NumPy) recursion is hundreds of times slower than the compiled core: a line labelled
    # NumPy that shows the compiled core's time (as it did) is caught by the ratio
    pytest.importorskip("pinocchio")
    env = dict(os.environ, PYTHONIOENCODING="utf-8")
    proc = subprocess.run([sys.executable, str(EXAMPLES / "23_speed_claims.py")], cwd=EXAMPLES, capture_output=True,
                          text=True, timeout=TIMEOUT_S, env=env, check=False)
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]

    def micros(label: str) -> float:
        line = next((ln for ln in proc.stdout.splitlines() if label in ln), None)
        assert line is not None, f"no line with {label!r} in\n{proc.stdout}"
        return float(line.split(":", 1)[1].split("µs")[0])

    t_numpy = micros("backend='reference', NumPy")
    t_compiled = micros("compiled core, C++")
    assert t_numpy > 20 * t_compiled, (t_numpy, t_compiled)
