"""The spatial rigid-body inertia: parameters, constructors, algebra and physical validity.

A :class:`SpatialInertia` holds ``(m, c, I_c)`` and maps motion to force
(momentum ``h = I v``); inertias of bodies rigidly joined add::

    I = [[ I_c − m [c]×[c]×,   m [c]× ],
         [ m [c]×ᵀ,            m 1    ]]

Sources: RBDA (2008) §2.13, eq. 2.63; chapter §5.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import ArrayLike, DTypeLike

from ..errors import DTypeError, InertiaError, SpatialTypeError
from ..frames import Frame, check_same_frame, merge_frames
from ..tolerances import INERTIA_PHYSICAL, INERTIA_STRUCTURE
from .ops import (
    adopt_dtype,
    batch_index,
    broadcast_batch,
    cross3,
    format_array,
    format_tags,
    matrix_transpose,
    matvec,
    raw_vector_hint,
    skew_unchecked,
    sum_last,
    type_name,
    unskew_unchecked,
)
from .validation import as_array, readonly, result_dtype
from .vectors import SpatialForce, SpatialMotion, SpatialValue, mix_error


@dataclass(frozen=True, slots=True, init=False, eq=False, repr=False)
class SpatialInertia(SpatialValue):
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
    _mix_note: ClassVar[str] = (
        "a SpatialInertia maps motion to force (inertia @ motion = momentum); it only adds to another SpatialInertia"
    )

    def __init__(self, mass: ArrayLike, com: ArrayLike, inertia_com: ArrayLike, frame: Frame = None) -> None:
        exact = _exact_float64(mass, com, inertia_com)  # stacked float64 of matching shapes: nothing to convert
        if exact:
            m, c, ic = np.array(mass), np.array(com), np.asarray(inertia_com)
            if bool((ic == matrix_transpose(ic)).all()):  # exactly symmetric (a loader's): nothing to check or average
                _init_i(self, m, c, np.array(ic), frame)
                return
        else:
            m, c, ic = adopt_dtype(
                (mass, com, inertia_com),
                [as_array(mass, "mass"), as_array(com, "com", (3,)), as_array(inertia_com, "inertia_com", (3, 3))],
            )
        if ic.dtype.kind != "O":
            asym = np.abs(ic - matrix_transpose(ic)).max(axis=(-2, -1), initial=0.0)
            scale = np.maximum(np.abs(ic).max(axis=(-2, -1), initial=0.0), 1.0)
            tol = INERTIA_STRUCTURE.of(ic.dtype)
            if np.any(asym > tol * scale):
                raise InertiaError(
                    f"inertia_com: expected a symmetric 3×3 matrix, max |I − Iᵀ| = {float(np.max(asym)):.3g}"
                )
            ic = (ic + matrix_transpose(ic)) / 2
        if exact:
            _init_i(self, m, c, ic, frame)
        else:
            _init_i(self, *broadcast_inertia(m, c, ic), frame)

    @classmethod
    def _wrap(cls, m: np.ndarray, c: np.ndarray, ic: np.ndarray, frame: Frame) -> SpatialInertia:
        obj = object.__new__(cls)
        _init_i(obj, m, c, ic, frame)
        return obj

    # constructors --------------------------------------------------------------

    @classmethod
    def from_matrix(cls, matrix: ArrayLike, frame: Frame = None, *, tol: float | None = None) -> SpatialInertia:
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

        asym = np.abs(mat - matrix_transpose(mat)).max(axis=(-2, -1))
        fail(asym > tol * scale, f"not symmetric (max |I − Iᵀ| = {float(np.max(asym)):.3g})")
        lower = mat[..., 3:, 3:]
        m = np.trace(lower, axis1=-2, axis2=-1) / 3
        dev = np.abs(lower - m[..., None, None] * np.eye(3, dtype=mat.dtype)).max(axis=(-2, -1))
        fail(dev > tol * scale, f"lower-right block is not m·1 (max deviation {float(np.max(dev)):.3g})")
        b = mat[..., :3, 3:]
        bsym = np.abs(b + matrix_transpose(b)).max(axis=(-2, -1))
        fail(bsym > tol * scale, f"upper-right block is not skew-symmetric m[c]× (max |B + Bᵀ| = {float(np.max(bsym)):.3g})")
        h = unskew_unchecked(b)
        hn = np.sqrt(sum_last(h * h))
        zero_mass = np.abs(m) <= tol * scale
        fail(zero_mass & (hn > tol * scale), "zero mass with a non-zero first moment m·c")
        safe = np.where(zero_mass, 1.0, m)
        c = np.where(zero_mass[..., None], 0.0, h / safe[..., None])
        cx = skew_unchecked(c)
        ic = mat[..., :3, :3] + m[..., None, None] * (cx @ cx)
        return cls(m, c, ic, frame)

    @classmethod
    def from_dynamic_parameters(cls, params: ArrayLike, frame: Frame = None) -> SpatialInertia:
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
        cx = skew_unchecked(c)
        return cls(m, c, i_o + m[..., None, None] * (cx @ cx), frame)

    @classmethod
    def box(cls, mass: ArrayLike, size: ArrayLike, frame: Frame = None) -> SpatialInertia:
        """A solid box of side lengths ``size`` `(..., 3)` centred at the origin::

            I_c = m/12 · diag(y² + z², x² + z², x² + y²)
        """
        m, s = adopt_dtype((mass, size), [as_array(mass, "mass"), as_array(size, "size", (3,))])
        sq = s * s
        d = np.stack([sq[..., 1] + sq[..., 2], sq[..., 0] + sq[..., 2], sq[..., 0] + sq[..., 1]], axis=-1)
        return cls._from_diag(m, d * (m[..., None] / 12), frame, size=s)

    @classmethod
    def cylinder(cls, mass: ArrayLike, radius: ArrayLike, length: ArrayLike, frame: Frame = None) -> SpatialInertia:
        """A solid cylinder along z, centred at the origin::

            I_c = diag(m(3r² + l²)/12, m(3r² + l²)/12, m r²/2)
        """
        m, r, ln = adopt_dtype(
            (mass, radius, length), [as_array(mass, "mass"), as_array(radius, "radius"), as_array(length, "length")]
        )
        a = m * (3 * r * r + ln * ln) / 12
        return cls._from_diag(m, np.stack(np.broadcast_arrays(a, a, m * r * r / 2), axis=-1), frame, radius=r, length=ln)

    @classmethod
    def sphere(cls, mass: ArrayLike, radius: ArrayLike, frame: Frame = None) -> SpatialInertia:
        """A solid sphere centred at the origin: ``I_c = 2/5 m r² 1``."""
        m, r = adopt_dtype((mass, radius), [as_array(mass, "mass"), as_array(radius, "radius")])
        a = 2 * m * r * r / 5
        return cls._from_diag(m, np.stack([a, a, a], axis=-1), frame, radius=r)

    @classmethod
    def point_mass(cls, mass: ArrayLike, com: ArrayLike, frame: Frame = None) -> SpatialInertia:
        """A point mass at ``com`` (``I_c = 0``)."""
        m, c = adopt_dtype((mass, com), [as_array(mass, "mass"), as_array(com, "com", (3,))])
        return cls(m, c, np.zeros(c.shape[:-1] + (3, 3), dtype=result_dtype(m, c)), frame)

    @classmethod
    def zero(cls, shape: tuple[int, ...] = (), dtype: DTypeLike = np.float64, frame: Frame = None) -> SpatialInertia:
        """The zero inertia (the neutral element of ``+``)."""
        shape = tuple(shape)
        return cls._wrap(np.zeros(shape, dtype), np.zeros(shape + (3,), dtype), np.zeros(shape + (3, 3), dtype), frame)

    @classmethod
    def _from_diag(cls, m: np.ndarray, d: np.ndarray, frame: Frame, **sizes: np.ndarray) -> SpatialInertia:
        # the moments are squares of the sizes, so the sizes themselves are checked
        for name, val in (("mass", m), *sizes.items()):
            if val.dtype.kind != "O" and np.any(val < 0):
                raise InertiaError(f"{name}: expected non-negative values, got {format_array(val)}")
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
        cx = skew_unchecked(self.com)
        return self.inertia_com - self.mass[..., None, None] * (cx @ cx)

    def __getitem__(self, idx: Any) -> SpatialInertia:
        idx = batch_index(self.com, idx, 1)
        return SpatialInertia._wrap(
            np.array(self.mass[idx]), np.array(self.com[idx]), np.array(self.inertia_com[idx]), self.frame
        )

    def matrix(self) -> np.ndarray:
        """The `(..., 6, 6)` spatial inertia matrix (see the class docstring)."""
        m = self.mass[..., None, None]
        cx = skew_unchecked(self.com)
        # object arrays get exact integer ones, so SymPy sees m, not 1.0*m
        eye = np.eye(3, dtype=self.dtype) if self.dtype.kind != "O" else np.eye(3, dtype=int).astype(object)
        top = np.concatenate([self.inertia_origin, m * cx], axis=-1)
        bottom = np.concatenate([m * matrix_transpose(cx), m * eye], axis=-1)
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

    def __matmul__(self, motion: SpatialMotion) -> SpatialForce:
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
            raise SpatialTypeError(f"inertia @ x needs a SpatialMotion, got a {type_name(motion)}: " + raw_vector_hint("SpatialMotion"))
        frame = merge_frames(self.frame, motion.frame, "inertia @ motion")
        return SpatialForce._wrap(self._momentum(motion.vector), frame)

    def _momentum(self, v: np.ndarray) -> np.ndarray:
        w, lin = v[..., :3], v[..., 3:]
        hf = self.mass[..., None] * (lin - cross3(self.com, w))
        hn = matvec(self.inertia_com, w) + cross3(self.com, hf)
        return np.concatenate(broadcast_batch(hn, hf), axis=-1)

    def __add__(self, other: SpatialInertia) -> SpatialInertia:
        """Composite inertia of two bodies rigidly joined (both expressed in the same frame).

        Adds the linear parameters ``(m, m c, Ī)`` (chapter §5.3)::

            m = m₁ + m₂,   c = (m₁c₁ + m₂c₂)/m,   I_c = Ī₁ + Ī₂ + m [c]×[c]×
        """
        if not isinstance(other, SpatialInertia):
            mix_error("add", self, other)
        frame = merge_frames(self.frame, other.frame, "inertia + inertia")
        m = np.asarray(self.mass + other.mass)  # 0-d object arrays add to a bare object
        h = self.com * self.mass[..., None] + other.com * other.mass[..., None]
        i_o = self.inertia_origin + other.inertia_origin
        if m.dtype.kind == "O":
            c = h / m[..., None]
        else:
            zero = m == 0
            c = np.where(zero[..., None], 0.0, h / np.where(zero, 1.0, m)[..., None])
        cx = skew_unchecked(c)
        return SpatialInertia._wrap(*broadcast_inertia(m, c, i_o + m[..., None, None] * (cx @ cx)), frame)

    def __radd__(self, other: object) -> SpatialInertia:
        if isinstance(other, int) and other == 0:  # sum() starts from 0
            return self
        mix_error("add", other, self)

    def kinetic_energy(self, motion: SpatialMotion) -> Any:
        """Kinetic energy `(...)` of the body moving with ``motion``::

            T = ½ vᵀ I v
        """
        if not isinstance(motion, SpatialMotion):
            mix_error("compute the kinetic energy of", self, motion)
        check_same_frame(self.frame, motion.frame, "inertia.kinetic_energy(motion)")
        return sum_last(motion.vector * self._momentum(motion.vector)) / 2

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

    def is_physical(self, *, tol: float | None = None) -> bool | np.ndarray:
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
                    f"principal moments {format_array(ev[idx])}"
                )

    def __repr__(self) -> str:
        return (
            f"SpatialInertia(mass={format_array(self.mass)}, com={format_array(self.com)}, "
            f"inertia_com={format_array(self.inertia_com)}{format_tags(self)})"
        )


def _sym_from(
    xx: np.ndarray, xy: np.ndarray, yy: np.ndarray, xz: np.ndarray, yz: np.ndarray, zz: np.ndarray
) -> np.ndarray:
    rows = [np.stack([xx, xy, xz], axis=-1), np.stack([xy, yy, yz], axis=-1), np.stack([xz, yz, zz], axis=-1)]
    return np.stack(rows, axis=-2)


def _exact_float64(m: Any, c: Any, ic: Any) -> bool:
    """Whether ``(m, c, ic)`` are finite float64 arrays of shapes ``S``, ``S + (3,)``, ``S + (3, 3)``."""
    return (type(m) is np.ndarray and type(c) is np.ndarray and type(ic) is np.ndarray
            and m.dtype == c.dtype == ic.dtype == np.float64
            and c.shape == m.shape + (3,) and ic.shape == m.shape + (3, 3)
            and bool(np.isfinite(m).all() and np.isfinite(c).all() and np.isfinite(ic).all()))


def broadcast_inertia(m: np.ndarray, c: np.ndarray, ic: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mass `(...)`, centre of mass `(..., 3)` and ``I_C`` `(..., 3, 3)` broadcast to their common batch shape."""
    shape = np.broadcast_shapes(m.shape, c.shape[:-1], ic.shape[:-2])
    dtype = result_dtype(m, c, ic)
    return (
        np.array(np.broadcast_to(m, shape), dtype=dtype),
        np.array(np.broadcast_to(c, shape + (3,)), dtype=dtype),
        np.array(np.broadcast_to(ic, shape + (3, 3)), dtype=dtype),
    )


def _init_i(obj: object, m: np.ndarray, c: np.ndarray, ic: np.ndarray, frame: Frame) -> None:
    object.__setattr__(obj, "mass", readonly(m))
    object.__setattr__(obj, "com", readonly(c))
    object.__setattr__(obj, "inertia_com", readonly(ic))
    object.__setattr__(obj, "frame", frame)
