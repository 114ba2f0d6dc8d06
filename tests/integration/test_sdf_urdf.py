"""The SDF loader against the URDF loader and against Drake: the same robots written in both formats.

example-robot-data URDFs are converted to SDFormat by the test-side converter
``_urdf_to_sdf`` (plain ElementTree and NumPy, in six pose styles: SDFormat
1.4's model-frame poses and axes, 1.6's ``use_parent_model_frame``, 1.7+
``relative_to`` a parent link, a joint or a ``<frame>``, quaternions and
degrees). The SDF model must agree with ``fd.load_urdf`` of the URDF: the
same joints in the same order, and ``fd.crba``, ``fd.rnea`` and every frame
placement the URDF has to 1e-12 (relative to the largest entry), fixed (the
root on ``world`` by a fixed joint) and floating (no joint to the world:
``load_urdf(floating_base=True)``). With ``pydrake`` installed, Drake's own
SDFormat parser reads the same files and its mass matrix and gravity forces
are compared (skipped only when ``pydrake`` cannot be imported).
"""

from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.errors import PhysicalityWarning

sys.path.insert(0, str(Path(__file__).parent))
from _urdf_to_sdf import STYLES, urdf_to_sdf

ROBOTS = ["panda", "ur5_robot", "solo12", "double_pendulum", "talos_left_arm"]
TOL = 1e-12


def _urdf_text(robot: str) -> str:
    from featherdyn.errors import MissingDependencyError
    from featherdyn.robots import robot_path

    try:
        return Path(robot_path(robot)).read_text()
    except MissingDependencyError:
        pytest.skip("example-robot-data (a test dependency) provides the URDFs")


def _quiet(load, *args, **kw) -> fd.Model:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PhysicalityWarning)
        return load(*args, **kw)


def _close(a: np.ndarray, b: np.ndarray, what: str) -> None:
    scale = max(1.0, float(np.abs(b).max()))
    err = float(np.abs(a - b).max()) / scale
    assert err <= TOL, f"{what}: relative difference {err:.3g} > {TOL}"


#: (robot, fixed base); ur5_robot's URDF roots it on a link named "world" (SDFormat's world frame): fixed only
CASES = [(r, fixed) for r in ROBOTS for fixed in (True, False) if fixed or r != "ur5_robot"]


@pytest.mark.parametrize("style", STYLES)
@pytest.mark.parametrize(("robot", "fixed"), CASES, ids=[f"{r}-{'fixed' if f else 'floating'}" for r, f in CASES])
def test_sdf_equals_urdf(robot: str, style: str, fixed: bool) -> None:
    text = _urdf_text(robot)
    urdf = _quiet(fd.load_urdf, text, floating_base=not fixed)
    model = _quiet(fd.load_sdf, urdf_to_sdf(text, style, fixed))
    assert model.joint_names == urdf.joint_names
    assert model.nq == urdf.nq and model.nv == urdf.nv
    np.testing.assert_array_equal(model.lower, urdf.lower)
    np.testing.assert_array_equal(model.upper, urdf.upper)
    assert model.total_mass == pytest.approx(urdf.total_mass, rel=TOL)
    rng = np.random.default_rng(7)
    names = {f.name for f in model.frames}
    common = [f.name for f in urdf.frames if f.name in names]
    assert len(common) >= len(urdf.frames) - 1  # (a URDF link named "world" is SDFormat's world, not a frame)
    for _ in range(3):
        q = fd.random_configuration(urdf, rng)
        v, a = rng.normal(size=urdf.nv), rng.normal(size=urdf.nv)
        _close(fd.crba(model, q), fd.crba(urdf, q), f"{robot} {style}: M")
        _close(fd.rnea(model, q, v, a), fd.rnea(urdf, q, v, a), f"{robot} {style}: rnea")
        for name in common:
            _close(fd.frame_placement(model, q, name).matrix(), fd.frame_placement(urdf, q, name).matrix(),
                   f"{robot} {style}: frame {name}")


