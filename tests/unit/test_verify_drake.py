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
    # half_cheetah's settotalmass is ignored by Drake: another model, refused with Drake's words, not compared
    from featherdyn.verify.drake import DrakeRefusedError

    drake_log = logging.getLogger("drake")
    drake_log.setLevel(logging.ERROR)  # Drake silenced by the caller: the report still says what it ignored
    try:
        with pytest.raises(DrakeRefusedError, match="not comparable: Drake's parser changed the model.*settotalmass"):
            run(str(ant.parent / "half_cheetah.xml"), oracle="drake", samples=2)
        cheetah = run(str(ant.parent / "half_cheetah.xml"), oracle="all", samples=2)
    finally:
        drake_log.setLevel(logging.NOTSET)
    assert cheetah.passed and "settotalmass" in cheetah.meta["oracles_skipped"]["drake"]
    assert "drake" not in {r.group for r in cheetah.results} and "mujoco" in {r.group for r in cheetah.results}


TWO_JOINTS = """<mujoco model="two">
  <worldbody>
    <body name="a" pos="1 0 0">
      <joint name="jz" type="hinge" axis="0 0 1"/>{second}
      <geom type="sphere" size="0.1" mass="1"/>
    </body>
  </worldbody>
</mujoco>
"""


@needs_drake
def test_several_joints_on_one_mjcf_body(tmp_path: Path) -> None:
    """Two hinges on a body at x = 1: MuJoCo turns it about the line x = 1 (and agrees with featherdyn), Drake's
    MJCF parser about x = 0: refused as another model, naming the joint and both lines; one hinge is compared."""
    from featherdyn.verify.drake import DrakeRefusedError

    two = tmp_path / "two.xml"
    two.write_text(TWO_JOINTS.format(second='\n      <joint name="jy" type="hinge" axis="0 1 0"/>'), encoding="utf-8")
    with pytest.raises(DrakeRefusedError, match=r"moved the axis.*'jz' of body 'a': featherdyn through \[1\.0, 0\.0"):
        run(str(two), oracle="drake", samples=1)
    both = run(str(two), oracle="all", samples=2)
    assert both.passed and "'jz'" in both.meta["oracles_skipped"]["drake"]
    assert all(r.max_rel < 1e-9 for r in both.results if r.group == "mujoco")
    one = tmp_path / "one.xml"
    one.write_text(TWO_JOINTS.format(second=""), encoding="utf-8")
    report = run(str(one), oracle="drake", samples=2)
    assert report.passed and drake_rows(report)


@needs_drake
def test_armature_on_a_joint_without_actuator(tmp_path: Path) -> None:
    """An MJCF armature on a hinge no motor drives (as swimmer's sliders): Drake's plant has nowhere to hold it
    (rotor inertia lives on a JointActuator), so the model is refused naming the joint; with a motor it is
    compared and agrees."""
    from featherdyn.verify.drake import DrakeRefusedError

    text = TWO_JOINTS.format(second="").replace('axis="0 0 1"/>', 'axis="0 0 1" armature="0.1"/>')
    bare = tmp_path / "bare.xml"
    bare.write_text(text, encoding="utf-8")
    with pytest.raises(DrakeRefusedError, match=r"drops the armature of joints without an actuator.*jz \(armature 0\.1\)"):
        run(str(bare), oracle="drake", samples=1)
    motor = tmp_path / "motor.xml"
    motor.write_text(text.replace("</mujoco>", '<actuator><motor joint="jz"/></actuator></mujoco>'), encoding="utf-8")
    report = run(str(motor), oracle="drake", samples=2)
    assert report.passed and drake_rows(report)["armature vs JointActuator reflected inertia"].max_rel < 1e-12


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
    assert "mimic" in p.stderr  # Drake's own words
    from featherdyn.verify import refused_by, run_or_report

    report = run_or_report(str(path), oracle="drake", samples=1)  # as verify --all: listed, not failed
    assert report.passed and not report.results and "mimic" in refused_by(report)["drake"]


def _urdf(links: str, joints: str) -> str:
    return f'<robot name="r">{links}{joints}</robot>'


def _link(name: str, inertia: str = 'ixx="0.1" iyy="0.1" izz="0.1"') -> str:
    return (f'<link name="{name}"><inertial><mass value="1"/><inertia {inertia} ixy="0" ixz="0" iyz="0"/>'
            "</inertial></link>")


def _hinge(name: str, parent: str, child: str) -> str:
    return (f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>'
            '<origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>')


@needs_drake
def test_an_inertia_drake_replaces_is_not_comparable(tmp_path: Path) -> None:
    """A moving link whose inertia breaks the triangle inequality (0.001, 0.001, 0.01, as pr2's): Drake's parser
    replaces it and warns; the model is listed as not comparable with that warning, never compared."""
    from featherdyn.verify import refused_by, run_or_report

    path = tmp_path / "bad_inertia.urdf"
    path.write_text(_urdf(_link("base") + _link("arm", 'ixx="0.001" iyy="0.001" izz="0.01"'),
                          _hinge("j", "base", "arm")), encoding="utf-8")
    p = cli("verify", path, "--oracle", "drake", "--samples", "1")
    assert p.returncode == 2 and "not comparable: Drake's parser changed the model" in p.stderr, p.stderr
    assert "triangle inequality" in p.stderr and "FAIL" not in p.stdout
    report = run_or_report(str(path), oracle="drake", samples=1)
    assert report.passed and "an inertia it judged unphysical, replaced" in refused_by(report)["drake"]
    # --oracle all: Pinocchio still compares it (MuJoCo refuses the inertia too, and builds no floating base)
    every = run(str(path), oracle="all", samples=2, floating_base=True)
    assert "CouldBePhysicallyValid" in every.meta["oracles_skipped"]["drake"]
    assert "drake" not in {r.group for r in every.results} and "pinocchio" in {r.group for r in every.results}


