"""Property tests of featherdyn.rotation (hypothesis, derandomized).

Group and round-trip identities over random batches of every batch shape, in
float64 and float32: quaternion ⇄ matrix, Hamilton product = matrix product,
roll-pitch-yaw round trip (gimbal lock included), exp∘log and log∘exp on SO(3)
and SE(3), one-parameter subgroups, batch == loop, symbolic == numeric.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
import sympy as sp
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from featherdyn import rotation as rot

BATCH_SHAPES = [(), (1,), (3,), (2, 3)]
DTYPES = [np.float64, np.float32]
# Round-trip and identity tolerances by dtype (absolute, on quantities of size ~1–10).
TOL = {np.float64: 1e-11, np.float32: 5e-5}
# Batched vs one-at-a-time: the same arithmetic, up to summation order in matmul.
LOOP_TOL = {np.float64: 1e-15, np.float32: 1e-6}

SETTINGS = settings(
    derandomize=True,
    database=None,
    max_examples=30,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)

shapes = st.sampled_from(BATCH_SHAPES)


def _floats(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False, width=64)


@st.composite
def unit_quats(draw: st.DrawFn, shape: tuple[int, ...] | None = None) -> np.ndarray:
    shape = draw(shapes) if shape is None else shape
    q = draw(hnp.arrays(np.float64, (*shape, 4), elements=_floats(-1, 1)))
    norm = np.linalg.norm(q, axis=-1, keepdims=True)
    assume(np.all(norm > 0.1))
    return q / norm


@st.composite
def rotation_vectors(draw: st.DrawFn, max_angle: float, shape: tuple[int, ...] | None = None) -> np.ndarray:
    shape = draw(shapes) if shape is None else shape
    direction = draw(hnp.arrays(np.float64, (*shape, 3), elements=_floats(-1, 1)))
    norm = np.linalg.norm(direction, axis=-1, keepdims=True)
    assume(np.all(norm > 0.1))
    angle = draw(hnp.arrays(np.float64, shape, elements=_floats(0, max_angle)))
    return direction / norm * angle[..., None]


@st.composite
def rpy_angles(draw: st.DrawFn) -> np.ndarray:
    """roll, yaw in [−π, π]; pitch in [−π/2, π/2], exactly ±π/2 (gimbal lock) about a third of the time."""
    shape = draw(shapes)
    rpy = draw(hnp.arrays(np.float64, (*shape, 3), elements=_floats(-np.pi, np.pi)))
    pitch = st.one_of(_floats(-np.pi / 2, np.pi / 2), st.sampled_from([np.pi / 2, -np.pi / 2]))
    rpy[..., 1] = draw(hnp.arrays(np.float64, shape, elements=pitch))
    return rpy


def _pin_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrices of (x, y, z, w) quaternions, built by Pinocchio."""
    flat = q.reshape(-1, 4)
    mats = [pin.Quaternion(float(w), float(x), float(y), float(z)).toRotationMatrix() for x, y, z, w in flat]
    return np.array(mats).reshape((*q.shape[:-1], 3, 3))


def _each(shape: tuple[int, ...]):
    return np.ndindex(*shape) if shape else iter([()])


def _assert_rotation(R: np.ndarray, tol: float, what: str) -> None:
    RtR = np.swapaxes(R, -1, -2) @ R
    np.testing.assert_allclose(RtR, np.broadcast_to(np.eye(3), RtR.shape), rtol=0, atol=tol, err_msg=f"{what}: RᵀR")
    np.testing.assert_allclose(np.linalg.det(R.astype(np.float64)), 1.0, rtol=0, atol=tol, err_msg=f"{what}: det")


def _wrap(angle: np.ndarray) -> np.ndarray:
    return np.angle(np.exp(1j * angle))


# --------------------------------------------------------------------------
# quaternions
# --------------------------------------------------------------------------


@pytest.mark.parametrize("dtype", DTYPES)
@SETTINGS
@given(q=unit_quats())
def test_quat_matrix_quat_round_trip_up_to_sign(dtype, q):
    q = q.astype(dtype)
    R = rot.quat_to_matrix(q)
    _assert_rotation(R, TOL[dtype], "quat_to_matrix")
    back = rot.matrix_to_quat(R)
    assert back.dtype == dtype
    assert np.all(back[..., 3] >= 0)
    err = np.minimum(np.abs(back - q).max(axis=-1), np.abs(back + q).max(axis=-1))
    assert np.all(err <= TOL[dtype]), f"worst |q' ∓ q| = {err.max()}"


