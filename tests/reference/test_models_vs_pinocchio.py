"""Models loaded by featherdyn.load_urdf against Pinocchio's URDF parser, robot by robot.

Every URDF of example-robot-data, the bundled 2R arm and a few synthetic
files exercising the joint types real robots lack are loaded with a fixed and with a floating base
by both libraries, then compared:

* sizes: bodies (``njoints − 1``), ``nv``, and ``nq`` from Pinocchio's joint
  types (its continuous joints store ``(cos, sin)``, nq 2, and its planar joint
  ``[x, y, cos, sin]``, nq 4; featherdyn's use an angle);
* total mass (``Σ model.inertias[1:]``, the fixed root link dropped);
* per moving joint, mapped by name: the joint kind, the joint placement, the
  motion subspace in world coordinates at the neutral configuration (the
  columns of Pinocchio's WORLD joint Jacobian: robust to how either library
  represents a negative or unaligned axis), the lumped body inertia as a 6×6
  matrix (Pinocchio's is linear first: ``P I P``), and the limits;
* every frame: same set of (name, kind), same parent joint, same world
  placement at the neutral configuration. (A Pinocchio JOINT frame hangs on
  the joint it names and moves with it; featherdyn's ``"joint"`` frame is
  fixed to the parent body at the joint placement: the same pose at the
  neutral configuration, the parent joint's body otherwise.)

Pinocchio orders a link's children by joint name, featherdyn by document
order, so nothing here compares by index. Each URDF is parsed once per base
type (module-level cache).
"""

from __future__ import annotations

import functools
import importlib.metadata
import warnings
from pathlib import Path

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.errors import PhysicalityWarning, URDFError
from featherdyn.testing import assert_close

pin = pytest.importorskip("pinocchio")

P = np.block([[np.zeros((3, 3)), np.eye(3)], [np.eye(3), np.zeros((3, 3))]])
#: Agreement of parsed quantities: both libraries read the same decimals, so
#: only the lumping and the products of placements round differently.
RTOL, ATOL = 1e-10, 1e-12


def _erd_urdfs() -> list[Path]:
    try:
        files = importlib.metadata.files("example-robot-data") or []
    except importlib.metadata.PackageNotFoundError:
        return []
    return sorted(Path(str(f.locate())) for f in files if str(f).endswith(".urdf"))


ERD = _erd_urdfs()
STUBS = {"ur3.urdf"}  # an empty <robot/> left by xacro: both libraries reject it
ROBOTS = [p for p in ERD if p.name not in STUBS]


def _rid(p: Path) -> str:
    return f"{p.parent.parent.name}/{p.stem}"


# synthetic files: the joint types example-robot-data lacks, with Pinocchio-compatible axes
SYNTHETIC = {
    "planar_floating_continuous": """<robot name="synthetic">
  <link name="world"/>
  <joint name="slide" type="planar"><parent link="world"/><child link="cart"/>
    <origin xyz="0.1 0.2 0.3" rpy="0.1 0.2 0.3"/><axis xyz="0 0 1"/></joint>
  <link name="cart"><inertial><origin xyz="0.1 0 0" rpy="0.3 -0.2 1.0"/><mass value="2"/>
    <inertia ixx="0.3" ixy="0.01" ixz="-0.02" iyy="0.4" iyz="0.03" izz="0.5"/></inertial></link>
  <joint name="drone" type="floating"><parent link="cart"/><child link="body"/><origin xyz="0 1 0" rpy="0 0 1.2"/></joint>
  <link name="body"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <joint name="wheel" type="continuous"><parent link="body"/><child link="w"/><axis xyz="0 0 -1"/></joint>
  <link name="w"><inertial><origin xyz="0 0 0.2"/><mass value="0.5"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.02"/></inertial></link>
  <joint name="fix" type="fixed"><parent link="w"/><child link="tool"/><origin xyz="0.3 0 0" rpy="1.5 0 0"/></joint>
  <link name="tool"><inertial><origin xyz="0 0.1 0" rpy="0 0.7 0"/><mass value="0.2"/>
    <inertia ixx="0.002" ixy="0.0001" ixz="0" iyy="0.003" iyz="0" izz="0.004"/></inertial></link>
  <joint name="lift" type="prismatic"><parent link="tool"/><child link="fork"/><origin xyz="0 0 0.1" rpy="0 0.5 0"/>
    <axis xyz="0.6 -0.8 0"/><limit lower="-0.5" upper="0.5" effort="100" velocity="1"/></joint>
  <link name="fork"><inertial><mass value="0.1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <joint name="tilt" type="revolute"><parent link="fork"/><child link="tip"/><axis xyz="-1 0 0"/>
    <limit lower="-1" upper="1" effort="5" velocity="2"/></joint>
  <link name="tip"><inertial><mass value="0.1"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
</robot>""",
    "heavy_fixed_root": """<robot name="heavy_root">
  <link name="base"><inertial><mass value="10"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
  <joint name="mount" type="fixed"><parent link="base"/><child link="plate"/><origin xyz="0 0 0.5" rpy="0 0 0.3"/></joint>
  <link name="plate"><inertial><mass value="3"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
  <joint name="b_joint" type="revolute"><parent link="plate"/><child link="b"/><origin xyz="0 0.2 0"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="b"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <joint name="a_joint" type="revolute"><parent link="plate"/><child link="a"/><origin xyz="0.2 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="a"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
</robot>""",
}

