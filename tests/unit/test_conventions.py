"""Tests of featherdyn.conventions: round trips of every pair, and cross-checks against
Pinocchio objects, Modern Robotics identities, rigid-body kinematics by finite
differences, MuJoCo's free-joint layout and ROS message shapes.

Expected values are built here from first principles (own skew / Rodrigues /
point kinematics) or taken from Pinocchio, never from the code under test.
"""

from __future__ import annotations

import sys
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

import featherdyn as fd
from featherdyn import conventions as cv
from featherdyn.errors import (
    DTypeError,
    FeatherdynError,
    FrameMismatchError,
    NonFiniteError,
    QuaternionNormError,
    RotationError,
    ShapeError,
    SpatialTypeError,
)

pin = pytest.importorskip("pinocchio")

BATCHES = [(), (4,), (2, 3)]
DTYPES = [np.float64, np.float32]


def tol(dtype: Any) -> dict[str, float]:
    return {"rtol": 1e-10, "atol": 1e-10} if np.dtype(dtype) == np.float64 else {"rtol": 1e-5, "atol": 1e-4}


def fd_tol(dtype: Any) -> dict[str, float]:
    """Tolerance for comparisons with 5-point finite differences (h = 1e-2, error ~1e-9)."""
    return {"rtol": 1e-6, "atol": 1e-6} if np.dtype(dtype) == np.float64 else {"rtol": 1e-4, "atol": 1e-3}


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(20240607)


# --------------------------------------------------------------------------
# independent helpers (no featherdyn)
# --------------------------------------------------------------------------