@needs_drake
def test_a_world_link_with_floating_base(tmp_path: Path) -> None:
    """A URDF whose root link is called 'world' (as the UR arms'): compared with a fixed base; with
    --floating-base Drake welds it (featherdyn floats it), so it is refused with that reason."""
    from featherdyn.verify import refused_by, run_or_report

    path = tmp_path / "arm.urdf"
    path.write_text(_urdf('<link name="world"/>' + _link("base") + _link("arm"),
                          '<joint name="fix" type="fixed"><parent link="world"/><child link="base"/></joint>'
                          + _hinge("j", "base", "arm")), encoding="utf-8")
    fixed = run(str(path), oracle="drake", samples=2)
    assert fixed.passed and max(r.max_rel for r in drake_rows(fixed).values()) < 1e-9
    floating = run_or_report(str(path), oracle="drake", samples=1, floating_base=True)
    assert floating.passed and not floating.results
    assert "Drake welds body 'world' to its world, featherdyn floats it" in refused_by(floating)["drake"]


@needs_drake
def test_a_floating_base_with_a_singular_mass_matrix() -> None:
    """two_link_arm floating (a massless base; M singular): compared with Drake, the identities that solve with M
    left out as with Pinocchio (it used to stop the run with featherdyn's SingularMassMatrixError)."""
    report = run("two_link_arm", floating_base=True, oracle="drake", samples=2)
    assert report.passed and "ABA(RNEA(a)) = a" not in {r.quantity for r in report.results}
    assert {q.split(" vs ")[0] for q in drake_rows(report)} >= {"crba", "generalized_gravity", "rnea"}


@needs_drake
def test_all_with_refusals_exit_codes(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                      capsys: pytest.CaptureFixture[str]) -> None:
    """verify --all --oracle drake over a compared robot and a refused one: exit 0, a 'refused by Drake' section,
    the totals line, refusals in the JSON; a compared robot that disagrees makes it exit 1 with the refusal
    still listed."""
    import featherdyn.robots
    from featherdyn.tools.cli import main
    from featherdyn.verify import drake as oracle

    bad = tmp_path / "bad_inertia.urdf"
    bad.write_text(_urdf(_link("base") + _link("arm", 'ixx="0.001" iyy="0.001" izz="0.01"'),
                         _hinge("j", "base", "arm")), encoding="utf-8")
    monkeypatch.setattr(featherdyn.robots, "list_robots", lambda: ["panda", str(bad)])
    js, page = tmp_path / "all.json", tmp_path / "all.html"
    assert main(["verify", "--all", "--oracle", "drake", "--samples", "1", "--json", str(js), "--report",
                 str(page)]) == 0
    assert "refused by Drake: not compared" in page.read_text(encoding="utf-8")
    out = capsys.readouterr().out
    assert "refused by Drake (not compared; the oracle's reason):" in out
    assert f"  {bad}: bad_inertia.urdf: not comparable: Drake's parser changed the model" in out
    assert "total: 2 robots: 1 compared, 1 agree, 0 disagree, 1 refused by the oracle;" in out
    data = json.loads(js.read_text(encoding="utf-8"))
    assert list(data["refused"]) == [str(bad)] and "triangle inequality" in data["refused"][str(bad)]["drake"]
    heavier = _heavier(robot_path("panda"), tmp_path, "panda_link4")
    build = oracle.build_drake
    monkeypatch.setattr(oracle, "build_drake", lambda path, model, **kw: build(
        heavier if Path(path).name == "panda.urdf" else path, model, **kw))
    assert main(["verify", "--all", "--oracle", "drake", "--samples", "1"]) == 1
    out = capsys.readouterr().out
    assert "total: 2 robots: 1 compared, 0 agree, 1 disagree, 1 refused by the oracle;" in out
    assert "FAIL panda: crba vs CalcMassMatrix" in out and "refused by Drake" in out


@needs_drake
@pytest.mark.parametrize("floating", [False, True])
def test_all_robots_against_drake(floating: bool) -> None:
    """--all --oracle drake (fixed and floating): every compared robot agrees (exit 0); talos_reduced (a mimic of a
    0-dof joint) and bolt (an inertia Drake replaces) are listed under 'refused by Drake' with Drake's words, and
    with --floating-base ur5_robot (a link named 'world', which Drake welds)."""
    p = cli("verify", "--all", "--oracle", "drake", "--samples", "1", *(["--floating-base"] if floating else []))
    assert p.returncode == 0 and "Traceback" not in p.stderr, p.stdout[-3000:] + p.stderr[-2000:]
    table, _, refused = p.stdout.partition("refused by Drake (not compared; the oracle's reason):")
    assert any(line.startswith("panda ") and line.split()[2] == "0" for line in table.splitlines())
    assert "FAIL" not in table
    reasons = {line.split(": ", 1)[0].strip(): line.split(": ", 1)[1] for line in refused.splitlines()
               if line.startswith("  ")}
    assert "mimic" in reasons["talos_reduced"] and "Drake's parser refuses it" in reasons["talos_reduced"]
    assert "an inertia it judged unphysical, replaced" in reasons["bolt"]
    assert ("welds a link named 'world'" in reasons.get("ur5_robot", "")) is floating
    assert "panda" not in reasons and "talos_reduced" not in table.split("refused by")[0]
    total = next(line for line in p.stdout.splitlines() if line.startswith("total: 69 robots: "))
    compared, agree = (int(total.split(": ")[2].split()[0]), int(total.split(", ")[1].split()[0]))
    assert compared == agree and f"{len(reasons)} refused by the oracle" in total and compared + len(reasons) == 69