BUNDLED = fd.robots.robot_path("two_link_arm")
CASES = (
    [pytest.param(str(p), id=_rid(p)) for p in ROBOTS]
    + [pytest.param(str(BUNDLED), id="bundled/two_link_arm")]
    + [pytest.param(k, id=k) for k in SYNTHETIC]
)


@functools.cache
def _models(case: str, floating: bool) -> tuple[fd.Model, object, object]:
    """``(featherdyn model, Pinocchio model, Pinocchio data at the neutral configuration)``, parsed once."""
    source = SYNTHETIC.get(case, case)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PhysicalityWarning)  # real robots have odd inertias
        model = fd.load_urdf(source if case in SYNTHETIC else Path(case), floating_base=floating)
    build = pin.buildModelFromXML if case in SYNTHETIC else pin.buildModelFromUrdf
    pmodel = build(source, pin.JointModelFreeFlyer()) if floating else build(source)
    pdata = pmodel.createData()
    q0 = pin.neutral(pmodel)
    pin.framesForwardKinematics(pmodel, pdata, q0)
    pin.computeJointJacobians(pmodel, pdata, q0)
    return model, pmodel, pdata


def _world_poses(model: fd.Model) -> list[tuple[np.ndarray, np.ndarray]]:
    """World pose ``(R, p)`` of each body at the neutral configuration (composing placements down the tree)."""
    out: list[tuple[np.ndarray, np.ndarray]] = []
    for i, joint in enumerate(model.joints):
        X = model.joint_placements[i] @ joint.pose(joint.neutral())
        R, p = X.rotation, X.translation
        parent = model.parents[i]
        if parent >= 0:
            Rp, pp = out[parent]
            R, p = Rp @ R, Rp @ p + pp
        out.append((R, p))
    return out


def _pin_nq(jmodel) -> int:
    """featherdyn's nq for a Pinocchio joint: continuous (RUB*) 1 instead of 2, planar 3 instead of 4."""
    name = jmodel.shortname()
    if "RUB" in name or "RevoluteUnbounded" in name:
        return 1
    if name == "JointModelPlanar":
        return 3
    return jmodel.nq


def _pin_kind(jmodel) -> str:
    name = jmodel.shortname().removeprefix("JointModel")
    if name == "FreeFlyer":
        return "free_flyer"
    if name == "Planar":
        return "planar"
    if name.startswith(("R", "Revolute")):
        return "revolute"
    if name.startswith(("P", "Prismatic")):
        return "prismatic"
    return name


# featherdyn's velocity coordinates (angular first) from Pinocchio's, per joint kind
_V_PERM = {"free_flyer": [3, 4, 5, 0, 1, 2], "planar": [2, 0, 1]}


@pytest.fixture(params=[False, True], ids=["fixed", "floating"])
def floating(request: pytest.FixtureRequest) -> bool:
    return bool(request.param)


@pytest.mark.parametrize("case", CASES)
def test_sizes_and_mass(case: str, floating: bool) -> None:
    model, pmodel, _ = _models(case, floating)
    where = f"{Path(case).name}, {'floating' if floating else 'fixed'} base"
    assert model.nbodies == pmodel.njoints - 1, where
    assert model.nv == pmodel.nv, where
    assert model.nq == sum(_pin_nq(j) for j in pmodel.joints[1:]), where
    assert sorted(model.joint_names) == sorted(pmodel.names[1:]), where
    if floating:
        assert model.floating_base and model.joint_names[0] == pmodel.names[1] == "root_joint", where
    pin_mass = sum(pmodel.inertias[j].mass for j in range(1, pmodel.njoints))
    assert_close(model.total_mass, pin_mass, "total mass", where=where)