@pytest.mark.parametrize("dtype", DTYPES)
@SETTINGS
@given(q=unit_quats())
def test_matrix_quat_matrix_round_trip(dtype, q):
    R = _pin_matrix(q).astype(dtype)
    np.testing.assert_allclose(rot.quat_to_matrix(rot.matrix_to_quat(R)), R, rtol=0, atol=TOL[dtype])


@pytest.mark.parametrize("dtype", DTYPES)
@SETTINGS
@given(data=st.data())
def test_hamilton_product_is_matrix_product_and_conjugate_is_transpose(dtype, data):
    shape = data.draw(shapes)
    q1 = data.draw(unit_quats(shape)).astype(dtype)
    q2 = data.draw(unit_quats(shape)).astype(dtype)
    R1, R2 = _pin_matrix(q1), _pin_matrix(q2)
    np.testing.assert_allclose(rot.quat_to_matrix(rot.quat_multiply(q1, q2)), R1 @ R2, rtol=0, atol=TOL[dtype])
    np.testing.assert_allclose(
        rot.quat_to_matrix(rot.quat_conjugate(q1)), np.swapaxes(R1, -1, -2), rtol=0, atol=TOL[dtype]
    )
    identity = rot.quat_multiply(q1, rot.quat_conjugate(q1))
    np.testing.assert_allclose(identity, np.broadcast_to([0, 0, 0, 1], identity.shape), rtol=0, atol=TOL[dtype])


@pytest.mark.parametrize("dtype", DTYPES)
@SETTINGS
@given(q=unit_quats(), scale=st.sampled_from([1e-30, 1e-3, 0.5, 7.0, 1e30]))
def test_normalize_undoes_scaling_and_unchecked_matrix_ignores_scale(dtype, q, scale):
    q = q.astype(dtype)
    scaled = (q * dtype(scale)).astype(dtype)
    assume(np.all(np.isfinite(scaled)) and np.all(np.abs(scaled).max(axis=-1) > 0))
    np.testing.assert_allclose(rot.quat_normalize(scaled), q, rtol=0, atol=TOL[dtype])
    if 1e-3 <= scale <= 7.0:
        np.testing.assert_allclose(
            rot.quat_to_matrix(scaled, check_norm=False), rot.quat_to_matrix(q), rtol=0, atol=TOL[dtype]
        )


# --------------------------------------------------------------------------
# roll-pitch-yaw
# --------------------------------------------------------------------------


@pytest.mark.parametrize("dtype", DTYPES)
@SETTINGS
@given(rpy=rpy_angles())
def test_rpy_round_trip_including_gimbal_lock(dtype, rpy):
    rpy = rpy.astype(dtype)
    R = rot.rpy_to_matrix(rpy)
    _assert_rotation(R, TOL[dtype], "rpy_to_matrix")
    out = rot.matrix_to_rpy(R)
    assert out.dtype == dtype
    assert np.all(np.abs(out[..., 1]) <= np.float32(np.pi / 2)), "pitch in [−π/2, π/2]"
    assert np.all(np.abs(out[..., [0, 2]]) <= np.float32(np.pi)), "roll, yaw in [−π, π]"
    np.testing.assert_allclose(rot.rpy_to_matrix(out), R, rtol=0, atol=TOL[dtype])
    # Away from gimbal lock the angles themselves come back (mod 2π).
    if dtype == np.float64:
        clear = np.abs(np.abs(rpy[..., 1]) - np.pi / 2) > 1e-3
        diff = np.abs(_wrap(out - rpy))[clear]
        assert np.all(diff <= 1e-9), f"worst angle error {diff.max() if diff.size else 0}"