@pytest.mark.parametrize("style", ["model", "parent", "joint", "frames"])
@pytest.mark.parametrize("robot", ["panda", "ur5_robot", "talos_left_arm"])
def test_sdf_agrees_with_drake(robot: str, style: str) -> None:
    """Drake's SDFormat parser (libsdformat) on the same files: M(q) and the gravity torques, joints by name."""
    pytest.importorskip("pydrake", reason="Drake (pip install drake) is the optional SDFormat oracle")
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    text = urdf_to_sdf(_urdf_text(robot), style, True)
    model = _quiet(fd.load_sdf, text)
    plant = MultibodyPlant(0.0)
    Parser(plant).AddModelsFromString(text, "sdf")
    plant.Finalize()
    context = plant.CreateDefaultContext()
    index = [plant.GetJointByName(name).position_start() for name in model.joint_names]
    assert sorted(index) == list(range(plant.num_positions()))
    rng = np.random.default_rng(11)
    for _ in range(3):
        q = fd.random_configuration(model, rng)
        q_drake = np.zeros(plant.num_positions())
        q_drake[index] = q
        plant.SetPositions(context, q_drake)
        _close(plant.CalcMassMatrix(context)[np.ix_(index, index)], fd.crba(model, q), f"{robot} {style}: M")
        # Drake's gravity "forces" are the generalized forces gravity applies: minus featherdyn's g(q)
        _close(-plant.CalcGravityGeneralizedForces(context)[index], fd.generalized_gravity(model, q),
               f"{robot} {style}: gravity")


# --------------------------------------------------------------------------
# hand-written SDF documents that exercise the frame rules, against Drake
# --------------------------------------------------------------------------

_I = ("<inertial><mass>{m}</mass><pose>0.1 -0.2 0.3 0.4 0.5 0.6</pose><inertia><ixx>0.3</ixx><ixy>0.01</ixy>"
      "<ixz>-0.02</ixz><iyy>0.4</iyy><iyz>0.03</iyz><izz>0.5</izz></inertia></inertial>")
HAND = {
    "frames_1_9": f"""<sdf version="1.9"><model name="m">
  <link name="base">{_I.format(m=2)}</link>
  <joint name="weld" type="fixed"><parent>world</parent><child>base</child><pose>0 0 1 0.2 0 0</pose></joint>
  <frame name="F" attached_to="base"><pose>0.3 0 0.1 0 0.4 0.2</pose></frame>
  <link name="a"><pose relative_to="F">0 0.2 0 0.1 0 0</pose>{_I.format(m=1.5)}</link>
  <joint name="j1" type="revolute"><parent>base</parent><child>a</child><pose relative_to="F">0.05 0 0 0 0 0</pose>
    <axis><xyz expressed_in="__model__">0 0.6 0.8</xyz></axis></joint>
  <model name="inner"><pose relative_to="a">0 0 -0.5 0 0.3 0</pose>
    <link name="b">{_I.format(m=1)}</link><link name="c"><pose>0.1 0 0 0 0 0.5</pose>{_I.format(m=0.7)}</link>
    <frame name="G" attached_to="b"><pose>0 0.1 0 0 0 0.3</pose></frame>
    <joint name="p" type="prismatic"><parent>b</parent><child>c</child>
      <axis><xyz expressed_in="G">1 0 0</xyz></axis></joint></model>
  <joint name="j2" type="continuous"><parent>a</parent><child>inner::b</child>
    <pose relative_to="inner::G">0 0 0.1 0 0 0</pose><axis><xyz>0 1 0</xyz></axis></joint>
</model></sdf>""",
    "axes_1_4": f"""<sdf version="1.4"><model name="m">
  <link name="base"><pose>0 0 0.5 0 0 0</pose>{_I.format(m=2)}</link>
  <joint name="weld" type="revolute"><parent>world</parent><child>base</child>
    <axis><xyz>0 0 1</xyz><limit><lower>-3</lower><upper>3</upper></limit></axis></joint>
  <link name="a"><pose>0.2 0.1 0.9 0.3 0.2 0.1</pose>{_I.format(m=1.5)}</link>
  <joint name="j1" type="revolute"><parent>base</parent><child>a</child><pose>0 0 -0.1 0 0 0</pose>
    <axis><xyz>0.6 0 0.8</xyz><limit><lower>-2</lower><upper>2</upper></limit></axis></joint>
  <link name="b"><pose>0.2 0.4 1.0 0 0.7 0</pose>{_I.format(m=0.5)}</link>
  <joint name="j2" type="prismatic"><parent>a</parent><child>b</child>
    <axis><xyz>0 1 0</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis></joint>
</model></sdf>""",
    "universal_floating_1_11": f"""<sdf version="1.11"><model name="m">
  <link name="base"><pose>0.1 0.2 0.3 0.4 0.5 0.6</pose>{_I.format(m=3)}</link>
  <link name="arm"><pose relative_to="base">0 0 -0.4 0 0 0</pose>{_I.format(m=1)}</link>
  <joint name="u" type="universal"><parent>base</parent><child>arm</child><pose>0 0 0.2 0 0 0</pose>
    <axis><xyz>1 0 0</xyz></axis><axis2><xyz>0 1 0</xyz></axis2></joint>
</model></sdf>""",
}