@pytest.mark.parametrize("case", CASES)
def test_joints(case: str, floating: bool) -> None:
    model, pmodel, pdata = _models(case, floating)
    where = f"{Path(case).name}, {'floating' if floating else 'fixed'} base"
    poses = _world_poses(model)
    for j in range(1, pmodel.njoints):
        name = pmodel.names[j]
        i = model.joint_id(name)
        jm = pmodel.joints[j]
        joint = model.joints[i]
        at = f"{where}, joint {name!r}"
        assert joint.kind == _pin_kind(jm), at
        assert model.body_names[i] == pmodel.frames[pmodel.getFrameId(name, pin.FrameType.JOINT) + 1].name, at
        parent = pmodel.parents[j]
        assert model.parents[i] == (model.joint_id(pmodel.names[parent]) if parent else -1), at
        Xp = model.joint_placements[i]
        Mp = pmodel.jointPlacements[j]
        assert_close(Xp.rotation, Mp.rotation, "joint placement rotation", where=at, rtol=RTOL, atol=ATOL)
        assert_close(Xp.translation, Mp.translation, "joint placement translation", where=at, rtol=RTOL, atol=ATOL)
        # world placement of the joint frame and its motion subspace at the neutral configuration
        R, p = poses[i]
        assert_close(R, pdata.oMi[j].rotation, "world rotation", where=at, rtol=RTOL, atol=1e-10)
        assert_close(p, pdata.oMi[j].translation, "world position", where=at, rtol=RTOL, atol=1e-10)
        X_world = fd.PluckerTransform(R, p, validate=False)
        S_world = X_world.matrix() @ joint.S
        J = pin.getJointJacobian(pmodel, pdata, j, pin.ReferenceFrame.WORLD)[:, jm.idx_v : jm.idx_v + jm.nv]
        J = (P @ J)[:, _V_PERM.get(joint.kind, list(range(joint.nv)))]
        assert_close(S_world, J, "motion subspace in world coordinates", where=at, rtol=RTOL, atol=1e-10)
        # inertia of the body (fixed children lumped in)
        I_pin = P @ pmodel.inertias[j].matrix() @ P
        scale = max(1.0, float(np.abs(I_pin).max()))
        assert_close(model.inertias[i].matrix(), I_pin, "body inertia", where=at, rtol=1e-9, atol=1e-12, scale=scale)
        # limits (Pinocchio's free-flyer, planar and continuous joints have their own conventions)
        if joint.kind in ("revolute", "prismatic") and _pin_nq(jm) == jm.nq:
            iq, iv = model.idx_q[i], model.idx_v[i]
            assert model.lower[iq] == pmodel.lowerPositionLimit[jm.idx_q], at
            assert model.upper[iq] == pmodel.upperPositionLimit[jm.idx_q], at
            assert model.velocity_limit[iv] == pmodel.velocityLimit[jm.idx_v], at
            assert model.effort_limit[iv] == pmodel.effortLimit[jm.idx_v], at


_KIND = {"BODY": ("body", "link"), "JOINT": ("joint",), "FIXED_JOINT": ("fixed_joint",)}


@pytest.mark.parametrize("case", CASES)
def test_frames(case: str, floating: bool) -> None:
    model, pmodel, pdata = _models(case, floating)
    where = f"{Path(case).name}, {'floating' if floating else 'fixed'} base"
    poses = _world_poses(model)
    ours = {(f.name, f.kind): f for f in model.frames}
    group = {k: kind for kind, kinds in _KIND.items() for k in kinds}
    assert len(ours) == len(model.frames), f"{where}: duplicate (name, kind) frames"
    pin_frames = {(f.name, str(f.type).rsplit(".", 1)[-1]) for f in pmodel.frames[1:]}  # [0] is "universe"
    assert {(n, group[k]) for n, k in ours} == pin_frames, where
    for k, frame in enumerate(pmodel.frames):
        ftype = str(frame.type).rsplit(".", 1)[-1]
        if k == 0 or ftype not in _KIND:
            continue
        mine = next(ours[(frame.name, kind)] for kind in _KIND[ftype] if (frame.name, kind) in ours)
        at = f"{where}, frame {frame.name!r} ({ftype})"
        parent_joint = frame.parentJoint  # a JOINT frame hangs on its own joint (moves with q) in both libraries
        expected_body = model.joint_id(pmodel.names[parent_joint]) if parent_joint else -1
        assert mine.body == expected_body, at
        X = mine.placement
        if mine.body >= 0:
            R0, p0 = poses[mine.body]
            R, p = R0 @ X.rotation, R0 @ X.translation + p0
        else:
            R, p = X.rotation, X.translation
        assert_close(R, pdata.oMf[k].rotation, "frame world rotation", where=at, rtol=RTOL, atol=1e-10)
        assert_close(p, pdata.oMf[k].translation, "frame world position", where=at, rtol=RTOL, atol=1e-10)


def test_every_robot_loads_and_the_stub_is_rejected() -> None:
    if not ERD:
        pytest.skip("example-robot-data is not installed")
    assert len(ROBOTS) >= 60
    for stub in (p for p in ERD if p.name in STUBS):
        with pytest.raises(URDFError, match=r"ur3\.urdf.*no <link>"):
            fd.load_urdf(stub)
        with pytest.raises(ValueError):  # Pinocchio (urdfdom) rejects it too
            pin.buildModelFromUrdf(str(stub))


def test_pinocchio_ignores_the_planar_normal() -> None:
    """A documented disagreement: URDF says the planar axis is the plane's normal; Pinocchio always uses z."""
    xml = """<robot name="p"><link name="a"/>
      <joint name="j" type="planar"><parent link="a"/><child link="b"/><axis xyz="1 0 0"/></joint>
      <link name="b"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
    </robot>"""
    model = fd.load_urdf(xml)
    assert np.allclose(model.joints[0].S[:3, 0], [1, 0, 0])  # rotation about the normal x
    pmodel = pin.buildModelFromXML(xml)
    pdata = pmodel.createData()
    pin.computeJointJacobians(pmodel, pdata, pin.neutral(pmodel))
    J = pin.getJointJacobian(pmodel, pdata, 1, pin.ReferenceFrame.WORLD)
    assert np.allclose(J[3:, 2], [0, 0, 1])  # Pinocchio rotates about z