@SETTINGS
@given(rpy=rpy_angles())
def test_rpy_to_matrix_agrees_with_pinocchio_and_matrix_to_rpy_with_its_matrix(rpy):
    R = rot.rpy_to_matrix(rpy)
    out = rot.matrix_to_rpy(R)
    for i in _each(rpy.shape[:-1]):
        np.testing.assert_allclose(R[i], pin.rpy.rpyToMatrix(rpy[i]), rtol=0, atol=1e-14)
        # Pinocchio may split roll/yaw differently at gimbal lock; the rotations agree.
        np.testing.assert_allclose(
            pin.rpy.rpyToMatrix(out[i]), pin.rpy.rpyToMatrix(pin.rpy.matrixToRpy(R[i])), rtol=0, atol=1e-11
        )


# --------------------------------------------------------------------------
# axis-angle and SO(3)
# --------------------------------------------------------------------------


@pytest.mark.parametrize("dtype", DTYPES)
@SETTINGS
@given(omega=rotation_vectors(np.pi - 1e-3))
def test_so3_log_inverts_exp_below_half_turn(dtype, omega):
    omega = omega.astype(dtype)
    R = rot.so3_exp(omega)
    _assert_rotation(R, TOL[dtype], "so3_exp")
    np.testing.assert_allclose(rot.so3_log(R), omega, rtol=0, atol=TOL[dtype])


@pytest.mark.parametrize("dtype", DTYPES)
@SETTINGS
@given(q=unit_quats())
def test_so3_exp_inverts_log_everywhere(dtype, q):
    R = _pin_matrix(q).astype(dtype)
    omega = rot.so3_log(R)
    assert np.all(np.linalg.norm(omega.astype(np.float64), axis=-1) <= np.pi + TOL[dtype])
    np.testing.assert_allclose(rot.so3_exp(omega), R, rtol=0, atol=TOL[dtype])


@pytest.mark.parametrize("dtype", DTYPES)
@SETTINGS
@given(data=st.data())
def test_so3_exp_agrees_with_pinocchio_for_any_angle(dtype, data):
    omega = data.draw(rotation_vectors(20.0)).astype(dtype)
    R = rot.so3_exp(omega)
    for i in _each(omega.shape[:-1]):
        np.testing.assert_allclose(R[i], pin.exp3(omega[i].astype(np.float64)), rtol=0, atol=TOL[dtype])


@pytest.mark.parametrize("dtype", DTYPES)
@SETTINGS
@given(data=st.data())
def test_axis_angle_round_trip_and_agrees_with_so3_exp(dtype, data):
    shape = data.draw(shapes)
    axis = data.draw(hnp.arrays(np.float64, (*shape, 3), elements=_floats(-5, 5)))
    assume(np.all(np.linalg.norm(axis, axis=-1) > 0.1))
    angle = data.draw(hnp.arrays(np.float64, shape, elements=_floats(1e-3, np.pi - 1e-3)))
    axis, angle = axis.astype(dtype), angle.astype(dtype)
    R = rot.axis_angle_to_matrix(axis, angle)
    unit = axis / np.linalg.norm(axis, axis=-1, keepdims=True)
    np.testing.assert_allclose(R, rot.so3_exp(unit * angle[..., None]), rtol=0, atol=TOL[dtype])
    # negating both axis and angle is the same rotation
    np.testing.assert_allclose(rot.axis_angle_to_matrix(-axis, -angle), R, rtol=0, atol=TOL[dtype])
    k, theta = rot.matrix_to_axis_angle(R)
    np.testing.assert_allclose(theta, angle, rtol=0, atol=TOL[dtype])
    np.testing.assert_allclose(k, unit, rtol=0, atol=10 * TOL[dtype])
    np.testing.assert_allclose(np.linalg.norm(k, axis=-1), 1.0, rtol=0, atol=TOL[dtype])


# --------------------------------------------------------------------------
# SE(3)
# --------------------------------------------------------------------------


@st.composite
def twists(draw: st.DrawFn, max_angle: float) -> np.ndarray:
    shape = draw(shapes)
    omega = draw(rotation_vectors(max_angle, shape))
    v = draw(hnp.arrays(np.float64, (*shape, 3), elements=_floats(-3, 3)))
    return np.concatenate([omega, v], axis=-1)


@pytest.mark.parametrize("dtype", DTYPES)
@SETTINGS
@given(xi=twists(np.pi - 1e-3))
def test_se3_log_inverts_exp_below_half_turn(dtype, xi):
    xi = xi.astype(dtype)
    X = rot.se3_exp(xi)
    back = rot.se3_log(X)
    # the linear part is divided by up to ~θ/2 cot(θ/2) → 0 near π: allow 10×
    np.testing.assert_allclose(back.vector, xi, rtol=0, atol=10 * TOL[dtype])


