"""Rotations: quaternions, roll-pitch-yaw, axis-angle and the exponential maps.

Conventions (fixed, see ``docs/architecture.md``):

* quaternions are stored **(x, y, z, w)** — the order of Pinocchio's, Eigen's
  and ROS's ``coeffs()`` — never (w, x, y, z);
* roll-pitch-yaw is the URDF convention ``R = Rz(yaw) Ry(pitch) Rx(roll)``
  (fixed axes X, then Y, then Z);
* a rotation ``R`` maps coordinates in the rotated frame to coordinates in the
  reference frame (``R`` holds the rotated frame's axes as columns);
* a 6D twist is Featherstone-ordered ``[ω; v]`` (angular first).

Every function broadcasts over leading batch axes and keeps float32 as float32.
:func:`rpy_to_matrix`, :func:`axis_angle_to_matrix`, :func:`quat_to_matrix`,
:func:`so3_exp` and the quaternion algebra also accept object arrays of SymPy
expressions (finiteness and norm checks are skipped for them).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

from .errors import DTypeError, QuaternionNormError, RotationError, SpatialTypeError
from .spatial.ops import matvec, skew_unchecked
from .spatial.validation import as_array, check_rotation, result_dtype
from .tolerances import QUATERNION_NORM, SMALL_ANGLE

if TYPE_CHECKING:
    from .spatial import PluckerTransform, SpatialMotion

__all__ = [
    "axis_angle_to_matrix",
    "matrix_to_axis_angle",
    "matrix_to_quat",
    "matrix_to_rpy",
    "quat_conjugate",
    "quat_multiply",
    "quat_normalize",
    "quat_to_matrix",
    "rpy_to_matrix",
    "se3_exp",
    "se3_log",
    "so3_exp",
    "so3_log",
]

# Below these angles the closed forms divide ~0 by ~0; a Taylor series to θ⁴
# is used instead. Its truncation error (~θ⁶/5040) is below the dtype's
# rounding there, and above them the closed forms lose at most a few digits.



# --------------------------------------------------------------------------
# private helpers: dtype dispatch (NumPy or SymPy) and small kernels
# --------------------------------------------------------------------------


def _is_symbolic(*arrays: np.ndarray) -> bool:
    return any(a.dtype.kind == "O" for a in arrays)


def _sympy_map(fn_name: str, x: np.ndarray) -> np.ndarray:
    import sympy  # only object (SymPy) arrays need it

    fn = getattr(sympy, fn_name)
    return np.asarray(np.frompyfunc(fn, 1, 1)(x), dtype=object)


def _elementwise(fn_name: str, numpy_fn: Callable[[np.ndarray], np.ndarray]) -> Callable[[np.ndarray], np.ndarray]:
    def apply(x: np.ndarray) -> np.ndarray:
        x = np.asarray(x)
        if x.dtype.kind == "O":
            return _sympy_map(fn_name, x)
        return np.asarray(numpy_fn(x))

    return apply


_cos = _elementwise("cos", np.cos)
_sin = _elementwise("sin", np.sin)
_sqrt = _elementwise("sqrt", np.sqrt)


def _small_angle(dtype: np.dtype) -> float:
    return SMALL_ANGLE.of(dtype)


def _require_numeric(arr: np.ndarray, name: str, function: str) -> None:
    if arr.dtype.kind == "O":
        raise DTypeError(
            f"{name}: {function} needs numeric input (float64 or float32), got an object (SymPy) array; "
            "its branch choices cannot be made on symbols"
        )


def _matrix(rows: list[list[Any]]) -> np.ndarray:
    """Assemble ``(..., 3, 3)`` from a 3×3 nested list of broadcastable ``(...)`` entries."""
    flat = np.broadcast_arrays(*[np.asarray(e) for row in rows for e in row])
    entries = np.stack(flat, axis=-1)
    return entries.reshape((*entries.shape[:-1], 3, 3))


def _vee(m: np.ndarray) -> np.ndarray:
    """``(..., 3, 3) -> (..., 3)``: ``vee(R - Rᵀ)`` = twice the axial vector of the skew part."""
    return np.stack([m[..., 2, 1] - m[..., 1, 2], m[..., 0, 2] - m[..., 2, 0], m[..., 1, 0] - m[..., 0, 1]], axis=-1)


def _dot3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.asarray(a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1] + a[..., 2] * b[..., 2])


def _eye_like(shape: tuple[int, ...], dtype: np.dtype) -> np.ndarray:
    return np.broadcast_to(np.eye(3, dtype=dtype), (*shape, 3, 3))


def _quat_norm_error(name: str, norm: np.ndarray, bad: np.ndarray, tol: float) -> QuaternionNormError:
    idx = tuple(int(i) for i in np.argwhere(bad)[0]) if bad.ndim else ()
    where = f" at batch index {idx}" if idx else ""
    found = float(norm[idx])
    if found == 0.0:
        return QuaternionNormError(
            f"{name}: expected a unit quaternion (x, y, z, w), got the zero quaternion{where}; "
            "a zero quaternion has no rotation"
        )
    return QuaternionNormError(
        f"{name}: expected a unit quaternion, got norm {found:.9g}{where} (tolerance {tol:g}); "
        "featherdyn stores quaternions in (x, y, z, w) order (like Pinocchio's coeffs()), "
        "check for (w, x, y, z) input or normalise with quat_normalize"
    )


def _quat_norm(q: np.ndarray) -> np.ndarray:
    return np.asarray(np.sqrt(np.sum(q * q, axis=-1)))


# --------------------------------------------------------------------------
# quaternions
# --------------------------------------------------------------------------


def quat_to_matrix(quat: ArrayLike, *, check_norm: bool = True) -> np.ndarray:
    """Rotation matrix of a unit quaternion in (x, y, z, w) order.

    With ``q = (v, w)``, ``v = (x, y, z)``::

        R = 1 + 2 w [v]× + 2 [v]×²

    For numeric input the factor 2 is taken as ``2 / |q|²``, so with
    ``check_norm=False`` a slightly non-unit quaternion gives the rotation of
    ``q / |q|``. Object (SymPy) input is assumed unit and is not checked.

    Source: Lynch & Park (2017) Appendix B.3; Eigen ``Quaternion::toRotationMatrix``.

    Args:
        quat: `(..., 4)` quaternion ``(x, y, z, w)``.
        check_norm: raise unless ``| |q| − 1 |`` is within 1e-6 (float64) or
            1e-4 (float32).

    Returns:
        `(..., 3, 3)` rotation matrix.

    Raises:
        QuaternionNormError: ``quat`` is zero, or off unit norm with ``check_norm``.
    """
    q = as_array(quat, "quat", (4,))
    if _is_symbolic(q):
        two: Any = 2
    else:
        norm = _quat_norm(q)
        tol = QUATERNION_NORM.of(q.dtype)
        bad = (np.abs(norm - 1) > tol) if check_norm else (norm == 0)
        if np.any(bad):
            raise _quat_norm_error("quat", norm, bad, tol)
        two = 2 / (norm * norm)
    x, y, z, w = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return _matrix(
        [
            [1 - two * (y * y + z * z), two * (x * y - w * z), two * (x * z + w * y)],
            [two * (x * y + w * z), 1 - two * (x * x + z * z), two * (y * z - w * x)],
            [two * (x * z - w * y), two * (y * z + w * x), 1 - two * (x * x + y * y)],
        ]
    )


def matrix_to_quat(rotation: ArrayLike) -> np.ndarray:
    """Unit quaternion (x, y, z, w) of a rotation matrix, with ``w >= 0``.

    Shepperd's method: the symmetric matrix ``K = 4 q qᵀ`` is read off ``R``
    and ``q`` is taken from the row of ``K`` with the largest diagonal entry,
    which is at least 1, so no small number is ever divided by (exact for
    180° rotations too)::

        4 x² = 1 + R00 − R11 − R22      4 xy = R01 + R10    4 xw = R21 − R12
        4 y² = 1 − R00 + R11 − R22      4 xz = R02 + R20    4 yw = R02 − R20
        4 z² = 1 − R00 − R11 + R22      4 yz = R12 + R21    4 zw = R10 − R01
        4 w² = 1 + R00 + R11 + R22
        q = K[i] / (2 sqrt(K[i, i])),   i = argmax diag K

    ``q`` and ``−q`` are the same rotation; the one with ``w >= 0`` is
    returned (for a half turn, ``w = 0`` and the sign is not normalised).

    Source: Shepperd (1978), "Quaternion from rotation matrix", J. Guidance
    Control 1(3); Lynch & Park (2017) Appendix B.3.

    Args:
        rotation: `(..., 3, 3)` rotation matrix.

    Returns:
        `(..., 4)` unit quaternion ``(x, y, z, w)``.

    Raises:
        RotationError: ``rotation`` is not orthonormal with determinant +1.
    """
    R = as_array(rotation, "rotation", (3, 3))
    _require_numeric(R, "rotation", "matrix_to_quat")
    check_rotation(R, "rotation")
    r00, r11, r22 = R[..., 0, 0], R[..., 1, 1], R[..., 2, 2]
    xy, xz, yz = R[..., 0, 1] + R[..., 1, 0], R[..., 0, 2] + R[..., 2, 0], R[..., 1, 2] + R[..., 2, 1]
    xw, yw, zw = R[..., 2, 1] - R[..., 1, 2], R[..., 0, 2] - R[..., 2, 0], R[..., 1, 0] - R[..., 0, 1]
    K = np.stack(
        [
            np.stack([1 + r00 - r11 - r22, xy, xz, xw], axis=-1),
            np.stack([xy, 1 - r00 + r11 - r22, yz, yw], axis=-1),
            np.stack([xz, yz, 1 - r00 - r11 + r22, zw], axis=-1),
            np.stack([xw, yw, zw, 1 + r00 + r11 + r22], axis=-1),
        ],
        axis=-2,
    )
    i = np.argmax(np.diagonal(K, axis1=-2, axis2=-1), axis=-1)
    row = np.take_along_axis(K, i[..., None, None], axis=-2)[..., 0, :]
    q = row / (2 * np.sqrt(np.take_along_axis(row, i[..., None], axis=-1)))
    q = q / _quat_norm(q)[..., None]  # remove the rounding of a nearly orthonormal R
    return np.asarray(np.where(q[..., 3:4] < 0, -q, q))


def quat_multiply(q1: ArrayLike, q2: ArrayLike) -> np.ndarray:
    """Hamilton product ``q1 ⊗ q2`` of quaternions in (x, y, z, w) order.

    With ``q = (v, w)``::

        q1 ⊗ q2 = (w1 v2 + w2 v1 + v1 × v2,  w1 w2 − v1 · v2)

    so that ``quat_to_matrix(q1 ⊗ q2) = quat_to_matrix(q1) @ quat_to_matrix(q2)``.

    Source: Lynch & Park (2017) Appendix B.3; Sola (2017), "Quaternion
    kinematics for the error-state Kalman filter", eq. (12).

    Args:
        q1: `(..., 4)` quaternion ``(x, y, z, w)``.
        q2: `(..., 4)` quaternion ``(x, y, z, w)``; batch axes broadcast with ``q1``'s.

    Returns:
        `(..., 4)` quaternion ``(x, y, z, w)`` (unit if both factors are).
    """
    a = as_array(q1, "q1", (4,))
    b = as_array(q2, "q2", (4,))
    x1, y1, z1, w1 = a[..., 0], a[..., 1], a[..., 2], a[..., 3]
    x2, y2, z2, w2 = b[..., 0], b[..., 1], b[..., 2], b[..., 3]
    return np.stack(
        np.broadcast_arrays(
            w1 * x2 + w2 * x1 + y1 * z2 - z1 * y2,
            w1 * y2 + w2 * y1 + z1 * x2 - x1 * z2,
            w1 * z2 + w2 * z1 + x1 * y2 - y1 * x2,
            w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
        ),
        axis=-1,
    )


def quat_conjugate(quat: ArrayLike) -> np.ndarray:
    """Conjugate of a quaternion in (x, y, z, w) order (the inverse of a unit one).

    ::

        q* = (−x, −y, −z, w),    q ⊗ q* = |q|² (0, 0, 0, 1)

    Source: Lynch & Park (2017) Appendix B.3.

    Args:
        quat: `(..., 4)` quaternion ``(x, y, z, w)``.

    Returns:
        `(..., 4)` conjugate quaternion.
    """
    q = as_array(quat, "quat", (4,))
    return np.concatenate([-q[..., :3], q[..., 3:]], axis=-1)


def quat_normalize(quat: ArrayLike) -> np.ndarray:
    """Scale a quaternion to unit norm.

    ::

        q̂ = q / |q|

    Object (SymPy) input is divided by ``sympy.sqrt(x² + y² + z² + w²)``.

    Source: Lynch & Park (2017) Appendix B.3.

    Args:
        quat: `(..., 4)` non-zero quaternion ``(x, y, z, w)``.

    Returns:
        `(..., 4)` unit quaternion.

    Raises:
        QuaternionNormError: ``quat`` is the zero quaternion.
    """
    q = as_array(quat, "quat", (4,))
    if _is_symbolic(q):
        return np.asarray(q / _sqrt(np.sum(q * q, axis=-1))[..., None])
    # Scale by the largest entry first so tiny or huge quaternions do not under/overflow.
    scale = np.max(np.abs(q), axis=-1, keepdims=True)
    zero = scale[..., 0] == 0
    if np.any(zero):
        raise _quat_norm_error("quat", np.zeros_like(scale[..., 0]), zero, 0.0)
    q = q / scale
    return np.asarray(q / _quat_norm(q)[..., None])


# --------------------------------------------------------------------------
# roll-pitch-yaw (URDF)
# --------------------------------------------------------------------------


def rpy_to_matrix(rpy: ArrayLike) -> np.ndarray:
    """Rotation matrix of URDF roll-pitch-yaw angles.

    Roll about the fixed X axis, then pitch about fixed Y, then yaw about
    fixed Z::

        R = Rz(yaw) Ry(pitch) Rx(roll)

          = [ cy cp   cy sp sr − sy cr   cy sp cr + sy sr ]
            [ sy cp   sy sp sr + cy cr   sy sp cr − cy sr ]
            [ −sp     cp sr              cp cr            ]

    Source: URDF specification, ``<origin rpy="...">``; Pinocchio ``rpy::rpyToMatrix``.

    Args:
        rpy: `(..., 3)` angles ``(roll, pitch, yaw)`` in radians (SymPy allowed).

    Returns:
        `(..., 3, 3)` rotation matrix.
    """
    a = as_array(rpy, "rpy", (3,))
    c, s = _cos(a), _sin(a)
    cr, cp, cy = c[..., 0], c[..., 1], c[..., 2]
    sr, sp, sy = s[..., 0], s[..., 1], s[..., 2]
    return _matrix(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def matrix_to_rpy(rotation: ArrayLike) -> np.ndarray:
    """URDF roll-pitch-yaw angles of a rotation matrix, pitch in ``[−π/2, π/2]``.

    Yaw is read first, then roll from the matrix with the yaw taken out, which
    stays accurate close to gimbal lock::

        yaw   = atan2(R10, R00)
        R'    = Rz(−yaw) R = Ry(pitch) Rx(roll)
        pitch = atan2(−R20, R'00),     R'00 = sqrt(R00² + R10²) = cos(pitch)
        roll  = atan2(−R'12, R'11)

    At gimbal lock (``cos(pitch)`` below a few ulps, i.e. ``pitch = ±π/2``) only
    ``yaw ∓ roll`` is defined; the convention is **roll = 0** and
    ``yaw = atan2(−R01, R11)``. Then ``rpy_to_matrix(matrix_to_rpy(R)) = R``
    still holds. (Pinocchio 4 splits the angle differently there; the matrices
    agree.) Roll and yaw are in ``[−π, π]``.

    Source: URDF specification; Slabaugh, "Computing Euler angles from a
    rotation matrix"; Eigen ``MatrixBase::eulerAngles``.

    Args:
        rotation: `(..., 3, 3)` rotation matrix.

    Returns:
        `(..., 3)` angles ``(roll, pitch, yaw)``.

    Raises:
        RotationError: ``rotation`` is not orthonormal with determinant +1.
    """
    R = as_array(rotation, "rotation", (3, 3))
    _require_numeric(R, "rotation", "matrix_to_rpy")
    check_rotation(R, "rotation")
    cos_pitch = np.hypot(R[..., 0, 0], R[..., 1, 0])
    locked = cos_pitch <= 8 * np.finfo(R.dtype).eps
    yaw = np.where(locked, np.arctan2(-R[..., 0, 1], R[..., 1, 1]), np.arctan2(R[..., 1, 0], R[..., 0, 0]))
    cy, sy = np.cos(yaw), np.sin(yaw)
    pitch = np.arctan2(-R[..., 2, 0], cos_pitch)
    roll = np.arctan2(sy * R[..., 0, 2] - cy * R[..., 1, 2], cy * R[..., 1, 1] - sy * R[..., 0, 1])
    roll = np.where(locked, np.zeros_like(roll), roll)
    return np.stack([roll, pitch, yaw], axis=-1)


# --------------------------------------------------------------------------
# axis-angle and the exponential map of SO(3)
# --------------------------------------------------------------------------


def so3_exp(omega: ArrayLike) -> np.ndarray:
    """Exponential map of so(3): the rotation by ``|ω|`` about ``ω`` (Rodrigues).

    ::

        R = exp([ω]×) = 1 + (sin θ / θ) [ω]× + ((1 − cos θ) / θ²) [ω]×²,   θ = |ω|

    ``(1 − cos θ) / θ²`` is evaluated as ``2 (sin(θ/2) / θ)²`` (no
    cancellation), and ``sin θ / θ`` by its Taylor series ``1 − θ²/6 + θ⁴/120``
    below a small-angle threshold, so tiny rotations are exact to rounding.
    Object (SymPy) input uses ``sympy.sinc``.

    Source: Lynch & Park (2017) §3.2.3.3, Proposition 3.11; Pinocchio ``exp3``.

    Args:
        omega: `(..., 3)` rotation vector ``θ k`` (unit axis ``k``, angle ``θ``).

    Returns:
        `(..., 3, 3)` rotation matrix.
    """
    w = as_array(omega, "omega", (3,))
    W = skew_unchecked(w)
    batch = W.shape[:-2]
    if _is_symbolic(w):
        theta = _sqrt(_dot3(w, w))
        A = _sympy_map("sinc", theta)
        half_sinc = _sympy_map("sinc", theta / 2)
        B = np.asarray(half_sinc * half_sinc / 2)
        eye = _object_eye(batch)
    else:
        A, B = _rodrigues_coefficients(np.sqrt(_dot3(w, w)))
        eye = _eye_like(batch, W.dtype)
    return np.asarray(eye + A[..., None, None] * W + B[..., None, None] * (W @ W))


def _object_eye(shape: tuple[int, ...]) -> np.ndarray:
    import sympy

    eye = np.array([[sympy.Integer(int(i == j)) for j in range(3)] for i in range(3)], dtype=object)
    return np.broadcast_to(eye, (*shape, 3, 3))


def _rodrigues_coefficients(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(sin θ / θ, (1 − cos θ) / θ²)`` for numeric ``θ >= 0``, exact near 0."""
    small = theta < _small_angle(theta.dtype)
    t = np.where(small, np.ones_like(theta), theta)
    t2 = theta * theta
    A = np.where(small, 1 - t2 / 6 * (1 - t2 / 20), np.sin(t) / t)
    half_sinc = np.where(small, 1 - t2 / 24 * (1 - t2 / 80), np.sin(t / 2) / (t / 2))
    return np.asarray(A), np.asarray(half_sinc * half_sinc / 2)


def so3_log(rotation: ArrayLike) -> np.ndarray:
    """Logarithm of SO(3): the rotation vector ``ω = θ k`` with ``θ`` in ``[0, π]``.

    The angle comes from both the trace and the skew part, which is accurate
    at every angle; the axis from the skew part, except for ``θ > 2π/3``
    (``cos θ < −½``), where ``sin θ → 0`` and the axis is read from the
    symmetric part instead (largest diagonal entry, no division by ``sin θ``)::

        cos θ = (tr R − 1) / 2,    sin θ = |vee(R − Rᵀ)| / 2,    θ = atan2(sin θ, cos θ)
        ω = (θ / (2 sin θ)) vee(R − Rᵀ)                                 (θ <= 2π/3)
        k kᵀ = (½(R + Rᵀ) − cos θ 1) / (1 − cos θ),   ω = θ k,
        sign(k) = sign(k · vee(R − Rᵀ))                                 (θ > 2π/3)

    At exactly ``θ = π`` both ``±π k`` are logarithms; either may be returned.

    Source: Lynch & Park (2017) §3.2.3.3, Algorithm for the matrix logarithm;
    Pinocchio ``log3``.

    Args:
        rotation: `(..., 3, 3)` rotation matrix.

    Returns:
        `(..., 3)` rotation vector with norm in ``[0, π]``.

    Raises:
        RotationError: ``rotation`` is not orthonormal with determinant +1.
    """
    R = as_array(rotation, "rotation", (3, 3))
    _require_numeric(R, "rotation", "so3_log")
    check_rotation(R, "rotation")
    return _so3_log(R)


def _so3_log(R: np.ndarray) -> np.ndarray:
    batch = R.shape[:-2]
    R = R.reshape((-1, 3, 3))
    skew2 = _vee(R)  # 2 sin θ k
    cos_t = np.clip((np.trace(R, axis1=-2, axis2=-1) - 1) / 2, -1, 1)
    sin_t = np.sqrt(_dot3(skew2, skew2)) / 2
    theta = np.arctan2(sin_t, cos_t)

    # Away from π: ω = θ / (2 sin θ) · vee(R − Rᵀ), with θ / sin θ ≈ 1 + θ²/6 + 7θ⁴/360 near 0.
    small = theta < _small_angle(R.dtype)
    near_pi = cos_t < -0.5  # these rows are replaced below
    t = np.where(small | near_pi, np.ones_like(theta), theta)
    s = np.where(small | near_pi, np.ones_like(sin_t), sin_t)
    t2 = theta * theta
    factor = np.where(small, 1 + t2 / 6 * (1 + 7 * t2 / 60), t / s)
    omega = (factor / 2)[:, None] * skew2

    # Near π (cos θ < −1/2): k kᵀ from the symmetric part, the column with the largest diagonal.
    if np.any(near_pi):
        Rn, cn = R[near_pi], cos_t[near_pi]
        sym = (Rn + np.swapaxes(Rn, -1, -2)) / 2
        kk = (sym - cn[:, None, None] * np.eye(3, dtype=R.dtype)) / (1 - cn)[:, None, None]
        i = np.argmax(np.diagonal(kk, axis1=-2, axis2=-1), axis=-1)
        col = np.take_along_axis(kk, i[:, None, None], axis=-1)[..., 0]
        k = col / np.sqrt(np.take_along_axis(col, i[:, None], axis=-1))
        k = k / np.sqrt(_dot3(k, k))[:, None]
        k = np.where((_dot3(k, skew2[near_pi]) < 0)[:, None], -k, k)
        omega[near_pi] = theta[near_pi][:, None] * k
    return omega.reshape((*batch, 3))


def axis_angle_to_matrix(axis: ArrayLike, angle: ArrayLike) -> np.ndarray:
    """Rotation matrix of a rotation by ``angle`` about ``axis`` (normalised here).

    ::

        k = axis / |axis|
        R = 1 + sin θ [k]× + (1 − cos θ) [k]×²

    An object (SymPy) axis is divided by ``sympy.sqrt(k·k)`` unchecked; a
    numeric axis with symbolic angles (a joint axis) is normalised numerically.

    Source: Lynch & Park (2017) §3.2.3.3, eq. (3.51) (Rodrigues' formula); URDF
    ``<axis>`` (need not be unit).

    Args:
        axis: `(..., 3)` non-zero rotation axis, any length.
        angle: `(...)` angle in radians; batch axes broadcast with ``axis``'s.

    Returns:
        `(..., 3, 3)` rotation matrix.

    Raises:
        RotationError: ``axis`` has zero length.
    """
    a = as_array(axis, "axis", (3,))
    theta = as_array(angle, "angle", ())
    if _is_symbolic(a):
        k = a / _sqrt(_dot3(a, a))[..., None]
    else:
        scale = np.max(np.abs(a), axis=-1)
        zero = scale == 0
        if np.any(zero):
            idx = tuple(int(i) for i in np.argwhere(zero)[0]) if zero.ndim else ()
            where = f" at batch index {idx}" if idx else ""
            raise RotationError(f"axis: zero-length axis{where}; a rotation axis must be a non-zero 3-vector")
        a = a / scale[..., None]  # avoid under/overflow of |axis|²
        k = a / np.sqrt(_dot3(a, a))[..., None]
    dtype = result_dtype(k, theta)
    if dtype.kind != "O":
        k = k.astype(dtype, copy=False)
        theta = theta.astype(dtype, copy=False)
    K = skew_unchecked(k)
    s = _sin(theta)[..., None, None]
    one_minus_c = np.asarray(1 - _cos(theta))[..., None, None]
    batch = np.broadcast_shapes(K.shape[:-2], theta.shape)
    eye = _object_eye(batch) if dtype.kind == "O" else _eye_like(batch, dtype)
    return np.asarray(eye + s * K + one_minus_c * (K @ K))


def matrix_to_axis_angle(rotation: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Unit axis and angle in ``[0, π]`` of a rotation matrix.

    ::

        θ k = so3_log(R),    θ = |so3_log(R)|,    k = so3_log(R) / θ

    For the identity (``θ = 0``) the axis is undefined; by convention
    ``k = (0, 0, 1)`` is returned. For a half turn both ``±k`` are valid.

    Source: Lynch & Park (2017) §3.2.3.3.

    Args:
        rotation: `(..., 3, 3)` rotation matrix.

    Returns:
        ``(axis, angle)``: `(..., 3)` unit axis and `(...)` angle.

    Raises:
        RotationError: ``rotation`` is not orthonormal with determinant +1.
    """
    R = as_array(rotation, "rotation", (3, 3))
    _require_numeric(R, "rotation", "matrix_to_axis_angle")
    check_rotation(R, "rotation")
    omega = _so3_log(R)
    theta = np.sqrt(_dot3(omega, omega))
    zero = theta == 0
    safe = np.where(zero, np.ones_like(theta), theta)
    z_axis = np.array([0, 0, 1], dtype=R.dtype)
    axis = np.where(zero[..., None], z_axis, omega / safe[..., None])
    return np.asarray(axis), np.asarray(theta)


# --------------------------------------------------------------------------
# the exponential map of SE(3)
# --------------------------------------------------------------------------


def _se3_coefficients(theta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``((1 − cos θ) / θ², (θ − sin θ) / θ³)``, by Taylor series near 0."""
    small = theta < _small_angle(theta.dtype)
    t = np.where(small, np.ones_like(theta), theta)
    t2 = theta * theta
    _, B = _rodrigues_coefficients(theta)
    C = np.where(small, 1 / 6 - t2 / 120 * (1 - t2 / 42), (t - np.sin(t)) / (t * t * t))
    return B, np.asarray(C)


def se3_exp(twist: ArrayLike | SpatialMotion) -> PluckerTransform:
    """Exponential map of se(3): the transform reached by following ``twist`` for unit time.

    With the twist ``[ω; v]`` (Featherstone order, angular first)::

        R = so3_exp(ω)
        p = V(ω) v,    V(ω) = 1 + ((1 − cos θ) / θ²) [ω]× + ((θ − sin θ) / θ³) [ω]×²,   θ = |ω|

    with Taylor series for the coefficients near ``θ = 0``. The result is the
    pose ``PluckerTransform(R, p)``; it equals Pinocchio's
    ``pin.exp6(pin.Motion(v, ω))`` (Pinocchio's ``Motion`` takes linear first).

    Source: Lynch & Park (2017) §3.3.3.2, Proposition 3.25; Pinocchio ``exp6``.

    Args:
        twist: a :class:`~featherdyn.spatial_algebra.SpatialMotion` or a
            `(..., 6)` array ``[ω; v]``.

    Returns:
        A ``PluckerTransform`` with `(..., 3, 3)` rotation and `(..., 3)` translation.

    Raises:
        SpatialTypeError: ``twist`` is a force, not a motion.
    """
    from .spatial import PluckerTransform, SpatialForce, SpatialMotion

    if isinstance(twist, SpatialForce):
        raise SpatialTypeError(
            "twist: expected a SpatialMotion (or a (..., 6) array [ω; v]), got a SpatialForce; "
            "the exponential map takes a motion vector"
        )
    xi = as_array(twist.vector if isinstance(twist, SpatialMotion) else twist, "twist", (6,))
    _require_numeric(xi, "twist", "se3_exp")
    omega, v = xi[..., :3], xi[..., 3:]
    theta = np.sqrt(_dot3(omega, omega))
    A, B = _rodrigues_coefficients(theta)
    _, C = _se3_coefficients(theta)
    W = skew_unchecked(omega)
    W2 = W @ W
    eye = _eye_like(W.shape[:-2], W.dtype)
    rotation = eye + A[..., None, None] * W + B[..., None, None] * W2
    V = eye + B[..., None, None] * W + C[..., None, None] * W2
    return PluckerTransform(rotation=np.asarray(rotation), translation=matvec(V, v))


def se3_log(transform: PluckerTransform) -> SpatialMotion:
    """Logarithm of SE(3): the twist ``[ω; v]`` with ``se3_exp([ω; v]) = transform``.

    ::

        ω = so3_log(R),   θ = |ω|  in [0, π]
        v = V(ω)⁻¹ p,     V(ω)⁻¹ = 1 − ½ [ω]× + ((1 − (θ/2) cot(θ/2)) / θ²) [ω]×²

    The coefficient is finite up to and including ``θ = π`` and replaced by its
    Taylor series ``1/12 + θ²/720 + θ⁴/30240`` near 0. Equals Pinocchio's
    ``pin.log6(pin.SE3(R, p))`` with its ``.linear`` and ``.angular`` swapped
    into Featherstone order.

    Source: Lynch & Park (2017) §3.3.3.2, Algorithm for the matrix logarithm of
    rigid-body motions; Pinocchio ``log6``.

    Args:
        transform: a ``PluckerTransform`` (rotation `(..., 3, 3)`, translation `(..., 3)`).

    Returns:
        ``SpatialMotion`` with `(..., 3)` angular ``ω`` and linear ``v`` parts.

    Raises:
        SpatialTypeError: ``transform`` is not a ``PluckerTransform``.
        RotationError: its rotation is not orthonormal with determinant +1.
    """
    from .spatial import PluckerTransform, SpatialMotion

    if not isinstance(transform, PluckerTransform):
        raise SpatialTypeError(
            f"transform: expected a PluckerTransform, got {type(transform).__name__}; "
            "build one with PluckerTransform(rotation, translation)"
        )
    R = as_array(transform.rotation, "transform.rotation", (3, 3))
    p = as_array(transform.translation, "transform.translation", (3,))
    _require_numeric(R, "transform.rotation", "se3_log")
    check_rotation(R, "transform.rotation")
    omega = _so3_log(R)
    theta = np.sqrt(_dot3(omega, omega))
    small = theta < _small_angle(theta.dtype)
    t = np.where(small, np.ones_like(theta), theta)
    t2 = theta * theta
    half = t / 2
    D = np.where(small, 1 / 12 + t2 / 720 * (1 + t2 / 42), (1 - half * np.cos(half) / np.sin(half)) / (t * t))
    W = skew_unchecked(omega)
    V_inv = _eye_like(W.shape[:-2], W.dtype) - W / 2 + D[..., None, None] * (W @ W)
    v = matvec(V_inv, p)
    omega, v = (x.copy() for x in np.broadcast_arrays(omega, v))
    return SpatialMotion(angular=omega, linear=v)
