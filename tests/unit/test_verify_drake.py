"""``featherdyn verify --oracle drake|all``: Drake's MultibodyPlant as a third oracle (``verify/drake.py``).

Oracle: Drake's own parse of the same file. The checks must agree to round-off on robots both libraries read
the same way (fixed and floating bases), and must fail, naming the quantity, when Drake's model or the
conversion at the boundary is altered behind featherdyn's back.
"""

from __future__ import annotations

import importlib.util
import json
import logging
import subprocess
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.errors import MissingDependencyError
from featherdyn.robots import robot_path
from featherdyn.verify import run


def cli(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "featherdyn", *map(str, args)], capture_output=True, text=True,
                          timeout=600)


def test_without_pydrake_the_oracle_is_a_clear_error(monkeypatch: pytest.MonkeyPatch,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    """No pydrake: MissingDependencyError naming the install, and the CLI's one line (exit 2)."""
    from featherdyn.tools.cli import main

    for name in ("pydrake", "pydrake.multibody", "pydrake.multibody.plant", "pydrake.multibody.parsing"):
        monkeypatch.setitem(sys.modules, name, None)
    with pytest.raises(MissingDependencyError, match="pip install drake"):
        run("panda", oracle="drake", samples=1)
    assert main(["verify", "panda", "--oracle", "drake", "--samples", "1"]) == 2
    err = capsys.readouterr().err
    assert "pip install drake" in err and "Traceback" not in err and err.count("\n") == 1


#: pydrake is in the `test` extra, so everything below runs in CI; without it only the test above runs
needs_drake = pytest.mark.skipif(importlib.util.find_spec("pydrake") is None, reason="pydrake is not installed")

#: the rows every Drake comparison carries (quantity up to " vs ")
QUANTITIES = {"total mass", "armature", "crba", "generalized_gravity", "rnea − g at Drake's v̇ = 0", "rnea", "aba"}


def drake_rows(report: Any) -> dict[str, Any]:
    return {r.quantity: r for r in report.results if r.group == "drake"}


@needs_drake
@pytest.mark.parametrize("robot, floating", [("panda", False), ("ur5_robot", False), ("solo12", True),
                                             ("talos_full_v2", True)])
def test_robots_agree_with_drake(robot: str, floating: bool) -> None:
    """Fixed (panda, ur5) and floating (solo12, the talos humanoid) bases: every Drake row below 1e-9."""
    report = run(robot, floating_base=floating, oracle="drake", samples=4, seed=3)
    rows = drake_rows(report)
    assert {q.split(" vs ")[0] for q in rows} >= QUANTITIES
    assert any(q.startswith("frame placements") for q in rows)
    jacobians = [q for q in rows if q.startswith("frame_jacobian")]
    assert len(jacobians) == 9 and {q.split()[2] for q in jacobians} == {"LOCAL", "WORLD", "LOCAL_WORLD_ALIGNED"}
    worst = max(r.max_rel for r in rows.values())
    assert worst < 1e-9, [(r.quantity, r.max_rel) for r in rows.values() if r.max_rel >= 1e-9]
    assert report.passed and report.meta["drake"] != "not installed"
    assert report.meta["floating_base"] is floating and "Drake" in report.title


def _heavier(path: str | Path, tmp_path: Path, link: str) -> Path:
    """A copy of the URDF in which ``link`` is 10 % heavier (meshes resolved as in the original's folder)."""
    text = Path(path).read_text(encoding="utf-8")
    start = text.index(f'<link name="{link}"')
    at = text.index("<mass value=", start)
    value_start = at + len('<mass value="')
    value_end = text.index('"', value_start)
    mass = float(text[value_start:value_end])
    out = tmp_path / Path(path).name
    out.write_text(text[:value_start] + repr(1.1 * mass) + text[value_end:], encoding="utf-8")
    return out


@needs_drake
def test_a_model_drake_reads_differently_is_caught(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Drake parses a copy with one link 10 % heavier: the mass, M, gravity and dynamics rows fail by name."""
    from featherdyn.verify import drake as oracle

    heavier = _heavier(robot_path("panda"), tmp_path, "panda_link4")
    build = oracle.build_drake
    monkeypatch.setattr(oracle, "build_drake", lambda path, model, **kw: build(heavier, model, **kw))
    report = run("panda", oracle="drake", samples=3, seed=1)
    failed = {r.quantity.split(" vs ")[0] for r in report.failures}
    assert {"total mass", "crba", "generalized_gravity", "rnea", "aba"} <= failed
    assert not any(q.startswith(("frame placements", "frame_jacobian")) for q in failed)  # kinematics unchanged
    p = subprocess.run([sys.executable, "-c", f"""
import featherdyn.verify.drake as o, featherdyn.tools.cli as c, sys
b = o.build_drake
o.build_drake = lambda path, model, **kw: b({str(heavier)!r}, model, **kw)
sys.exit(c.main(["verify", "panda", "--oracle", "drake", "--samples", "2"]))
"""], capture_output=True, text=True, timeout=600)
    assert p.returncode == 1, p.stderr
    assert "crba vs CalcMassMatrix" in p.stdout and "FAIL" in p.stdout


@needs_drake
def test_a_wrong_conversion_is_caught(monkeypatch: pytest.MonkeyPatch) -> None:
    """Drake's gravity taken with featherdyn's sign, or its free-flyer v read in base axes: the rows that
    depend on it fail, by name, and the others still pass."""
    from featherdyn.conventions import drake as conv
    from featherdyn.verify import drake as oracle

    monkeypatch.setattr(oracle._conv, "generalized_gravity_to_drake",
                        lambda model, layout, q, g: conv.tau_to_drake(model, layout, q, g))
    report = run("solo12", floating_base=True, oracle="drake", samples=2, seed=0)
    assert {r.quantity for r in report.failures} == {"generalized_gravity vs −CalcGravityGeneralizedForces"}
    monkeypatch.undo()

    def base_axes(model: Any, layout: Any, q: np.ndarray) -> np.ndarray:  # forgets R on the free block
        V = np.zeros((model.nv, model.nv))
        for iv, n, dv in zip(model.idx_v, model.nvs, layout.v_start, strict=True):
            V[dv:dv + n, iv:iv + n] = np.eye(n)
        return V

    monkeypatch.setattr(conv, "drake_velocity_map", base_axes)
    failed = {r.quantity.split(" vs ")[0] for r in run("solo12", floating_base=True, oracle="drake", samples=2,
                                                       seed=0).failures}
    assert {"crba", "generalized_gravity", "rnea"} <= failed


@needs_drake
def test_oracle_all_and_reports(tmp_path: Path) -> None:
    """--oracle all: Pinocchio, MuJoCo and Drake rows in one table, JSON and HTML; a floating base leaves
    MuJoCo out and says why."""
    js, html = tmp_path / "r.json", tmp_path / "r.html"
    p = cli("verify", "panda", "--oracle", "all", "--samples", "2", "--json", js, "--report", html)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-2000:]
    for row in ("crba vs pin.crba", "crba vs mj_fullM", "crba vs CalcMassMatrix"):
        assert row in p.stdout
    data = json.loads(js.read_text(encoding="utf-8"))
    groups = {r["group"] for r in data["results"]}
    assert {"pinocchio", "mujoco", "drake", "identity"} <= groups
    assert data["meta"]["oracle"] == "all" and data["meta"]["drake"] and "drake_warnings" in data["meta"]
    drake = [r for r in data["results"] if r["group"] == "drake"]
    assert drake and all(r["passed"] and r["max_rel"] < 1e-9 for r in drake)
    page = html.read_text(encoding="utf-8")
    assert "CalcMassMatrix" in page and "CalcJacobianSpatialVelocity" in page
    assert "What the oracles ignore or leave out" in page and "joint damping" in page  # panda's URDF has damping
    report = run("solo12", floating_base=True, oracle="all", samples=2)
    assert report.passed and "builds no free joint" in report.meta["oracles_skipped"]["mujoco"]
    assert {"pinocchio", "drake"} <= {r.group for r in report.results} and "mujoco" not in {
        r.group for r in report.results}
    assert "oracles left out" in report.to_table()


@needs_drake
def test_an_mjcf_model_through_drakes_parser() -> None:
    """ant.xml (a free joint, hinges, armature): Drake's MJCF parser agrees; half_cheetah's settotalmass it ignores, and says so."""
    gymnasium = pytest.importorskip("gymnasium")
    ant = Path(gymnasium.__file__).parent / "envs" / "mujoco" / "assets" / "ant.xml"
    report = run(str(ant), oracle="drake", samples=2)
    assert report.passed and max(r.max_rel for r in drake_rows(report).values()) < 1e-9
    assert report.meta["floating_base"] is True
    # half_cheetah's settotalmass is ignored by Drake: the masses differ and the report says why
    drake_log = logging.getLogger("drake")
    drake_log.setLevel(logging.ERROR)  # Drake silenced by the caller: the report still says what it ignored
    try:
        cheetah = run(str(ant.parent / "half_cheetah.xml"), oracle="drake", samples=2)
    finally:
        drake_log.setLevel(logging.NOTSET)
    assert "total mass vs Drake body masses (moving bodies)" in {r.quantity for r in cheetah.failures}
    assert any("settotalmass" in n for n in cheetah.meta["oracle_notes"])


SDF = """<?xml version="1.0"?>
<sdf version="1.7">
  <model name="pendulum">
    <joint name="fix" type="fixed"><parent>world</parent><child>base</child></joint>
    <link name="base"><inertial><mass>1.0</mass>
      <inertia><ixx>0.1</ixx><iyy>0.1</iyy><izz>0.1</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial></link>
    <link name="arm"><pose>0 0 -0.5 0 0 0</pose><inertial><pose>0 0 -0.25 0 0 0</pose><mass>2.0</mass>
      <inertia><ixx>0.05</ixx><iyy>0.06</iyy><izz>0.01</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
    </link>
    <joint name="hinge" type="revolute"><parent>base</parent><child>arm</child><axis><xyz>0 1 0</xyz></axis></joint>
  </model>
</sdf>
"""


@needs_drake
def test_an_sdf_file(tmp_path: Path) -> None:
    """Drake reads SDFormat; featherdyn compares it when its SDF loader is there, else says clearly it cannot."""
    path = tmp_path / "pendulum.sdf"
    path.write_text(SDF, encoding="utf-8")
    p = cli("verify", path, "--samples", "2")  # an .sdf file defaults to --oracle drake
    if importlib.util.find_spec("featherdyn.readers.sdf") is None:
        assert p.returncode == 2 and "featherdyn cannot load SDFormat" in p.stderr, p.stderr
        assert "nothing was compared" in p.stderr and "Traceback" not in p.stderr
    else:
        assert p.returncode == 0 and "crba vs CalcMassMatrix" in p.stdout, p.stdout + p.stderr
    p = cli("verify", path, "--oracle", "mujoco")
    assert p.returncode == 2 and "MuJoCo reads no SDF" in p.stderr


@needs_drake
def test_a_file_drakes_parser_refuses_is_a_clean_error(tmp_path: Path) -> None:
    """A joint mimicking a joint that does not exist: Drake's parser refuses, featherdyn says so in one line."""
    path = tmp_path / "mimic.urdf"
    path.write_text("""<robot name="m">
  <link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/><mimic joint="nope"/></joint>
</robot>""", encoding="utf-8")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # featherdyn's loader warns of the dangling <mimic> and ignores it
        nv = fd.load_urdf(path).nv
    if nv != 1:
        pytest.skip("featherdyn's URDF loader changed how it treats a dangling mimic")
    p = cli("verify", path, "--oracle", "drake", "--samples", "1")
    assert p.returncode == 2 and "Drake's parser refuses it" in p.stderr and "Traceback" not in p.stderr, p.stderr


@needs_drake
def test_all_robots_against_drake() -> None:
    """--all --oracle drake: one row per robot; where Drake's parser changed a robot (an inertia it refused as
    unphysical), the table says so under the robot's failures."""
    p = cli("verify", "--all", "--oracle", "drake", "--samples", "1")
    assert p.returncode in (0, 1) and "Traceback" not in p.stderr, p.stderr[-2000:]
    lines = p.stdout.splitlines()
    assert any(line.startswith("panda ") and line.split()[2] == "0" for line in lines)
    for line in lines:
        if line.startswith("FAIL ") and "CalcMassMatrix" in line:
            robot = line.split()[1].rstrip(":")
            assert any(n.startswith(f"  {robot}: Drake's parser") for n in lines), robot
