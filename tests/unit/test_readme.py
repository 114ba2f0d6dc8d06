"""The README's promises: its tour runs, its quick start has exactly two commands, CI runs them."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def _blocks(lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", README, flags=re.S)


def test_tour_runs_and_its_claims_hold() -> None:
    algebra, dynamics, lazy = _blocks("python")
    env: dict[str, Any] = {}
    exec(compile(algebra, "README.md", "exec"), env)
    # the tour states these values in comments; check them
    v, f, X = env["v"], env["f"], env["X"]
    assert abs(v.dot(f) - 5.0) < 1e-12
    assert abs((X @ v).dot(X @ f) - 5.0) < 1e-12
    env = {}
    exec(compile(dynamics, "README.md", "exec"), env)
    assert np.allclose(env["ddq"], env["a"], atol=1e-9)
    assert env["taus"].shape == (1000, env["model"].nv) and env["J"].shape == (6, env["model"].nv)
    assert np.allclose(env["M"], env["M"].T)
    env = {}
    exec(compile(lazy, "README.md", "exec"), env)  # the Dask section: its assert compares with NumPy
    M = env["M"]
    assert type(M).__module__.startswith("dask") and M.shape == (10_000, env["model"].nv, env["model"].nv)


def test_quick_start_has_exactly_two_commands_run_by_ci() -> None:
    section = README.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    (block,) = re.findall(r"```sh\n(.*?)```", section, flags=re.S)
    commands = [line for line in block.splitlines() if line.strip()]
    assert len(commands) == 2
    assert "featherdyn verify" in commands[0]
    assert "pytest" in commands[1]
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    for command in commands:
        assert command in ci, f"CI does not run the README command {command!r}"
