"""featherdyn.conventions.drake: a MultibodyPlant's q / v / v̇ / τ / M / Jacobians, both ways.

Round trips need no Drake (the converters are NumPy); what each converter means is checked from first
principles (a hand-built layout, rotation matrices, point kinematics) and, where pydrake is installed (the
``test`` extra: CI), against a plant of the same robot.
"""

from __future__ import annotations

import logging
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

import featherdyn as fd
from featherdyn import conventions as cv
from featherdyn.errors import QuaternionNormError, ShapeError

BATCHES = [(), (4,), (2, 3)]


def quat_xyzw(rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
    x = rng.normal(size=(*shape, 4))
    return x / np.linalg.norm(x, axis=-1, keepdims=True)


def rotation_of(qxyzw: np.ndarray) -> np.ndarray:
    """Rotation matrix of (x, y, z, w), written out here (not featherdyn's)."""
    x, y, z, w = (qxyzw[..., k] for k in range(4))
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1)], -2)


def skew(p: np.ndarray) -> np.ndarray:
    return np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]], [-p[1], p[0], 0]])


#: a floating base, a hinge and a slider, placed in a plant's vectors hinge first, free joint last (nq 9, nv 8): a
#: permutation the converters must undo whatever order a Drake version picks
MODEL = SimpleNamespace(
    joints=[SimpleNamespace(kind="free_flyer"), SimpleNamespace(kind="revolute"), SimpleNamespace(kind="prismatic")],
    joint_names=("root", "j1", "j2"), idx_q=(0, 7, 8), nqs=(7, 1, 1), idx_v=(0, 6, 7), nvs=(6, 1, 1))
LAYOUT = cv.DrakeLayout(q_start=(2, 0, 1), v_start=(2, 0, 1))


