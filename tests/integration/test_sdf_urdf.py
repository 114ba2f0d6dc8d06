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
