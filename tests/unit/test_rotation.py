"""Unit tests of featherdyn.rotation: Pinocchio cross-checks, closed forms, edge cases, errors."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
import sympy as sp

from featherdyn import rotation as rot
from featherdyn.errors import (
    DTypeError,
    FeatherdynError,
    NonFiniteError,
    QuaternionNormError,
    RotationError,
    ShapeError,
    SpatialTypeError,
)

BATCH_SHAPES = [(), (1,), (3,), (2, 3)]
DTYPES = [np.float64, np.float32]
# Agreement with Pinocchio / closed forms, by dtype (float32 input is compared
# with the float64 answer for the same float32 numbers).
TOL = {np.float64: 1e-12, np.float32: 2e-5}
SEED = 20240611


def _rng(*salt: int) -> np.random.Generator:
    return np.random.default_rng([SEED, *salt])


def _random_rpy(rng: np.random.Generator, shape: tuple[int, ...], margin: float = 0.05) -> np.ndarray:
    """roll, yaw in (−π, π), pitch in (−π/2 + margin, π/2 − margin): away from gimbal lock."""
    rpy = rng.uniform(-np.pi, np.pi, size=(*shape, 3))
    rpy[..., 1] = rng.uniform(-np.pi / 2 + margin, np.pi / 2 - margin, size=shape)
    return rpy


def _random_quat(rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
    q = rng.normal(size=(*shape, 4))
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def _random_rotvec(rng: np.random.Generator, shape: tuple[int, ...], max_angle: float) -> np.ndarray:
    axis = rng.normal(size=(*shape, 3))
    axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
    return axis * rng.uniform(0.0, max_angle, size=shape)[..., None]


def _rotations(rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
    """Random rotation matrices built by Pinocchio (independent of the code under test)."""
    flat = _random_quat(rng, (int(np.prod(shape, dtype=int)),))
    mats = [pin.Quaternion(q[3], q[0], q[1], q[2]).toRotationMatrix() for q in flat]
    return np.array(mats).reshape((*shape, 3, 3))


def _each(shape: tuple[int, ...]):
    return np.ndindex(*shape) if shape else iter([()])


def _rz(theta: float) -> np.ndarray:
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


# --------------------------------------------------------------------------
# cross-checks against Pinocchio, every batch shape and dtype
# --------------------------------------------------------------------------


@pytest.mark.parametrize("shape", BATCH_SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_rpy_to_matrix_matches_pinocchio(shape, dtype):
    rpy = _random_rpy(_rng(1), shape, margin=0.0).astype(dtype)
    R = rot.rpy_to_matrix(rpy)
    assert R.shape == (*shape, 3, 3)
    assert R.dtype == dtype
    for i in _each(shape):
        expected = pin.rpy.rpyToMatrix(rpy[i].astype(np.float64))
        np.testing.assert_allclose(R[i], expected, rtol=0, atol=TOL[dtype], err_msg=f"rpy_to_matrix at {i}")


@pytest.mark.parametrize("shape", BATCH_SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_matrix_to_rpy_matches_pinocchio_away_from_gimbal_lock(shape, dtype):
    R64 = np.array([pin.rpy.rpyToMatrix(a) for a in _random_rpy(_rng(2), shape).reshape(-1, 3)])
    R = R64.reshape((*shape, 3, 3)).astype(dtype)
    rpy = rot.matrix_to_rpy(R)
    assert rpy.shape == (*shape, 3)
    assert rpy.dtype == dtype
    tol = TOL[dtype] * (10 if dtype == np.float32 else 1)  # angles from near-unit cos(pitch) in float32
    for i in _each(shape):
        expected = pin.rpy.matrixToRpy(R[i].astype(np.float64))
        np.testing.assert_allclose(rpy[i], expected, rtol=0, atol=tol, err_msg=f"matrix_to_rpy at {i}")


@pytest.mark.parametrize("shape", BATCH_SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_quat_to_matrix_matches_pinocchio(shape, dtype):
    q = _random_quat(_rng(3), shape).astype(dtype)
    R = rot.quat_to_matrix(q)
    assert R.shape == (*shape, 3, 3)
    assert R.dtype == dtype
    for i in _each(shape):
        x, y, z, w = q[i].astype(np.float64)
        expected = pin.Quaternion(w, x, y, z).toRotationMatrix()
        np.testing.assert_allclose(R[i], expected, rtol=0, atol=TOL[dtype], err_msg=f"quat_to_matrix at {i}")


@pytest.mark.parametrize("shape", BATCH_SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_matrix_to_quat_matches_pinocchio_up_to_sign(shape, dtype):
    R = _rotations(_rng(4), shape).astype(dtype)
    q = rot.matrix_to_quat(R)
    assert q.shape == (*shape, 4)
    assert q.dtype == dtype
    assert np.all(q[..., 3] >= 0), "canonical form has w >= 0"
    for i in _each(shape):
        expected = pin.Quaternion(R[i].astype(np.float64)).coeffs()  # (x, y, z, w)
        expected = expected if expected[3] >= 0 else -expected
        np.testing.assert_allclose(q[i], expected, rtol=0, atol=TOL[dtype], err_msg=f"matrix_to_quat at {i}")


@pytest.mark.parametrize("shape", BATCH_SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_quat_multiply_matches_pinocchio(shape, dtype):
    rng = _rng(5)
    q1 = _random_quat(rng, shape).astype(dtype)
    q2 = _random_quat(rng, shape).astype(dtype)
    q = rot.quat_multiply(q1, q2)
    assert q.shape == (*shape, 4)
    assert q.dtype == dtype
    for i in _each(shape):
        a, b = q1[i].astype(np.float64), q2[i].astype(np.float64)
        expected = (pin.Quaternion(a[3], *a[:3]) * pin.Quaternion(b[3], *b[:3])).coeffs()
        np.testing.assert_allclose(q[i], expected, rtol=0, atol=TOL[dtype], err_msg=f"quat_multiply at {i}")


@pytest.mark.parametrize("shape", BATCH_SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_quat_conjugate_matches_pinocchio_inverse(shape, dtype):
    q = _random_quat(_rng(6), shape).astype(dtype)
    qc = rot.quat_conjugate(q)
    assert qc.dtype == dtype
    for i in _each(shape):
        a = q[i].astype(np.float64)
        expected = pin.Quaternion(a[3], *a[:3]).inverse().coeffs()
        np.testing.assert_allclose(qc[i], expected, rtol=0, atol=TOL[dtype])


@pytest.mark.parametrize("shape", BATCH_SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_quat_normalize_matches_pinocchio(shape, dtype):
    q = (_rng(7).normal(size=(*shape, 4)) * 3).astype(dtype)
    qn = rot.quat_normalize(q)
    assert qn.dtype == dtype
    for i in _each(shape):
        a = q[i].astype(np.float64)
        expected = pin.Quaternion(a[3], *a[:3]).normalized().coeffs()
        np.testing.assert_allclose(qn[i], expected, rtol=0, atol=TOL[dtype])


@pytest.mark.parametrize("shape", BATCH_SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_axis_angle_to_matrix_matches_pinocchio(shape, dtype):
    rng = _rng(8)
    axis = (rng.normal(size=(*shape, 3)) * 2.5).astype(dtype)  # not unit: normalised inside
    angle = rng.uniform(-4, 4, size=shape).astype(dtype)
    R = rot.axis_angle_to_matrix(axis, angle)
    assert R.shape == (*shape, 3, 3)
    assert R.dtype == dtype
    for i in _each(shape):
        a = axis[i].astype(np.float64)
        expected = pin.AngleAxis(float(angle[i]), a / np.linalg.norm(a)).toRotationMatrix()
        np.testing.assert_allclose(R[i], expected, rtol=0, atol=TOL[dtype], err_msg=f"axis_angle_to_matrix at {i}")


@pytest.mark.parametrize("shape", BATCH_SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_matrix_to_axis_angle_matches_pinocchio(shape, dtype):
    R = np.array([pin.exp3(w) for w in _random_rotvec(_rng(9), shape, np.pi - 0.1).reshape(-1, 3)])
    R = R.reshape((*shape, 3, 3)).astype(dtype)
    axis, angle = rot.matrix_to_axis_angle(R)
    assert axis.shape == (*shape, 3)
    assert angle.shape == shape
    assert axis.dtype == angle.dtype == dtype
    tol = TOL[dtype] * (10 if dtype == np.float32 else 1)
    for i in _each(shape):
        expected = pin.AngleAxis(R[i].astype(np.float64))
        np.testing.assert_allclose(angle[i], expected.angle, rtol=0, atol=tol)
        np.testing.assert_allclose(axis[i], expected.axis, rtol=0, atol=tol)


@pytest.mark.parametrize("shape", BATCH_SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_so3_exp_matches_pinocchio(shape, dtype):
    omega = (_rng(10).normal(size=(*shape, 3)) * 2).astype(dtype)
    R = rot.so3_exp(omega)
    assert R.shape == (*shape, 3, 3)
    assert R.dtype == dtype
    for i in _each(shape):
        np.testing.assert_allclose(R[i], pin.exp3(omega[i].astype(np.float64)), rtol=0, atol=TOL[dtype])


@pytest.mark.parametrize("shape", BATCH_SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_so3_log_matches_pinocchio(shape, dtype):
    R = _rotations(_rng(11), shape)
    # Pinocchio's log3 loses digits close to a half turn: compare where |ω| < π − 0.1.
    angles = np.arccos(np.clip((np.trace(R, axis1=-2, axis2=-1) - 1) / 2, -1, 1))
    R = np.where((angles < np.pi - 0.1)[..., None, None], R, np.eye(3)).astype(dtype)
    omega = rot.so3_log(R)
    assert omega.shape == (*shape, 3)
    assert omega.dtype == dtype
    tol = TOL[dtype] * (10 if dtype == np.float32 else 1)
    for i in _each(shape):
        np.testing.assert_allclose(omega[i], pin.log3(R[i].astype(np.float64)), rtol=0, atol=tol)


@pytest.mark.parametrize("shape", BATCH_SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_se3_exp_matches_pinocchio(shape, dtype):
    from featherdyn.spatial_algebra import PluckerTransform

    twist = (_rng(12).normal(size=(*shape, 6)) * 1.5).astype(dtype)
    X = rot.se3_exp(twist)
    assert isinstance(X, PluckerTransform)
    assert X.rotation.shape == (*shape, 3, 3)
    assert X.translation.shape == (*shape, 3)
    assert X.rotation.dtype == X.translation.dtype == dtype
    for i in _each(shape):
        xi = twist[i].astype(np.float64)
        M = pin.exp6(pin.Motion(xi[3:], xi[:3]))  # Pinocchio: Motion(linear, angular)
        np.testing.assert_allclose(X.rotation[i], M.rotation, rtol=0, atol=TOL[dtype], err_msg=f"rotation at {i}")
        np.testing.assert_allclose(
            X.translation[i], M.translation, rtol=0, atol=10 * TOL[dtype], err_msg=f"translation at {i}"
        )


@pytest.mark.parametrize("shape", BATCH_SHAPES)
@pytest.mark.parametrize("dtype", DTYPES)
def test_se3_log_matches_pinocchio(shape, dtype):
    from featherdyn.spatial_algebra import PluckerTransform, SpatialMotion

    rng = _rng(13)
    R = np.array([pin.exp3(w) for w in _random_rotvec(rng, shape, np.pi - 0.1).reshape(-1, 3)])
    R = R.reshape((*shape, 3, 3)).astype(dtype)
    p = rng.normal(size=(*shape, 3)).astype(dtype)
    xi = rot.se3_log(PluckerTransform(R, p))
    assert isinstance(xi, SpatialMotion)
    assert xi.vector.shape == (*shape, 6)
    assert xi.vector.dtype == dtype
    for i in _each(shape):
        m = pin.log6(pin.SE3(R[i].astype(np.float64), p[i].astype(np.float64)))
        np.testing.assert_allclose(xi.angular[i], m.angular, rtol=0, atol=10 * TOL[dtype], err_msg=f"angular at {i}")
        np.testing.assert_allclose(xi.linear[i], m.linear, rtol=0, atol=10 * TOL[dtype], err_msg=f"linear at {i}")


# --------------------------------------------------------------------------
# closed forms (numbers worked out by hand, not by the code under test)
# --------------------------------------------------------------------------

QUARTER_TURN_Z = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
HALF_TURNS = {  # (x, y, z, w) -> matrix
    (1.0, 0.0, 0.0, 0.0): np.diag([1.0, -1.0, -1.0]),
    (0.0, 1.0, 0.0, 0.0): np.diag([-1.0, 1.0, -1.0]),
    (0.0, 0.0, 1.0, 0.0): np.diag([-1.0, -1.0, 1.0]),
    (np.sqrt(0.5), np.sqrt(0.5), 0.0, 0.0): np.array([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]]),
}


def test_quarter_turn_about_z_in_every_parametrisation():
    s = np.sqrt(0.5)
    cases = {
        "quat_to_matrix": rot.quat_to_matrix([0.0, 0.0, s, s]),
        "rpy_to_matrix": rot.rpy_to_matrix([0.0, 0.0, np.pi / 2]),
        "axis_angle_to_matrix": rot.axis_angle_to_matrix([0.0, 0.0, 7.0], np.pi / 2),
        "so3_exp": rot.so3_exp([0.0, 0.0, np.pi / 2]),
    }
    for name, R in cases.items():
        np.testing.assert_allclose(R, QUARTER_TURN_Z, rtol=0, atol=1e-15, err_msg=name)
    np.testing.assert_allclose(rot.matrix_to_quat(QUARTER_TURN_Z), [0.0, 0.0, s, s], rtol=0, atol=1e-15)
    np.testing.assert_allclose(rot.matrix_to_rpy(QUARTER_TURN_Z), [0.0, 0.0, np.pi / 2], rtol=0, atol=1e-15)
    np.testing.assert_allclose(rot.so3_log(QUARTER_TURN_Z), [0.0, 0.0, np.pi / 2], rtol=0, atol=1e-15)
    axis, angle = rot.matrix_to_axis_angle(QUARTER_TURN_Z)
    np.testing.assert_allclose(axis, [0.0, 0.0, 1.0], rtol=0, atol=1e-15)
    np.testing.assert_allclose(angle, np.pi / 2, rtol=0, atol=1e-15)


def test_quaternion_order_is_xyzw_not_wxyz():
    # (x, y, z, w) = (1, 0, 0, 0) is a half turn about x, not the identity.
    np.testing.assert_allclose(rot.quat_to_matrix([1.0, 0.0, 0.0, 0.0]), np.diag([1.0, -1.0, -1.0]), atol=0)
    np.testing.assert_array_equal(rot.quat_to_matrix([0.0, 0.0, 0.0, 1.0]), np.eye(3))
    np.testing.assert_array_equal(rot.matrix_to_quat(np.eye(3)), [0.0, 0.0, 0.0, 1.0])


@pytest.mark.parametrize("quat", list(HALF_TURNS))
def test_half_turns_quaternion_both_ways(quat):
    R = HALF_TURNS[quat]
    np.testing.assert_allclose(rot.quat_to_matrix(quat), R, rtol=0, atol=1e-15)
    q = rot.matrix_to_quat(R)
    assert min(np.abs(q - quat).max(), np.abs(q + quat).max()) < 1e-15, q
    omega = rot.so3_log(R)
    assert np.isclose(np.linalg.norm(omega), np.pi, rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.abs(omega), np.pi * np.abs(quat[:3]), rtol=0, atol=1e-15)
    np.testing.assert_allclose(rot.so3_exp(omega), R, rtol=0, atol=1e-15)


def test_quat_multiply_of_basis_quaternions():
    i, j, k, one = np.eye(4)  # (x, y, z, w): i, j, k, 1
    np.testing.assert_array_equal(rot.quat_multiply(i, j), k)  # Hamilton: ij = k
    np.testing.assert_array_equal(rot.quat_multiply(j, i), -k)
    np.testing.assert_array_equal(rot.quat_multiply(i, i), -one)
    np.testing.assert_array_equal(rot.quat_multiply(one, j), j)


def test_quat_multiply_composes_rotations_and_broadcasts():
    rng = _rng(20)
    q1 = _random_quat(rng, (2, 3))
    q2 = _random_quat(rng, ())
    q = rot.quat_multiply(q1, q2)
    assert q.shape == (2, 3, 4)
    np.testing.assert_allclose(
        rot.quat_to_matrix(q), rot.quat_to_matrix(q1) @ rot.quat_to_matrix(q2), rtol=0, atol=1e-14
    )


def test_rpy_order_is_yaw_pitch_roll_about_fixed_axes():
    roll, pitch, yaw = 0.3, -0.4, 1.1
    rx = np.array([[1, 0, 0], [0, np.cos(roll), -np.sin(roll)], [0, np.sin(roll), np.cos(roll)]])
    ry = np.array([[np.cos(pitch), 0, np.sin(pitch)], [0, 1, 0], [-np.sin(pitch), 0, np.cos(pitch)]])
    np.testing.assert_allclose(rot.rpy_to_matrix([roll, pitch, yaw]), _rz(yaw) @ ry @ rx, rtol=0, atol=1e-15)


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("pitch_sign", [1.0, -1.0])
def test_matrix_to_rpy_at_gimbal_lock_sets_roll_zero_and_round_trips(dtype, pitch_sign):
    rng = _rng(21)
    rpy = rng.uniform(-np.pi, np.pi, size=(5, 3))
    rpy[:, 1] = pitch_sign * np.pi / 2
    R = rot.rpy_to_matrix(rpy.astype(dtype))
    out = rot.matrix_to_rpy(R)
    assert out.dtype == dtype
    np.testing.assert_array_equal(out[:, 0], 0.0)
    np.testing.assert_allclose(out[:, 1], pitch_sign * np.pi / 2, rtol=0, atol=TOL[dtype])
    np.testing.assert_allclose(rot.rpy_to_matrix(out), R, rtol=0, atol=TOL[dtype])
    # Only yaw ∓ roll is defined there: R depends on roll − yaw (pitch +π/2) or roll + yaw (−π/2).
    combo_in = rpy[:, 2] - pitch_sign * rpy[:, 0]
    np.testing.assert_allclose(np.cos(out[:, 2] - combo_in), 1.0, rtol=0, atol=TOL[dtype])


@pytest.mark.parametrize("offset", [1e-15, 1e-12, 1e-9, 1e-7, 1e-5, 1e-3])
def test_matrix_to_rpy_round_trips_near_gimbal_lock(offset):
    for sign in (1.0, -1.0):
        R = pin.rpy.rpyToMatrix(0.7, sign * (np.pi / 2 - offset), -2.1)
        out = rot.matrix_to_rpy(R)
        assert abs(out[1]) <= np.pi / 2
        np.testing.assert_allclose(rot.rpy_to_matrix(out), R, rtol=0, atol=1e-14, err_msg=f"offset {offset}")


def test_identity_axis_angle_convention():
    axis, angle = rot.matrix_to_axis_angle(np.eye(3))
    np.testing.assert_array_equal(axis, [0.0, 0.0, 1.0])
    assert angle == 0.0
    axes, angles = rot.matrix_to_axis_angle(np.stack([np.eye(3), QUARTER_TURN_Z.T, np.diag([1.0, -1.0, -1.0])]))
    np.testing.assert_allclose(angles, [0.0, np.pi / 2, np.pi], rtol=0, atol=1e-15)
    np.testing.assert_allclose(axes[:2], [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]], rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.abs(axes[2]), [1.0, 0.0, 0.0], rtol=0, atol=1e-15)


def test_axis_angle_broadcasts_axis_against_angle_batch():
    angles = np.linspace(-3, 3, 6).reshape(2, 3)
    R = rot.axis_angle_to_matrix([0, 0, 2], angles)
    assert R.shape == (2, 3, 3, 3)
    for i in np.ndindex(2, 3):
        np.testing.assert_allclose(R[i], _rz(angles[i]), rtol=0, atol=1e-15)


def test_axis_angle_tiny_and_huge_axes_are_normalised():
    for scale in (1e-200, 1e-20, 1e20, 1e200):
        np.testing.assert_allclose(rot.axis_angle_to_matrix([0, 0, scale], 0.4), _rz(0.4), rtol=0, atol=1e-15)


@pytest.mark.parametrize("theta", [0.0, 1e-300, 1e-12, 1e-8, 1e-4, 9e-3, 1.1e-2, 0.3])
def test_so3_exp_log_accurate_for_tiny_angles(theta):
    k = np.array([2.0, -3.0, 6.0]) / 7.0
    omega = theta * k
    R = rot.so3_exp(omega)
    # Rodrigues, to second order, is exact to rounding below 1e-8.
    if theta < 1e-8:
        expected = np.eye(3) + theta * np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        np.testing.assert_allclose(R, expected, rtol=0, atol=1e-16)
    else:
        np.testing.assert_allclose(R, pin.exp3(omega), rtol=0, atol=1e-15)
    assert np.all(np.isfinite(R))
    back = rot.so3_log(R)
    np.testing.assert_allclose(back, omega, rtol=1e-12, atol=1e-300)


@pytest.mark.parametrize("gap", [0.0, 1e-12, 1e-9, 1e-6, 1e-3, 0.1, 0.6])
def test_so3_log_accurate_near_half_turn(gap):
    k = np.array([1.0, 4.0, -8.0]) / 9.0
    theta = np.pi - gap
    R = pin.exp3(theta * k)
    omega = rot.so3_log(R)
    assert np.linalg.norm(omega) <= np.pi + 1e-15
    np.testing.assert_allclose(rot.so3_exp(omega), R, rtol=0, atol=1e-15)
    if gap > 0:  # at exactly π both signs are logarithms
        np.testing.assert_allclose(omega, theta * k, rtol=0, atol=1e-14)


def test_se3_exp_of_a_pure_translation_and_of_a_rotation_about_an_offset_axis():
    from featherdyn.spatial_algebra import SpatialMotion

    X = rot.se3_exp(np.array([0.0, 0.0, 0.0, 1.0, -2.0, 0.5]))
    np.testing.assert_array_equal(X.rotation, np.eye(3))
    np.testing.assert_allclose(X.translation, [1.0, -2.0, 0.5], rtol=0, atol=0)

    # Rotation θ about the z-axis through the point c: ω = θ ẑ, v_O = −ω × c,
    # and the pose is R = Rz(θ), p = (1 − R) c.
    theta, c = 0.8, np.array([1.0, 2.0, 3.0])
    omega = np.array([0.0, 0.0, theta])
    X = rot.se3_exp(SpatialMotion(omega, -np.cross(omega, c)))
    np.testing.assert_allclose(X.rotation, _rz(theta), rtol=0, atol=1e-15)
    np.testing.assert_allclose(X.translation, (np.eye(3) - _rz(theta)) @ c, rtol=0, atol=1e-15)


@pytest.mark.parametrize("theta", [1e-6, 5e-3, 9.9e-3, 1.01e-2, 5e-2, 0.099, 0.101])
def test_se3_exp_and_log_match_pinocchio_across_the_small_angle_switch(theta):
    """Either side of the Taylor-series switch, to ~1e-14 relative (|v| ≈ 20)."""
    from featherdyn.spatial_algebra import PluckerTransform

    omega = theta * np.array([2.0, -3.0, 6.0]) / 7.0
    v = np.array([10.0, -20.0, 5.0])
    M = pin.exp6(pin.Motion(v, omega))
    X = rot.se3_exp(np.concatenate([omega, v]))
    np.testing.assert_allclose(X.rotation, M.rotation, rtol=0, atol=5e-16)
    np.testing.assert_allclose(X.translation, M.translation, rtol=0, atol=2e-13)
    xi = rot.se3_log(PluckerTransform(M.rotation, M.translation))
    m = pin.log6(M)
    np.testing.assert_allclose(xi.angular, m.angular, rtol=1e-13, atol=0)
    np.testing.assert_allclose(xi.linear, m.linear, rtol=0, atol=2e-13)


def test_se3_exp_accepts_spatial_motion_and_raw_array_alike():
    from featherdyn.spatial_algebra import SpatialMotion

    twist = _rng(22).normal(size=(4, 6))
    a = rot.se3_exp(twist)
    b = rot.se3_exp(SpatialMotion.from_vector(twist))
    np.testing.assert_array_equal(a.rotation, b.rotation)
    np.testing.assert_array_equal(a.translation, b.translation)


@pytest.mark.parametrize("angle", [0.0, 1e-10, 1e-4, 1.0, np.pi - 1e-6, np.pi])
def test_se3_log_exp_round_trip_near_zero_and_half_turn(angle):
    from featherdyn.spatial_algebra import PluckerTransform

    k = np.array([-2.0, 6.0, 3.0]) / 7.0
    R = pin.exp3(angle * k)
    p = np.array([0.4, -1.2, 2.0])
    xi = rot.se3_log(PluckerTransform(R, p))
    X = rot.se3_exp(xi)
    np.testing.assert_allclose(X.rotation, R, rtol=0, atol=1e-14)
    np.testing.assert_allclose(X.translation, p, rtol=0, atol=1e-14)
    if angle < np.pi:
        np.testing.assert_allclose(xi.angular, angle * k, rtol=0, atol=1e-14)


# --------------------------------------------------------------------------
# dtypes and SymPy
# --------------------------------------------------------------------------


def test_integer_input_gives_float64():
    assert rot.rpy_to_matrix([0, 0, 0]).dtype == np.float64
    assert rot.quat_to_matrix([0, 0, 0, 1]).dtype == np.float64
    assert rot.so3_exp([0, 0, 1]).dtype == np.float64
    assert rot.matrix_to_quat(np.eye(3, dtype=int)).dtype == np.float64
    assert rot.axis_angle_to_matrix([1, 0, 0], 1).dtype == np.float64


def test_float32_stays_float32_everywhere():
    from featherdyn.spatial_algebra import PluckerTransform

    f = np.float32
    R = rot.rpy_to_matrix(np.array([0.1, 0.2, 0.3], f))
    checks = {
        "rpy_to_matrix": R,
        "matrix_to_rpy": rot.matrix_to_rpy(R),
        "matrix_to_quat": rot.matrix_to_quat(R),
        "quat_to_matrix": rot.quat_to_matrix(np.array([0, 0, 0, 1], f)),
        "quat_multiply": rot.quat_multiply(np.array([0, 0, 0, 1], f), np.array([1, 0, 0, 0], f)),
        "quat_conjugate": rot.quat_conjugate(np.array([0, 0, 0, 1], f)),
        "quat_normalize": rot.quat_normalize(np.array([0, 0, 0, 2], f)),
        "axis_angle_to_matrix": rot.axis_angle_to_matrix(np.array([0, 0, 1], f), f(0.5)),
        "matrix_to_axis_angle": rot.matrix_to_axis_angle(R)[0],
        "matrix_to_axis_angle angle": rot.matrix_to_axis_angle(R)[1],
        "so3_exp": rot.so3_exp(np.array([0, 0, 1e-3], f)),
        "so3_log": rot.so3_log(R),
        "se3_exp": rot.se3_exp(np.ones(6, f)).translation,
        "se3_log": rot.se3_log(PluckerTransform(R, np.ones(3, f))).vector,
    }
    for name, arr in checks.items():
        assert np.asarray(arr).dtype == np.float32, name


def test_symbolic_rpy_to_matrix_equals_numeric_after_substitution():
    r, p, y = sp.symbols("r p y", real=True)
    R_sym = rot.rpy_to_matrix(np.array([r, p, y], dtype=object))
    assert R_sym.dtype == object and R_sym.shape == (3, 3)
    values = {r: 0.3, p: -1.2, y: 2.5}
    numeric = np.array([[float(e.subs(values)) for e in row] for row in R_sym])
    np.testing.assert_allclose(numeric, pin.rpy.rpyToMatrix(0.3, -1.2, 2.5), rtol=0, atol=1e-14)
    # symbolic identity: RᵀR = 1
    assert sp.simplify(sp.Matrix(R_sym).T * sp.Matrix(R_sym) - sp.eye(3)) == sp.zeros(3, 3)


def test_symbolic_axis_angle_quat_and_so3_exp_agree_with_numeric():
    q = sp.Symbol("q", real=True)
    value = 0.9
    axis = np.array([1.0, -2.0, 2.0])
    numeric = pin.AngleAxis(value, axis / 3.0).toRotationMatrix()

    def evaluate(m: np.ndarray) -> np.ndarray:
        return np.array([[float(sp.sympify(e).subs(q, value)) for e in row] for row in m])

    sym_aa = rot.axis_angle_to_matrix(axis, np.array(q, dtype=object))
    np.testing.assert_allclose(evaluate(sym_aa), numeric, rtol=0, atol=1e-14)
    sym_exp = rot.so3_exp(np.array([q * 1 / 3, -q * 2 / 3, q * 2 / 3], dtype=object))
    np.testing.assert_allclose(evaluate(sym_exp), numeric, rtol=0, atol=1e-14)
    half = q / 2
    quat = np.array([sp.sin(half) / 3, -2 * sp.sin(half) / 3, 2 * sp.sin(half) / 3, sp.cos(half)], dtype=object)
    np.testing.assert_allclose(evaluate(rot.quat_to_matrix(quat)), numeric, rtol=0, atol=1e-14)
    # the symbolic zero rotation is the identity (sinc handles θ = 0)
    zero = rot.so3_exp(np.array([q, 0, 0], dtype=object))
    assert sp.sympify(zero[1, 1]).subs(q, 0) == 1


def test_symbolic_quat_multiply_and_batched_rpy():
    a, b = sp.symbols("a b", real=True)
    qa = np.array([0, 0, sp.sin(a / 2), sp.cos(a / 2)], dtype=object)
    qb = np.array([0, 0, sp.sin(b / 2), sp.cos(b / 2)], dtype=object)
    q = rot.quat_multiply(qa, qb)
    assert sp.simplify(q[2] - sp.sin((a + b) / 2)) == 0
    assert sp.simplify(q[3] - sp.cos((a + b) / 2)) == 0
    batch = rot.rpy_to_matrix(np.array([[0, 0, a], [a, 0, 0]], dtype=object))
    assert batch.shape == (2, 3, 3)
    assert sp.simplify(batch[0, 0, 1] + sp.sin(a)) == 0
    assert sp.simplify(batch[1, 2, 1] - sp.sin(a)) == 0


# --------------------------------------------------------------------------
# bad input: every error is a featherdyn error that names the argument
# --------------------------------------------------------------------------

ONE_ARG = {
    "quat_to_matrix": (rot.quat_to_matrix, "quat", (4,)),
    "matrix_to_quat": (rot.matrix_to_quat, "rotation", (3, 3)),
    "quat_conjugate": (rot.quat_conjugate, "quat", (4,)),
    "quat_normalize": (rot.quat_normalize, "quat", (4,)),
    "rpy_to_matrix": (rot.rpy_to_matrix, "rpy", (3,)),
    "matrix_to_rpy": (rot.matrix_to_rpy, "rotation", (3, 3)),
    "matrix_to_axis_angle": (rot.matrix_to_axis_angle, "rotation", (3, 3)),
    "so3_exp": (rot.so3_exp, "omega", (3,)),
    "so3_log": (rot.so3_log, "rotation", (3, 3)),
    "se3_exp": (rot.se3_exp, "twist", (6,)),
}


def _valid(trailing: tuple[int, ...]) -> np.ndarray:
    if trailing == (3, 3):
        return np.eye(3)
    if trailing == (4,):
        return np.array([0.0, 0.0, 0.0, 1.0])
    return np.full(trailing, 0.1)


@pytest.mark.parametrize("name", list(ONE_ARG))
def test_wrong_shape_raises_shape_error_naming_argument(name):
    fn, arg, trailing = ONE_ARG[name]
    wrong = np.zeros((*trailing[:-1], trailing[-1] + 1))
    with pytest.raises(ShapeError, match=rf"^{arg}: expected shape \(\.\.\., "):
        fn(wrong)
    with pytest.raises(ShapeError, match=arg):
        fn(np.zeros((2, 2)))
    with pytest.raises(ShapeError, match=arg):
        fn(1.0)


@pytest.mark.parametrize("name", list(ONE_ARG))
def test_nan_raises_non_finite_error(name):
    fn, arg, trailing = ONE_ARG[name]
    bad = np.stack([_valid(trailing), _valid(trailing)])
    bad[(1,) + (0,) * len(trailing)] = np.nan
    with pytest.raises(NonFiniteError, match=rf"^{arg}: expected finite numbers.*\(1, 0"):
        fn(bad)
    bad[(1,) + (0,) * len(trailing)] = np.inf
    with pytest.raises(NonFiniteError, match=arg):
        fn(bad)


@pytest.mark.parametrize("name", list(ONE_ARG))
def test_complex_dtype_raises_dtype_error(name):
    fn, arg, trailing = ONE_ARG[name]
    with pytest.raises(DTypeError, match=rf"^{arg}: expected real numbers"):
        fn(_valid(trailing).astype(complex))


def test_two_argument_functions_validate_each_argument():
    q = np.array([0.0, 0.0, 0.0, 1.0])
    with pytest.raises(ShapeError, match=r"^q1: "):
        rot.quat_multiply(q[:3], q)
    with pytest.raises(ShapeError, match=r"^q2: "):
        rot.quat_multiply(q, np.zeros(5))
    with pytest.raises(NonFiniteError, match=r"^q2: "):
        rot.quat_multiply(q, [0.0, np.nan, 0.0, 1.0])
    with pytest.raises(ShapeError, match=r"^axis: "):
        rot.axis_angle_to_matrix([1.0, 0.0], 0.3)
    with pytest.raises(NonFiniteError, match=r"^angle: "):
        rot.axis_angle_to_matrix([1.0, 0.0, 0.0], np.inf)
    with pytest.raises(DTypeError, match=r"^angle: "):
        rot.axis_angle_to_matrix([1.0, 0.0, 0.0], 1j)
    with pytest.raises(ValueError):  # incompatible batch shapes
        rot.axis_angle_to_matrix(np.ones((2, 3)), np.ones(3))


def test_non_unit_quaternion_raises_with_norm_and_order_hint():
    with pytest.raises(QuaternionNormError, match=r"^quat: .*norm 2\b.*\(x, y, z, w\)"):
        rot.quat_to_matrix([0.0, 0.0, 0.0, 2.0])
    batch = np.array([[0.0, 0.0, 0.0, 1.0], [0.5, 0.5, 0.5, 0.6]])
    with pytest.raises(QuaternionNormError, match=r"batch index \(1,\)"):
        rot.quat_to_matrix(batch)
    # tolerance: 1e-6 in float64, 1e-4 in float32
    slightly_off = np.array([0.0, 0.0, 0.0, 1.0 + 5e-5])
    with pytest.raises(QuaternionNormError):
        rot.quat_to_matrix(slightly_off)
    assert rot.quat_to_matrix(slightly_off.astype(np.float32)).dtype == np.float32
    np.testing.assert_allclose(rot.quat_to_matrix([0.0, 0.0, 0.0, 1.0 + 5e-7]), np.eye(3), rtol=0, atol=1e-15)
    with pytest.raises(QuaternionNormError):
        rot.quat_to_matrix(np.array([0.0, 0.0, 0.0, 1.0 + 5e-4], dtype=np.float32))


def test_unchecked_quaternion_gives_rotation_of_normalised_quaternion():
    q = np.array([1.0, -2.0, 3.0, 0.5])
    R = rot.quat_to_matrix(q, check_norm=False)
    x, y, z, w = q / np.linalg.norm(q)
    np.testing.assert_allclose(R, pin.Quaternion(w, x, y, z).toRotationMatrix(), rtol=0, atol=1e-15)


def test_zero_quaternion_always_raises():
    zero = np.zeros(4)
    for call in (
        lambda: rot.quat_to_matrix(zero),
        lambda: rot.quat_to_matrix(zero, check_norm=False),
        lambda: rot.quat_normalize(zero),
        lambda: rot.quat_normalize(np.stack([np.ones(4), zero])),
    ):
        with pytest.raises(QuaternionNormError, match=r"^quat: .*zero quaternion"):
            call()


def test_zero_axis_raises_rotation_error():
    with pytest.raises(RotationError, match=r"^axis: zero-length axis"):
        rot.axis_angle_to_matrix([0.0, 0.0, 0.0], 0.5)
    with pytest.raises(RotationError, match=r"batch index \(1,\)"):
        rot.axis_angle_to_matrix([[1.0, 0.0, 0.0], [0.0, 0.0, 0.0]], 0.5)


NOT_ROTATIONS = {
    "scaled": 1.1 * np.eye(3),
    "sheared": np.array([[1.0, 0.2, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
    "zero": np.zeros((3, 3)),
    "reflection": np.diag([1.0, 1.0, -1.0]),
    "inversion": -np.eye(3),
}
MATRIX_FUNCTIONS = [rot.matrix_to_quat, rot.matrix_to_rpy, rot.matrix_to_axis_angle, rot.so3_log]


@pytest.mark.parametrize("kind", list(NOT_ROTATIONS))
@pytest.mark.parametrize("fn", MATRIX_FUNCTIONS, ids=lambda f: f.__name__)
def test_non_rotation_matrices_raise_rotation_error(fn, kind):
    M = NOT_ROTATIONS[kind]
    with pytest.raises(RotationError, match=r"^rotation: expected a"):
        fn(M)
    with pytest.raises(RotationError, match=r"batch index \(1,\)"):
        fn(np.stack([np.eye(3), M]))


def test_reflection_message_says_reflection():
    with pytest.raises(RotationError, match="reflection"):
        rot.so3_log(np.diag([1.0, -1.0, 1.0]))


def test_se3_type_errors_and_invalid_rotation():
    from featherdyn.spatial_algebra import PluckerTransform, SpatialForce

    with pytest.raises(SpatialTypeError, match=r"^twist: .*SpatialForce"):
        rot.se3_exp(SpatialForce(np.zeros(3), np.ones(3)))
    with pytest.raises(SpatialTypeError, match=r"^transform: expected a PluckerTransform"):
        rot.se3_log(np.eye(4))
    unchecked = PluckerTransform(np.diag([1.0, 1.0, -1.0]), np.zeros(3), validate=False)
    with pytest.raises(RotationError, match=r"^transform\.rotation: "):
        rot.se3_log(unchecked)


def test_symbolic_input_to_numeric_only_functions_raises_dtype_error():
    a = sp.Symbol("a")
    R_sym = rot.rpy_to_matrix(np.array([0, 0, a], dtype=object))
    for fn in MATRIX_FUNCTIONS:
        with pytest.raises(DTypeError, match=r"^rotation: .*numeric"):
            fn(R_sym)


def test_every_error_is_a_featherdyn_value_or_type_error():
    for call in (
        lambda: rot.quat_to_matrix([1.0, 1.0, 1.0, 1.0]),
        lambda: rot.axis_angle_to_matrix(np.zeros(3), 1.0),
        lambda: rot.so3_log(np.zeros((3, 3))),
        lambda: rot.rpy_to_matrix([np.nan, 0.0, 0.0]),
        lambda: rot.so3_exp(np.zeros(4)),
    ):
        with pytest.raises(FeatherdynError) as info:
            call()
        assert isinstance(info.value, ValueError)
