"""Spatial vector algebra: the chapter's ``spatial_algebra.py``.

Motion vectors ``m = [ω; v_O]`` (M⁶) and force vectors ``f = [n_O; f]`` (F⁶)
in Featherstone's order (angular first), Plücker transforms, the spatial
cross products and the spatial rigid-body inertia. Everything broadcasts over
leading batch axes and keeps the dtype it is given (float64, float32, or
object arrays of SymPy expressions).

The classes exist for type safety: a motion and a force never add, a force is
never moved with the motion transform, and the only mixed product is power::

    motion.dot(force) = ωᵀ n_O + vᵀ f         (invariant under any X)

Sources: Featherstone, *Rigid Body Dynamics Algorithms* (2008) ch. 2;
chapter §2–§5, §13 and appendices A, F, H.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple, NoReturn

import numpy as np

from ._validation import as_array, check_rotation, readonly, result_dtype
from .errors import DTypeError, InertiaError, NonFiniteError, ShapeError, SpatialTypeError
from .frames import Frame, chain_bodies, check_same_frame, merge_frames
from .tolerances import INERTIA_PHYSICAL, INERTIA_STRUCTURE, SPATIAL_STRUCTURE

__all__ = [
    "SpatialMotion",
    "SpatialForce",
    "PluckerTransform",
    "SpatialInertia",
    "Screw",
    "cross_motion",
    "cross_force",
    "crm",
    "crf",
    "skew",
    "unskew",
    "screw_parameters",
    "rotx",
    "roty",
    "rotz",
    "xlt",
    "plux",
]


# --------------------------------------------------------------------------
# raw-array kernels (dtype-generic: float32, float64 and object arrays)
# --------------------------------------------------------------------------


_NEXT = np.array([1, 2, 0])
_PREV = np.array([2, 0, 1])


def _cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a × b`` over the last axis, broadcasting; works for object arrays.

    ::

        (a × b)_i = a_{i+1} b_{i+2} − a_{i+2} b_{i+1}     (indices mod 3)
    """
    # ndarray.take is ~3× cheaper than fancy indexing a[..., _NEXT] on small arrays (the same result)
    return a.take(_NEXT, axis=-1) * b.take(_PREV, axis=-1) - a.take(_PREV, axis=-1) * b.take(_NEXT, axis=-1)


