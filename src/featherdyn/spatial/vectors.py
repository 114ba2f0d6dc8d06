"""Motion and force vectors: the two types, their cross products, and screws.

``SpatialMotion`` ``[ω; v_O]`` (M⁶) and ``SpatialForce`` ``[n_O; f]`` (F⁶) never
add to each other; the only mixed product is power, and the cross products
take a motion on the left::

    v × m = crm(v) m,   v ×* f = crf(v) f = −crm(v)ᵀ f,   m · f = ωᵀ n_O + v_Oᵀ f

:class:`SpatialValue` is the common base of the four spatial value classes
(also :class:`~featherdyn.spatial.inertia.SpatialInertia` and
:class:`~featherdyn.spatial.transform.PluckerTransform`, defined in modules that
build on this one), so the type errors here can name any of them without
importing them.

Sources: RBDA (2008) §2.2–§2.9; chapter §2, §4 and §13.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar, NamedTuple, NoReturn, overload

import numpy as np
from numpy.typing import ArrayLike, DTypeLike

from ..errors import DTypeError, NonFiniteError, ShapeError, SpatialTypeError
from ..frames import Frame, chain_bodies, check_same_frame, merge_frames
from .ops import (
    adopt_dtype,
    batch_index,
    crf_apply,
    crm_apply,
    cross3,
    format_array,
    format_tags,
    is_weak_scalar,
    matrix_transpose,
    raw_vector_hint,
    skew_unchecked,
    sum_last,
    type_name,
)
from .validation import as_array, result_dtype


class SpatialValue:
    """Base of the spatial value classes: lets a type error recognise any of them.

    ``_mix_note`` is what a class adds to the message when it is mixed with
    another type in ``+``, ``-``, comparisons or energies (empty: the generic
    hint to wrap raw 6-vectors).
    """

    __slots__ = ()
    _mix_note: ClassVar[str] = ""


def mix_error(op: str, left: object, right: object) -> NoReturn:
    """Raise the :class:`~featherdyn.errors.SpatialTypeError` for ``left <op> right`` of two kinds that never combine."""
    lk, rk = type_name(left), type_name(right)
    pair = {type(left), type(right)}
    if pair == {SpatialMotion, SpatialForce}:
        raise SpatialTypeError(
            f"cannot {op} a {lk} and a {rk}: motion vectors (M⁶) and force vectors (F⁶) are dual spaces "
            "and never combine linearly. Did you mean motion.dot(force) (power), or was one of them built "
            "with the wrong class (a velocity or acceleration is a SpatialMotion; a force, wrench or "
            "momentum is a SpatialForce)?"
        )
    note = next((x._mix_note for x in (left, right) if isinstance(x, SpatialValue) and x._mix_note), "")
    if note:
        raise SpatialTypeError(f"cannot {op} a {lk} and a {rk}: {note}")
    cls = lk if isinstance(left, (SpatialMotion, SpatialForce)) else rk
    raise SpatialTypeError(f"cannot {op} a {lk} and a {rk}: {raw_vector_hint(cls)}")


def _raw_motion(v: object, name: str) -> np.ndarray:
    """A motion argument as a raw (..., 6) array; a SpatialForce is refused."""
    if isinstance(v, SpatialMotion):
        return v.vector
    if isinstance(v, SpatialForce):
        raise SpatialTypeError(
            f"{name}: expected a motion vector, got a SpatialForce; the spatial cross products take a "
            "motion on the left (v × m, v ×* f). Did you swap the arguments?"
        )
    if isinstance(v, SpatialValue):  # an inertia or a transform
        raise SpatialTypeError(f"{name}: expected a motion vector (..., 6), got a {type_name(v)}")
    return as_array(v, name, (6,))


def _raw_force(f: object, name: str) -> np.ndarray:
    if isinstance(f, SpatialForce):
        return f.vector
    if isinstance(f, SpatialMotion):
        raise SpatialTypeError(
            f"{name}: expected a force vector, got a SpatialMotion; motion × motion is cross_motion "
            "(crm), motion ×* force is cross_force (crf)"
        )
    if isinstance(f, SpatialValue):  # an inertia or a transform
        raise SpatialTypeError(f"{name}: expected a force vector (..., 6), got a {type_name(f)}")
    return as_array(f, name, (6,))


def _scalar_factor(s: object, batch_shape: tuple[int, ...], what: str, dtype: np.dtype) -> np.ndarray:
    if isinstance(s, SpatialValue):
        raise SpatialTypeError(
            f"{what}: cannot multiply by a {type_name(s)}; use cross (v × m, v ×* f), dot (power) or inertia @ motion"
        )
    arr = as_array(s, "scalar")
    if is_weak_scalar(s) and dtype.kind == "f":  # float32 * 2.0 stays float32
        arr = arr.astype(dtype)
    try:
        np.broadcast_shapes(arr.shape, batch_shape)
    except ValueError:
        raise ShapeError(
            f"scalar: expected a scalar or an array broadcastable to the batch shape {batch_shape}, got shape {arr.shape}"
        ) from None
    return arr


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
class SpatialMotion(SpatialValue):
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
        self, angular: ArrayLike, linear: ArrayLike, frame: Frame = None, *, body: Frame = None, relative_to: Frame = None
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
        cls, vector: ArrayLike, frame: Frame = None, *, body: Frame = None, relative_to: Frame = None
    ) -> SpatialMotion:
        """Wrap a raw `(..., 6)` array in Featherstone order ``[ω; v]`` (copied, read-only)."""
        vec = as_array(vector, "vector", (6,), copy=True)
        return cls._wrap(vec, frame, body, relative_to)

    @classmethod
    def zero(cls, shape: tuple[int, ...] = (), dtype: DTypeLike = np.float64, frame: Frame = None) -> SpatialMotion:
        """The zero motion with batch shape ``shape``."""
        return cls._wrap(np.zeros(tuple(shape) + (6,), dtype=dtype), frame, None, None)

    @classmethod
    def from_screw(
        cls, direction: ArrayLike, point: ArrayLike, pitch: ArrayLike, magnitude: ArrayLike = 1.0, frame: Frame = None
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
        d, q, h, mag = adopt_dtype(
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
        norm = np.sqrt(sum_last(d * d))
        if np.any(norm == 0):
            raise ShapeError("direction: zero-length screw axis")
        d = d / norm[..., None]
        inf = np.isinf(h)
        zero = np.zeros_like(mag)
        w = d * np.where(inf, zero, mag)[..., None]  # pitch inf: no rotation ...
        h_fin = np.where(inf, np.zeros_like(h), h)
        lin = h_fin[..., None] * w + cross3(q, w) + d * np.where(inf, mag, zero)[..., None]  # ... only sliding
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
        idx = batch_index(self.vector, idx, 1)
        return SpatialMotion._wrap(np.array(self.vector[idx]), self.frame, self.body, self.relative_to)

    def __len__(self) -> int:
        if self.vector.ndim < 2:
            raise TypeError("len() of an unbatched SpatialMotion")
        return int(self.vector.shape[0])

    # linear structure within the type ------------------------------------

    def __add__(self, other: SpatialMotion) -> SpatialMotion:
        if not isinstance(other, SpatialMotion):
            mix_error("add", self, other)
        frame = merge_frames(self.frame, other.frame, "motion + motion")
        body, rel = chain_bodies(self.body, self.relative_to, other.body, other.relative_to, "motion + motion")
        return SpatialMotion._wrap(self.vector + other.vector, frame, body, rel)

    def __radd__(self, other: object) -> NoReturn:
        mix_error("add", other, self)

    def __sub__(self, other: SpatialMotion) -> SpatialMotion:
        if not isinstance(other, SpatialMotion):
            mix_error("subtract", self, other)
        return self + (-other)

    def __rsub__(self, other: object) -> NoReturn:
        mix_error("subtract", other, self)

    def __neg__(self) -> SpatialMotion:
        # v_B/A = −v_A/B
        return SpatialMotion._wrap(-self.vector, self.frame, self.relative_to, self.body)

    def __mul__(self, scalar: ArrayLike) -> SpatialMotion:
        s = _scalar_factor(scalar, self.shape, "motion * scalar", self.dtype)
        return SpatialMotion._wrap(self.vector * s[..., None], self.frame, self.body, self.relative_to)

    __rmul__ = __mul__

    def __truediv__(self, scalar: ArrayLike) -> SpatialMotion:
        s = _scalar_factor(scalar, self.shape, "motion / scalar", self.dtype)
        return SpatialMotion._wrap(self.vector / s[..., None], self.frame, self.body, self.relative_to)

    def __matmul__(self, other: object) -> NoReturn:
        raise SpatialTypeError(
            "motion @ x is not defined: use motion.dot(force) for power, motion.cross(x) for the spatial "
            "cross product, or X @ motion / inertia @ motion"
        )

    __rmatmul__ = __matmul__

    # products ----------------------------------------------------------------

    def dot(self, force: SpatialForce) -> Any:
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
            mix_error("take the power (dot) of", self, force)
        check_same_frame(self.frame, force.frame, "motion.dot(force)")
        return sum_last(self.vector * force.vector)

    @overload
    def cross(self, other: SpatialMotion) -> SpatialMotion: ...
    @overload
    def cross(self, other: SpatialForce) -> SpatialForce: ...

    def cross(self, other: SpatialMotion | SpatialForce) -> SpatialMotion | SpatialForce:
        """Spatial cross product, dispatching on the argument type.

        ``motion.cross(m)`` is ``v × m`` (:func:`cross_motion`), ``motion.cross(f)``
        is ``v ×* f`` (:func:`cross_force`).
        """
        if isinstance(other, SpatialForce):
            return cross_force(self, other)
        if isinstance(other, SpatialMotion):
            return cross_motion(self, other)
        raise SpatialTypeError(
            f"motion.cross expects a SpatialMotion (v × m) or a SpatialForce (v ×* f), got a {type_name(other)}: "
            + raw_vector_hint("SpatialMotion")
        )

    def screw(self) -> Screw:
        """The screw (Chasles) parameters of this motion; see :func:`screw_parameters`."""
        return screw_parameters(self)

    def allclose(self, other: SpatialMotion, rtol: float = 1e-9, atol: float = 1e-12) -> bool:
        """``np.allclose`` of the vectors after a type and frame check."""
        if not isinstance(other, SpatialMotion):
            mix_error("compare", self, other)
        check_same_frame(self.frame, other.frame, "motion.allclose")
        return bool(np.allclose(self.vector, other.vector, rtol=rtol, atol=atol))

    def __repr__(self) -> str:
        return f"SpatialMotion(angular={format_array(self.angular)}, linear={format_array(self.linear)}{format_tags(self)})"


@dataclass(frozen=True, slots=True, init=False, eq=False, repr=False)
class SpatialForce(SpatialValue):
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

    def __init__(self, angular: ArrayLike, linear: ArrayLike, frame: Frame = None) -> None:
        n = as_array(angular, "angular", (3,))
        f = as_array(linear, "linear", (3,))
        shape = np.broadcast_shapes(n.shape[:-1], f.shape[:-1])
        vec = np.empty(shape + (6,), dtype=result_dtype(n, f))
        vec[..., :3] = n
        vec[..., 3:] = f
        _init(self, vec, frame)

    @classmethod
    def from_vector(cls, vector: ArrayLike, frame: Frame = None) -> SpatialForce:
        """Wrap a raw `(..., 6)` array in Featherstone order ``[n; f]`` (copied, read-only)."""
        return cls._wrap(as_array(vector, "vector", (6,), copy=True), frame)

    @classmethod
    def zero(cls, shape: tuple[int, ...] = (), dtype: DTypeLike = np.float64, frame: Frame = None) -> SpatialForce:
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
        idx = batch_index(self.vector, idx, 1)
        return SpatialForce._wrap(np.array(self.vector[idx]), self.frame)

    def __len__(self) -> int:
        if self.vector.ndim < 2:
            raise TypeError("len() of an unbatched SpatialForce")
        return int(self.vector.shape[0])

    def __add__(self, other: SpatialForce) -> SpatialForce:
        if not isinstance(other, SpatialForce):
            mix_error("add", self, other)
        return SpatialForce._wrap(self.vector + other.vector, merge_frames(self.frame, other.frame, "force + force"))

    def __radd__(self, other: object) -> NoReturn:
        mix_error("add", other, self)

    def __sub__(self, other: SpatialForce) -> SpatialForce:
        if not isinstance(other, SpatialForce):
            mix_error("subtract", self, other)
        return SpatialForce._wrap(self.vector - other.vector, merge_frames(self.frame, other.frame, "force - force"))

    def __rsub__(self, other: object) -> NoReturn:
        mix_error("subtract", other, self)

    def __neg__(self) -> SpatialForce:
        return SpatialForce._wrap(-self.vector, self.frame)

    def __mul__(self, scalar: ArrayLike) -> SpatialForce:
        s = _scalar_factor(scalar, self.shape, "force * scalar", self.dtype)
        return SpatialForce._wrap(self.vector * s[..., None], self.frame)

    __rmul__ = __mul__

    def __truediv__(self, scalar: ArrayLike) -> SpatialForce:
        s = _scalar_factor(scalar, self.shape, "force / scalar", self.dtype)
        return SpatialForce._wrap(self.vector / s[..., None], self.frame)

    def __matmul__(self, other: object) -> NoReturn:
        raise SpatialTypeError(
            "force @ x is not defined: use motion.dot(force) for power or X @ force to transform it"
        )

    __rmatmul__ = __matmul__

    def dot(self, motion: SpatialMotion) -> Any:
        """Power ``f · m``, the same pairing as :meth:`SpatialMotion.dot`, `(...)`."""
        if isinstance(motion, SpatialForce):
            raise SpatialTypeError(
                "force.dot(force) is not defined: the invariant scalar product pairs a force with a motion "
                "(power). Did you mean np.dot(f1.vector, f2.vector) for a plain Euclidean product?"
            )
        if not isinstance(motion, SpatialMotion):
            mix_error("take the power (dot) of", self, motion)
        return motion.dot(self)

    def cross(self, other: object) -> NoReturn:
        raise SpatialTypeError(
            "a force has no cross product on the left: the spatial cross products are motion × motion "
            "(cross_motion, crm) and motion ×* force (cross_force, crf). Did you mean motion.cross(force)?"
        )

    def allclose(self, other: SpatialForce, rtol: float = 1e-9, atol: float = 1e-12) -> bool:
        """``np.allclose`` of the vectors after a type and frame check."""
        if not isinstance(other, SpatialForce):
            mix_error("compare", self, other)
        check_same_frame(self.frame, other.frame, "force.allclose")
        return bool(np.allclose(self.vector, other.vector, rtol=rtol, atol=atol))

    def __repr__(self) -> str:
        return f"SpatialForce(angular={format_array(self.angular)}, linear={format_array(self.linear)}{format_tags(self)})"


#: per class, the slots' own setters (a frozen dataclass refuses ``obj.x = …``; ``object.__setattr__``
#: costs a type lookup per field, and building results is on the compiled one-state calls' hot path)
_SETTERS: dict[type, dict[str, Callable[[object, object], None]]] = {}


def _init(obj: object, vec: np.ndarray, frame: Frame, **tags: Frame) -> None:
    cls = type(obj)
    setters = _SETTERS.get(cls)
    if setters is None:
        setters = _SETTERS[cls] = {f.name: getattr(cls, f.name).__set__ for f in dataclasses.fields(cls)}  # type: ignore[arg-type]
    vec.setflags(write=False)  # (readonly() inlined)
    setters["vector"](obj, vec)
    setters["frame"](obj, frame)
    for k, val in tags.items():
        setters[k](obj, val)


# --------------------------------------------------------------------------
# cross products and screws
# --------------------------------------------------------------------------


def crm(v: SpatialMotion | ArrayLike) -> np.ndarray:
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
    w, lin = skew_unchecked(v6[..., :3]), skew_unchecked(v6[..., 3:])
    zero = np.zeros_like(w)
    return np.concatenate([np.concatenate([w, zero], axis=-1), np.concatenate([lin, w], axis=-1)], axis=-2)


def crf(v: SpatialMotion | ArrayLike) -> np.ndarray:
    """The force cross-product matrix ``[v]×* = −[v]×ᵀ`` (Lynch–Park ``−[ad_V]ᵀ``).

    Args:
        v: `(..., 6)` motion vector ``[ω; v]`` or a :class:`SpatialMotion`.

    Returns:
        `(..., 6, 6)` upper block-triangular matrix (chapter appendix A.2)::

            [v]×* = −[v]×ᵀ = [[ [ω]×,  [v]× ],
                              [  0  ,  [ω]× ]]

    Source: RBDA (2008) eq. 2.32; chapter §4.2.
    """
    return -matrix_transpose(crm(v))


def cross_motion(v: SpatialMotion | ArrayLike, m: SpatialMotion | ArrayLike) -> SpatialMotion:
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
    return SpatialMotion._wrap(crm_apply(vv, mm), frame)


def cross_force(v: SpatialMotion | ArrayLike, f: SpatialForce | ArrayLike) -> SpatialForce:
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
    return SpatialForce._wrap(crf_apply(vv, ff), frame)


def screw_parameters(motion: SpatialMotion | ArrayLike) -> Screw:
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
    ww = sum_last(w * w)
    vv = sum_last(v * v)
    scale = np.maximum(ww, vv)
    rot = ww > (np.finfo(vec.dtype).eps ** 2) * np.where(scale > 0, scale, 1.0) * 1e4
    safe = np.where(rot, ww, 1.0)
    wn = np.sqrt(safe)
    direction_rot = w / wn[..., None]
    point = np.where(rot[..., None], cross3(w, v) / safe[..., None], 0.0)
    pitch = np.where(rot, sum_last(w * v) / safe, np.where(vv > 0, np.inf, 0.0))
    vn = np.sqrt(np.where(vv > 0, vv, 1.0))
    direction_tr = np.where((vv > 0)[..., None], v / vn[..., None], 0.0)
    direction = np.where(rot[..., None], direction_rot, direction_tr)
    magnitude = np.where(rot, np.sqrt(ww), np.sqrt(vv))
    return Screw(direction.astype(vec.dtype), point.astype(vec.dtype), pitch.astype(vec.dtype), magnitude.astype(vec.dtype))