@pytest.mark.parametrize("name", sorted(HAND))
def test_hand_written_sdf_agrees_with_drake(name: str) -> None:
    """Frames, nested models, relative_to chains, 1.4 model-frame axes, universal joints and a floating base:
    M(q) and gravity torques against Drake's parser (a free body converts: M_fd = Tᵀ M_drake T, T = diag(R, R))."""
    pytest.importorskip("pydrake", reason="Drake (pip install drake) is the optional SDFormat oracle")
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant

    text = HAND[name]
    model = _quiet(fd.load_sdf, text)
    plant = MultibodyPlant(0.0)
    Parser(plant).AddModelsFromString(text, "sdf")
    plant.Finalize()
    context = plant.CreateDefaultContext()
    v_index: list[int] = []
    for i, (joint, jname) in enumerate(zip(model.joints, model.joint_names, strict=True)):
        if joint.kind == "free_flyer":
            start = plant.GetBodyByName(model.body_names[i]).floating_velocities_start_in_v()
            v_index += list(range(start, start + 6))
        else:
            base, _, second = jname.partition("/axis")
            v_index.append(plant.GetJointByName(base.split("::")[-1]).velocity_start() + (second == "2"))
    assert sorted(v_index) == list(range(plant.num_velocities()))
    rng = np.random.default_rng(5)
    for _ in range(3):
        q = fd.random_configuration(model, rng)
        q_drake = np.zeros(plant.num_positions())
        T = np.eye(model.nv)
        for i, (joint, jname) in enumerate(zip(model.joints, model.joint_names, strict=True)):
            qi = q[model.idx_q[i]: model.idx_q[i] + joint.nq]
            if joint.kind == "free_flyer":
                body = plant.GetBodyByName(model.body_names[i])
                s = body.floating_positions_start()
                q_drake[s: s + 7] = [qi[6], *qi[3:6], *qi[:3]]
                R = fd.rotation.quat_to_matrix(qi[3:7])
                v0 = model.idx_v[i]
                T[v0: v0 + 3, v0: v0 + 3] = T[v0 + 3: v0 + 6, v0 + 3: v0 + 6] = R
            else:
                base, _, second = jname.partition("/axis")
                q_drake[plant.GetJointByName(base.split("::")[-1]).position_start() + (second == "2")] = qi[0]
        plant.SetPositions(context, q_drake)
        M = T.T @ plant.CalcMassMatrix(context)[np.ix_(v_index, v_index)] @ T
        g = T.T @ -plant.CalcGravityGeneralizedForces(context)[v_index]
        _close(fd.crba(model, q), M, f"{name}: M")
        _close(fd.generalized_gravity(model, q), g, f"{name}: gravity")