def skew_t(w: np.ndarray) -> np.ndarray:
    out = np.zeros((*w.shape[:-1], 3, 3), dtype=w.dtype)
    out[..., 0, 1], out[..., 0, 2] = -w[..., 2], w[..., 1]
    out[..., 1, 0], out[..., 1, 2] = w[..., 2], -w[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -w[..., 1], w[..., 0]
    return out


def vee_t(s: np.ndarray) -> np.ndarray:
    return np.stack([s[..., 2, 1], s[..., 0, 2], s[..., 1, 0]], axis=-1)


def rodrigues(u: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Rotation by ``theta`` about the unit axis ``u`` (batched)."""
    K = skew_t(u)
    s, c = np.sin(theta)[..., None, None], np.cos(theta)[..., None, None]
    return np.eye(3) + s * K + (1 - c) * (K @ K)


def unit(rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
    x = rng.standard_normal((*shape, 3))
    return x / np.linalg.norm(x, axis=-1, keepdims=True)


def axis_angle(rng: np.random.Generator, shape: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray]:
    return unit(rng, shape), rng.uniform(-3.0, 3.0, size=shape)


def rand_rotation(rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
    return rodrigues(*axis_angle(rng, shape))


def quat_xyzw_of(u: np.ndarray, theta: np.ndarray) -> np.ndarray:
    return np.concatenate([np.sin(theta / 2)[..., None] * u, np.cos(theta / 2)[..., None]], axis=-1)


def mv(m: np.ndarray, x: np.ndarray) -> np.ndarray:
    return np.einsum("...ij,...j->...i", m, x)


def rand(rng: np.random.Generator, shape: tuple[int, ...], dtype: Any, *trailing: int) -> np.ndarray:
    return rng.standard_normal(shape + trailing).astype(dtype)


def d1(f: Any, h: float = 1e-2) -> np.ndarray:
    """First derivative at t = 0, 5-point central stencil (error O(h⁴))."""
    return (-f(2 * h) + 8 * f(h) - 8 * f(-h) + f(-2 * h)) / (12 * h)


def d2(f: Any, h: float = 1e-2) -> np.ndarray:
    """Second derivative at t = 0, 5-point central stencil (error O(h⁴))."""
    return (-f(2 * h) + 16 * f(h) - 30 * f(0.0) + 16 * f(-h) - f(-2 * h)) / (12 * h * h)


def rand_transform(rng: np.random.Generator, shape: tuple[int, ...], dtype: Any) -> fd.PluckerTransform:
    return fd.PluckerTransform(rand_rotation(rng, shape).astype(dtype), rand(rng, shape, dtype, 3))


# --------------------------------------------------------------------------
# the module's own contract
# --------------------------------------------------------------------------


def test_every_public_name_is_in_the_table_and_documented() -> None:
    doc = cv.__doc__ or ""
    for name in cv.__all__:
        obj = getattr(cv, name)
        assert obj.__doc__, name
        if name == "MissingDependencyError":
            continue
        assert f"``{name}``" in doc, f"{name} missing from the module table"
        assert "::" in obj.__doc__, f"{name}: no formula block"
        assert "Source" in obj.__doc__ or "source" in obj.__doc__, f"{name}: no source"
        assert "`(" in obj.__doc__, f"{name}: no shapes"


# --------------------------------------------------------------------------
# round trips
# --------------------------------------------------------------------------


RAW_ROUND_TRIPS = {
    "motion_pinocchio": ((6,), lambda x: cv.motion_from_pinocchio(cv.motion_to_pinocchio(x)).vector),
    "motion_pinocchio_rev": ((6,), lambda x: cv.motion_to_pinocchio(cv.motion_from_pinocchio(x))),
    "force_pinocchio": ((6,), lambda x: cv.force_from_pinocchio(cv.force_to_pinocchio(x)).vector),
    "force_pinocchio_rev": ((6,), lambda x: cv.force_to_pinocchio(cv.force_from_pinocchio(x))),
    "matrix6_pinocchio": ((6, 6), lambda x: cv.matrix6_from_pinocchio(cv.matrix6_to_pinocchio(x))),
    "jacobian_pinocchio": ((6, 5), lambda x: cv.jacobian_from_pinocchio(cv.jacobian_to_pinocchio(x))),
    "jacobian_pinocchio_fb": (
        (6, 9),
        lambda x: cv.jacobian_from_pinocchio(cv.jacobian_to_pinocchio(x, floating_base=True), floating_base=True),
    ),
    "freeflyer_v_pinocchio": ((6,), lambda x: cv.freeflyer_v_from_pinocchio(cv.freeflyer_v_to_pinocchio(x))),
    "twist_mr": ((6,), lambda x: cv.twist_from_mr(cv.twist_to_mr(x)).vector),
    "wrench_mr": ((6,), lambda x: cv.wrench_from_mr(cv.wrench_to_mr(x)).vector),
    "ros_twist": ((6,), lambda x: cv.motion_from_ros_twist(cv.motion_to_ros_twist(x)).vector),
    "ros_wrench": ((6,), lambda x: cv.force_from_ros_wrench(cv.force_to_ros_wrench(x)).vector),
    "ros_twist_array": ((6,), lambda x: cv.twist_array_from_ros(cv.twist_array_to_ros(x)).vector),
    "ros_wrench_array": ((6,), lambda x: cv.wrench_array_from_ros(cv.wrench_array_to_ros(x)).vector),
    "planar_v_pinocchio": ((3,), lambda x: cv.planar_v_from_pinocchio(cv.planar_v_to_pinocchio(x))),
    "planar_v_pinocchio_rev": ((3,), lambda x: cv.planar_v_to_pinocchio(cv.planar_v_from_pinocchio(x))),
    "quat_order": ((4,), lambda x: cv.quat_wxyz_to_xyzw(cv.quat_xyzw_to_wxyz(x))),
    "quat_order_rev": ((4,), lambda x: cv.quat_xyzw_to_wxyz(cv.quat_wxyz_to_xyzw(x))),
}


@pytest.mark.parametrize("pair", sorted(RAW_ROUND_TRIPS))
@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_round_trip_raw(pair: str, shape: tuple[int, ...], dtype: Any, rng: np.random.Generator) -> None:
    trailing, trip = RAW_ROUND_TRIPS[pair]
    x = rand(rng, shape, dtype, *trailing)
    y = trip(x)
    assert y.shape == x.shape
    # one ROS message holds Python floats, so only batches keep float32 through a dict
    if not (pair in ("ros_twist", "ros_wrench") and shape == ()):
        assert y.dtype == dtype
    np.testing.assert_array_equal(y, x)  # pure permutations: exact


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_round_trip_with_context(shape: tuple[int, ...], dtype: Any, rng: np.random.Generator) -> None:
    t = tol(dtype)
    m = rand(rng, shape, dtype, 6)
    f = rand(rng, shape, dtype, 6)
    X = rand_transform(rng, shape, dtype)
    p = rand(rng, shape, dtype, 3)
    R = rand_rotation(rng, shape).astype(dtype)
    v = rand(rng, shape, dtype, 6)

    out = cv.spatial_twist_to_body_twist(X, cv.body_twist_to_spatial_twist(X, m)).vector
    assert out.dtype == dtype
    np.testing.assert_allclose(out, m, **t)
    out = cv.body_twist_to_spatial_twist(X.homogeneous(), cv.spatial_twist_to_body_twist(X.homogeneous(), m)).vector
    np.testing.assert_allclose(out, m, **t)

    np.testing.assert_allclose(cv.drake_shift_velocity(cv.drake_shift_velocity(m, p), -p).vector, m, **t)
    np.testing.assert_allclose(cv.drake_shift_force(cv.drake_shift_force(f, p), -p).vector, f, **t)
    w = rand(rng, shape, dtype, 3)
    np.testing.assert_allclose(cv.drake_shift_acceleration(cv.drake_shift_acceleration(m, p, w), -p, w), m, **t)
    back = cv.drake_reexpress(np.swapaxes(R, -1, -2), cv.drake_reexpress(R, m))
    assert back.dtype == dtype
    np.testing.assert_allclose(back, m, **t)

    a = cv.classical_to_spatial_acceleration(cv.spatial_to_classical_acceleration(m, v), v).vector
    assert a.dtype == dtype
    np.testing.assert_allclose(a, m, **t)
    c = cv.spatial_to_classical_acceleration(cv.classical_to_spatial_acceleration(m, v), v)
    np.testing.assert_allclose(c, m, **t)

    u, theta = axis_angle(rng, shape)
    q = np.concatenate([rand(rng, shape, np.float64, 3), quat_xyzw_of(u, theta)], axis=-1).astype(dtype)
    q2 = cv.freeflyer_q_from_mujoco(cv.freeflyer_q_to_mujoco(q))
    assert q2.dtype == dtype
    np.testing.assert_array_equal(q2, q)
    qpos = cv.freeflyer_q_to_mujoco(q)
    np.testing.assert_array_equal(cv.freeflyer_q_to_mujoco(cv.freeflyer_q_from_mujoco(qpos)), qpos)
    v2 = cv.freeflyer_v_from_mujoco(qpos, cv.freeflyer_v_to_mujoco(q, v))
    assert v2.dtype == dtype
    np.testing.assert_allclose(v2, v, **t)
    qvel = rand(rng, shape, dtype, 6)
    np.testing.assert_allclose(cv.freeflyer_v_to_mujoco(q, cv.freeflyer_v_from_mujoco(qpos, qvel)), qvel, **t)


def test_round_trip_pinocchio_objects(rng: np.random.Generator) -> None:
    for _ in range(5):
        m = fd.SpatialMotion.from_vector(rng.standard_normal(6))
        f = fd.SpatialForce.from_vector(rng.standard_normal(6))
        X = rand_transform(rng, (), np.float64)
        inertia = fd.SpatialInertia(2.5, rng.standard_normal(3), np.diag([0.3, 0.4, 0.5]))
        np.testing.assert_array_equal(cv.from_pinocchio_motion(cv.to_pinocchio_motion(m)).vector, m.vector)
        np.testing.assert_array_equal(cv.from_pinocchio_force(cv.to_pinocchio_force(f)).vector, f.vector)
        assert cv.transform_from_pinocchio_se3(cv.transform_to_pinocchio_se3(X)).allclose(X, rtol=0, atol=1e-15)
        back = cv.from_pinocchio_inertia(cv.to_pinocchio_inertia(inertia))
        np.testing.assert_allclose(back.matrix(), inertia.matrix(), rtol=1e-14, atol=1e-14)
        # and the other way round, from Pinocchio's random objects
        pm, pf, ps, pi = pin.Motion.Random(), pin.Force.Random(), pin.SE3.Random(), pin.Inertia.Random()
        assert cv.to_pinocchio_motion(cv.from_pinocchio_motion(pm)).isApprox(pm, 1e-14)
        assert cv.to_pinocchio_force(cv.from_pinocchio_force(pf)).isApprox(pf, 1e-14)
        assert cv.transform_to_pinocchio_se3(cv.transform_from_pinocchio_se3(ps)).isApprox(ps, 1e-12)
        assert cv.to_pinocchio_inertia(cv.from_pinocchio_inertia(pi)).isApprox(pi, 1e-12)


def test_from_functions_tag_frames() -> None:
    assert cv.motion_from_pinocchio(np.zeros(6), frame="world").frame == "world"
    assert cv.force_from_pinocchio(np.zeros(6), frame="b").frame == "b"
    assert cv.from_pinocchio_motion(pin.Motion.Zero(), frame="b").frame == "b"
    X = cv.transform_from_pinocchio_se3(pin.SE3.Identity(), source="body", target="world")
    assert (X.source, X.target) == ("body", "world")
    assert cv.motion_from_ros_twist({"linear": (0, 0, 0), "angular": (0, 0, 0)}, frame="odom").frame == "odom"


# --------------------------------------------------------------------------
# Pinocchio: order and semantics, checked against Pinocchio's objects
# --------------------------------------------------------------------------


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_pinocchio_vector_order(shape: tuple[int, ...], dtype: Any, rng: np.random.Generator) -> None:
    t = tol(dtype)
    x = rand(rng, shape, dtype, 6)
    m_pin = cv.motion_to_pinocchio(fd.SpatialMotion.from_vector(x))
    f_pin = cv.force_to_pinocchio(fd.SpatialForce.from_vector(x))
    for idx in np.ndindex(*shape):
        xi = x[idx].astype(np.float64)
        # pin.Motion(vec6) reads [linear; angular]; pin.Motion(linear, angular) takes linear first
        pm = pin.Motion(np.asarray(m_pin[idx], dtype=np.float64))
        np.testing.assert_allclose(pm.angular, xi[:3], **t)
        np.testing.assert_allclose(pm.linear, xi[3:], **t)
        np.testing.assert_allclose(pin.Motion(xi[3:], xi[:3]).vector, m_pin[idx], **t)
        pf = pin.Force(np.asarray(f_pin[idx], dtype=np.float64))
        np.testing.assert_allclose(pf.angular, xi[:3], **t)
        np.testing.assert_allclose(pf.linear, xi[3:], **t)
        np.testing.assert_allclose(cv.motion_from_pinocchio(pm.vector).vector, xi, **t)
        np.testing.assert_allclose(cv.force_from_pinocchio(pf.vector).vector, xi, **t)


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_matrix6_against_pinocchio_matrices(shape: tuple[int, ...], dtype: Any, rng: np.random.Generator) -> None:
    t = tol(dtype)
    R = rand_rotation(rng, shape)
    p = rng.standard_normal((*shape, 3))
    X = fd.PluckerTransform(R.astype(dtype), p.astype(dtype))
    V = rand(rng, shape, dtype, 6)
    mass = rng.uniform(0.5, 3.0, size=shape)
    com = rng.standard_normal((*shape, 3))
    A = rng.standard_normal((*shape, 3, 3))
    Ic = A @ np.swapaxes(A, -1, -2) + np.eye(3)
    inertia = fd.SpatialInertia(mass.astype(dtype), com.astype(dtype), Ic.astype(dtype))

    act = cv.matrix6_to_pinocchio(X.matrix())
    dual = cv.matrix6_to_pinocchio(X.dual_matrix())
    action = cv.matrix6_to_pinocchio(fd.crm(V))
    dual_action = cv.matrix6_to_pinocchio(fd.crf(V))
    imat = cv.matrix6_to_pinocchio(inertia.matrix())
    for arr in (act, dual, action, imat):
        assert arr.dtype == dtype and arr.shape == (*shape, 6, 6)
    for idx in np.ndindex(*shape):
        se3 = pin.SE3(R[idx], p[idx])
        np.testing.assert_allclose(act[idx], se3.toActionMatrix(), **t)
        np.testing.assert_allclose(dual[idx], se3.toDualActionMatrix(), **t)
        np.testing.assert_allclose(cv.matrix6_from_pinocchio(se3.toActionMatrix()), X.matrix()[idx], **t)
        pm = pin.Motion(V[idx].astype(np.float64)[3:], V[idx].astype(np.float64)[:3])
        np.testing.assert_allclose(action[idx], pm.action, **t)
        np.testing.assert_allclose(dual_action[idx], pm.dualAction, **t)
        pI = pin.Inertia(float(mass[idx]), com[idx], Ic[idx])
        np.testing.assert_allclose(imat[idx], pI.matrix(), **t)
        np.testing.assert_allclose(cv.matrix6_from_pinocchio(pI.matrix()), inertia.matrix()[idx], **t)


def test_transform_se3_acts_like_plucker_transform(rng: np.random.Generator) -> None:
    for _ in range(5):
        R, p = rand_rotation(rng, ()), rng.standard_normal(3)
        X = fd.PluckerTransform(R, p)
        se3 = cv.transform_to_pinocchio_se3(X)
        np.testing.assert_allclose(se3.rotation, R, atol=1e-15)
        np.testing.assert_allclose(se3.translation, p, atol=1e-15)
        assert cv.transform_to_pinocchio_se3(X.homogeneous()).isApprox(se3, 1e-14)
        m = fd.SpatialMotion.from_vector(rng.standard_normal(6))
        f = fd.SpatialForce.from_vector(rng.standard_normal(6))
        pm, pf = cv.to_pinocchio_motion(m), cv.to_pinocchio_force(f)
        np.testing.assert_allclose(cv.from_pinocchio_motion(se3.act(pm)).vector, X.apply(m).vector, atol=1e-12)
        np.testing.assert_allclose(
            cv.from_pinocchio_motion(se3.actInv(pm)).vector, X.apply_inverse(m).vector, atol=1e-12
        )
        np.testing.assert_allclose(cv.from_pinocchio_force(se3.act(pf)).vector, X.apply(f).vector, atol=1e-12)
        np.testing.assert_allclose(
            cv.from_pinocchio_force(se3.actInv(pf)).vector, X.apply_inverse(f).vector, atol=1e-12
        )
        back = cv.transform_from_pinocchio_se3(se3)
        np.testing.assert_allclose(back.rotation, R, atol=1e-15)
        np.testing.assert_allclose(back.translation, p, atol=1e-15)


def test_inertia_object_matches_pinocchio_constructor(rng: np.random.Generator) -> None:
    for _ in range(5):
        mass, com = rng.uniform(0.1, 5.0), rng.standard_normal(3)
        A = rng.standard_normal((3, 3))
        Ic = A @ A.T + 0.1 * np.eye(3)
        expected = pin.Inertia(mass, com, Ic)
        got = cv.to_pinocchio_inertia(fd.SpatialInertia(mass, com, Ic))
        assert got.isApprox(expected, 1e-12)
        assert abs(got.mass - mass) < 1e-14
        np.testing.assert_allclose(got.lever, com, atol=1e-15)
        np.testing.assert_allclose(got.inertia, Ic, atol=1e-14)
        back = cv.from_pinocchio_inertia(expected)
        np.testing.assert_allclose(back.com, com, atol=1e-14)
        np.testing.assert_allclose(back.inertia_com, Ic, atol=1e-12)


def test_object_converters_keep_float32_values_in_float64_objects() -> None:
    m = fd.SpatialMotion.from_vector(np.arange(6, dtype=np.float32))
    pm = cv.to_pinocchio_motion(m)
    np.testing.assert_array_equal(pm.angular, [0, 1, 2])
    np.testing.assert_array_equal(pm.linear, [3, 4, 5])


def _jacobian_case(rng: np.random.Generator) -> tuple[Any, Any, np.ndarray, np.ndarray, np.ndarray]:
    model = pin.buildSampleModelManipulator()
    data = model.createData()
    q = pin.randomConfiguration(model)
    qd = rng.standard_normal(model.nv)
    jid = model.njoints - 1
    J = pin.computeJointJacobian(model, data, q, jid)  # LOCAL
    pin.forwardKinematics(model, data, q, qd)
    vel = pin.getVelocity(model, data, jid, pin.LOCAL)
    return model, data, J.copy(), qd, vel.vector.copy()


def test_jacobian_from_pinocchio_maps_qdot_to_featherdyn_velocity(rng: np.random.Generator) -> None:
    Js, qds, vels = [], [], []
    for _ in range(4):
        _, _, J, qd, vel = _jacobian_case(rng)
        Js.append(J)
        qds.append(qd)
        vels.append(vel)
    J_pin = np.stack(Js)  # (4, 6, n): batched
    J_fd = cv.jacobian_from_pinocchio(J_pin)
    assert J_fd.shape == J_pin.shape
    for k in range(4):
        expected = cv.motion_from_pinocchio(vels[k]).vector
        np.testing.assert_allclose(J_fd[k] @ qds[k], expected, atol=1e-12)
        # rows: angular first
        np.testing.assert_allclose(J_fd[k][:3] @ qds[k], pin.Motion(vels[k]).angular, atol=1e-12)
    np.testing.assert_array_equal(cv.jacobian_to_pinocchio(J_fd), J_pin)


def test_jacobian_floating_base_columns(rng: np.random.Generator) -> None:
    model = pin.Model()
    ff = model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "base")
    j2 = model.addJoint(ff, pin.JointModelRY(), pin.SE3(rand_rotation(rng, ()), rng.standard_normal(3)), "j2")
    data = model.createData()
    u, theta = axis_angle(rng, ())
    q = np.concatenate([rng.standard_normal(3), quat_xyzw_of(u, theta), [0.7]])
    v_pin = rng.standard_normal(model.nv)
    J_pin = pin.computeJointJacobian(model, data, q, j2).copy()
    pin.forwardKinematics(model, data, q, v_pin)
    vel = cv.motion_from_pinocchio(pin.getVelocity(model, data, j2, pin.LOCAL).vector).vector
    v_fd = np.concatenate([cv.freeflyer_v_from_pinocchio(v_pin[:6]), v_pin[6:]])
    J_fd = cv.jacobian_from_pinocchio(J_pin, floating_base=True)
    np.testing.assert_allclose(J_fd @ v_fd, vel, atol=1e-12)
    # without the column swap the free-flyer block is read in the wrong order
    assert not np.allclose(cv.jacobian_from_pinocchio(J_pin) @ v_fd, vel, atol=1e-6)
    np.testing.assert_array_equal(cv.jacobian_to_pinocchio(J_fd, floating_base=True), J_pin)


def _freeflyer_model() -> tuple[Any, Any]:
    model = pin.Model()
    model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "base")
    return model, model.createData()


def test_freeflyer_v_pinocchio_semantics(rng: np.random.Generator) -> None:
    """featherdyn's free-flyer v = [ω; v] in base coordinates, checked by integrating in Pinocchio."""
    model, data = _freeflyer_model()
    for _ in range(3):
        u, theta = axis_angle(rng, ())
        R = rodrigues(u, theta)
        q = np.concatenate([rng.standard_normal(3), quat_xyzw_of(u, theta)])
        v = rng.standard_normal(6)  # featherdyn [ω_b; v_b]
        v_pin = cv.freeflyer_v_to_pinocchio(v)

        def pose(t: float, q: np.ndarray = q, v_pin: np.ndarray = v_pin) -> np.ndarray:
            qt = pin.integrate(model, q, v_pin * t)
            return np.concatenate([qt[:3], pin.Quaternion(qt[6], qt[3], qt[4], qt[5]).matrix().ravel()])

        rate = d1(pose)
        np.testing.assert_allclose(rate[:3], R @ v[3:], atol=1e-7)  # origin velocity, world axes
        Rdot = rate[3:].reshape(3, 3)
        np.testing.assert_allclose(vee_t(R.T @ Rdot), v[:3], atol=1e-7)  # body angular velocity
        pin.forwardKinematics(model, data, q, v_pin)
        np.testing.assert_allclose(cv.from_pinocchio_motion(data.v[1]).vector, v, atol=1e-12)


def test_classical_acceleration_matches_pinocchio(rng: np.random.Generator) -> None:
    model = pin.buildSampleModelManipulator()
    data = model.createData()
    fid = model.nframes - 1
    for _ in range(3):
        q = pin.randomConfiguration(model)
        qd, qdd = rng.standard_normal(model.nv), rng.standard_normal(model.nv)
        pin.forwardKinematics(model, data, q, qd, qdd)
        pin.updateFramePlacements(model, data)
        for ref in (pin.LOCAL, pin.LOCAL_WORLD_ALIGNED):
            v = cv.motion_from_pinocchio(pin.getFrameVelocity(model, data, fid, ref).vector)
            a = cv.motion_from_pinocchio(pin.getFrameAcceleration(model, data, fid, ref).vector)
            expected = cv.motion_from_pinocchio(pin.getFrameClassicalAcceleration(model, data, fid, ref).vector).vector
            np.testing.assert_allclose(cv.spatial_to_classical_acceleration(a, v), expected, atol=1e-10)
            np.testing.assert_allclose(cv.classical_to_spatial_acceleration(expected, v).vector, a.vector, atol=1e-10)


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_continuous_and_planar_q_round_trip(shape: tuple[int, ...], dtype: Any, rng: np.random.Generator) -> None:
    t = tol(dtype)
    theta = rng.uniform(-3.1, 3.1, size=shape).astype(dtype)
    cs = cv.continuous_q_to_pinocchio(theta)
    assert cs.shape == (*shape, 2) and cs.dtype == dtype
    back = cv.continuous_q_from_pinocchio(cs)
    assert back.shape == shape and back.dtype == dtype
    np.testing.assert_allclose(back, theta, **t)
    # an angle outside (−π, π] comes back wrapped
    np.testing.assert_allclose(
        cv.continuous_q_from_pinocchio(cv.continuous_q_to_pinocchio(theta + 2 * np.pi)), theta, rtol=1e-5, atol=1e-5
    )
    q = np.concatenate([rand(rng, shape, dtype, 2), theta[..., None]], axis=-1)
    q_pin = cv.planar_q_to_pinocchio(q)
    assert q_pin.shape == (*shape, 4) and q_pin.dtype == dtype
    np.testing.assert_allclose(q_pin[..., 2:], np.stack([np.cos(theta), np.sin(theta)], axis=-1), **t)
    q2 = cv.planar_q_from_pinocchio(q_pin)
    assert q2.dtype == dtype
    np.testing.assert_allclose(q2, q, **t)


def test_continuous_and_planar_layouts_match_pinocchio_joints(rng: np.random.Generator) -> None:
    continuous = pin.Model()
    continuous.addJoint(0, pin.JointModelRUBZ(), pin.SE3.Identity(), "c")
    planar = pin.Model()
    planar.addJoint(0, pin.JointModelPlanar(), pin.SE3.Identity(), "p")
    data = planar.createData()
    for _ in range(5):
        theta = rng.uniform(-3.1, 3.1)
        # Pinocchio's own (cos, sin) of a rotation by θ from the neutral configuration
        q_c = pin.integrate(continuous, pin.neutral(continuous), np.array([theta]))
        np.testing.assert_allclose(cv.continuous_q_to_pinocchio(theta), q_c, atol=1e-12)
        np.testing.assert_allclose(cv.continuous_q_from_pinocchio(q_c), theta, atol=1e-12)
        q = np.array([rng.standard_normal(), rng.standard_normal(), theta])  # featherdyn [x, y, θ]
        v = rng.standard_normal(3)  # featherdyn [ω, v_x, v_y], moving frame
        pin.forwardKinematics(planar, data, cv.planar_q_to_pinocchio(q), cv.planar_v_to_pinocchio(v))
        placement = data.oMi[1]
        np.testing.assert_allclose(placement.translation, [q[0], q[1], 0.0], atol=1e-12)
        np.testing.assert_allclose(
            placement.rotation, rodrigues(np.array([0.0, 0.0, 1.0]), np.array(theta)), atol=1e-12
        )
        np.testing.assert_allclose(data.v[1].angular, [0.0, 0.0, v[0]], atol=1e-12)
        np.testing.assert_allclose(data.v[1].linear, [v[1], v[2], 0.0], atol=1e-12)
        np.testing.assert_allclose(cv.planar_v_from_pinocchio(pin.Motion(data.v[1]).vector[[0, 1, 5]]), v, atol=1e-12)


def test_missing_pinocchio_raises_clear_error(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "pinocchio", None)  # makes `import pinocchio` raise ImportError
    calls = [
        lambda: cv.to_pinocchio_motion(np.zeros(6)),
        lambda: cv.from_pinocchio_motion(object()),
        lambda: cv.to_pinocchio_force(np.zeros(6)),
        lambda: cv.from_pinocchio_force(object()),
        lambda: cv.to_pinocchio_inertia(fd.SpatialInertia(1.0, np.zeros(3), np.eye(3))),
        lambda: cv.from_pinocchio_inertia(object()),
        lambda: cv.transform_to_pinocchio_se3(fd.PluckerTransform.identity()),
        lambda: cv.transform_from_pinocchio_se3(object()),
    ]
    for call in calls:
        with pytest.raises(cv.MissingDependencyError, match="pip install pin") as info:
            call()
        assert isinstance(info.value, ImportError) and isinstance(info.value, FeatherdynError)
    # the raw-array converters need no Pinocchio
    np.testing.assert_array_equal(cv.motion_to_pinocchio(np.arange(6.0)), [3, 4, 5, 0, 1, 2])


# --------------------------------------------------------------------------
# Lynch–Park / Modern Robotics, checked with the book's own formulas
# --------------------------------------------------------------------------


def se3_hat(V: np.ndarray) -> np.ndarray:
    """MR's 4×4 [V] = [[ [ω], v ], [0, 0]]."""
    out = np.zeros((*V.shape[:-1], 4, 4))
    out[..., :3, :3] = skew_t(V[..., :3])
    out[..., :3, 3] = V[..., 3:]
    return out


def se3_vee(M: np.ndarray) -> np.ndarray:
    return np.concatenate([vee_t(M[..., :3, :3]), M[..., :3, 3]], axis=-1)


def homogeneous(R: np.ndarray, p: np.ndarray) -> np.ndarray:
    T = np.zeros((*R.shape[:-2], 4, 4))
    T[..., :3, :3], T[..., :3, 3], T[..., 3, 3] = R, p, 1.0
    return T


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_adjoint_matrix_is_the_books_formula(shape: tuple[int, ...], dtype: Any, rng: np.random.Generator) -> None:
    R, p = rand_rotation(rng, shape), rng.standard_normal((*shape, 3))
    book = np.zeros((*shape, 6, 6))
    book[..., :3, :3] = R
    book[..., 3:, 3:] = R
    book[..., 3:, :3] = skew_t(p) @ R
    T = homogeneous(R, p).astype(dtype)
    got = cv.adjoint_matrix(T)
    assert got.dtype == dtype
    np.testing.assert_allclose(got, book, **tol(dtype))
    np.testing.assert_allclose(cv.adjoint_matrix(fd.PluckerTransform(R, p)), book, atol=1e-12)
    # MR: [Ad_T] V_b = V_s with [V_s] = T [V_b] T⁻¹
    Vb = rng.standard_normal((*shape, 6))
    Vs = se3_vee(homogeneous(R, p) @ se3_hat(Vb) @ np.linalg.inv(homogeneous(R, p)))
    np.testing.assert_allclose(mv(cv.adjoint_matrix(homogeneous(R, p)), Vb), Vs, atol=1e-12)


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_ad_matrix_is_the_lie_bracket(shape: tuple[int, ...], dtype: Any, rng: np.random.Generator) -> None:
    V1, V2 = rng.standard_normal((*shape, 6)), rng.standard_normal((*shape, 6))
    A, B = se3_hat(V1), se3_hat(V2)
    bracket = se3_vee(A @ B - B @ A)
    ad = cv.ad_matrix(V1.astype(dtype))
    assert ad.dtype == dtype and ad.shape == (*shape, 6, 6)
    np.testing.assert_allclose(mv(ad, V2.astype(dtype)), bracket, **tol(dtype))
    np.testing.assert_allclose(mv(cv.ad_matrix(fd.SpatialMotion.from_vector(V1)), V2), bracket, atol=1e-12)


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_wrench_transform_preserves_power(shape: tuple[int, ...], dtype: Any, rng: np.random.Generator) -> None:
    R, p = rand_rotation(rng, shape), rng.standard_normal((*shape, 3))
    T = homogeneous(R, p)
    V, F = rng.standard_normal((*shape, 6)), rng.standard_normal((*shape, 6))
    W = cv.wrench_transform_matrix(T.astype(dtype))
    assert W.dtype == dtype
    Ad = np.zeros((*shape, 6, 6))
    Ad[..., :3, :3], Ad[..., 3:, 3:], Ad[..., 3:, :3] = R, R, skew_t(p) @ R
    np.testing.assert_allclose(W, np.swapaxes(np.linalg.inv(Ad), -1, -2), **tol(dtype))
    power_b = np.sum(V * F, axis=-1)
    power_a = np.sum(mv(Ad, V) * mv(W.astype(np.float64), F), axis=-1)
    np.testing.assert_allclose(power_a, power_b, **tol(dtype))
    # MR eq. 3.98 read backwards: F_b = [Ad_T]ᵀ F_a
    np.testing.assert_allclose(mv(np.swapaxes(Ad, -1, -2), mv(W.astype(np.float64), F)), F, **tol(dtype))


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_body_and_spatial_twists(shape: tuple[int, ...], dtype: Any, rng: np.random.Generator) -> None:
    R, p = rand_rotation(rng, shape), rng.standard_normal((*shape, 3))
    T = homogeneous(R, p)
    Vb = rng.standard_normal((*shape, 6))
    Tdot = T @ se3_hat(Vb)  # definition of the body twist: [V_b] = T⁻¹ Ṫ
    Vs = se3_vee(Tdot @ np.linalg.inv(T))  # definition of the spatial twist: [V_s] = Ṫ T⁻¹
    X = fd.PluckerTransform(R.astype(dtype), p.astype(dtype))
    got = cv.body_twist_to_spatial_twist(X, Vb.astype(dtype))
    assert isinstance(got, fd.SpatialMotion) and got.dtype == dtype
    np.testing.assert_allclose(got.vector, Vs, **tol(dtype))
    np.testing.assert_allclose(cv.spatial_twist_to_body_twist(T, Vs).vector, Vb, atol=1e-12)


def test_twist_and_wrench_mr_are_angular_first() -> None:
    # rotation about the z axis through the point q = (1, 0, 0): MR's V_s = [ω; −ω × q]
    w, q = np.array([0.0, 0.0, 2.0]), np.array([1.0, 0.0, 0.0])
    V_s = np.concatenate([w, -np.cross(w, q)])
    m = cv.twist_from_mr(V_s)
    np.testing.assert_array_equal(m.angular, w)
    np.testing.assert_array_equal(m.linear, [0.0, -2.0, 0.0])  # the body point at the origin moves along −y
    np.testing.assert_array_equal(cv.twist_to_mr(m), V_s)
    F = np.array([1.0, 2.0, 3.0, 4.0, 5.0, 6.0])  # [m; f]
    np.testing.assert_array_equal(cv.wrench_from_mr(F).angular, [1, 2, 3])
    np.testing.assert_array_equal(cv.wrench_to_mr(fd.SpatialForce([1, 2, 3], [4, 5, 6])), F)
    assert not np.shares_memory(cv.twist_to_mr(m), m.vector)


# --------------------------------------------------------------------------
# Drake and classical acceleration: rigid-body kinematics by finite differences
# --------------------------------------------------------------------------


class RigidMotion:
    """A body spinning with constant angular acceleration about an offset fixed axis while translating.

    World position of the body point with body coordinates ``b``::

        x_b(t) = c + Rot(u, θ(t)) (R0 b + x0 − c) + d(t),   θ = w0 t + ½ α t²,   d = vt t + ½ at t²
    """

    def __init__(self, rng: np.random.Generator, shape: tuple[int, ...]) -> None:
        self.u = unit(rng, shape)
        self.c = rng.standard_normal((*shape, 3))
        self.R0 = rand_rotation(rng, shape)
        self.x0 = rng.standard_normal((*shape, 3))
        self.w0 = rng.uniform(0.5, 2.0, size=shape)
        self.alpha = rng.uniform(-1.0, 1.0, size=shape)
        self.vt = rng.standard_normal((*shape, 3))
        self.at = rng.standard_normal((*shape, 3))

    def theta(self, t: float) -> np.ndarray:
        return self.w0 * t + 0.5 * self.alpha * t * t

    def rot(self, t: float) -> np.ndarray:
        return rodrigues(self.u, self.theta(t)) @ self.R0

    def point(self, b: np.ndarray, t: float) -> np.ndarray:
        Q = rodrigues(self.u, self.theta(t))
        return self.c + mv(Q, mv(self.R0, b) + self.x0 - self.c) + self.vt * t + 0.5 * self.at * t * t

    def omega(self, t: float) -> np.ndarray:
        return (self.w0 + self.alpha * t)[..., None] * self.u

    def origin_velocity(self, t: float) -> np.ndarray:
        """Hand-differentiated velocity of the body origin (b = 0)."""
        Q = rodrigues(self.u, self.theta(t))
        return np.cross(self.omega(t), mv(Q, self.x0 - self.c)) + self.vt + self.at * t


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_drake_shift_velocity_is_point_velocity(shape: tuple[int, ...], dtype: Any, rng: np.random.Generator) -> None:
    body = RigidMotion(rng, shape)
    b = rng.standard_normal((*shape, 3))  # body coordinates of Bq
    zero = np.zeros((*shape, 3))
    v_Bo = d1(lambda t: body.point(zero, t))
    v_Bq = d1(lambda t: body.point(b, t))
    p_BoBq_W = body.point(b, 0.0) - body.point(zero, 0.0)
    V_WBo_W = np.concatenate([body.omega(0.0), v_Bo], axis=-1)
    got = cv.drake_shift_velocity(V_WBo_W.astype(dtype), p_BoBq_W.astype(dtype))
    assert isinstance(got, fd.SpatialMotion) and got.dtype == dtype
    np.testing.assert_allclose(got.linear, v_Bq, **fd_tol(dtype))
    np.testing.assert_allclose(got.angular, body.omega(0.0), **tol(dtype))


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_drake_shift_force_is_moment_about_new_point(
    shape: tuple[int, ...], dtype: Any, rng: np.random.Generator
) -> None:
    x_A = rng.standard_normal((*shape, 3))  # where a pure force f acts
    x_Bo = rng.standard_normal((*shape, 3))
    x_Bq = rng.standard_normal((*shape, 3))
    f = rng.standard_normal((*shape, 3))
    F_Bo = np.concatenate([np.cross(x_A - x_Bo, f), f], axis=-1)
    got = cv.drake_shift_force(fd.SpatialForce.from_vector(F_Bo.astype(dtype), frame="W"), (x_Bq - x_Bo).astype(dtype))
    assert isinstance(got, fd.SpatialForce) and got.frame == "W" and got.dtype == dtype
    np.testing.assert_allclose(got.angular, np.cross(x_A - x_Bq, f), **tol(dtype))
    np.testing.assert_allclose(got.linear, f, **tol(dtype))


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_drake_shift_acceleration_is_point_acceleration(
    shape: tuple[int, ...], dtype: Any, rng: np.random.Generator
) -> None:
    body = RigidMotion(rng, shape)
    b = rng.standard_normal((*shape, 3))
    zero = np.zeros((*shape, 3))
    a_Bo = d2(lambda t: body.point(zero, t))
    a_Bq = d2(lambda t: body.point(b, t))
    alpha = d1(body.omega)
    A_WBo_W = np.concatenate([alpha, a_Bo], axis=-1)
    p = body.point(b, 0.0) - body.point(zero, 0.0)
    got = cv.drake_shift_acceleration(A_WBo_W.astype(dtype), p.astype(dtype), body.omega(0.0).astype(dtype))
    assert got.dtype == dtype
    np.testing.assert_allclose(got[..., 3:], a_Bq, **fd_tol(dtype))
    np.testing.assert_allclose(got[..., :3], alpha, **fd_tol(dtype))


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_classical_acceleration_by_finite_differences_world(
    shape: tuple[int, ...], dtype: Any, rng: np.random.Generator
) -> None:
    """World coordinates, reference point the world origin O."""
    body = RigidMotion(rng, shape)
    zero = np.zeros((*shape, 3))

    def v_O(t: float) -> np.ndarray:  # velocity of the body point at O at time t
        x_Bo = body.point(zero, t)
        return body.origin_velocity(t) - np.cross(body.omega(t), x_Bo)

    v = np.concatenate([body.omega(0.0), v_O(0.0)], axis=-1)
    a_spatial = np.concatenate([d1(body.omega), d1(v_O)], axis=-1)
    # the body point that is at O at t = 0, followed in time
    b_star = mv(np.swapaxes(body.R0, -1, -2), -body.point(zero, 0.0))
    np.testing.assert_allclose(body.point(b_star, 0.0), zero, atol=1e-12)
    a_classical = d2(lambda t: body.point(b_star, t))

    got = cv.spatial_to_classical_acceleration(a_spatial.astype(dtype), v.astype(dtype))
    assert isinstance(got, np.ndarray) and got.dtype == dtype
    np.testing.assert_allclose(got[..., 3:], a_classical, **fd_tol(dtype))
    np.testing.assert_allclose(got[..., :3], a_spatial[..., :3], **tol(dtype))
    assert np.all(np.linalg.norm(a_classical - a_spatial[..., 3:], axis=-1) > 1e-3)  # the two really differ
    back = cv.classical_to_spatial_acceleration(
        np.concatenate([a_spatial[..., :3], a_classical], -1).astype(dtype), v.astype(dtype)
    )
    np.testing.assert_allclose(back.vector, a_spatial, **fd_tol(dtype))


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_classical_acceleration_by_finite_differences_body(
    shape: tuple[int, ...], dtype: Any, rng: np.random.Generator
) -> None:
    """Body coordinates: the spatial acceleration is the derivative of the body-coordinate velocity."""
    body = RigidMotion(rng, shape)
    zero = np.zeros((*shape, 3))

    def v_body(t: float) -> np.ndarray:
        Rt = np.swapaxes(body.rot(t), -1, -2)
        return np.concatenate([mv(Rt, body.omega(t)), mv(Rt, body.origin_velocity(t))], axis=-1)

    a_body = d1(v_body)
    expected = mv(np.swapaxes(body.R0, -1, -2), d2(lambda t: body.point(zero, t)))  # origin's acceleration, body axes
    got = cv.spatial_to_classical_acceleration(
        fd.SpatialMotion.from_vector(a_body.astype(dtype), frame="B"),
        fd.SpatialMotion.from_vector(v_body(0.0).astype(dtype), frame="B"),
    )
    np.testing.assert_allclose(got[..., 3:], expected, **fd_tol(dtype))


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_drake_reexpress(shape: tuple[int, ...], dtype: Any, rng: np.random.Generator) -> None:
    R = rand_rotation(rng, shape)
    x = rng.standard_normal((*shape, 6))
    expected = np.concatenate([mv(R, x[..., :3]), mv(R, x[..., 3:])], axis=-1)
    raw = cv.drake_reexpress(R.astype(dtype), x.astype(dtype))
    assert isinstance(raw, np.ndarray) and raw.dtype == dtype
    np.testing.assert_allclose(raw, expected, **tol(dtype))
    m = cv.drake_reexpress(R, fd.SpatialMotion.from_vector(x, frame="E"), frame="A")
    assert isinstance(m, fd.SpatialMotion) and m.frame == "A"
    np.testing.assert_allclose(m.vector, expected, atol=1e-12)
    f = cv.drake_reexpress(R, fd.SpatialForce.from_vector(x))
    assert isinstance(f, fd.SpatialForce)
    np.testing.assert_allclose(f.vector, expected, atol=1e-12)
    # a pure rotation is also what pin.SE3(R, 0).act does
    for idx in np.ndindex(*shape):
        pm = pin.SE3(R[idx], np.zeros(3)).act(cv.to_pinocchio_motion(x[idx]))
        np.testing.assert_allclose(
            cv.motion_to_pinocchio(m[idx]) if shape else cv.motion_to_pinocchio(m), pm.vector, atol=1e-12
        )


# --------------------------------------------------------------------------
# MuJoCo free joint
# --------------------------------------------------------------------------


@pytest.mark.parametrize("shape", BATCHES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_mujoco_free_joint(shape: tuple[int, ...], dtype: Any, rng: np.random.Generator) -> None:
    u, theta = axis_angle(rng, shape)
    R = rodrigues(u, theta)
    pos = rng.standard_normal((*shape, 3))
    q = np.concatenate([pos, np.sin(theta / 2)[..., None] * u, np.cos(theta / 2)[..., None]], axis=-1)
    qpos_expected = np.concatenate([pos, np.cos(theta / 2)[..., None], np.sin(theta / 2)[..., None] * u], axis=-1)
    qpos = cv.freeflyer_q_to_mujoco(q.astype(dtype))
    assert qpos.dtype == dtype
    np.testing.assert_allclose(qpos, qpos_expected, **tol(dtype))
    np.testing.assert_allclose(cv.freeflyer_q_from_mujoco(qpos_expected), q, atol=1e-15)

    v = rng.standard_normal((*shape, 6))  # featherdyn [ω_b; v_b]
    qvel = cv.freeflyer_v_to_mujoco(q.astype(dtype), v.astype(dtype))
    assert qvel.dtype == dtype
    np.testing.assert_allclose(qvel[..., :3], mv(R, v[..., 3:]), **tol(dtype))  # world linear velocity
    np.testing.assert_allclose(qvel[..., 3:], v[..., :3], **tol(dtype))  # body angular velocity
    np.testing.assert_allclose(cv.freeflyer_v_from_mujoco(qpos_expected, qvel.astype(np.float64)), v, **tol(dtype))


def test_mujoco_qvel_linear_is_world_velocity_of_origin(rng: np.random.Generator) -> None:
    """Cross-check with Pinocchio: moving the free flyer with v, the world position changes at qvel[:3]."""
    model, _ = _freeflyer_model()
    for _ in range(3):
        u, theta = axis_angle(rng, ())
        q = np.concatenate([rng.standard_normal(3), quat_xyzw_of(u, theta)])
        v = rng.standard_normal(6)
        v_pin = cv.freeflyer_v_to_pinocchio(v)
        rate = d1(lambda t, q=q, v_pin=v_pin: pin.integrate(model, q, v_pin * t)[:3])
        qvel = cv.freeflyer_v_to_mujoco(q, v)
        np.testing.assert_allclose(qvel[:3], rate, atol=1e-7)


def test_quaternion_order_helpers() -> None:
    np.testing.assert_array_equal(cv.quat_xyzw_to_wxyz([1.0, 2.0, 3.0, 4.0]), [4, 1, 2, 3])
    np.testing.assert_array_equal(cv.quat_wxyz_to_xyzw([4.0, 1.0, 2.0, 3.0]), [1, 2, 3, 4])
    # Pinocchio's Quaternion(w, x, y, z) constructor against the (x, y, z, w) coeffs
    pq = pin.Quaternion(0.5, 0.5, -0.5, 0.5)
    np.testing.assert_array_equal(cv.quat_xyzw_to_wxyz(pq.coeffs()), [0.5, 0.5, -0.5, 0.5])


# --------------------------------------------------------------------------
# ROS
# --------------------------------------------------------------------------


def test_ros_twist_and_wrench_fields() -> None:
    m = fd.SpatialMotion([1.0, 2.0, 3.0], [4.0, 5.0, 6.0])
    assert cv.motion_to_ros_twist(m) == {"linear": (4.0, 5.0, 6.0), "angular": (1.0, 2.0, 3.0)}
    f = fd.SpatialForce([1.0, 2.0, 3.0], [4.0, 5.0, 6.0])
    assert cv.force_to_ros_wrench(f) == {"force": (4.0, 5.0, 6.0), "torque": (1.0, 2.0, 3.0)}
    np.testing.assert_array_equal(cv.twist_array_to_ros(m), [4, 5, 6, 1, 2, 3])
    np.testing.assert_array_equal(cv.wrench_array_to_ros(f), [4, 5, 6, 1, 2, 3])
    np.testing.assert_array_equal(cv.twist_array_from_ros([4, 5, 6, 1, 2, 3]).angular, [1, 2, 3])
    np.testing.assert_array_equal(cv.wrench_array_from_ros([4, 5, 6, 1, 2, 3]).angular, [1, 2, 3])


def test_ros_input_forms() -> None:
    expected = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
    forms = [
        {"linear": [4, 5, 6], "angular": (1, 2, 3)},
        {"linear": {"x": 4, "y": 5, "z": 6}, "angular": {"x": 1.0, "y": 2.0, "z": 3.0}},
        SimpleNamespace(linear=SimpleNamespace(x=4.0, y=5.0, z=6.0), angular=SimpleNamespace(x=1.0, y=2.0, z=3.0)),
        {"linear": np.array([4.0, 5.0, 6.0]), "angular": np.array([1.0, 2.0, 3.0]), "extra": "ignored"},
    ]
    for twist in forms:
        np.testing.assert_array_equal(cv.motion_from_ros_twist(twist).vector, expected)
    wrench = SimpleNamespace(force=SimpleNamespace(x=4.0, y=5.0, z=6.0), torque={"x": 1, "y": 2, "z": 3})
    np.testing.assert_array_equal(cv.force_from_ros_wrench(wrench).vector, expected)


@pytest.mark.parametrize("shape", [(4,), (2, 3)])
@pytest.mark.parametrize("dtype", DTYPES)
def test_ros_dicts_batched(shape: tuple[int, ...], dtype: Any, rng: np.random.Generator) -> None:
    x = rand(rng, shape, dtype, 6)
    d = cv.motion_to_ros_twist(x)
    assert d["linear"].shape == (*shape, 3) and d["linear"].dtype == dtype
    np.testing.assert_array_equal(d["angular"], x[..., :3])
    d2_ = cv.motion_to_ros_twist(cv.motion_from_ros_twist(d))
    np.testing.assert_array_equal(d2_["linear"], d["linear"])
    w = cv.force_to_ros_wrench(x)
    np.testing.assert_array_equal(w["torque"], x[..., :3])
    np.testing.assert_array_equal(cv.force_from_ros_wrench(w).vector, x)


@pytest.mark.parametrize(
    ("call", "missing"),
    [
        (lambda: cv.motion_from_ros_twist({"linear": [0, 0, 0]}), "'angular'"),
        (lambda: cv.motion_from_ros_twist({"angular": [0, 0, 0]}), "'linear'"),
        (lambda: cv.motion_from_ros_twist({"linear": {"x": 1, "y": 2}, "angular": [0, 0, 0]}), "'z'"),
        (lambda: cv.force_from_ros_wrench({"force": [0, 0, 0]}), "'torque'"),
        (lambda: cv.force_from_ros_wrench({"linear": [0, 0, 0], "angular": [0, 0, 0]}), "'force'"),
        (lambda: cv.motion_from_ros_twist(SimpleNamespace(linear=[0, 0, 0])), "'angular'"),
    ],
)
def test_ros_missing_keys(call: Any, missing: str) -> None:
    with pytest.raises(ShapeError, match=missing) as info:
        call()
    assert isinstance(info.value, FeatherdynError)


def test_ros_bad_inputs() -> None:
    with pytest.raises(ShapeError, match="twist_array_from_ros"):
        cv.motion_from_ros_twist([1, 2, 3, 4, 5, 6])
    with pytest.raises(ShapeError, match=r"twist\['linear'\]"):
        cv.motion_from_ros_twist({"linear": [1, 2], "angular": [0, 0, 0]})
    with pytest.raises(NonFiniteError, match="angular"):
        cv.motion_from_ros_twist({"linear": [1, 2, 3], "angular": [0, np.nan, 0]})
    with pytest.raises(DTypeError):
        cv.motion_from_ros_twist({"linear": ["a", "b", "c"], "angular": [0, 0, 0]})
    with pytest.raises(SpatialTypeError):
        cv.motion_from_ros_twist(fd.SpatialForce.zero())
    with pytest.raises(SpatialTypeError):
        cv.force_to_ros_wrench(fd.SpatialMotion.zero())


# --------------------------------------------------------------------------
# bad inputs
# --------------------------------------------------------------------------

_GOOD_Q = np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])
_NAN6 = np.array([0.0, np.nan, 0.0, 0.0, 0.0, 0.0])
_REFLECT = np.diag([1.0, 1.0, -1.0])

BAD_INPUTS = [
    (lambda: cv.motion_to_pinocchio(np.zeros(5)), ShapeError, "m:"),
    (lambda: cv.motion_from_pinocchio(_NAN6), NonFiniteError, "v6:"),
    (lambda: cv.force_to_pinocchio(["a"] * 6), DTypeError, "f:"),
    (lambda: cv.force_from_pinocchio(np.zeros((2, 5))), ShapeError, "f6:"),
    (lambda: cv.matrix6_to_pinocchio(np.zeros((6, 5))), ShapeError, "M:"),
    (lambda: cv.matrix6_from_pinocchio(np.full((6, 6), np.inf)), NonFiniteError, "M:"),
    (lambda: cv.jacobian_to_pinocchio(np.zeros((5, 3))), ShapeError, "J:"),
    (lambda: cv.jacobian_from_pinocchio(np.zeros(6)), ShapeError, "J:"),
    (lambda: cv.jacobian_to_pinocchio(np.zeros((6, 3)), floating_base=True), ShapeError, "J:"),
    (lambda: cv.freeflyer_v_to_pinocchio(np.zeros(7)), ShapeError, "v:"),
    (lambda: cv.freeflyer_v_from_pinocchio(_NAN6), NonFiniteError, "v:"),
    (lambda: cv.freeflyer_q_to_mujoco(np.zeros(7)), QuaternionNormError, "q[..., 3:7]"),
    (lambda: cv.freeflyer_q_to_mujoco(np.zeros(6)), ShapeError, "q:"),
    (lambda: cv.freeflyer_q_from_mujoco([0, 0, 0, 2, 0, 0, 0]), QuaternionNormError, "qpos"),
    (lambda: cv.freeflyer_v_to_mujoco(_GOOD_Q, np.zeros(5)), ShapeError, "v:"),
    (lambda: cv.freeflyer_v_to_mujoco([0, 0, 0, 0, 0, 0, 2], np.zeros(6)), QuaternionNormError, "q[..., 3:7]"),
    (lambda: cv.freeflyer_v_from_mujoco([0, 0, 0, 1, 0, 0, 0], _NAN6), NonFiniteError, "qvel:"),
    (lambda: cv.quat_xyzw_to_wxyz(np.zeros(3)), ShapeError, "quat:"),
    (lambda: cv.continuous_q_to_pinocchio([np.inf]), NonFiniteError, "theta:"),
    (lambda: cv.continuous_q_from_pinocchio(np.zeros(3)), ShapeError, "q:"),
    (lambda: cv.planar_q_to_pinocchio(np.zeros(4)), ShapeError, "q:"),
    (lambda: cv.planar_q_from_pinocchio(np.zeros(3)), ShapeError, "q:"),
    (lambda: cv.planar_v_to_pinocchio(np.zeros(6)), ShapeError, "v:"),
    (lambda: cv.planar_v_from_pinocchio([np.nan, 0, 0]), NonFiniteError, "v:"),
    (lambda: cv.adjoint_matrix(np.eye(3)), ShapeError, "T:"),
    (lambda: cv.adjoint_matrix(np.ones((4, 4))), ShapeError, "last row"),
    (lambda: cv.adjoint_matrix(homogeneous(_REFLECT, np.zeros(3))), RotationError, "T[..., :3, :3]"),
    (lambda: cv.ad_matrix(np.zeros(3)), ShapeError, "V:"),
    (lambda: cv.ad_matrix(fd.SpatialForce.zero()), SpatialTypeError, "V:"),
    (lambda: cv.wrench_transform_matrix(fd.SpatialMotion.zero()), SpatialTypeError, "T:"),
    (lambda: cv.body_twist_to_spatial_twist(np.eye(4), np.zeros(4)), ShapeError, "V_b:"),
    (lambda: cv.drake_reexpress(_REFLECT, np.zeros(6)), RotationError, "R_AE"),
    (lambda: cv.drake_reexpress(np.eye(3), np.zeros(5)), ShapeError, "V_E:"),
    (lambda: cv.drake_shift_velocity(np.zeros(6), np.zeros(2)), ShapeError, "p_BoBq_E:"),
    (lambda: cv.drake_shift_force(fd.SpatialMotion.zero(), np.zeros(3)), SpatialTypeError, "F_Bo_E:"),
    (
        lambda: cv.drake_shift_acceleration(fd.SpatialMotion.zero(), np.zeros(3), np.zeros(3)),
        SpatialTypeError,
        "A_WBo_E",
    ),
    (lambda: cv.drake_shift_acceleration(np.zeros(6), np.zeros(3), [np.nan, 0, 0]), NonFiniteError, "w_WB_E:"),
    (
        lambda: cv.classical_to_spatial_acceleration(fd.SpatialMotion.zero(), np.zeros(6)),
        SpatialTypeError,
        "a_classical",
    ),
    (lambda: cv.spatial_to_classical_acceleration(np.zeros(6), np.zeros(4)), ShapeError, "v:"),
    (
        lambda: cv.spatial_to_classical_acceleration(
            fd.SpatialMotion.zero(frame="A"), fd.SpatialMotion.zero(frame="B")
        ),
        FrameMismatchError,
        "'A'",
    ),
    (lambda: cv.motion_to_pinocchio(fd.SpatialForce.zero()), SpatialTypeError, "m:"),
    (lambda: cv.force_to_pinocchio(fd.SpatialMotion.zero()), SpatialTypeError, "f:"),
    (lambda: cv.motion_from_pinocchio(fd.SpatialMotion.zero()), SpatialTypeError, "v6:"),
    (lambda: cv.motion_from_pinocchio(pin.Motion.Zero()), SpatialTypeError, "from_pinocchio_motion"),
    (lambda: cv.twist_from_mr(fd.SpatialMotion.zero()), SpatialTypeError, "V:"),
    (lambda: cv.to_pinocchio_motion(np.zeros((2, 6))), ShapeError, "batch shape"),
    (lambda: cv.to_pinocchio_force(fd.SpatialMotion.zero()), SpatialTypeError, "f:"),
    (lambda: cv.to_pinocchio_inertia(np.eye(6)), SpatialTypeError, "inertia:"),
    (
        lambda: cv.to_pinocchio_inertia(fd.SpatialInertia(np.ones(2), np.zeros((2, 3)), np.eye(3))),
        ShapeError,
        "batch shape",
    ),
    (lambda: cv.from_pinocchio_motion(np.zeros(6)), SpatialTypeError, "motion_from_pinocchio"),
    (lambda: cv.from_pinocchio_motion(pin.Force.Zero()), SpatialTypeError, "pinocchio.Force"),
    (lambda: cv.from_pinocchio_force(pin.Motion.Zero()), SpatialTypeError, "pinocchio.Motion"),
    (lambda: cv.from_pinocchio_inertia(np.eye(6)), SpatialTypeError, "inertia:"),
    (lambda: cv.transform_to_pinocchio_se3(fd.PluckerTransform.identity((3,))), ShapeError, "batch shape"),
    (lambda: cv.transform_to_pinocchio_se3(pin.SE3.Identity()), SpatialTypeError, "transform_from_pinocchio_se3"),
    (lambda: cv.transform_from_pinocchio_se3(np.eye(4)), SpatialTypeError, "from_homogeneous"),
]


@pytest.mark.parametrize(("call", "error", "text"), BAD_INPUTS)
def test_bad_inputs_raise_featherdyn_errors(call: Any, error: type[Exception], text: str) -> None:
    with pytest.raises(error) as info:
        call()
    assert isinstance(info.value, FeatherdynError)
    assert text in str(info.value), str(info.value)


def test_sympy_object_arrays_pass_through() -> None:
    sympy = pytest.importorskip("sympy")
    a = np.array(sympy.symbols("a0:6"), dtype=object)
    assert list(cv.motion_to_pinocchio(a)) == list(a[[3, 4, 5, 0, 1, 2]])
    assert list(cv.force_from_pinocchio(a).vector) == list(a[[3, 4, 5, 0, 1, 2]])
    t = sympy.Symbol("t", real=True)
    cs = cv.continuous_q_to_pinocchio(np.array(t, dtype=object))
    assert sympy.simplify(cs[0] - sympy.cos(t)) == 0 and sympy.simplify(cs[1] - sympy.sin(t)) == 0
    q = np.array([0, 0, 0, 0, 0, sympy.sin(t / 2), sympy.cos(t / 2)], dtype=object)  # rotation t about z
    qvel = cv.freeflyer_v_to_mujoco(q, a)
    assert sympy.simplify(qvel[0] - (sympy.cos(t) * a[3] - sympy.sin(t) * a[4])) == 0
    assert qvel[5] == a[2]


# --------------------------------------------------------------------------
# MuJoCo: whole models (q ↔ qpos, v ↔ qvel, a ↔ qacc, τ ↔ qfrc)
# --------------------------------------------------------------------------


def _mujoco_like_model() -> fd.Model:
    b = fd.ModelBuilder("mj")
    I = fd.SpatialInertia(1.0, [0.1, 0.0, 0.0], np.diag([0.1, 0.2, 0.25]))
    base = b.add_body("base", -1, fd.FreeFlyerJoint(), inertia=I)
    arm = b.add_body("arm", base, fd.RevoluteJoint([0, 1, 0]), inertia=I)
    ball = b.add_body("ball", arm, fd.SphericalJoint(), inertia=I)
    b.add_body("slide", ball, fd.PrismaticJoint([1, 0, 0]), inertia=I)
    return b.build()


@pytest.mark.parametrize("shape", [(), (3,), (2, 1)])
def test_mujoco_model_converters_round_trip(shape: tuple[int, ...]) -> None:
    model = _mujoco_like_model()
    rng = np.random.default_rng(11)
    q = fd.random_configuration(model, rng, size=shape) if shape else fd.random_configuration(model, rng)
    v, a, tau = (rng.normal(size=(*shape, model.nv)) for _ in range(3))
    qpos = cv.q_to_mujoco(model, q)
    # the layout: free joint [p; w x y z], the hinge unchanged, the ball (w x y z)
    np.testing.assert_array_equal(qpos[..., 3], q[..., 6])
    np.testing.assert_array_equal(qpos[..., 7], q[..., 7])
    np.testing.assert_array_equal(qpos[..., 8], q[..., 11])
    np.testing.assert_allclose(cv.q_from_mujoco(model, qpos), q, atol=0)
    qvel = cv.v_to_mujoco(model, q, v)
    np.testing.assert_allclose(cv.v_from_mujoco(model, qpos, qvel), v, atol=1e-14)
    # power is invariant: qfrc · qvel = τ · v
    np.testing.assert_allclose(np.sum(cv.tau_to_mujoco(model, q, tau) * qvel, axis=-1), np.sum(tau * v, axis=-1),
                               rtol=1e-12)
    np.testing.assert_allclose(cv.a_from_mujoco(model, qpos, qvel, cv.a_to_mujoco(model, q, v, a)), a, atol=1e-13)
    M = fd.crba(model, q)
    Mj = cv.joint_matrix_to_mujoco(model, q, M)
    # kinetic energy is invariant: ½ qvelᵀ M_mj qvel = ½ vᵀ M v
    np.testing.assert_allclose(np.einsum("...i,...ij,...j", qvel, Mj, qvel), np.einsum("...i,...ij,...j", v, M, v),
                               rtol=1e-12)
    np.testing.assert_allclose(cv.joint_matrix_from_mujoco(model, qpos, Mj), M, atol=1e-13)


def test_mujoco_model_converters_refuse_what_mujoco_lacks() -> None:
    b = fd.ModelBuilder("p")
    b.add_body("p", -1, fd.PlanarJoint([0, 0, 1]), inertia=fd.SpatialInertia(1.0, [0, 0, 0], np.eye(3)))
    model = b.build()
    with pytest.raises(fd.ShapeError, match="no MuJoCo equivalent"):
        cv.q_to_mujoco(model, np.zeros(3))
    mj = _mujoco_like_model()
    bad = fd.neutral(mj)
    bad[7 + 1:7 + 1 + 4] = [0.0, 0.0, 0.0, 2.0]
    with pytest.raises(fd.QuaternionNormError):
        cv.q_to_mujoco(mj, bad)
    with pytest.raises(fd.ShapeError):
        cv.q_from_mujoco(mj, np.zeros(5))
