"""``featherdyn verify --oracle mujoco|both``: MuJoCo as a second oracle (``verify/mujoco.py``).

Oracle: MuJoCo's compiled model of the same file. The checks must pass on
models featherdyn loads exactly, and must fail when MuJoCo's model is altered
behind featherdyn's back (a mass, an inertia, an armature): a comparison that
could not fail would prove nothing.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.verify.mujoco import compile_mujoco, mujoco_checks

mujoco = pytest.importorskip("mujoco")  # in the `test` extra: runs in CI
gymnasium = pytest.importorskip("gymnasium")

ASSETS = Path(os.path.dirname(gymnasium.__file__)) / "envs" / "mujoco" / "assets"


def cli(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "featherdyn", *map(str, args)], capture_output=True, text=True,
                          timeout=600)


@pytest.mark.parametrize("name", ["ant.xml", "humanoid.xml", "walker2d.xml"])
def test_mjcf_models_agree_and_an_altered_mujoco_model_is_caught(name: str) -> None:
    path = ASSETS / name
    model = fd.load_mjcf(path)
    m = compile_mujoco(path, "mjcf")
    results = mujoco_checks(model, m, "mjcf", samples=3, seed=1)
    assert results and all(r.passed for r in results), [r for r in results if not r.passed]
    quantities = {r.quantity.split(" vs ")[0] for r in results}
    assert {"total mass", "crba", "generalized_gravity", "rnea", "aba", "body spatial inertias (world)"} <= quantities
    # a 1 % heavier body in MuJoCo only: mass, inertias, M, gravity and RNEA all disagree
    heavier = compile_mujoco(path, "mjcf")
    heavier.body_mass[2] *= 1.01
    failed = {r.quantity.split(" vs ")[0] for r in mujoco_checks(model, heavier, "mjcf", samples=3, seed=1)
              if not r.passed}
    assert {"total mass", "body spatial inertias (world)", "crba", "generalized_gravity", "rnea"} <= failed
    # an armature MuJoCo has and featherdyn does not
    geared = compile_mujoco(path, "mjcf")
    geared.dof_armature[-1] += 0.05
    failed = {r.quantity.split(" vs ")[0] for r in mujoco_checks(model, geared, "mjcf", samples=2, seed=1)
              if not r.passed}
    assert {"armature", "crba"} <= failed


def test_a_urdf_through_mujocos_importer() -> None:
    """panda's URDF: MuJoCo's importer (geometry removed) against featherdyn, joints permuted by name."""
    from featherdyn.robots import robot_path

    path = robot_path("panda")
    model = fd.load_urdf(path)
    results = mujoco_checks(model, compile_mujoco(Path(path), "urdf"), "urdf", samples=3, seed=2)
    assert all(r.passed for r in results), [r for r in results if not r.passed]


def test_cli_oracles() -> None:
    p = cli("verify", ASSETS / "hopper.xml", "--samples", "2")
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    assert "crba vs mj_fullM" in p.stdout and "against MuJoCo" in p.stdout and "pin." not in p.stdout
    p = cli("verify", "panda", "--oracle", "both", "--samples", "2")
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    assert "crba vs mj_fullM" in p.stdout and "crba vs pin.crba" in p.stdout
    for args, words in [((ASSETS / "hopper.xml", "--oracle", "pinocchio"), "compared with MuJoCo (--oracle mujoco)"),
                        (("solo12", "--floating-base", "--oracle", "mujoco"), "builds no free joint"),
                        ((ASSETS / "hopper.xml", "--floating-base"), "--floating-base applies to a URDF"),
                        (("--all", "--oracle", "mujoco"), "--oracle mujoco takes one model")]:
        p = cli("verify", *args)
        assert p.returncode == 2 and words in p.stderr and "Traceback" not in p.stderr, (args, p.stderr)


def test_info_and_dataset_take_an_mjcf_file(tmp_path: Path) -> None:
    p = cli("info", ASSETS / "ant.xml")
    assert p.returncode == 0 and "nq=15, nv=14" in p.stdout, p.stdout + p.stderr
    out = tmp_path / "ant.zarr"
    p = cli("dataset", ASSETS / "ant.xml", "--states", "50", "--chunk", "20", "--out", out, "--scheduler", "sync",
            "--quantities", "M,tau")
    assert p.returncode == 0, p.stderr
    zarr = pytest.importorskip("zarr")
    g = zarr.open_group(str(out), mode="r")
    model = fd.load_mjcf(ASSETS / "ant.xml")
    np.testing.assert_array_equal(g["M"][:], fd.crba(model, g["q"][:]))


def test_check_takes_an_mjcf_model(tmp_path: Path) -> None:
    """``featherdyn check VALUES.npz --robot model.xml``: the user's numbers against featherdyn's model of the MJCF
    file; a wrong mass matrix is caught."""
    path = ASSETS / "walker2d.xml"
    model = fd.load_mjcf(path)
    rng = np.random.default_rng(3)
    q = fd.random_configuration(model, rng, 3)
    v, a = rng.normal(size=(2, 3, model.nv))
    good, bad = tmp_path / "good.npz", tmp_path / "bad.npz"
    np.savez(good, q=q, v=v, a=a, tau=fd.rnea(model, q, v, a), M=fd.crba(model, q))
    np.savez(bad, q=q, v=v, a=a, M=1.01 * fd.crba(model, q))
    p = cli("check", good, "--robot", path)
    assert p.returncode == 0 and "all 2 comparisons agree" in p.stdout, p.stdout + p.stderr
    p = cli("check", bad, "--robot", path)
    assert p.returncode == 1, p.stdout + p.stderr


def test_an_mjcf_model_with_a_free_joint_is_reported_as_floating() -> None:
    """Issue 32 item 4: the label (title and JSON meta) comes from the model, as `featherdyn info` says it."""
    from featherdyn.verify import run

    report = run(str(ASSETS / "ant.xml"), samples=1, seed=0)
    assert fd.load_mjcf(ASSETS / "ant.xml").floating_base
    assert "(floating base," in report.title and report.meta["floating_base"] is True
    fixed = run(str(ASSETS / "reacher.xml"), samples=1, seed=0)
    assert "(fixed base," in fixed.title and fixed.meta["floating_base"] is False