def _matvec(m: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``m @ x`` for ``(..., n, k)`` matrices and ``(..., k)`` vectors."""
    return (m @ x[..., None])[..., 0]


def _mT(m: np.ndarray) -> np.ndarray:
    return np.swapaxes(m, -1, -2)


def _sum_last(x: np.ndarray) -> Any:
    return x.sum(axis=-1)


def _is_weak(x: Any) -> bool:
    """A plain Python number: like NumPy (NEP 50), it takes the dtype of the arrays it meets."""
    return isinstance(x, (int, float)) and not isinstance(x, np.generic)


def _adopt_dtype(raw: tuple[Any, ...], arrays: list[np.ndarray]) -> list[np.ndarray]:
    """Cast the arrays made from plain Python numbers to the floating dtype of the others.

    ``as_array`` turns ``2.0`` into a float64 array, which would promote a
    float32 computation to float64; NumPy keeps ``float32_array * 2.0`` float32.
    """
    strong = [a for x, a in zip(raw, arrays, strict=True) if not _is_weak(x)]
    if not strong:
        return arrays
    dtype = result_dtype(*strong)
    if dtype.kind != "f":
        return arrays
    return [a.astype(dtype) if _is_weak(x) else a for x, a in zip(raw, arrays, strict=True)]


def skew(w: Any) -> np.ndarray:
    """The cross-product matrix ``[w]×`` of a 3-vector.

    Args:
        w: `(..., 3)`.

    Returns:
        `(..., 3, 3)`, with ``skew(w) @ x == w × x``::

            [w]× = [[ 0,  -w3,  w2],
                    [ w3,  0,  -w1],
                    [-w2,  w1,  0 ]]
    """
    w = as_array(w, "w", (3,))
    return _skew(w)


def _skew(w: np.ndarray) -> np.ndarray:
    z = np.zeros_like(w[..., 0])
    x, y, zz = w[..., 0], w[..., 1], w[..., 2]
    rows = [np.stack([z, -zz, y], axis=-1), np.stack([zz, z, -x], axis=-1), np.stack([-y, x, z], axis=-1)]
    return np.stack(rows, axis=-2)


def unskew(matrix: Any) -> np.ndarray:
    """The vector ``w`` of a skew-symmetric ``[w]×`` (the "vee" map; inverse of :func:`skew`).

    Args:
        matrix: `(..., 3, 3)`; only its skew-symmetric part is used.

    Returns:
        `(..., 3)`::

            w = ½ (S32 − S23, S13 − S31, S21 − S12)
    """
    s = as_array(matrix, "matrix", (3, 3))
    return _unskew(s)


def _unskew(s: np.ndarray) -> np.ndarray:
    return np.stack(
        [(s[..., 2, 1] - s[..., 1, 2]) / 2, (s[..., 0, 2] - s[..., 2, 0]) / 2, (s[..., 1, 0] - s[..., 0, 1]) / 2],
        axis=-1,
    )


def crm(v: Any) -> np.ndarray:
    """The motion cross-product matrix ``[v]×`` (Lynch–Park ``[ad_V]``).

    Args:
        v: `(..., 6)` motion vector ``[ω; v]`` or a :class:`SpatialMotion`.

    Returns:
        `(..., 6, 6)` lower block-triangular matrix (chapter appendix A.1)::

            [v]× = [[ [ω]×,   0  ],
                    [ [v]×,  [ω]× ]]

    Source: RBDA (2008) eq. 2.31; chapter §4.1.
    """
    v6 = _raw_motion(v, "v")
    w, lin = _skew(v6[..., :3]), _skew(v6[..., 3:])
    zero = np.zeros_like(w)
    return np.concatenate([np.concatenate([w, zero], axis=-1), np.concatenate([lin, w], axis=-1)], axis=-2)


def crf(v: Any) -> np.ndarray:
    """The force cross-product matrix ``[v]×* = −[v]×ᵀ`` (Lynch–Park ``−[ad_V]ᵀ``).

    Args:
        v: `(..., 6)` motion vector ``[ω; v]`` or a :class:`SpatialMotion`.

    Returns:
        `(..., 6, 6)` upper block-triangular matrix (chapter appendix A.2)::

            [v]×* = −[v]×ᵀ = [[ [ω]×,  [v]× ],
                              [  0  ,  [ω]× ]]

    Source: RBDA (2008) eq. 2.32; chapter §4.2.
    """
    return -_mT(crm(v))


# the three 3D cross products of each spatial one, gathered so one vectorised call does them all
_CRM_A, _CRM_B = np.array([0, 1, 2, 0, 1, 2, 3, 4, 5]), np.array([0, 1, 2, 3, 4, 5, 0, 1, 2])
_CRF_A, _CRF_B = np.array([0, 1, 2, 3, 4, 5, 0, 1, 2]), np.array([0, 1, 2, 3, 4, 5, 3, 4, 5])


def _crm_apply(v: np.ndarray, m: np.ndarray) -> np.ndarray:
    """``[ω × m_ω;  ω × m_v + v × m_ω]`` via the three products (ω×m_ω, ω×m_v, v×m_ω)."""
    c = _cross3(v[..., _CRM_A].reshape(v.shape[:-1] + (3, 3)), m[..., _CRM_B].reshape(m.shape[:-1] + (3, 3)))
    return np.concatenate([c[..., 0, :], c[..., 1, :] + c[..., 2, :]], axis=-1)


def _crf_apply(v: np.ndarray, f: np.ndarray) -> np.ndarray:
    """``[ω × n + v × f;  ω × f]`` via the three products (ω×n, v×f, ω×f)."""
    c = _cross3(v[..., _CRF_A].reshape(v.shape[:-1] + (3, 3)), f[..., _CRF_B].reshape(f.shape[:-1] + (3, 3)))
    return np.concatenate([c[..., 0, :] + c[..., 1, :], c[..., 2, :]], axis=-1)


# --------------------------------------------------------------------------
# type errors that say what was meant
# --------------------------------------------------------------------------


def _kind(x: Any) -> str:
    return type(x).__name__ if not isinstance(x, np.ndarray) else "numpy.ndarray"


def _raw_hint(cls_name: str) -> str:
    return (
        f"wrap raw 6-vectors explicitly with {cls_name}.from_vector(x) (Featherstone order, angular first) "
        "so that the type (motion or force) and the order are stated"
    )


def _mix_error(op: str, left: Any, right: Any) -> NoReturn:
    lk, rk = _kind(left), _kind(right)
    pair = {type(left), type(right)}
    if pair == {SpatialMotion, SpatialForce}:
        raise SpatialTypeError(
            f"cannot {op} a {lk} and a {rk}: motion vectors (M⁶) and force vectors (F⁶) are dual spaces "
            "and never combine linearly. Did you mean motion.dot(force) (power), or was one of them built "
            "with the wrong class (a velocity or acceleration is a SpatialMotion; a force, wrench or "
            "momentum is a SpatialForce)?"
        )
    if SpatialInertia in pair:
        raise SpatialTypeError(
            f"cannot {op} a {lk} and a {rk}: a SpatialInertia maps motion to force (inertia @ motion = "
            "momentum); it only adds to another SpatialInertia"
        )
    cls = lk if isinstance(left, (SpatialMotion, SpatialForce)) else rk
    raise SpatialTypeError(f"cannot {op} a {lk} and a {rk}: {_raw_hint(cls)}")


def _raw_motion(v: Any, name: str) -> np.ndarray:
    """A motion argument as a raw (..., 6) array; a SpatialForce is refused."""
    if isinstance(v, SpatialMotion):
        return v.vector
    if isinstance(v, SpatialForce):
        raise SpatialTypeError(
            f"{name}: expected a motion vector, got a SpatialForce; the spatial cross products take a "
            "motion on the left (v × m, v ×* f). Did you swap the arguments?"
        )
    if isinstance(v, (SpatialInertia, PluckerTransform)):
        raise SpatialTypeError(f"{name}: expected a motion vector (..., 6), got a {_kind(v)}")
    return as_array(v, name, (6,))


def _raw_force(f: Any, name: str) -> np.ndarray:
    if isinstance(f, SpatialForce):
        return f.vector
    if isinstance(f, SpatialMotion):
        raise SpatialTypeError(
            f"{name}: expected a force vector, got a SpatialMotion; motion × motion is cross_motion "
            "(crm), motion ×* force is cross_force (crf)"
        )
    if isinstance(f, (SpatialInertia, PluckerTransform)):
        raise SpatialTypeError(f"{name}: expected a force vector (..., 6), got a {_kind(f)}")
    return as_array(f, name, (6,))


def _scalar_factor(s: Any, batch_shape: tuple[int, ...], what: str, dtype: np.dtype) -> np.ndarray:
    if isinstance(s, (SpatialMotion, SpatialForce, SpatialInertia, PluckerTransform)):
        raise SpatialTypeError(
            f"{what}: cannot multiply by a {_kind(s)}; use cross (v × m, v ×* f), dot (power) or inertia @ motion"
        )
    arr = as_array(s, "scalar")
    if _is_weak(s) and dtype.kind == "f":  # float32 * 2.0 stays float32
        arr = arr.astype(dtype)
    try:
        np.broadcast_shapes(arr.shape, batch_shape)
    except ValueError:
        raise ShapeError(
            f"scalar: expected a scalar or an array broadcastable to the batch shape {batch_shape}, got shape {arr.shape}"
        ) from None
    return arr


def _batch_index(vec: np.ndarray, idx: Any, trailing: int) -> Any:
    if not isinstance(idx, tuple):
        idx = (idx,)
    if any(i is Ellipsis for i in idx):
        raise IndexError("spatial values index their batch axes only; Ellipsis is not supported")
    if len(idx) > vec.ndim - trailing:
        raise IndexError(f"too many indices for batch shape {vec.shape[: vec.ndim - trailing]}")
    return idx


# --------------------------------------------------------------------------
# motion and force vectors
# --------------------------------------------------------------------------


class Screw(NamedTuple):
    """Screw (Chasles) parameters of a motion: rotate about and slide along one axis.

    Attributes:
        direction: `(..., 3)` unit axis direction (``ω/|ω|``; ``v/|v|`` for a pure
            translation; zeros for the zero motion).
        point: `(..., 3)` the point of the axis nearest the origin (zeros for a
            pure translation or the zero motion).
        pitch: `(...)` translation per radian, ``h = ω·v/|ω|²`` (``inf`` for a pure
            translation, 0 for the zero motion).
        magnitude: `(...)` ``|ω|``, or ``|v|`` for a pure translation.
    """

    direction: np.ndarray
    point: np.ndarray
    pitch: np.ndarray
    magnitude: np.ndarray


@dataclass(frozen=True, slots=True, init=False, eq=False, repr=False)
class SpatialMotion:
    """A spatial motion vector (velocity, acceleration, twist) ``[ω; v_O]``.

    ``vector`` has shape `(..., 6)`: the angular part ``ω`` first, then ``v_O``,
    the velocity of the body-fixed point at the frame origin O (Featherstone;
    Pinocchio stores the reverse, ``[v; ω]``: convert with
    :mod:`featherdyn.conventions`).

    Args:
        angular: `(..., 3)` ``ω``.
        linear: `(..., 3)` ``v_O``.
        frame: optional tag of the frame the coordinates are expressed in.
        body: optional tag of the body whose motion this is.
        relative_to: optional tag of the body it moves relative to.

    The reference point changes with the frame (chapter §2.1)::

        v_P = v_O + ω × r_OP
    """

    vector: np.ndarray
    frame: Frame
    body: Frame
    relative_to: Frame

    __array_ufunc__ = None  # make numpy defer to our reflected operators

    def __init__(
        self, angular: Any, linear: Any, frame: Frame = None, *, body: Frame = None, relative_to: Frame = None
    ) -> None:
        w = as_array(angular, "angular", (3,))
        v = as_array(linear, "linear", (3,))
        dtype = result_dtype(w, v)
        shape = np.broadcast_shapes(w.shape[:-1], v.shape[:-1])
        vec = np.empty(shape + (6,), dtype=dtype)
        vec[..., :3] = w
        vec[..., 3:] = v
        _init(self, vec, frame, body=body, relative_to=relative_to)

    @classmethod
    def from_vector(
        cls, vector: Any, frame: Frame = None, *, body: Frame = None, relative_to: Frame = None
    ) -> SpatialMotion:
        """Wrap a raw `(..., 6)` array in Featherstone order ``[ω; v]`` (copied, read-only)."""
        vec = as_array(vector, "vector", (6,), copy=True)
        return cls._wrap(vec, frame, body, relative_to)

    @classmethod
    def zero(cls, shape: tuple[int, ...] = (), dtype: Any = np.float64, frame: Frame = None) -> SpatialMotion:
        """The zero motion with batch shape ``shape``."""
        return cls._wrap(np.zeros(tuple(shape) + (6,), dtype=dtype), frame, None, None)

    @classmethod
    def from_screw(
        cls, direction: Any, point: Any, pitch: Any, magnitude: Any = 1.0, frame: Frame = None
    ) -> SpatialMotion:
        """The motion of a screw: rotation ``magnitude`` about the axis through ``point`` along ``direction``.

        Args:
            direction: `(..., 3)` axis direction (normalised here).
            point: `(..., 3)` any point of the axis.
            pitch: `(...)` translation per radian; ``inf`` means a pure translation
                of speed ``magnitude`` along ``direction``.
            magnitude: `(...)` angular speed (or linear speed for ``pitch = inf``).

        Inverse of :meth:`screw`::

            ω = |ω| d,   v_O = h ω + q × ω     (q on the axis)
        """
        d, q, h, mag = _adopt_dtype(
            (direction, point, pitch, magnitude),
            [
                as_array(direction, "direction", (3,)),
                as_array(point, "point", (3,)),
                as_array(pitch, "pitch", (), check_finite=False),
                as_array(magnitude, "magnitude", ()),
            ],
        )
        if h.dtype.kind == "f" and np.any(np.isnan(h)):
            raise NonFiniteError("pitch: expected a number or inf, got NaN")
        norm = np.sqrt(_sum_last(d * d))
        if np.any(norm == 0):
            raise ShapeError("direction: zero-length screw axis")
        d = d / norm[..., None]
        inf = np.isinf(h)
        zero = np.zeros_like(mag)
        w = d * np.where(inf, zero, mag)[..., None]  # pitch inf: no rotation ...
        h_fin = np.where(inf, np.zeros_like(h), h)
        lin = h_fin[..., None] * w + _cross3(q, w) + d * np.where(inf, mag, zero)[..., None]  # ... only sliding
        return cls(w, lin, frame)

    @classmethod
    def _wrap(cls, vec: np.ndarray, frame: Frame, body: Frame = None, relative_to: Frame = None) -> SpatialMotion:
        obj = object.__new__(cls)
        _init(obj, vec, frame, body=body, relative_to=relative_to)
        return obj

    @property
    def angular(self) -> np.ndarray:
        """`(..., 3)` the angular part ``ω`` (read-only view)."""
        return self.vector[..., :3]

    @property
    def linear(self) -> np.ndarray:
        """`(..., 3)` the linear part ``v_O`` (read-only view)."""
        return self.vector[..., 3:]

    @property
    def shape(self) -> tuple[int, ...]:
        """The batch shape (``vector.shape[:-1]``)."""
        return tuple(self.vector.shape[:-1])

    @property
    def dtype(self) -> np.dtype:
        return self.vector.dtype

    def __getitem__(self, idx: Any) -> SpatialMotion:
        idx = _batch_index(self.vector, idx, 1)
        return SpatialMotion._wrap(np.array(self.vector[idx]), self.frame, self.body, self.relative_to)

    def __len__(self) -> int:
        if self.vector.ndim < 2:
            raise TypeError("len() of an unbatched SpatialMotion")
        return int(self.vector.shape[0])

    # linear structure within the type ------------------------------------

    def __add__(self, other: Any) -> SpatialMotion:
        if not isinstance(other, SpatialMotion):
            _mix_error("add", self, other)
        frame = merge_frames(self.frame, other.frame, "motion + motion")
        body, rel = chain_bodies(self.body, self.relative_to, other.body, other.relative_to, "motion + motion")
        return SpatialMotion._wrap(self.vector + other.vector, frame, body, rel)

    def __radd__(self, other: Any) -> NoReturn:
        _mix_error("add", other, self)

    def __sub__(self, other: Any) -> SpatialMotion:
        if not isinstance(other, SpatialMotion):
            _mix_error("subtract", self, other)
        return self + (-other)

    def __rsub__(self, other: Any) -> NoReturn:
        _mix_error("subtract", other, self)

    def __neg__(self) -> SpatialMotion:
        # v_B/A = −v_A/B
        return SpatialMotion._wrap(-self.vector, self.frame, self.relative_to, self.body)

    def __mul__(self, scalar: Any) -> SpatialMotion:
        s = _scalar_factor(scalar, self.shape, "motion * scalar", self.dtype)
        return SpatialMotion._wrap(self.vector * s[..., None], self.frame, self.body, self.relative_to)

    __rmul__ = __mul__

    def __truediv__(self, scalar: Any) -> SpatialMotion:
        s = _scalar_factor(scalar, self.shape, "motion / scalar", self.dtype)
        return SpatialMotion._wrap(self.vector / s[..., None], self.frame, self.body, self.relative_to)

    def __matmul__(self, other: Any) -> NoReturn:
        raise SpatialTypeError(
            "motion @ x is not defined: use motion.dot(force) for power, motion.cross(x) for the spatial "
            "cross product, or X @ motion / inertia @ motion"
        )

    __rmatmul__ = __matmul__

    # products ----------------------------------------------------------------

    def dot(self, force: Any) -> Any:
        """Power: the scalar product of this motion with a force, `(...)`.

        ::

            P = m · f = ωᵀ n_O + v_Oᵀ f

        Invariant under coordinate transforms: ``(X m)·(X* f) = m·f``.
        """
        if isinstance(force, SpatialMotion):
            raise SpatialTypeError(
                "motion.dot(motion) is not defined: the invariant scalar product pairs a motion with a force "
                "(power = v·f). Did you mean inertia.kinetic_energy(v), or np.dot(m1.vector, m2.vector) for a "
                "plain (frame-dependent) Euclidean product?"
            )
        if not isinstance(force, SpatialForce):
            _mix_error("take the power (dot) of", self, force)
        check_same_frame(self.frame, force.frame, "motion.dot(force)")
        return _sum_last(self.vector * force.vector)

    def cross(self, other: Any) -> SpatialMotion | SpatialForce:
        """Spatial cross product, dispatching on the argument type.

        ``motion.cross(m)`` is ``v × m`` (:func:`cross_motion`), ``motion.cross(f)``
        is ``v ×* f`` (:func:`cross_force`).
        """
        if isinstance(other, SpatialForce):
            return cross_force(self, other)
        if isinstance(other, SpatialMotion):
            return cross_motion(self, other)
        raise SpatialTypeError(
            f"motion.cross expects a SpatialMotion (v × m) or a SpatialForce (v ×* f), got a {_kind(other)}: "
            + _raw_hint("SpatialMotion")
        )

    def screw(self) -> Screw:
        """The screw (Chasles) parameters of this motion; see :func:`screw_parameters`."""
        return screw_parameters(self)

    def allclose(self, other: SpatialMotion, rtol: float = 1e-9, atol: float = 1e-12) -> bool:
        """``np.allclose`` of the vectors after a type and frame check."""
        if not isinstance(other, SpatialMotion):
            _mix_error("compare", self, other)
        check_same_frame(self.frame, other.frame, "motion.allclose")
        return bool(np.allclose(self.vector, other.vector, rtol=rtol, atol=atol))

    def __repr__(self) -> str:
        return f"SpatialMotion(angular={_fmt(self.angular)}, linear={_fmt(self.linear)}{_tags(self)})"


@dataclass(frozen=True, slots=True, init=False, eq=False, repr=False)
class SpatialForce:
    """A spatial force vector (wrench, momentum) ``[n_O; f]``.

    ``vector`` has shape `(..., 6)`: the moment ``n_O`` about the frame origin
    first, then the resultant force ``f`` (Featherstone; Pinocchio stores
    ``[f; n]``).

    Args:
        angular: `(..., 3)` the moment ``n_O``.
        linear: `(..., 3)` the force ``f``.
        frame: optional tag of the frame the coordinates are expressed in.

    The moment changes with the reference point (chapter §2.2)::

        n_P = n_O − r_OP × f
    """

    vector: np.ndarray
    frame: Frame

    __array_ufunc__ = None

    def __init__(self, angular: Any, linear: Any, frame: Frame = None) -> None:
        n = as_array(angular, "angular", (3,))
        f = as_array(linear, "linear", (3,))
        shape = np.broadcast_shapes(n.shape[:-1], f.shape[:-1])
        vec = np.empty(shape + (6,), dtype=result_dtype(n, f))
        vec[..., :3] = n
        vec[..., 3:] = f
        _init(self, vec, frame)

    @classmethod
    def from_vector(cls, vector: Any, frame: Frame = None) -> SpatialForce:
        """Wrap a raw `(..., 6)` array in Featherstone order ``[n; f]`` (copied, read-only)."""
        return cls._wrap(as_array(vector, "vector", (6,), copy=True), frame)

    @classmethod
    def zero(cls, shape: tuple[int, ...] = (), dtype: Any = np.float64, frame: Frame = None) -> SpatialForce:
        """The zero force with batch shape ``shape``."""
        return cls._wrap(np.zeros(tuple(shape) + (6,), dtype=dtype), frame)

    @classmethod
    def _wrap(cls, vec: np.ndarray, frame: Frame) -> SpatialForce:
        obj = object.__new__(cls)
        _init(obj, vec, frame)
        return obj

    @property
    def angular(self) -> np.ndarray:
        """`(..., 3)` the moment ``n_O`` (read-only view)."""
        return self.vector[..., :3]

    @property
    def linear(self) -> np.ndarray:
        """`(..., 3)` the force ``f`` (read-only view)."""
        return self.vector[..., 3:]

    @property
    def shape(self) -> tuple[int, ...]:
        """The batch shape (``vector.shape[:-1]``)."""
        return tuple(self.vector.shape[:-1])

    @property
    def dtype(self) -> np.dtype:
        return self.vector.dtype

    def __getitem__(self, idx: Any) -> SpatialForce:
        idx = _batch_index(self.vector, idx, 1)
        return SpatialForce._wrap(np.array(self.vector[idx]), self.frame)

    def __len__(self) -> int:
        if self.vector.ndim < 2:
            raise TypeError("len() of an unbatched SpatialForce")
        return int(self.vector.shape[0])

    def __add__(self, other: Any) -> SpatialForce:
        if not isinstance(other, SpatialForce):
            _mix_error("add", self, other)
        return SpatialForce._wrap(self.vector + other.vector, merge_frames(self.frame, other.frame, "force + force"))

    def __radd__(self, other: Any) -> NoReturn:
        _mix_error("add", other, self)

    def __sub__(self, other: Any) -> SpatialForce:
        if not isinstance(other, SpatialForce):
            _mix_error("subtract", self, other)
        return SpatialForce._wrap(self.vector - other.vector, merge_frames(self.frame, other.frame, "force - force"))

    def __rsub__(self, other: Any) -> NoReturn:
        _mix_error("subtract", other, self)

    def __neg__(self) -> SpatialForce:
        return SpatialForce._wrap(-self.vector, self.frame)

    def __mul__(self, scalar: Any) -> SpatialForce:
        s = _scalar_factor(scalar, self.shape, "force * scalar", self.dtype)
        return SpatialForce._wrap(self.vector * s[..., None], self.frame)

    __rmul__ = __mul__

    def __truediv__(self, scalar: Any) -> SpatialForce:
        s = _scalar_factor(scalar, self.shape, "force / scalar", self.dtype)
        return SpatialForce._wrap(self.vector / s[..., None], self.frame)

    def __matmul__(self, other: Any) -> NoReturn:
        raise SpatialTypeError(
            "force @ x is not defined: use motion.dot(force) for power or X @ force to transform it"
        )

    __rmatmul__ = __matmul__

    def dot(self, motion: Any) -> Any:
        """Power ``f · m``, the same pairing as :meth:`SpatialMotion.dot`, `(...)`."""
        if isinstance(motion, SpatialForce):
            raise SpatialTypeError(
                "force.dot(force) is not defined: the invariant scalar product pairs a force with a motion "
                "(power). Did you mean np.dot(f1.vector, f2.vector) for a plain Euclidean product?"
            )
        if not isinstance(motion, SpatialMotion):
            _mix_error("take the power (dot) of", self, motion)
        return motion.dot(self)

    def cross(self, other: Any) -> NoReturn:
        raise SpatialTypeError(
            "a force has no cross product on the left: the spatial cross products are motion × motion "
            "(cross_motion, crm) and motion ×* force (cross_force, crf). Did you mean motion.cross(force)?"
        )

    def allclose(self, other: SpatialForce, rtol: float = 1e-9, atol: float = 1e-12) -> bool:
        """``np.allclose`` of the vectors after a type and frame check."""
        if not isinstance(other, SpatialForce):
            _mix_error("compare", self, other)
        check_same_frame(self.frame, other.frame, "force.allclose")
        return bool(np.allclose(self.vector, other.vector, rtol=rtol, atol=atol))

    def __repr__(self) -> str:
        return f"SpatialForce(angular={_fmt(self.angular)}, linear={_fmt(self.linear)}{_tags(self)})"


def _init(obj: Any, vec: np.ndarray, frame: Frame, **tags: Frame) -> None:
    object.__setattr__(obj, "vector", readonly(vec))
    object.__setattr__(obj, "frame", frame)
    for k, val in tags.items():
        object.__setattr__(obj, k, val)


def _fmt(a: np.ndarray) -> str:
    return np.array2string(np.asarray(a), precision=6, separator=", ", threshold=20)


def _tags(obj: Any) -> str:
    out = []
    for name in ("frame", "body", "relative_to", "source", "target"):
        val = getattr(obj, name, None)
        if val is not None:
            out.append(f", {name}={val!r}")
    return "".join(out)


def cross_motion(v: Any, m: Any) -> SpatialMotion:
    """Motion cross product ``v × m`` (the Lie bracket of se(3), ``ad_v m``).

    Args:
        v: `(..., 6)` motion (:class:`SpatialMotion` or raw ``[ω; v]``).
        m: `(..., 6)` motion.

    Returns:
        :class:`SpatialMotion` `(..., 6)`::

            v × m = crm(v) @ m = [ ω × m_ω ;  ω × m_v + v × m_ω ]

    Source: RBDA (2008) eq. 2.31; chapter §4.1.
    """
    vv, mm = _raw_motion(v, "v"), _raw_motion(m, "m")
    frame = merge_frames(getattr(v, "frame", None), getattr(m, "frame", None), "cross_motion(v, m)")
    return SpatialMotion._wrap(_crm_apply(vv, mm), frame)


def cross_force(v: Any, f: Any) -> SpatialForce:
    """Force cross product ``v ×* f`` (the coadjoint ``−ad_vᵀ f``).

    Args:
        v: `(..., 6)` motion (:class:`SpatialMotion` or raw ``[ω; v]``).
        f: `(..., 6)` force (:class:`SpatialForce` or raw ``[n; f]``).

    Returns:
        :class:`SpatialForce` `(..., 6)`::

            v ×* f = crf(v) @ f = −crm(v)ᵀ f = [ ω × n + v × f ;  ω × f ]

    Source: RBDA (2008) eq. 2.32; chapter §4.2.
    """
    vv, ff = _raw_motion(v, "v"), _raw_force(f, "f")
    frame = merge_frames(getattr(v, "frame", None), getattr(f, "frame", None), "cross_force(v, f)")
    return SpatialForce._wrap(_crf_apply(vv, ff), frame)


def screw_parameters(motion: Any) -> Screw:
    """Chasles' screw of a motion: axis direction, nearest axis point, pitch, magnitude.

    Args:
        motion: :class:`SpatialMotion` or raw `(..., 6)` ``[ω; v_O]`` (float dtype).

    Returns:
        :class:`Screw` with ``direction`` `(..., 3)`, ``point`` `(..., 3)`,
        ``pitch`` `(...)`, ``magnitude`` `(...)`. For ``ω ≠ 0`` (chapter §2.1)::

            d = ω/|ω|,   q = ω × v_O / |ω|²,   h = ω · v_O / |ω|²

        A pure translation (``ω = 0``) has ``d = v/|v|``, ``q = 0``,
        ``h = inf``; the zero motion has all zeros.
    """
    vec = _raw_motion(motion, "motion")
    if vec.dtype.kind == "O":
        raise DTypeError("motion: screw parameters need floating-point numbers, got an object array")
    w, v = vec[..., :3], vec[..., 3:]
    ww = _sum_last(w * w)
    vv = _sum_last(v * v)
    scale = np.maximum(ww, vv)
    rot = ww > (np.finfo(vec.dtype).eps ** 2) * np.where(scale > 0, scale, 1.0) * 1e4
    safe = np.where(rot, ww, 1.0)
    wn = np.sqrt(safe)
    direction_rot = w / wn[..., None]
    point = np.where(rot[..., None], _cross3(w, v) / safe[..., None], 0.0)
    pitch = np.where(rot, _sum_last(w * v) / safe, np.where(vv > 0, np.inf, 0.0))
    vn = np.sqrt(np.where(vv > 0, vv, 1.0))
    direction_tr = np.where((vv > 0)[..., None], v / vn[..., None], 0.0)
    direction = np.where(rot[..., None], direction_rot, direction_tr)
    magnitude = np.where(rot, np.sqrt(ww), np.sqrt(vv))
    return Screw(direction.astype(vec.dtype), point.astype(vec.dtype), pitch.astype(vec.dtype), magnitude.astype(vec.dtype))


# --------------------------------------------------------------------------
# Plücker transforms
# --------------------------------------------------------------------------


@dataclass(frozen=True, slots=True, init=False, eq=False, repr=False)
class PluckerTransform:
    """A Plücker coordinate transform ``ᴮX_A``: the pose of frame A in frame B.

    ``rotation`` `(..., 3, 3)` holds A's axes in B-coordinates and
    ``translation`` `(..., 3)` A's origin in B. It maps A-coordinates to
    B-coordinates: motions with ``X``, forces with ``X* = X⁻ᵀ``, inertias with
    ``X* I X⁻¹`` (chapter §3; the semantics of Pinocchio's ``SE3(R, p).act``)::

        X  = [[ R,     0 ],        X* = X⁻ᵀ = [[ R,  [p]×R ],
              [ [p]×R, R ]]                    [ 0,   R    ]]

    Args:
        rotation: `(..., 3, 3)` proper rotation (checked: orthonormal within 1e-6
            for float64, det > 0; pass ``validate=False`` to skip).
        translation: `(..., 3)`.
        source: optional tag of frame A.
        target: optional tag of frame B.
    """

    rotation: np.ndarray
    translation: np.ndarray
    source: Frame
    target: Frame

    __array_ufunc__ = None

    def __init__(
        self, rotation: Any, translation: Any, source: Frame = None, target: Frame = None, *, validate: bool = True
    ) -> None:
        rot = as_array(rotation, "rotation", (3, 3))
        p = as_array(translation, "translation", (3,))
        if validate:
            check_rotation(rot, "rotation")
        dtype = result_dtype(rot, p)
        shape = np.broadcast_shapes(rot.shape[:-2], p.shape[:-1])
        _init_x(self, np.broadcast_to(rot, shape + (3, 3)).astype(dtype), np.broadcast_to(p, shape + (3,)).astype(dtype), source, target)

    @classmethod
    def _wrap(cls, rot: np.ndarray, p: np.ndarray, source: Frame, target: Frame) -> PluckerTransform:
        obj = object.__new__(cls)
        _init_x(obj, rot, p, source, target)
        return obj

    @classmethod
    def identity(
        cls, shape: tuple[int, ...] = (), dtype: Any = np.float64, source: Frame = None, target: Frame = None
    ) -> PluckerTransform:
        """The identity transform with batch shape ``shape``."""
        rot = np.broadcast_to(np.eye(3, dtype=dtype), tuple(shape) + (3, 3)).copy()
        return cls._wrap(rot, np.zeros(tuple(shape) + (3,), dtype=dtype), source, target)

    @classmethod
    def from_homogeneous(
        cls, matrix: Any, source: Frame = None, target: Frame = None, *, validate: bool = True
    ) -> PluckerTransform:
        """From a `(..., 4, 4)` homogeneous matrix ``[[R, p], [0, 1]]`` (the pose of A in B)."""
        t = as_array(matrix, "matrix", (4, 4))
        if t.dtype.kind != "O":
            bottom = t[..., 3, :]
            expected = np.array([0, 0, 0, 1], dtype=t.dtype)
            if not np.allclose(bottom, expected, atol=SPATIAL_STRUCTURE.of(t.dtype), rtol=0):
                raise ShapeError(
                    f"matrix: expected a homogeneous transform with last row [0, 0, 0, 1], got {_fmt(bottom.reshape(-1, 4)[0])}"
                )
        return cls(t[..., :3, :3], t[..., :3, 3], source, target, validate=validate)

    @classmethod
    def from_plux(cls, E: Any, r: Any, source: Frame = None, target: Frame = None) -> PluckerTransform:
        """From Featherstone's ``plux(E, r)``: ``E`` rotates A- to B-coordinates, ``r`` is B's origin in A.

        ::

            plux(E, r) = [[E, 0], [−E [r]×, E]]   ⇒   R = E,  p = −E r

        Source: spatial_v2 ``plux``; RBDA (2008) eq. 2.24.
        """
        e = as_array(E, "E", (3, 3))
        rr = as_array(r, "r", (3,))
        check_rotation(e, "E")
        return cls._wrap(*_bcast_rp(e, -_matvec(e, rr)), source, target)

    @classmethod
    def from_matrix(cls, matrix: Any, source: Frame = None, target: Frame = None) -> PluckerTransform:
        """From a `(..., 6, 6)` motion transform matrix ``[[R, 0], [[p]×R, R]]`` (structure checked)."""
        x = as_array(matrix, "matrix", (6, 6))
        rot = x[..., :3, :3]
        check_rotation(rot, "matrix[:3, :3]")
        tol = SPATIAL_STRUCTURE.of(x.dtype)
        scale = max(1.0, float(np.abs(x).max())) if x.size else 1.0
        if np.abs(x[..., :3, 3:]).max(initial=0.0) > tol * scale or np.abs(x[..., 3:, 3:] - rot).max(initial=0.0) > tol * scale:
            raise ShapeError("matrix: not a Plücker motion transform: expected [[R, 0], [[p]×R, R]]")
        px = x[..., 3:, :3] @ _mT(rot)
        if np.abs(px + _mT(px)).max(initial=0.0) > tol * scale:
            raise ShapeError("matrix: not a Plücker motion transform: lower-left block times Rᵀ is not skew-symmetric")
        return cls._wrap(np.array(rot), _unskew(px), source, target)

    @property
    def shape(self) -> tuple[int, ...]:
        """The batch shape."""
        return tuple(self.translation.shape[:-1])

    @property
    def dtype(self) -> np.dtype:
        return self.translation.dtype

    def __getitem__(self, idx: Any) -> PluckerTransform:
        idx = _batch_index(self.translation, idx, 1)
        return PluckerTransform._wrap(np.array(self.rotation[idx]), np.array(self.translation[idx]), self.source, self.target)

    # action on spatial values ----------------------------------------------

    def apply(self, x: Any) -> Any:
        """Transform a motion (``X m``), a force (``X* f``) or an inertia (``X* I X⁻¹``) from A to B.

        Args:
            x: :class:`SpatialMotion`, :class:`SpatialForce` or :class:`SpatialInertia`
               expressed in A (batch shapes broadcast with the transform's).

        Returns:
            The same type, expressed in B (its ``frame`` tag becomes ``target``)::

                X m:        ω' = R ω,   v' = R v + p × (R ω)
                X* f:       f' = R f,   n' = R n + p × (R f)
                X* I X⁻¹:   m' = m,     c' = R c + p,   I_c' = R I_c Rᵀ
        """
        if isinstance(x, SpatialMotion):
            check_same_frame(x.frame, self.source, "X.apply(motion): motion frame vs X.source")
            rw = _matvec(self.rotation, x.angular)
            rv = _matvec(self.rotation, x.linear) + _cross3(self.translation, rw)
            return SpatialMotion._wrap(np.concatenate(_bcast(rw, rv), axis=-1), self.target, x.body, x.relative_to)
        if isinstance(x, SpatialForce):
            check_same_frame(x.frame, self.source, "X.apply(force): force frame vs X.source")
            rf = _matvec(self.rotation, x.linear)
            rn = _matvec(self.rotation, x.angular) + _cross3(self.translation, rf)
            return SpatialForce._wrap(np.concatenate(_bcast(rn, rf), axis=-1), self.target)
        if isinstance(x, SpatialInertia):
            check_same_frame(x.frame, self.source, "X.apply(inertia): inertia frame vs X.source")
            com = _matvec(self.rotation, x.com) + self.translation
            ic = self.rotation @ x.inertia_com @ _mT(self.rotation)
            return SpatialInertia._wrap(*_bcast_inertia(x.mass, com, ic), self.target)
        raise _apply_type_error("X.apply", x)

    def apply_inverse(self, x: Any) -> Any:
        """Transform from B back to A: ``X⁻¹ m``, ``X⁻¹* f = Xᵀ f``, ``Xᵀ I X`` (Pinocchio's ``actInv``).

        Equal to ``X.inverse().apply(x)`` without forming the inverse::

            X⁻¹ m:  ω = Rᵀ ω',  v = Rᵀ (v' − p × ω')
            Xᵀ f:   f = Rᵀ f',  n = Rᵀ (n' − p × f')
        """
        rt = _mT(self.rotation)
        if isinstance(x, SpatialMotion):
            check_same_frame(x.frame, self.target, "X.apply_inverse(motion): motion frame vs X.target")
            w = _matvec(rt, x.angular)
            v = _matvec(rt, x.linear - _cross3(self.translation, x.angular))
            return SpatialMotion._wrap(np.concatenate(_bcast(w, v), axis=-1), self.source, x.body, x.relative_to)
        if isinstance(x, SpatialForce):
            check_same_frame(x.frame, self.target, "X.apply_inverse(force): force frame vs X.target")
            f = _matvec(rt, x.linear)
            n = _matvec(rt, x.angular - _cross3(self.translation, x.linear))
            return SpatialForce._wrap(np.concatenate(_bcast(n, f), axis=-1), self.source)
        if isinstance(x, SpatialInertia):
            check_same_frame(x.frame, self.target, "X.apply_inverse(inertia): inertia frame vs X.target")
            com = _matvec(rt, x.com - self.translation)
            ic = rt @ x.inertia_com @ self.rotation
            return SpatialInertia._wrap(*_bcast_inertia(x.mass, com, ic), self.source)
        raise _apply_type_error("X.apply_inverse", x)

    def __matmul__(self, other: Any) -> Any:
        """``X_CB @ X_BA = X_CA`` (composition); ``X @ value`` is ``X.apply(value)``.

        ::

            (R₁, p₁) ∘ (R₂, p₂) = (R₁ R₂,  R₁ p₂ + p₁)
        """
        if isinstance(other, PluckerTransform):
            check_same_frame(self.source, other.target, "X_CB @ X_BA: X_CB.source vs X_BA.target")
            rot = self.rotation @ other.rotation
            p = _matvec(self.rotation, other.translation) + self.translation
            return PluckerTransform._wrap(*_bcast_rp(rot, p), other.source, self.target)
        return self.apply(other)

    def __rmatmul__(self, other: Any) -> NoReturn:
        raise _apply_type_error("@", other)

    def inverse(self) -> PluckerTransform:
        """``ᴬX_B = (ᴮX_A)⁻¹``: the pose of B in A (source and target swap).

        ::

            (R, p)⁻¹ = (Rᵀ, −Rᵀ p)
        """
        rt = _mT(self.rotation)
        return PluckerTransform._wrap(np.array(rt), -_matvec(rt, self.translation), self.target, self.source)

    # matrices ----------------------------------------------------------------

    def matrix(self) -> np.ndarray:
        """The `(..., 6, 6)` motion transform ``X = [[R, 0], [[p]×R, R]]``."""
        rot = self.rotation
        zero = np.zeros_like(rot)
        return np.concatenate(
            [np.concatenate([rot, zero], axis=-1), np.concatenate([_skew(self.translation) @ rot, rot], axis=-1)], axis=-2
        )

    def dual_matrix(self) -> np.ndarray:
        """The `(..., 6, 6)` force transform ``X* = X⁻ᵀ = [[R, [p]×R], [0, R]]`` (formed directly, not by inversion)."""
        rot = self.rotation
        zero = np.zeros_like(rot)
        return np.concatenate(
            [np.concatenate([rot, _skew(self.translation) @ rot], axis=-1), np.concatenate([zero, rot], axis=-1)], axis=-2
        )

    def inverse_matrix(self) -> np.ndarray:
        """The `(..., 6, 6)` inverse motion transform ``X⁻¹ = [[Rᵀ, 0], [−Rᵀ[p]×, Rᵀ]]``."""
        return self.inverse().matrix()

    def homogeneous(self) -> np.ndarray:
        """The `(..., 4, 4)` homogeneous matrix ``[[R, p], [0, 1]]``."""
        out = np.zeros(self.shape + (4, 4), dtype=self.dtype)
        out[..., :3, :3] = self.rotation
        out[..., :3, 3] = self.translation
        out[..., 3, 3] = 1
        return out

    def allclose(self, other: PluckerTransform, rtol: float = 1e-9, atol: float = 1e-12) -> bool:
        """Elementwise closeness of rotation and translation, after a type and frame check."""
        if not isinstance(other, PluckerTransform):
            raise SpatialTypeError(f"X.allclose needs a PluckerTransform, got a {_kind(other)}")
        check_same_frame(self.source, other.source, "X.allclose: source frames")
        check_same_frame(self.target, other.target, "X.allclose: target frames")
        return bool(
            np.allclose(self.rotation, other.rotation, rtol=rtol, atol=atol)
            and np.allclose(self.translation, other.translation, rtol=rtol, atol=atol)
        )

    def __repr__(self) -> str:
        return f"PluckerTransform(rotation={_fmt(self.rotation)}, translation={_fmt(self.translation)}{_tags(self)})"


def _apply_type_error(what: str, x: Any) -> SpatialTypeError:
    return SpatialTypeError(
        f"{what} needs a SpatialMotion, SpatialForce or SpatialInertia, got a {_kind(x)}: motions transform "
        "with X and forces with X* = X⁻ᵀ, so a raw 6-vector is ambiguous. Wrap it with "
        "SpatialMotion.from_vector(v) or SpatialForce.from_vector(f), or use X.matrix() @ v / X.dual_matrix() @ f"
    )


def _init_x(obj: Any, rot: np.ndarray, p: np.ndarray, source: Frame, target: Frame) -> None:
    object.__setattr__(obj, "rotation", readonly(rot))
    object.__setattr__(obj, "translation", readonly(p))
    object.__setattr__(obj, "source", source)
    object.__setattr__(obj, "target", target)


def _bcast(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    if a.shape[:-1] == b.shape[:-1]:
        return a, b
    shape = np.broadcast_shapes(a.shape[:-1], b.shape[:-1])
    return np.broadcast_to(a, shape + a.shape[-1:]), np.broadcast_to(b, shape + b.shape[-1:])


def _bcast_rp(rot: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    shape = np.broadcast_shapes(rot.shape[:-2], p.shape[:-1])
    return np.array(np.broadcast_to(rot, shape + (3, 3))), np.array(np.broadcast_to(p, shape + (3,)))


def rotx(theta: Any) -> PluckerTransform:
    """spatial_v2 ``rotx``: the coordinate transform to a frame rotated by ``theta`` about x.

    A coordinate transform (as in the book), so ``R = Rx(θ)ᵀ``::

        rotx(θ) = [[E, 0], [0, E]],   E = [[1, 0, 0], [0, c, s], [0, −s, c]]
    """
    return _rot_axis(theta, 0)


def roty(theta: Any) -> PluckerTransform:
    """spatial_v2 ``roty``: ``E = [[c, 0, −s], [0, 1, 0], [s, 0, c]]`` (``R = Ry(θ)ᵀ``)."""
    return _rot_axis(theta, 1)


def rotz(theta: Any) -> PluckerTransform:
    """spatial_v2 ``rotz``: ``E = [[c, s, 0], [−s, c, 0], [0, 0, 1]]`` (``R = Rz(θ)ᵀ``)."""
    return _rot_axis(theta, 2)


def _rot_axis(theta: Any, axis: int) -> PluckerTransform:
    t = as_array(theta, "theta")
    if t.dtype.kind == "O":
        import sympy

        c = np.vectorize(sympy.cos, otypes=[object])(t)
        s = np.vectorize(sympy.sin, otypes=[object])(t)
        one, zero = np.ones_like(t), np.zeros_like(t)
    else:
        c, s = np.cos(t), np.sin(t)
        one, zero = np.ones_like(t), np.zeros_like(t)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    e = np.empty(t.shape + (3, 3), dtype=t.dtype)
    e[...] = zero[..., None, None]
    e[..., axis, axis] = one
    e[..., i, i] = c
    e[..., j, j] = c
    e[..., i, j] = s
    e[..., j, i] = -s
    return PluckerTransform._wrap(e, np.zeros(t.shape + (3,), dtype=t.dtype), None, None)


def xlt(r: Any) -> PluckerTransform:
    """spatial_v2 ``xlt``: the coordinate transform to a frame whose origin is at ``r``.

    ::

        xlt(r) = [[1, 0], [−[r]×, 1]]   ⇒   R = 1,  p = −r
    """
    rr = as_array(r, "r", (3,))
    rot = np.broadcast_to(np.eye(3, dtype=rr.dtype), rr.shape[:-1] + (3, 3)).copy()
    return PluckerTransform._wrap(rot, -rr, None, None)


def plux(E: Any, r: Any) -> PluckerTransform:
    """spatial_v2 ``plux(E, r) = rot(E) @ xlt(r)``; see :meth:`PluckerTransform.from_plux`."""
    return PluckerTransform.from_plux(E, r)


# --------------------------------------------------------------------------
# spatial inertia
# --------------------------------------------------------------------------


@dataclass(frozen=True, slots=True, init=False, eq=False, repr=False)
class SpatialInertia:
    """The spatial inertia of a rigid body, from its mass, centre of mass and rotational inertia.

    Args:
        mass: `(...)` mass ``m``.
        com: `(..., 3)` ``c``, the vector from the frame origin to the centre of mass.
        inertia_com: `(..., 3, 3)` symmetric rotational inertia about the centre of mass
            (symmetry checked; physical validity is *not* checked here, see :meth:`check`).
        frame: optional tag of the frame it is expressed in.

    The `(..., 6, 6)` matrix (chapter §5.1; RBDA eq. 2.63)::

        I = [[ I_c − m [c]×[c]×,   m [c]×  ],
             [ m [c]×ᵀ,            m 1     ]]
    """

    mass: np.ndarray
    com: np.ndarray
    inertia_com: np.ndarray
    frame: Frame

    __array_ufunc__ = None

    def __init__(self, mass: Any, com: Any, inertia_com: Any, frame: Frame = None) -> None:
        m, c, ic = _adopt_dtype(
            (mass, com, inertia_com),
            [as_array(mass, "mass"), as_array(com, "com", (3,)), as_array(inertia_com, "inertia_com", (3, 3))],
        )
        if ic.dtype.kind != "O":
            asym = np.abs(ic - _mT(ic)).max(axis=(-2, -1), initial=0.0)
            scale = np.maximum(np.abs(ic).max(axis=(-2, -1), initial=0.0), 1.0)
            tol = INERTIA_STRUCTURE.of(ic.dtype)
            if np.any(asym > tol * scale):
                raise InertiaError(
                    f"inertia_com: expected a symmetric 3×3 matrix, max |I − Iᵀ| = {float(np.max(asym)):.3g}"
                )
            ic = (ic + _mT(ic)) / 2
        _init_i(self, *_bcast_inertia(m, c, ic), frame)

    @classmethod
    def _wrap(cls, m: np.ndarray, c: np.ndarray, ic: np.ndarray, frame: Frame) -> SpatialInertia:
        obj = object.__new__(cls)
        _init_i(obj, m, c, ic, frame)
        return obj

    # constructors --------------------------------------------------------------

    @classmethod
    def from_matrix(cls, matrix: Any, frame: Frame = None, *, tol: float | None = None) -> SpatialInertia:
        """Recover ``(m, c, I_c)`` from a `(..., 6, 6)` spatial inertia matrix (inverse of :meth:`matrix`).

        Rejects (:class:`InertiaError`, naming the block and the error) a matrix
        that is not symmetric, whose lower-right block is not ``m 1``, or whose
        off-diagonal block is not ``m [c]×``::

            m = tr(I₂₂)/3,   c = vee(I₁₂)/m,   I_c = I₁₁ + m [c]×[c]×
        """
        mat = as_array(matrix, "matrix", (6, 6))
        if mat.dtype.kind == "O":
            raise DTypeError("matrix: from_matrix needs floating-point numbers, got an object array")
        if tol is None:
            tol = INERTIA_STRUCTURE.of(mat.dtype)
        scale = np.maximum(np.abs(mat).max(axis=(-2, -1), initial=0.0), 1.0)

        def fail(cond: np.ndarray, msg: str) -> None:
            if np.any(cond):
                raise InertiaError(f"matrix: not a rigid-body spatial inertia: {msg}")

        asym = np.abs(mat - _mT(mat)).max(axis=(-2, -1))
        fail(asym > tol * scale, f"not symmetric (max |I − Iᵀ| = {float(np.max(asym)):.3g})")
        lower = mat[..., 3:, 3:]
        m = np.trace(lower, axis1=-2, axis2=-1) / 3
        dev = np.abs(lower - m[..., None, None] * np.eye(3, dtype=mat.dtype)).max(axis=(-2, -1))
        fail(dev > tol * scale, f"lower-right block is not m·1 (max deviation {float(np.max(dev)):.3g})")
        b = mat[..., :3, 3:]
        bsym = np.abs(b + _mT(b)).max(axis=(-2, -1))
        fail(bsym > tol * scale, f"upper-right block is not skew-symmetric m[c]× (max |B + Bᵀ| = {float(np.max(bsym)):.3g})")
        h = _unskew(b)
        hn = np.sqrt(_sum_last(h * h))
        zero_mass = np.abs(m) <= tol * scale
        fail(zero_mass & (hn > tol * scale), "zero mass with a non-zero first moment m·c")
        safe = np.where(zero_mass, 1.0, m)
        c = np.where(zero_mass[..., None], 0.0, h / safe[..., None])
        cx = _skew(c)
        ic = mat[..., :3, :3] + m[..., None, None] * (cx @ cx)
        return cls(m, c, ic, frame)

    @classmethod
    def from_dynamic_parameters(cls, params: Any, frame: Frame = None) -> SpatialInertia:
        """From the 10 dynamic parameters `(..., 10)`, in Pinocchio's order::

            π = [m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz]

        where ``I`` is the rotational inertia about the *frame origin*
        (``I = I_c − m [c]×[c]×``). The model is linear in π (RBDA §2.13).
        """
        p = as_array(params, "params", (10,))
        m = p[..., 0]
        h = p[..., 1:4]
        i_o = _sym_from(p[..., 4], p[..., 5], p[..., 6], p[..., 7], p[..., 8], p[..., 9])
        if p.dtype.kind == "O":
            c = h / m[..., None]
        else:
            zero = m == 0
            if np.any(zero & (np.abs(h).max(axis=-1) > 0)):
                raise InertiaError("params: zero mass with a non-zero first moment m·c")
            c = np.where(zero[..., None], 0.0, h / np.where(zero, 1.0, m)[..., None])
        cx = _skew(c)
        return cls(m, c, i_o + m[..., None, None] * (cx @ cx), frame)

    @classmethod
    def box(cls, mass: Any, size: Any, frame: Frame = None) -> SpatialInertia:
        """A solid box of side lengths ``size`` `(..., 3)` centred at the origin::

            I_c = m/12 · diag(y² + z², x² + z², x² + y²)
        """
        m, s = _adopt_dtype((mass, size), [as_array(mass, "mass"), as_array(size, "size", (3,))])
        sq = s * s
        d = np.stack([sq[..., 1] + sq[..., 2], sq[..., 0] + sq[..., 2], sq[..., 0] + sq[..., 1]], axis=-1)
        return cls._from_diag(m, d * (m[..., None] / 12), frame, size=s)

    @classmethod
    def cylinder(cls, mass: Any, radius: Any, length: Any, frame: Frame = None) -> SpatialInertia:
        """A solid cylinder along z, centred at the origin::

            I_c = diag(m(3r² + l²)/12, m(3r² + l²)/12, m r²/2)
        """
        m, r, ln = _adopt_dtype(
            (mass, radius, length), [as_array(mass, "mass"), as_array(radius, "radius"), as_array(length, "length")]
        )
        a = m * (3 * r * r + ln * ln) / 12
        return cls._from_diag(m, np.stack(np.broadcast_arrays(a, a, m * r * r / 2), axis=-1), frame, radius=r, length=ln)

    @classmethod
    def sphere(cls, mass: Any, radius: Any, frame: Frame = None) -> SpatialInertia:
        """A solid sphere centred at the origin: ``I_c = 2/5 m r² 1``."""
        m, r = _adopt_dtype((mass, radius), [as_array(mass, "mass"), as_array(radius, "radius")])
        a = 2 * m * r * r / 5
        return cls._from_diag(m, np.stack([a, a, a], axis=-1), frame, radius=r)

    @classmethod
    def point_mass(cls, mass: Any, com: Any, frame: Frame = None) -> SpatialInertia:
        """A point mass at ``com`` (``I_c = 0``)."""
        m, c = _adopt_dtype((mass, com), [as_array(mass, "mass"), as_array(com, "com", (3,))])
        return cls(m, c, np.zeros(c.shape[:-1] + (3, 3), dtype=result_dtype(m, c)), frame)

    @classmethod
    def zero(cls, shape: tuple[int, ...] = (), dtype: Any = np.float64, frame: Frame = None) -> SpatialInertia:
        """The zero inertia (the neutral element of ``+``)."""
        shape = tuple(shape)
        return cls._wrap(np.zeros(shape, dtype), np.zeros(shape + (3,), dtype), np.zeros(shape + (3, 3), dtype), frame)

    @classmethod
    def _from_diag(cls, m: np.ndarray, d: np.ndarray, frame: Frame, **sizes: np.ndarray) -> SpatialInertia:
        # the moments are squares of the sizes, so the sizes themselves are checked
        for name, val in (("mass", m), *sizes.items()):
            if val.dtype.kind != "O" and np.any(val < 0):
                raise InertiaError(f"{name}: expected non-negative values, got {_fmt(val)}")
        ic = d[..., :, None] * np.eye(3, dtype=d.dtype)
        return cls(m, np.zeros(d.shape, dtype=d.dtype), ic, frame)

    # accessors -------------------------------------------------------------------

    @property
    def shape(self) -> tuple[int, ...]:
        """The batch shape."""
        return tuple(self.mass.shape)

    @property
    def dtype(self) -> np.dtype:
        return self.com.dtype

    @property
    def inertia_origin(self) -> np.ndarray:
        """`(..., 3, 3)` rotational inertia about the frame origin (parallel axis)::

            Ī = I_c − m [c]×[c]× = I_c + m (|c|² 1 − c cᵀ)
        """
        cx = _skew(self.com)
        return self.inertia_com - self.mass[..., None, None] * (cx @ cx)

    def __getitem__(self, idx: Any) -> SpatialInertia:
        idx = _batch_index(self.com, idx, 1)
        return SpatialInertia._wrap(
            np.array(self.mass[idx]), np.array(self.com[idx]), np.array(self.inertia_com[idx]), self.frame
        )

    def matrix(self) -> np.ndarray:
        """The `(..., 6, 6)` spatial inertia matrix (see the class docstring)."""
        m = self.mass[..., None, None]
        cx = _skew(self.com)
        # object arrays get exact integer ones, so SymPy sees m, not 1.0*m
        eye = np.eye(3, dtype=self.dtype) if self.dtype.kind != "O" else np.eye(3, dtype=int).astype(object)
        top = np.concatenate([self.inertia_origin, m * cx], axis=-1)
        bottom = np.concatenate([m * _mT(cx), m * eye], axis=-1)
        return np.concatenate([top, bottom], axis=-2)

    def to_dynamic_parameters(self) -> np.ndarray:
        """The 10 dynamic parameters `(..., 10)` in Pinocchio's order (see :meth:`from_dynamic_parameters`)."""
        i_o = self.inertia_origin
        m = self.mass
        h = self.com * m[..., None]
        return np.stack(
            [m, h[..., 0], h[..., 1], h[..., 2], i_o[..., 0, 0], i_o[..., 0, 1], i_o[..., 1, 1], i_o[..., 0, 2], i_o[..., 1, 2], i_o[..., 2, 2]],
            axis=-1,
        )

    # algebra ---------------------------------------------------------------------

    def __matmul__(self, motion: Any) -> SpatialForce:
        """Momentum ``h = I v`` (a force vector), computed without forming the 6×6 matrix.

        ::

            h_f = m (v − c × ω),   h_n = I_c ω + c × h_f
        """
        if not isinstance(motion, SpatialMotion):
            if isinstance(motion, SpatialForce):
                raise SpatialTypeError(
                    "inertia @ force is not defined: a spatial inertia maps motion to force (h = I v). "
                    "To get an acceleration from a force, solve I a = f (np.linalg.solve(I.matrix(), f.vector))"
                )
            raise SpatialTypeError(f"inertia @ x needs a SpatialMotion, got a {_kind(motion)}: " + _raw_hint("SpatialMotion"))
        frame = merge_frames(self.frame, motion.frame, "inertia @ motion")
        return SpatialForce._wrap(self._momentum(motion.vector), frame)

    def _momentum(self, v: np.ndarray) -> np.ndarray:
        w, lin = v[..., :3], v[..., 3:]
        hf = self.mass[..., None] * (lin - _cross3(self.com, w))
        hn = _matvec(self.inertia_com, w) + _cross3(self.com, hf)
        return np.concatenate(_bcast(hn, hf), axis=-1)

    def __add__(self, other: Any) -> SpatialInertia:
        """Composite inertia of two bodies rigidly joined (both expressed in the same frame).

        Adds the linear parameters ``(m, m c, Ī)`` (chapter §5.3)::

            m = m₁ + m₂,   c = (m₁c₁ + m₂c₂)/m,   I_c = Ī₁ + Ī₂ + m [c]×[c]×
        """
        if not isinstance(other, SpatialInertia):
            _mix_error("add", self, other)
        frame = merge_frames(self.frame, other.frame, "inertia + inertia")
        m = np.asarray(self.mass + other.mass)  # 0-d object arrays add to a bare object
        h = self.com * self.mass[..., None] + other.com * other.mass[..., None]
        i_o = self.inertia_origin + other.inertia_origin
        if m.dtype.kind == "O":
            c = h / m[..., None]
        else:
            zero = m == 0
            c = np.where(zero[..., None], 0.0, h / np.where(zero, 1.0, m)[..., None])
        cx = _skew(c)
        return SpatialInertia._wrap(*_bcast_inertia(m, c, i_o + m[..., None, None] * (cx @ cx)), frame)

    def __radd__(self, other: Any) -> SpatialInertia:
        if isinstance(other, int) and other == 0:  # sum() starts from 0
            return self
        _mix_error("add", other, self)

    def kinetic_energy(self, motion: Any) -> Any:
        """Kinetic energy `(...)` of the body moving with ``motion``::

            T = ½ vᵀ I v
        """
        if not isinstance(motion, SpatialMotion):
            _mix_error("compute the kinetic energy of", self, motion)
        check_same_frame(self.frame, motion.frame, "inertia.kinetic_energy(motion)")
        return _sum_last(motion.vector * self._momentum(motion.vector)) / 2

    # physical validity -----------------------------------------------------------

    def principal_moments(self) -> np.ndarray:
        """`(..., 3)` eigenvalues of ``I_c``, ascending."""
        if self.dtype.kind == "O":
            raise DTypeError("principal moments need floating-point numbers, got an object array")
        return np.linalg.eigvalsh(self.inertia_com)

    def _violations(self, tol: float | None) -> list[tuple[np.ndarray, str]]:
        if self.dtype.kind == "O":
            raise DTypeError("physical checks need floating-point numbers, got an object array")
        if tol is None:
            tol = INERTIA_PHYSICAL.of(self.dtype)
        ev = self.principal_moments()
        scale = np.maximum(np.abs(ev).max(axis=-1), np.finfo(self.dtype).tiny)
        a, b, c = ev[..., 0], ev[..., 1], ev[..., 2]
        return [
            (self.mass <= 0, "mass > 0"),
            (a <= 0, "rotational inertia about the centre of mass is positive definite"),
            (a + b < c - tol * scale, "principal moments satisfy the triangle inequality I1 + I2 >= I3"),
        ]

    def is_physical(self, *, tol: float | None = None) -> Any:
        """Whether each inertia is physically realisable, `(...)` bool (see :meth:`check`)."""
        bad = np.zeros(self.shape, dtype=bool)
        for cond, _ in self._violations(tol):
            bad |= cond
        return ~bad if bad.ndim else bool(~bad)

    def check(self, *, tol: float | None = None, name: str = "inertia") -> None:
        """Raise :class:`InertiaError` unless the inertia is physically realisable.

        Conditions, in order: ``m > 0``; ``I_c`` symmetric positive definite;
        the principal moments ``I1 <= I2 <= I3`` satisfy ``I1 + I2 >= I3``
        (with relative tolerance ``tol``, default 1e-12 for float64). The
        message names the failed condition, the batch index and the numbers.
        """
        ev = self.principal_moments()
        for cond, what in self._violations(tol):
            if np.any(cond):
                idx = tuple(int(i) for i in np.argwhere(cond)[0]) if cond.ndim else ()
                where = f" at batch index {idx}" if idx else ""
                raise InertiaError(
                    f"{name}: violates '{what}'{where}: mass {float(self.mass[idx]):.6g}, "
                    f"principal moments {_fmt(ev[idx])}"
                )

    def __repr__(self) -> str:
        return (
            f"SpatialInertia(mass={_fmt(self.mass)}, com={_fmt(self.com)}, "
            f"inertia_com={_fmt(self.inertia_com)}{_tags(self)})"
        )


def _sym_from(xx: Any, xy: Any, yy: Any, xz: Any, yz: Any, zz: Any) -> np.ndarray:
    rows = [np.stack([xx, xy, xz], axis=-1), np.stack([xy, yy, yz], axis=-1), np.stack([xz, yz, zz], axis=-1)]
    return np.stack(rows, axis=-2)


def _bcast_inertia(m: np.ndarray, c: np.ndarray, ic: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    shape = np.broadcast_shapes(m.shape, c.shape[:-1], ic.shape[:-2])
    dtype = result_dtype(m, c, ic)
    return (
        np.array(np.broadcast_to(m, shape), dtype=dtype),
        np.array(np.broadcast_to(c, shape + (3,)), dtype=dtype),
        np.array(np.broadcast_to(ic, shape + (3, 3)), dtype=dtype),
    )


def _init_i(obj: Any, m: np.ndarray, c: np.ndarray, ic: np.ndarray, frame: Frame) -> None:
    object.__setattr__(obj, "mass", readonly(m))
    object.__setattr__(obj, "com", readonly(c))
    object.__setattr__(obj, "inertia_com", readonly(ic))
    object.__setattr__(obj, "frame", frame)
