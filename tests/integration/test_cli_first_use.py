"""The command line as a new user meets it: missing Pinocchio, bad paths, first use, ``--version``.

Everything a command can refuse it refuses before any work (one line on stderr,
exit 2, nothing on stdout), and anything slow the first time says so on stderr.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

import featherdyn as fd

ONE_DOF = """<?xml version="1.0"?>
<robot name="one_dof">
  <link name="base"/>
  <link name="arm"><inertial><origin xyz="0.1 0 0"/><mass value="1.0"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial></link>
  <joint name="hinge" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
"""


def run(*args: str | Path, env: dict[str, str] | None = None, timeout: float = 600
        ) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "featherdyn", *map(str, args)], capture_output=True, text=True,
                          timeout=timeout, env=env)


def one_line_error(res: subprocess.CompletedProcess[str], *words: str) -> None:
    assert res.returncode == 2, res.stdout + res.stderr
    assert "Traceback" not in res.stderr, res.stderr
    assert res.stderr.strip().count("\n") == 0, res.stderr
    for w in words:
        assert w in res.stderr, res.stderr


def without_pinocchio(tmp_path: Path) -> dict[str, str]:
    """An environment where ``import pinocchio`` fails (a sitecustomize that blocks it)."""
    site = tmp_path / "no_pinocchio"
    site.mkdir()
    (site / "sitecustomize.py").write_text("import sys\nsys.modules['pinocchio'] = None\n", encoding="utf-8")
    path = os.pathsep.join(p for p in (str(site), os.environ.get("PYTHONPATH", "")) if p)
    return dict(os.environ, PYTHONPATH=path)


def test_version() -> None:
    res = run("--version")
    assert res.returncode == 0 and res.stdout.strip() == f"featherdyn {fd.__version__}", res.stdout + res.stderr


@pytest.mark.parametrize("command", [("bench", "panda", "--chains", "", "--no-compile-times"),
                                     ("verify", "two_link_arm")])
def test_without_pinocchio_one_line_says_how_to_install_it(tmp_path: Path, command: tuple[str, ...]) -> None:
    res = run(*command, env=without_pinocchio(tmp_path))
    one_line_error(res, "pip install pin")
    assert res.stdout == ""


def test_bench_unknown_robot_before_any_output() -> None:
    res = run("bench", "no_such_robot_xyz", "--chains", "", "--no-compile-times")
    one_line_error(res, "no_such_robot_xyz")
    assert res.stdout == ""


@pytest.mark.parametrize("command", [
    ("verify", "two_link_arm", "--samples", "1", "--report", "{missing}/r.html"),
    ("verify", "two_link_arm", "--samples", "1", "--json", "{missing}/r.json"),
    ("bench", "panda", "--repeats", "1", "--batch", "2", "--chains", "", "--no-compile-times",
     "--output", "{missing}/b.md"),
    ("check", "{values}", "--robot", "two_link_arm", "--json", "{missing}/c.json"),
])
def test_outputs_are_checked_before_the_run(tmp_path: Path, command: tuple[str, ...]) -> None:
    values = tmp_path / "v.npz"
    import numpy as np

    model = fd.load_robot("two_link_arm")
    q = np.zeros(model.nq)
    np.savez(values, q=q, v=q, a=q, tau=fd.rnea(model, q, q, q))
    args = [a.format(missing=tmp_path / "no_such_dir", values=values) for a in command]
    t0 = time.perf_counter()
    res = run(*args)
    one_line_error(res, "no_such_dir")
    assert res.stdout == "", res.stdout  # refused before the run: no table, no header
    assert time.perf_counter() - t0 < 60


@pytest.mark.parametrize("command", [("verify", "{d}"), ("info", "{d}"), ("check", "{d}/v.npz", "--robot", "{d}"),
                                     ("bench", "{d}", "--chains", "", "--no-compile-times")])
def test_a_directory_as_the_model_says_it_is_a_directory(tmp_path: Path, command: tuple[str, ...]) -> None:
    import numpy as np

    np.savez(tmp_path / "v.npz", q=np.zeros(2), v=np.zeros(2), a=np.zeros(2), tau=np.zeros(2))
    res = run(*(a.format(d=tmp_path) for a in command))
    one_line_error(res, "is a directory")


def test_info_shows_the_joint_limits() -> None:
    res = run("info", "panda")
    assert res.returncode == 0, res.stderr
    line = next(ln for ln in res.stdout.splitlines() if "'panda_joint1'" in ln)
    assert "-2.8973" in line and "2.8973" in line and "87" in line and "2.175" in line, line


def test_info_of_a_one_dof_urdf(tmp_path: Path) -> None:
    (tmp_path / "one.urdf").write_text(ONE_DOF, encoding="utf-8")
    res = run("info", tmp_path / "one.urdf")
    assert res.returncode == 0, res.stderr
    assert "'hinge'" in res.stdout


def test_first_use_compiles_nothing() -> None:
    """The compiled core is built at install: a fresh process imports no JIT and runs every kernel at once."""
    code = (
        "import sys, numpy as np, featherdyn as fd\n"
        "m = fd.load_robot('panda', floating_base=True); q = fd.neutral(m); z = np.zeros(m.nv)\n"
        "fd.rnea(m, q, z, z); fd.crba(m, q); fd.aba(m, q, z, z); fd.forward_kinematics(m, q, z, z)\n"
        "Q = fd.random_configuration(m, np.random.default_rng(0), size=8)\n"
        "fd.rnea(m, Q, z, z); fd.crba(m, Q); fd.aba(m, Q, z, z); fd.compile(m).rnea(q, z, z)\n"
        "print(sorted(k for k in ('numba', 'llvmlite') if k in sys.modules))\n"
    )
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600, check=False)
    assert res.returncode == 0, res.stderr
    assert res.stdout.strip() == "[]", res.stdout


def test_verify_says_nothing_about_compiling() -> None:
    res = run("verify", "two_link_arm", "--samples", "1")
    assert res.returncode == 0, res.stdout + res.stderr
    assert "compiling" not in res.stderr, res.stderr