@pytest.mark.parametrize("dtype", DTYPES)
@SETTINGS
@given(data=st.data())
def test_se3_exp_inverts_log_everywhere(dtype, data):
    from featherdyn.spatial_algebra import PluckerTransform

    shape = data.draw(shapes)
    R = _pin_matrix(data.draw(unit_quats(shape))).astype(dtype)
    p = data.draw(hnp.arrays(np.float64, (*shape, 3), elements=_floats(-3, 3))).astype(dtype)
    X = rot.se3_exp(rot.se3_log(PluckerTransform(R, p)))
    np.testing.assert_allclose(X.rotation, R, rtol=0, atol=TOL[dtype])
    np.testing.assert_allclose(X.translation, p, rtol=0, atol=TOL[dtype])


@SETTINGS
@given(xi=twists(6.0), s=_floats(-2, 2), t=_floats(-2, 2))
def test_se3_exp_is_a_one_parameter_subgroup(xi, s, t):
    """exp(s ξ) exp(t ξ) = exp((s + t) ξ): checked with Pinocchio's SE3 product."""
    Xs, Xt, Xst = rot.se3_exp(s * xi), rot.se3_exp(t * xi), rot.se3_exp((s + t) * xi)
    for i in _each(xi.shape[:-1]):
        composed = pin.SE3(Xs.rotation[i], Xs.translation[i]) * pin.SE3(Xt.rotation[i], Xt.translation[i])
        np.testing.assert_allclose(composed.rotation, Xst.rotation[i], rtol=0, atol=1e-12)
        np.testing.assert_allclose(composed.translation, Xst.translation[i], rtol=0, atol=1e-11)


@SETTINGS
@given(xi=twists(20.0))
def test_se3_exp_agrees_with_pinocchio_for_any_angle(xi):
    X = rot.se3_exp(xi)
    for i in _each(xi.shape[:-1]):
        M = pin.exp6(pin.Motion(xi[i][3:], xi[i][:3]))
        np.testing.assert_allclose(X.rotation[i], M.rotation, rtol=0, atol=1e-12)
        np.testing.assert_allclose(X.translation[i], M.translation, rtol=0, atol=1e-11)


# --------------------------------------------------------------------------
# batch == loop, float32 ≈ float64
# --------------------------------------------------------------------------


def _loop(fn, *args: np.ndarray, trailing: tuple[int, ...]) -> np.ndarray:
    shape = args[0].shape[: args[0].ndim - trailing[0]]
    results = [np.asarray(fn(*(a[i] for a in args))) for i in _each(shape)]
    return np.array(results).reshape(shape + results[0].shape)


def _axis_and_angle(R: np.ndarray) -> np.ndarray:
    # the axis is ill-conditioned near angle 0 (and its sign near π), so compare the rotation it describes
    axis, angle = rot.matrix_to_axis_angle(R)
    return rot.axis_angle_to_matrix(axis, angle)


CASES = {
    # name: (function, inputs built from a unit quaternion q, angles rpy and a rotation vector w,
    #        trailing ndim of the first input)
    "quat_to_matrix": (rot.quat_to_matrix, lambda q, rpy, w: (q,), (1,)),
    "matrix_to_quat": (rot.matrix_to_quat, lambda q, rpy, w: (_pin_matrix(q),), (2,)),
    "quat_multiply": (rot.quat_multiply, lambda q, rpy, w: (q, q[..., ::-1]), (1, 1)),
    "quat_conjugate": (rot.quat_conjugate, lambda q, rpy, w: (q,), (1,)),
    "quat_normalize": (rot.quat_normalize, lambda q, rpy, w: (3 * q,), (1,)),
    "rpy_to_matrix": (rot.rpy_to_matrix, lambda q, rpy, w: (rpy,), (1,)),
    "matrix_to_rpy": (rot.matrix_to_rpy, lambda q, rpy, w: (_pin_matrix(q),), (2,)),
    "axis_angle_to_matrix": (rot.axis_angle_to_matrix, lambda q, rpy, w: (q[..., :3] + 2, rpy[..., 0]), (1, 0)),
    "matrix_to_axis_angle": (_axis_and_angle, lambda q, rpy, w: (_pin_matrix(q),), (2,)),
    "so3_exp": (rot.so3_exp, lambda q, rpy, w: (w,), (1,)),
    "so3_log": (rot.so3_log, lambda q, rpy, w: (_pin_matrix(q),), (2,)),
    "se3_exp": (
        lambda xi: rot.se3_exp(xi).homogeneous(),
        lambda q, rpy, w: (np.concatenate([w, rpy], -1),),
        (1,),
    ),
}