def state(rng: np.random.Generator, shape: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    q = np.concatenate([rng.normal(size=(*shape, 3)), quat_xyzw(rng, shape), rng.normal(size=(*shape, 2))], -1)
    return q, rng.normal(size=(*shape, 8)), rng.normal(size=(*shape, 8))


@pytest.mark.parametrize("shape", BATCHES)
def test_round_trips(shape: tuple[int, ...]) -> None:
    rng = np.random.default_rng(1)
    q, v, a = state(rng, shape)
    M = rng.normal(size=(*shape, 8, 8))
    J = rng.normal(size=(*shape, 6, 8))
    X = fd.PluckerTransform(rotation_of(quat_xyzw(rng, shape)), rng.normal(size=(*shape, 3)))
    qd = cv.q_to_drake(MODEL, LAYOUT, q)
    close = {"rtol": 1e-12, "atol": 1e-12}
    np.testing.assert_array_equal(cv.q_from_drake(MODEL, LAYOUT, qd), q)
    vd = cv.v_to_drake(MODEL, LAYOUT, q, v)
    np.testing.assert_allclose(cv.v_from_drake(MODEL, LAYOUT, qd, vd), v, **close)
    np.testing.assert_allclose(cv.a_from_drake(MODEL, LAYOUT, qd, vd, cv.a_to_drake(MODEL, LAYOUT, q, v, a)), a,
                               **close)
    np.testing.assert_allclose(cv.tau_from_drake(MODEL, LAYOUT, qd, cv.tau_to_drake(MODEL, LAYOUT, q, a)), a, **close)
    np.testing.assert_allclose(
        cv.generalized_gravity_from_drake(MODEL, LAYOUT, qd, cv.generalized_gravity_to_drake(MODEL, LAYOUT, q, a)), a,
        **close)
    np.testing.assert_allclose(
        cv.joint_matrix_from_drake(MODEL, LAYOUT, qd, cv.joint_matrix_to_drake(MODEL, LAYOUT, q, M)), M, **close)
    for ref in (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED):
        np.testing.assert_allclose(
            cv.jacobian_from_drake(MODEL, LAYOUT, q, cv.jacobian_to_drake(MODEL, LAYOUT, q, J, X, ref), X, ref), J,
            **close)
        np.testing.assert_allclose(cv.velocity_from_drake(cv.velocity_to_drake(v[..., :6], X, ref), X, ref),
                                   v[..., :6], **close)
    q7 = q[..., :7]
    np.testing.assert_array_equal(cv.freeflyer_q_from_drake(cv.freeflyer_q_to_drake(q7)), q7)
    np.testing.assert_allclose(cv.freeflyer_v_from_drake(cv.freeflyer_q_to_drake(q7),
                                                         cv.freeflyer_v_to_drake(q7, v[..., :6])), v[..., :6], **close)


def test_what_each_converter_means() -> None:
    """The layout by hand: Drake's [j1, j2, qw qx qy qz, x y z] and [j1, j2, R ω, R v]; τ_g = −g; v̇ adds ω × v."""
    rng = np.random.default_rng(2)
    q, v, a = state(rng, ())
    R = rotation_of(q[3:7])
    qd = cv.q_to_drake(MODEL, LAYOUT, q)
    np.testing.assert_array_equal(qd, [q[7], q[8], q[6], q[3], q[4], q[5], q[0], q[1], q[2]])
    w, vb = v[:3], v[3:6]
    expect_v = np.concatenate([v[6:], R @ w, R @ vb])
    np.testing.assert_allclose(cv.v_to_drake(MODEL, LAYOUT, q, v), expect_v, atol=1e-14)
    # v̇_drake: the rate of R ω and of R v_b, with Ṙ = R [ω]×
    expect_a = np.concatenate([a[6:], R @ a[:3], R @ (a[3:6] + np.cross(w, vb))])
    np.testing.assert_allclose(cv.a_to_drake(MODEL, LAYOUT, q, v, a), expect_a, atol=1e-14)
    g = rng.normal(size=8)
    np.testing.assert_allclose(cv.generalized_gravity_to_drake(MODEL, LAYOUT, q, g),
                               -np.concatenate([g[6:], R @ g[:3], R @ g[3:6]]), atol=1e-14)
    # power is the same in both coordinates
    tau = rng.normal(size=8)
    assert np.isclose(cv.tau_to_drake(MODEL, LAYOUT, q, tau) @ expect_v, tau @ v)
    # the reference map: LOCAL = Rᵀ both halves; WORLD = the body point at the world origin
    X = fd.PluckerTransform(R, q[:3])
    V_d = rng.normal(size=6)
    np.testing.assert_allclose(cv.velocity_from_drake(V_d, X, fd.LOCAL), np.concatenate([R.T @ V_d[:3],
                                                                                          R.T @ V_d[3:]]), atol=1e-14)
    np.testing.assert_allclose(cv.velocity_from_drake(V_d, X, fd.WORLD),
                               np.concatenate([V_d[:3], V_d[3:] + np.cross(V_d[:3], -q[:3])]), atol=1e-14)
    np.testing.assert_array_equal(cv.velocity_from_drake(V_d, X, fd.LOCAL_WORLD_ALIGNED), V_d)


def test_bad_layouts_and_quaternions_are_refused() -> None:
    q, _, _ = state(np.random.default_rng(3), ())
    with pytest.raises(ShapeError, match="do not tile"):
        cv.q_to_drake(MODEL, cv.DrakeLayout(q_start=(0, 0, 1), v_start=(2, 0, 1)), q)
    with pytest.raises(ShapeError, match="one q_start and one v_start per joint"):
        cv.q_to_drake(MODEL, cv.DrakeLayout(q_start=(0,), v_start=(0,)), q)
    planar = SimpleNamespace(**{**vars(MODEL), "joints": [*MODEL.joints[:2], SimpleNamespace(kind="planar")]})
    with pytest.raises(ShapeError, match="not a planar joint"):
        cv.q_to_drake(planar, LAYOUT, q)
    bad = q.copy()
    bad[3:7] *= 2
    with pytest.raises(QuaternionNormError):
        cv.q_to_drake(MODEL, LAYOUT, bad)


# ---------------------------------------------------------------------------
# against a Drake plant (pydrake in the `test` extra: these run in CI)
# ---------------------------------------------------------------------------


@pytest.fixture(scope="module")
def solo12() -> Any:
    pytest.importorskip("pydrake")
    from pydrake.multibody.parsing import Parser
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.multibody.tree import JointIndex

    from featherdyn.robots import robot_path

    path = robot_path("solo12")
    model = fd.load_urdf(path, floating_base=True)
    plant = MultibodyPlant(0.0)
    logger = logging.getLogger("drake")
    level = logger.level
    logger.setLevel(logging.ERROR)  # solo12's URDF draws no warning that matters here
    try:
        Parser(plant).AddModels(str(path))
    finally:
        logger.setLevel(level)
    plant.Finalize()
    joints = {plant.get_joint(JointIndex(j)).name(): plant.get_joint(JointIndex(j)) for j in range(plant.num_joints())}
    found = [joints["base_link"] if name == "root_joint" else joints[name] for name in model.joint_names]
    layout = cv.DrakeLayout(tuple(j.position_start() for j in found), tuple(j.velocity_start() for j in found))
    return model, plant, layout


def test_against_a_plant(solo12: Any) -> None:
    """solo12 on a free base: Drake's base pose and velocity, M, τ_g and inverse dynamics through the converters."""
    from pydrake.multibody.tree import JacobianWrtVariable, MultibodyForces

    model, plant, layout = solo12
    ctx = plant.CreateDefaultContext()
    rng = np.random.default_rng(4)
    q = fd.random_configuration(model, rng)
    v, a = rng.normal(size=(2, model.nv))
    plant.SetPositions(ctx, cv.q_to_drake(model, layout, q))
    plant.SetVelocities(ctx, cv.v_to_drake(model, layout, q, v))
    base = plant.GetBodyByName("base_link")
    X_WB = plant.EvalBodyPoseInWorld(ctx, base)
    np.testing.assert_allclose(X_WB.GetAsMatrix4(), fd.frame_placement(model, q, "base_link").homogeneous(),
                               atol=1e-14)
    V_WB = plant.EvalBodySpatialVelocityInWorld(ctx, base).get_coeffs()
    np.testing.assert_allclose(cv.velocity_from_drake(V_WB, X_WB.GetAsMatrix4(), fd.LOCAL), v[:6], atol=1e-13)
    np.testing.assert_allclose(cv.joint_matrix_from_drake(model, layout, plant.GetPositions(ctx),
                                                          plant.CalcMassMatrix(ctx)), fd.crba(model, q), atol=1e-13)
    np.testing.assert_allclose(cv.generalized_gravity_from_drake(model, layout, plant.GetPositions(ctx),
                                                                 plant.CalcGravityGeneralizedForces(ctx)),
                               fd.generalized_gravity(model, q), atol=1e-12)
    forces = MultibodyForces(plant)
    plant.CalcForceElementsContribution(ctx, forces)  # gravity (solo12's URDF has no joint damping)
    tau = plant.CalcInverseDynamics(ctx, cv.a_to_drake(model, layout, q, v, a), forces)
    np.testing.assert_allclose(cv.tau_from_drake(model, layout, plant.GetPositions(ctx), tau),
                               fd.rnea(model, q, v, a), atol=1e-12)
    foot = plant.GetBodyByName("FL_FOOT")
    J = plant.CalcJacobianSpatialVelocity(ctx, JacobianWrtVariable.kV, foot.body_frame(), np.zeros(3),
                                          plant.world_frame(), plant.world_frame())
    X = plant.EvalBodyPoseInWorld(ctx, foot).GetAsMatrix4()
    for ref in (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED):
        np.testing.assert_allclose(cv.jacobian_from_drake(model, layout, q, J, X, ref),
                                   fd.frame_jacobian(model, q, "FL_FOOT", ref), atol=1e-13)
