"""Joint models: each joint is a small immutable value.

A joint connects a predecessor frame (the joint frame, fixed in the parent
body) to a successor frame (the child body's frame). It gives

* ``pose(q)``: the pose of the successor frame in the joint frame, a
  :class:`~featherdyn.PluckerTransform` (Pinocchio's ``jdata.M``); the
  Featherstone joint transform is its inverse action, ``X_J = pose(q)⁻¹``;
* ``S``: the motion subspace `(6, nv)` in successor coordinates, constant for
  every joint type here, so the joint velocity is ``v_J = S q̇`` and the bias
  ``c_J = Ṡ q̇ = 0`` (RBDA table 4.1);
* its part of configuration space: ``neutral``, ``integrate``,
  ``difference``, ``random``, ``normalize``, ``is_normalized``.

=============  ===  ===  ============================================  ==========================
joint          nq   nv   q                                             v
=============  ===  ===  ============================================  ==========================
revolute        1    1   angle                                         angular rate
prismatic       1    1   displacement                                  linear rate
spherical       4    3   unit quaternion (x, y, z, w)                  ω in the child frame
free-flyer      7    6   [x y z, qx qy qz qw] (pose in the parent)     [ω; v] in the child frame
planar          3    3   [x, y, θ] in the plane normal to ``normal``   [ω, v_x, v_y] child frame
=============  ===  ===  ============================================  ==========================

Source: RBDA (2008) §4.4 and table 4.1; chapter §8.3; docs/architecture.md ("Conventions").
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import Any, ClassVar, TypeVar

import numpy as np
from numpy.typing import ArrayLike

from . import rotation as rot
from .errors import ModelError, PhysicalityWarning, QuaternionNormError
from .spatial import PluckerTransform, SpatialMotion
from .spatial.validation import as_array
from .tolerances import QUATERNION_NORM, SMALL_ANGLE, UNIT_AXIS

_AxisJoint = TypeVar("_AxisJoint", "RevoluteJoint", "PrismaticJoint")

__all__ = [
    "Joint",
    "RevoluteJoint",
    "PrismaticJoint",
    "SphericalJoint",
    "FreeFlyerJoint",
    "PlanarJoint",
    "unit_axis",
]


def unit_axis(axis: ArrayLike, name: str = "axis", *, warn: bool = True, stacklevel: int = 3) -> np.ndarray:
    """Normalise a joint axis `(3,)`; zero length raises, non-unit length warns.

    Real URDFs have axes like ``0 0 -1`` (kept: the sign is meaningful) and
    ``0 0.7 0.7`` (normalised, with a :class:`PhysicalityWarning`).

    Args:
        axis: `(3,)` the axis, any non-zero length.
        name: the argument name for messages.
        warn: warn when the length is off 1 by more than 1e-6.
        stacklevel: passed to :func:`warnings.warn` (3 = the caller of the caller).

    Raises:
        ModelError: the axis is not a single 3-vector or has zero length.
    """
    a = as_array(axis, name, (3,)).astype(np.float64)
    if a.ndim != 1:
        raise ModelError(f"{name}: expected a single axis of shape (3,), got shape {a.shape}")
    n = float(np.linalg.norm(a))
    if n < 1e-12:
        raise ModelError(f"{name}: zero-length joint axis {a.tolist()}")
    if warn and abs(n - 1.0) > UNIT_AXIS:
        warnings.warn(
            f"{name}: axis {a.tolist()} has length {n:.6g}; normalised", PhysicalityWarning, stacklevel=stacklevel
        )
    out = a / n
    out.setflags(write=False)
    return out


def _with_unit_axis(cls: type[_AxisJoint], axis: Any) -> _AxisJoint:
    """``cls(axis)`` for an axis a loader has made unit itself (finite, length 1 within round-off): the
    constructor's conversion, length check and normalisation skipped."""
    obj = object.__new__(cls)
    object.__setattr__(obj, "axis", _frozen(np.array(axis, dtype=np.float64)))
    return obj


