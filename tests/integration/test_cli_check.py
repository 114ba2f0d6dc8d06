"""``featherdyn check`` end to end: ``python -m featherdyn check VALUES.npz --robot ROBOT`` in a subprocess.

Exit codes: 0 all agree, 1 a mismatch (the output names the suspect), 2 a usage
or model error (one line on stderr, never a traceback).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import featherdyn as fd

pytest.importorskip("pinocchio")

# the featherdyn this test imports (the source tree, or an installed wheel), for the command it runs
SRC = Path(fd.__file__).resolve().parents[1]


def run(*args: str | Path) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")]))
    return subprocess.run([sys.executable, "-m", "featherdyn", "check", *map(str, args)], capture_output=True,
                          text=True, env=env, timeout=120)


@pytest.fixture(scope="module")
def panda_values() -> dict[str, np.ndarray]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fd.load_robot("panda")
    rng = np.random.default_rng(0)
    q = fd.random_configuration(model, rng, size=(3,))
    v, a = rng.normal(size=(3, model.nv)), rng.normal(size=(3, model.nv))
    tau = fd.rnea(model, q, v, a)
    return {"q": q, "v": v, "a": a, "tau": tau, "M": fd.crba(model, q), "ddq": fd.aba(model, q, v, tau)}


def assert_no_traceback(p: subprocess.CompletedProcess[str]) -> None:
    assert "Traceback" not in p.stderr and "Traceback" not in p.stdout, p.stderr


def test_agree_exit_0_and_json(tmp_path: Path, panda_values: dict[str, np.ndarray]) -> None:
    np.savez(tmp_path / "good.npz", **panda_values)
    p = run(tmp_path / "good.npz", "--robot", "panda", "--json", tmp_path / "r.json")
    assert p.returncode == 0, p.stdout + p.stderr
    assert "all 3 comparisons agree" in p.stdout
    report = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))
    assert report["passed"] is True and report["diagnosis"] == []
    assert len(report["results"]) == 3 and report["meta"]["robot"] == "panda"


def test_mismatch_exit_1_names_the_suspect(tmp_path: Path, panda_values: dict[str, np.ndarray]) -> None:
    bad = dict(panda_values, M=np.triu(panda_values["M"]))
    np.savez(tmp_path / "tri.npz", **bad)
    p = run(tmp_path / "tri.npz", "--robot", "panda", "--json", tmp_path / "r.json")
    assert p.returncode == 1, p.stdout + p.stderr
    assert "suspect: mass_matrix_triangle" in p.stdout
    assert "corrected comparison" in p.stdout
    report = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))
    assert report["passed"] is False
    assert [d["suspect"] for d in report["diagnosis"]] == ["mass_matrix_triangle"]
    assert_no_traceback(p)


def test_unexplained_mismatch_exit_1(tmp_path: Path, panda_values: dict[str, np.ndarray]) -> None:
    bad = {k: panda_values[k] for k in ("q", "v", "a", "tau")}
    bad["tau"] = bad["tau"].copy()
    bad["tau"][2, 5] += 0.3
    np.savez(tmp_path / "noise.npz", **bad)
    p = run(tmp_path / "noise.npz", "--robot", "panda", "--tol", "1e-8")
    assert p.returncode == 1, p.stdout + p.stderr
    assert "no usual suspect explains it" in p.stdout
    assert "joint 'panda_joint6' at state 2" in p.stdout


@pytest.mark.parametrize("case, words", [
    ("missing_file", "file not found"),
    ("bad_npz", "not an .npz archive"),
    ("missing_key", "missing key 'v'"),
    ("wrong_shape", "tau: expected shape (9,) for one state or (N, 9)"),
    ("nan", "a: non-finite value nan"),
    ("unknown_robot", "no_such_robot"),
])
def test_usage_errors_exit_2(tmp_path: Path, panda_values: dict[str, np.ndarray], case: str, words: str) -> None:
    path = tmp_path / f"{case}.npz"
    robot = "panda"
    if case == "bad_npz":
        path.write_text("q,v,a\n1,2,3\n")
    elif case == "missing_key":
        np.savez(path, **{k: x for k, x in panda_values.items() if k != "v"})
    elif case == "wrong_shape":
        np.savez(path, **dict(panda_values, tau=panda_values["tau"][:, :7]))
    elif case == "nan":
        a = panda_values["a"].copy()
        a[1, 2] = np.nan
        np.savez(path, **dict(panda_values, a=a))
    elif case == "unknown_robot":
        np.savez(path, **panda_values)
        robot = "no_such_robot"
    p = run(path, "--robot", robot)
    assert p.returncode == 2, p.stdout + p.stderr
    assert words in p.stderr
    assert p.stderr.strip().count("\n") == 0  # one line
    assert_no_traceback(p)


def test_missing_robot_option_exit_2(tmp_path: Path) -> None:
    p = run(tmp_path / "x.npz")
    assert p.returncode == 2
    assert "--robot" in p.stderr
    assert_no_traceback(p)


def test_frame_derivatives_need_frame_and_name_pinocchios_rows(tmp_path: Path) -> None:
    """Pinocchio's getFrameVelocityDerivatives on panda (rows [v; ω]) given as featherdyn's: --frame and
    --reference are taken, the suspect is named; without --frame: exit 2 with one line saying so."""
    pin = pytest.importorskip("pinocchio")
    from featherdyn.robots import robot_path
    from featherdyn.verify.bridge import JointMap

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fd.load_robot("panda")
        pm = pin.buildModelFromUrdf(str(robot_path("panda")))
    pd, jm = pm.createData(), JointMap(model, pm)
    rng = np.random.default_rng(3)
    q = fd.random_configuration(model, rng)
    v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
    pin.computeForwardKinematicsDerivatives(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(a))
    dv_dq, dv_dv = pin.getFrameVelocityDerivatives(pm, pd, pm.getFrameId("panda_hand"), pin.WORLD)
    np.savez(tmp_path / "frame.npz", q=q, v=v, dv_dq=jm.columns_from_pin(dv_dq), dv_dv=jm.columns_from_pin(dv_dv))
    p = run(tmp_path / "frame.npz", "--robot", "panda", "--frame", "panda_hand", "--reference", "WORLD")
    assert p.returncode == 1, p.stdout + p.stderr
    assert "suspect: linear_first_rows" in p.stdout and "(panda_hand, WORLD)" in p.stdout
    assert_no_traceback(p)
    good = {"q": q, "v": v, "dv_dv": jm.columns_from_pin(dv_dv)[[3, 4, 5, 0, 1, 2]]}
    np.savez(tmp_path / "good.npz", **good)
    p = run(tmp_path / "good.npz", "--robot", "panda", "--frame", "panda_hand", "--reference", "WORLD")
    assert p.returncode == 0, p.stdout + p.stderr
    p = run(tmp_path / "good.npz", "--robot", "panda")
    assert p.returncode == 2 and "--frame" in p.stderr and not p.stdout, p.stdout + p.stderr
    assert_no_traceback(p)