@pytest.mark.parametrize("name", list(CASES))
@pytest.mark.parametrize("dtype", DTYPES)
@settings(derandomize=True, database=None, max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_batch_equals_loop_and_float32_tracks_float64(name, dtype, data):
    fn, build, trailing = CASES[name]
    shape = data.draw(st.sampled_from(BATCH_SHAPES[1:]))
    q = data.draw(unit_quats(shape))
    rpy = data.draw(hnp.arrays(np.float64, (*shape, 3), elements=_floats(-3, 3)))
    w = data.draw(rotation_vectors(3.0, shape))
    args64 = build(q, rpy, w)
    args = tuple(a.astype(dtype) for a in args64)
    batched = np.asarray(fn(*args))
    assert batched.dtype == dtype, name
    looped = _loop(fn, *args, trailing=trailing[:1])
    np.testing.assert_allclose(batched, looped, rtol=0, atol=LOOP_TOL[dtype], err_msg=f"{name}: batch != loop")
    if dtype == np.float32:
        reference = np.asarray(fn(*(a.astype(np.float64) for a in args)))
        if name == "matrix_to_rpy":
            # roll and yaw live on a circle: at ±π the sign of a rounded zero picks −π or π, one angle
            batched = reference + np.angle(np.exp(1j * (batched - reference)))
        np.testing.assert_allclose(batched, reference, rtol=0, atol=TOL[dtype], err_msg=f"{name}: float32 drift")


# --------------------------------------------------------------------------
# SymPy: one symbolic evaluation, many numeric checks
# --------------------------------------------------------------------------

_r, _p, _y = sp.symbols("r p y", real=True)
_RPY_SYMBOLIC = sp.lambdify((_r, _p, _y), sp.Matrix(rot.rpy_to_matrix(np.array([_r, _p, _y], dtype=object))), "numpy")
_th = sp.Symbol("theta", real=True)
_AXIS = np.array([2.0, -1.0, 2.0])
_AXIS_ANGLE_SYMBOLIC = sp.lambdify(
    _th, sp.Matrix(rot.axis_angle_to_matrix(_AXIS, np.array(_th, dtype=object))), "numpy"
)
# SymPy's NumPy printer turns sympy.sinc(x) = sin(x)/x into numpy.sinc(x/π).
_SO3_SYMBOLIC = sp.lambdify((_r, _p, _y), sp.Matrix(rot.so3_exp(np.array([_r, _p, _y], dtype=object))), "numpy")


@SETTINGS
@given(rpy=hnp.arrays(np.float64, 3, elements=_floats(-np.pi, np.pi)))
def test_symbolic_rpy_to_matrix_equals_numeric(rpy):
    symbolic = np.asarray(_RPY_SYMBOLIC(*rpy), dtype=np.float64)
    np.testing.assert_allclose(symbolic, rot.rpy_to_matrix(rpy), rtol=0, atol=1e-15)
    np.testing.assert_allclose(symbolic, pin.rpy.rpyToMatrix(rpy), rtol=0, atol=1e-14)


@SETTINGS
@given(theta=_floats(-10, 10), omega=hnp.arrays(np.float64, 3, elements=_floats(-4, 4)))
def test_symbolic_axis_angle_and_so3_exp_equal_numeric(theta, omega):
    np.testing.assert_allclose(
        np.asarray(_AXIS_ANGLE_SYMBOLIC(theta), dtype=np.float64),
        rot.axis_angle_to_matrix(_AXIS, theta),
        rtol=0,
        atol=1e-14,
    )
    np.testing.assert_allclose(np.asarray(_SO3_SYMBOLIC(*omega), dtype=np.float64), pin.exp3(omega), rtol=0, atol=1e-13)