def _skew3(w: np.ndarray) -> np.ndarray:
    x, y, z = (float(c) for c in w)
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def _frozen(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


def _q(q: ArrayLike, nq: int, name: str = "q") -> np.ndarray:
    return as_array(q, name, (nq,))


def _like(const: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``const`` (a float64 model constant) in the floating dtype of ``x`` (float32 stays float32)."""
    return const.astype(x.dtype) if x.dtype.kind == "f" else const


def _batch(size: Any) -> tuple[int, ...]:
    if size is None:
        return ()
    if isinstance(size, (int, np.integer)):
        return (int(size),)
    return tuple(int(s) for s in size)


def _limits(lower: Any, upper: Any, n: int) -> tuple[np.ndarray, np.ndarray]:
    lo = np.full(n, -np.inf) if lower is None else np.broadcast_to(np.asarray(lower, dtype=np.float64), (n,))
    hi = np.full(n, np.inf) if upper is None else np.broadcast_to(np.asarray(upper, dtype=np.float64), (n,))
    return lo, hi


_NO_LIMIT = 1e6


def _box(lower: np.ndarray, upper: np.ndarray, lo_default: Any, hi_default: Any) -> tuple[np.ndarray, np.ndarray]:
    """The sampling box: the limits where finite, else the default box.

    A half-infinite interval that misses the default box is given the
    default box's width on its finite side, so samples always respect the
    finite limit. Limits beyond ±1e6 count as unbounded: URDFs write "no
    limit" as ±1e16, and sampling angles of 1e15 rad loses all precision.
    """
    lo_d = np.broadcast_to(np.asarray(lo_default, dtype=np.float64), lower.shape)
    hi_d = np.broadcast_to(np.asarray(hi_default, dtype=np.float64), upper.shape)
    width = hi_d - lo_d
    with np.errstate(invalid="ignore"):
        fin_lo = np.isfinite(lower) & (np.abs(lower) < _NO_LIMIT)
        fin_hi = np.isfinite(upper) & (np.abs(upper) < _NO_LIMIT)
        lo = np.where(fin_lo, lower, np.where(fin_hi & (upper < lo_d), upper - width, lo_d))
        hi = np.where(fin_hi, upper, np.where(fin_lo & (lower > hi_d), lower + width, hi_d))
    return lo, hi


def _uniform(rng: np.random.Generator, lo: np.ndarray, hi: np.ndarray, shape: tuple[int, ...]) -> np.ndarray:
    return np.asarray(lo + (hi - lo) * rng.random(shape + lo.shape))


def _uniform_quat(rng: np.random.Generator, shape: tuple[int, ...]) -> np.ndarray:
    """Uniformly distributed unit quaternions (Shoemake 1992), xyzw, ``w >= 0``."""
    u1, u2, u3 = (rng.random(shape) for _ in range(3))
    a, b = np.sqrt(1 - u1), np.sqrt(u1)
    q = np.stack([a * np.sin(2 * np.pi * u2), a * np.cos(2 * np.pi * u2), b * np.sin(2 * np.pi * u3),
                  b * np.cos(2 * np.pi * u3)], axis=-1)
    return np.where(q[..., 3:] < 0, -q, q)


def _check_unit_quat(quat: np.ndarray, name: str) -> None:
    """Raise :class:`QuaternionNormError` naming ``name`` unless every `(..., 4)` quaternion is unit."""
    if quat.dtype.kind == "O":
        return
    tol = QUATERNION_NORM.of(quat.dtype)
    norm = np.sqrt(np.sum(quat * quat, axis=-1))
    bad = np.abs(norm - 1) > tol
    if np.any(bad):
        idx = tuple(int(i) for i in np.argwhere(bad)[0]) if bad.ndim else ()
        where = f" at batch index {idx}" if idx else ""
        raise QuaternionNormError(
            f"{name}: expected a unit quaternion (x, y, z, w), got norm {float(norm[idx]):.9g}{where} "
            f"(tolerance {tol:g}); normalise it first"
        )


def _quat_exp(omega: np.ndarray) -> np.ndarray:
    """`(..., 3) -> (..., 4)`: the unit quaternion of the rotation vector ``ω`` (xyzw)::

        exp(ω) = (sin(θ/2) ω/θ, cos(θ/2)),   θ = |ω|
    """
    theta = np.sqrt(np.sum(omega * omega, axis=-1))
    small = theta < SMALL_ANGLE.of(omega.dtype)
    t = np.where(small, np.ones_like(theta), theta)
    t2 = theta * theta
    half_sinc = np.where(small, 0.5 - t2 / 48 * (1 - t2 / 80), np.sin(t / 2) / t)  # sin(θ/2)/θ
    return np.concatenate([half_sinc[..., None] * omega, np.cos(theta / 2)[..., None]], axis=-1)


def _quat_mul_normalized(q0: np.ndarray, dq: np.ndarray) -> np.ndarray:
    out = rot.quat_multiply(q0, dq)
    return np.asarray(out / np.sqrt(np.sum(out * out, axis=-1, keepdims=True)))


class Joint:
    """Base class of the joint models (see the module docstring for the contract).

    Joints are immutable values; two joints are equal when they have the same
    type and the same parameters (axis, normal).
    """

    __slots__ = ()
    kind: ClassVar[str] = "joint"
    nq: ClassVar[int] = 0
    nv: ClassVar[int] = 0

    def _params(self) -> tuple[np.ndarray, ...]:
        return ()

    def __eq__(self, other: object) -> bool:
        if type(self) is not type(other) or not isinstance(other, Joint):
            return NotImplemented
        return all(np.array_equal(a, b) for a, b in zip(self._params(), other._params(), strict=True))

    def __hash__(self) -> int:
        return hash((type(self).__name__, *(tuple(p.tolist()) for p in self._params())))

    @property
    def S(self) -> np.ndarray:
        """`(6, nv)` motion subspace in successor coordinates (constant)."""
        raise NotImplementedError

    def pose(self, q: ArrayLike) -> PluckerTransform:
        """The pose of the successor frame in the joint frame for ``q`` `(..., nq)`."""
        raise NotImplementedError

    def neutral(self) -> np.ndarray:
        """`(nq,)` the neutral configuration (zero angle, identity quaternion)."""
        return np.zeros(self.nq)

    def integrate(self, q: ArrayLike, v: ArrayLike) -> np.ndarray:
        """`(..., nq)`: the configuration reached from ``q`` moving with ``v`` `(..., nv)` for unit time.

        Batch axes of ``q`` and ``v`` broadcast. For the vector-space joints::

            q' = q + v
        """
        return np.asarray(_q(q, self.nq) + as_array(v, "v", (self.nv,)))

    def difference(self, q0: ArrayLike, q1: ArrayLike) -> np.ndarray:
        """`(..., nv)`: the velocity ``v`` with ``integrate(q0, v) = q1``."""
        return np.asarray(_q(q1, self.nq, "q1") - _q(q0, self.nq, "q0"))

    def random(
        self, rng: np.random.Generator | int | None = None, lower: ArrayLike | None = None, upper: ArrayLike | None = None, size: int | tuple[int, ...] | None = None
    ) -> np.ndarray:
        """Random configurations `(*size, nq)` uniform within ``[lower, upper]`` `(nq,)`.

        Infinite bounds are replaced by ``±π`` (angles) or ``±1`` (lengths);
        ``rng`` is a :class:`numpy.random.Generator`, a seed or ``None``.
        """
        lo, hi = _box(*_limits(lower, upper, self.nq), -np.pi, np.pi)
        return _uniform(np.random.default_rng(rng), lo, hi, _batch(size))

    def normalize(self, q: ArrayLike) -> np.ndarray:
        """`(..., nq)` the nearest valid configuration (unit quaternions); identity for vector joints."""
        return np.array(_q(q, self.nq))

    def is_normalized(self, q: ArrayLike, tol: float = 1e-10) -> Any:
        """`(...)` bool: whether ``q`` is a valid configuration (``| |quat| − 1 | <= tol``)."""
        qq = _q(q, self.nq)
        return np.ones(qq.shape[:-1], dtype=bool)

    def motion(self, qd: ArrayLike) -> SpatialMotion:
        """Joint velocity ``v_J = S q̇`` `(..., 6)` in successor coordinates."""
        qd = as_array(qd, "qd", (self.nv,))
        return SpatialMotion.from_vector(qd @ self.S.T.astype(qd.dtype))


@dataclass(frozen=True, slots=True, repr=False, eq=False)
class RevoluteJoint(Joint):
    """Rotation by ``q`` about a unit ``axis`` (URDF ``revolute`` and ``continuous``).

    ::

        pose(q) = (exp(q [a]×), 0),    S = [a; 0]

    ``integrate`` and ``difference`` are ``q + v`` and ``q1 − q0`` (no wrapping,
    as Pinocchio's ``JointModelRX`` / ``JointModelRevoluteUnaligned``).
    """

    axis: np.ndarray = field(default_factory=lambda: _frozen(np.array([0.0, 0.0, 1.0])))
    kind: ClassVar[str] = "revolute"
    nq: ClassVar[int] = 1
    nv: ClassVar[int] = 1

    def __post_init__(self) -> None:
        object.__setattr__(self, "axis", unit_axis(self.axis, stacklevel=4))

    def _params(self) -> tuple[np.ndarray, ...]:
        return (self.axis,)

    @property
    def S(self) -> np.ndarray:
        return _frozen(np.concatenate([self.axis, np.zeros(3)])[:, None])

    def pose(self, q: ArrayLike) -> PluckerTransform:
        qq = _q(q, 1)
        if qq.dtype.kind == "O":  # SymPy: symbolic cos/sin
            R = rot.axis_angle_to_matrix(_like(self.axis, qq), qq[..., 0])
        else:  # Rodrigues with the constant [a]× and [a]×² of this axis: R = 1 + sin q [a]× + (1 − cos q) [a]×²
            K = _skew3(self.axis).astype(qq.dtype)
            th = qq[..., 0, None, None]
            R = np.eye(3, dtype=qq.dtype) + np.sin(th) * K + (1 - np.cos(th)) * (K @ K)
        return PluckerTransform._wrap(R, np.zeros(qq.shape[:-1] + (3,), dtype=R.dtype), None, None)

    def __repr__(self) -> str:
        return f"RevoluteJoint(axis={self.axis.tolist()})"


@dataclass(frozen=True, slots=True, repr=False, eq=False)
class PrismaticJoint(Joint):
    """Translation by ``q`` along a unit ``axis`` (URDF ``prismatic``).

    ::

        pose(q) = (1, q a),    S = [0; a]
    """

    axis: np.ndarray = field(default_factory=lambda: _frozen(np.array([0.0, 0.0, 1.0])))
    kind: ClassVar[str] = "prismatic"
    nq: ClassVar[int] = 1
    nv: ClassVar[int] = 1

    def __post_init__(self) -> None:
        object.__setattr__(self, "axis", unit_axis(self.axis, stacklevel=4))

    def _params(self) -> tuple[np.ndarray, ...]:
        return (self.axis,)

    @property
    def S(self) -> np.ndarray:
        return _frozen(np.concatenate([np.zeros(3), self.axis])[:, None])

    def pose(self, q: ArrayLike) -> PluckerTransform:
        qq = _q(q, 1)
        p = qq[..., 0:1] * _like(self.axis, qq)
        eye = np.broadcast_to(np.eye(3), qq.shape[:-1] + (3, 3)).astype(p.dtype)
        return PluckerTransform(eye, p, validate=False)

    def random(
        self, rng: np.random.Generator | int | None = None, lower: ArrayLike | None = None, upper: ArrayLike | None = None, size: int | tuple[int, ...] | None = None
    ) -> np.ndarray:
        lo, hi = _box(*_limits(lower, upper, 1), -1.0, 1.0)
        return _uniform(np.random.default_rng(rng), lo, hi, _batch(size))

    def __repr__(self) -> str:
        return f"PrismaticJoint(axis={self.axis.tolist()})"


@dataclass(frozen=True, slots=True, repr=True, eq=False)
class SphericalJoint(Joint):
    """A ball joint: ``q`` a unit quaternion (x, y, z, w), ``v = ω`` in the child frame.

    ::

        pose(q) = (R(q), 0),   S = [1₃; 0]
        integrate:  q' = q ⊗ exp(ω)         (R' = R exp([ω]×))
        difference: ω = log(R(q0)ᵀ R(q1)),  |ω| <= π

    ``integrate`` keeps the sign of the product (Pinocchio's
    ``JointModelSpherical``); ``q`` and ``−q`` are the same rotation.
    """

    kind: ClassVar[str] = "spherical"
    nq: ClassVar[int] = 4
    nv: ClassVar[int] = 3

    @property
    def S(self) -> np.ndarray:
        return _frozen(np.vstack([np.eye(3), np.zeros((3, 3))]))

    def pose(self, q: ArrayLike) -> PluckerTransform:
        qq = _q(q, 4)
        _check_unit_quat(qq, "q")
        R = rot.quat_to_matrix(qq, check_norm=False)
        return PluckerTransform(R, np.zeros(qq.shape[:-1] + (3,), dtype=R.dtype), validate=False)

    def neutral(self) -> np.ndarray:
        return np.array([0.0, 0.0, 0.0, 1.0])

    def integrate(self, q: ArrayLike, v: ArrayLike) -> np.ndarray:
        qq = _q(q, 4)
        w = as_array(v, "v", (3,))
        _check_unit_quat(qq, "q")
        dtype = np.result_type(qq, w)
        return _quat_mul_normalized(qq.astype(dtype), _quat_exp(w.astype(dtype))).astype(dtype)

    def difference(self, q0: ArrayLike, q1: ArrayLike) -> np.ndarray:
        a0, a1 = _q(q0, 4, "q0"), _q(q1, 4, "q1")
        _check_unit_quat(a0, "q0")
        _check_unit_quat(a1, "q1")
        R0 = rot.quat_to_matrix(a0, check_norm=False)
        R1 = rot.quat_to_matrix(a1, check_norm=False)
        return rot.so3_log(np.swapaxes(R0, -1, -2) @ R1)

    def random(
        self, rng: np.random.Generator | int | None = None, lower: ArrayLike | None = None, upper: ArrayLike | None = None, size: int | tuple[int, ...] | None = None
    ) -> np.ndarray:
        return _uniform_quat(np.random.default_rng(rng), _batch(size))

    def normalize(self, q: ArrayLike) -> np.ndarray:
        return rot.quat_normalize(_q(q, 4))

    def is_normalized(self, q: ArrayLike, tol: float = 1e-10) -> Any:
        qq = _q(q, 4)
        return np.abs(np.linalg.norm(qq, axis=-1) - 1) <= tol


@dataclass(frozen=True, slots=True, repr=True, eq=False)
class FreeFlyerJoint(Joint):
    """Six degrees of freedom (a floating base, or a URDF ``floating`` joint).

    ``q = [x y z, qx qy qz qw]``: the position of the child in the parent, then
    its orientation (Pinocchio's layout); ``v = [ω; v]``: the child's spatial
    velocity relative to the parent in child coordinates (Featherstone order;
    Pinocchio's is ``[v; ω]``)::

        pose(q) = (R(quat), p),   S = 1₆
        integrate:  T(q') = T(q) exp(v)
        difference: v = log(T(q0)⁻¹ T(q1))

    The quaternion of ``q'`` is chosen in the hemisphere of ``q``'s
    (``quat' · quat >= 0``), as Pinocchio's ``JointModelFreeFlyer`` does.
    """

    kind: ClassVar[str] = "free_flyer"
    nq: ClassVar[int] = 7
    nv: ClassVar[int] = 6

    @property
    def S(self) -> np.ndarray:
        return _frozen(np.eye(6))

    def pose(self, q: ArrayLike) -> PluckerTransform:
        return self._pose(_q(q, 7), "q")

    @staticmethod
    def _pose(qq: np.ndarray, name: str) -> PluckerTransform:
        _check_unit_quat(qq[..., 3:], f"{name}[3:7]")
        return PluckerTransform(rot.quat_to_matrix(qq[..., 3:], check_norm=False), qq[..., :3], validate=False)

    def neutral(self) -> np.ndarray:
        return np.array([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0])

    def integrate(self, q: ArrayLike, v: ArrayLike) -> np.ndarray:
        qq = _q(q, 7)
        vv = as_array(v, "v", (6,))
        _check_unit_quat(qq[..., 3:], "q[3:7]")
        dtype = np.result_type(qq, vv)
        qq, vv = qq.astype(dtype), vv.astype(dtype)
        quat = qq[..., 3:]
        step = rot.se3_exp(vv)  # exp(v) = (R_Δ, p_Δ) in the frame of q
        R0 = rot.quat_to_matrix(quat, check_norm=False)
        p = qq[..., :3] + (R0 @ step.translation[..., None])[..., 0]
        quat1 = _quat_mul_normalized(quat, _quat_exp(vv[..., :3]))
        quat1 = np.where(np.sum(quat1 * quat, axis=-1, keepdims=True) < 0, -quat1, quat1)
        batch = np.broadcast_shapes(p.shape[:-1], quat1.shape[:-1])
        p, quat1 = np.broadcast_to(p, batch + (3,)), np.broadcast_to(quat1, batch + (4,))
        return np.concatenate([p, quat1], axis=-1).astype(dtype)

    def difference(self, q0: ArrayLike, q1: ArrayLike) -> np.ndarray:
        T0 = self._pose(_q(q0, 7, "q0"), "q0")
        T1 = self._pose(_q(q1, 7, "q1"), "q1")
        return rot.se3_log(T0.inverse() @ T1).vector

    def random(
        self, rng: np.random.Generator | int | None = None, lower: ArrayLike | None = None, upper: ArrayLike | None = None, size: int | tuple[int, ...] | None = None
    ) -> np.ndarray:
        gen = np.random.default_rng(rng)
        shape = _batch(size)
        lo, hi = _limits(lower, upper, 7)
        pos = _uniform(gen, *_box(lo[:3], hi[:3], -1.0, 1.0), shape)
        return np.concatenate([pos, _uniform_quat(gen, shape)], axis=-1)

    def normalize(self, q: ArrayLike) -> np.ndarray:
        qq = np.array(_q(q, 7))
        qq[..., 3:] = rot.quat_normalize(qq[..., 3:])
        return qq

    def is_normalized(self, q: ArrayLike, tol: float = 1e-10) -> Any:
        qq = _q(q, 7)
        return np.abs(np.linalg.norm(qq[..., 3:], axis=-1) - 1) <= tol


def _plane_basis(normal: np.ndarray) -> np.ndarray:
    """A right-handed orthonormal basis ``[e1 e2 n]`` (columns) with ``n`` = normal; identity for +z."""
    n = normal
    helper = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    if np.allclose(n, [0.0, 0.0, 1.0]):
        return np.eye(3)
    e1 = helper - n * (helper @ n)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    return np.stack([e1, e2, n], axis=1)


@dataclass(frozen=True, slots=True, repr=False, eq=False)
class PlanarJoint(Joint):
    """Motion in the plane normal to ``normal`` (URDF ``planar``; the URDF axis is the normal).

    With the plane basis ``B = [e1 e2 n]`` (identity for ``normal = z``),
    ``q = [x, y, θ]`` and ``v = [ω, v_x, v_y]`` in the moving frame::

        pose(q) = (B Rz(θ) Bᵀ,  x e1 + y e2),   S = [[n, 0, 0], [0, e1, e2]]
        integrate: T(q') = T(q) exp(v)    (SE(2), body velocity)

    (Pinocchio stores ``q = [x, y, cos θ, sin θ]`` and ``v = [v_x, v_y, ω]``.)
    """

    normal: np.ndarray = field(default_factory=lambda: _frozen(np.array([0.0, 0.0, 1.0])))
    kind: ClassVar[str] = "planar"
    nq: ClassVar[int] = 3
    nv: ClassVar[int] = 3

    def __post_init__(self) -> None:
        object.__setattr__(self, "normal", unit_axis(self.normal, "normal", stacklevel=4))

    def _params(self) -> tuple[np.ndarray, ...]:
        return (self.normal,)

    @property
    def basis(self) -> np.ndarray:
        """`(3, 3)` the plane basis ``[e1 e2 n]`` as columns."""
        return _frozen(_plane_basis(self.normal))

    @property
    def S(self) -> np.ndarray:
        B = self.basis
        S = np.zeros((6, 3))
        S[:3, 0] = B[:, 2]
        S[3:, 1] = B[:, 0]
        S[3:, 2] = B[:, 1]
        return _frozen(S)

    def pose(self, q: ArrayLike) -> PluckerTransform:
        qq = _q(q, 3)
        B = _like(self.basis, qq)
        R = rot.axis_angle_to_matrix(_like(self.normal, qq), qq[..., 2])
        p = qq[..., 0:1] * B[:, 0] + qq[..., 1:2] * B[:, 1]
        return PluckerTransform(R, p, validate=False)

    def integrate(self, q: ArrayLike, v: ArrayLike) -> np.ndarray:
        # SE(2) exponential of the body velocity, composed on the right
        qq = _q(q, 3)
        vv = as_array(v, "v", (3,))
        w, vx, vy = vv[..., 0], vv[..., 1], vv[..., 2]
        small = np.abs(w) < 1e-8
        ws = np.where(small, 1.0, w)
        a = np.where(small, 1 - w * w / 6, np.sin(w) / ws)
        b = np.where(small, w / 2 - w**3 / 24, 2 * np.sin(ws / 2) ** 2 / ws)  # (1 − cos θ)/θ without cancellation
        dx, dy = a * vx - b * vy, b * vx + a * vy
        th = qq[..., 2]
        c, s = np.cos(th), np.sin(th)
        out = np.stack(np.broadcast_arrays(qq[..., 0] + c * dx - s * dy, qq[..., 1] + s * dx + c * dy, th + w), axis=-1)
        return out.astype(np.result_type(qq, vv))

    def difference(self, q0: ArrayLike, q1: ArrayLike) -> np.ndarray:
        a0, a1 = _q(q0, 3, "q0"), _q(q1, 3, "q1")
        dth = np.arctan2(np.sin(a1[..., 2] - a0[..., 2]), np.cos(a1[..., 2] - a0[..., 2]))
        c, s = np.cos(a0[..., 2]), np.sin(a0[..., 2])
        gx, gy = a1[..., 0] - a0[..., 0], a1[..., 1] - a0[..., 1]
        dx, dy = c * gx + s * gy, -s * gx + c * gy  # displacement in the frame of q0
        small = np.abs(dth) < 1e-8
        ws = np.where(small, 1.0, dth)
        a = np.where(small, 1 - dth * dth / 6, np.sin(dth) / ws)
        b = np.where(small, dth / 2 - dth**3 / 24, 2 * np.sin(ws / 2) ** 2 / ws)
        det = a * a + b * b
        vx, vy = (a * dx + b * dy) / det, (-b * dx + a * dy) / det
        return np.stack(np.broadcast_arrays(dth, vx, vy), axis=-1).astype(np.result_type(a0, a1))

    def random(
        self, rng: np.random.Generator | int | None = None, lower: ArrayLike | None = None, upper: ArrayLike | None = None, size: int | tuple[int, ...] | None = None
    ) -> np.ndarray:
        lo, hi = _box(*_limits(lower, upper, 3), [-1.0, -1.0, -np.pi], [1.0, 1.0, np.pi])
        return _uniform(np.random.default_rng(rng), lo, hi, _batch(size))

    def __repr__(self) -> str:
        return f"PlanarJoint(normal={self.normal.tolist()})"
