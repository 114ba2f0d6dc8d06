"""Plücker coordinate transforms ``ᴮX_A``, and spatial_v2's ``rotx``, ``roty``, ``rotz``, ``xlt``, ``plux``.

A :class:`PluckerTransform` ``(R, p)`` is the pose of frame A in frame B; it
maps motions with ``X``, forces with ``X* = X⁻ᵀ`` and inertias with
``X* I X⁻¹`` from A- to B-coordinates::

    X = [[ R, 0 ], [ [p]×R, R ]]

Sources: RBDA (2008) §2.8, eqs. 2.24–2.25; chapter §3; spatial_v2.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NoReturn, overload

import numpy as np
from numpy.typing import ArrayLike, DTypeLike

from ..errors import ShapeError, SpatialTypeError
from ..frames import Frame, check_same_frame
from ..tolerances import SPATIAL_STRUCTURE
from .inertia import SpatialInertia, broadcast_inertia
from .ops import (
    batch_index,
    broadcast_batch,
    broadcast_rotation_translation,
    cross3,
    format_array,
    format_tags,
    matrix_transpose,
    matvec,
    skew_unchecked,
    type_name,
    unskew_unchecked,
)
from .validation import as_array, check_rotation, result_dtype
from .vectors import SpatialForce, SpatialMotion, SpatialValue

#: what a transform acts on
_Transformable = SpatialMotion | SpatialForce | SpatialInertia


@dataclass(frozen=True, slots=True, init=False, eq=False, repr=False)
class PluckerTransform(SpatialValue):
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
        self, rotation: ArrayLike, translation: ArrayLike, source: Frame = None, target: Frame = None, *, validate: bool = True
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
    def _wrap_read_only(cls, rot: np.ndarray, p: np.ndarray) -> PluckerTransform:
        """:meth:`_wrap` of arrays that are already read-only (views of a read-only buffer), frames ``None``."""
        obj = object.__new__(cls)
        _SET_ROTATION(obj, rot)
        _SET_TRANSLATION(obj, p)
        _SET_SOURCE(obj, None)
        _SET_TARGET(obj, None)
        return obj

    @classmethod
    def identity(
        cls, shape: tuple[int, ...] = (), dtype: DTypeLike = np.float64, source: Frame = None, target: Frame = None
    ) -> PluckerTransform:
        """The identity transform with batch shape ``shape``."""
        rot = np.broadcast_to(np.eye(3, dtype=dtype), tuple(shape) + (3, 3)).copy()
        return cls._wrap(rot, np.zeros(tuple(shape) + (3,), dtype=dtype), source, target)

    @classmethod
    def from_homogeneous(
        cls, matrix: ArrayLike, source: Frame = None, target: Frame = None, *, validate: bool = True
    ) -> PluckerTransform:
        """From a `(..., 4, 4)` homogeneous matrix ``[[R, p], [0, 1]]`` (the pose of A in B)."""
        t = as_array(matrix, "matrix", (4, 4))
        if t.dtype.kind != "O":
            bottom = t[..., 3, :]
            expected = np.array([0, 0, 0, 1], dtype=t.dtype)
            if not np.allclose(bottom, expected, atol=SPATIAL_STRUCTURE.of(t.dtype), rtol=0):
                raise ShapeError(
                    f"matrix: expected a homogeneous transform with last row [0, 0, 0, 1], got {format_array(bottom.reshape(-1, 4)[0])}"
                )
        return cls(t[..., :3, :3], t[..., :3, 3], source, target, validate=validate)

    @classmethod
    def from_plux(cls, E: ArrayLike, r: ArrayLike, source: Frame = None, target: Frame = None) -> PluckerTransform:
        """From Featherstone's ``plux(E, r)``: ``E`` rotates A- to B-coordinates, ``r`` is B's origin in A.

        ::

            plux(E, r) = [[E, 0], [−E [r]×, E]]   ⇒   R = E,  p = −E r

        Source: spatial_v2 ``plux``; RBDA (2008) eq. 2.24.
        """
        e = as_array(E, "E", (3, 3))
        rr = as_array(r, "r", (3,))
        check_rotation(e, "E")
        return cls._wrap(*broadcast_rotation_translation(e, -matvec(e, rr)), source, target)

    @classmethod
    def from_matrix(cls, matrix: ArrayLike, source: Frame = None, target: Frame = None) -> PluckerTransform:
        """From a `(..., 6, 6)` motion transform matrix ``[[R, 0], [[p]×R, R]]`` (structure checked)."""
        x = as_array(matrix, "matrix", (6, 6))
        rot = x[..., :3, :3]
        check_rotation(rot, "matrix[:3, :3]")
        tol = SPATIAL_STRUCTURE.of(x.dtype)
        scale = max(1.0, float(np.abs(x).max())) if x.size else 1.0
        if np.abs(x[..., :3, 3:]).max(initial=0.0) > tol * scale or np.abs(x[..., 3:, 3:] - rot).max(initial=0.0) > tol * scale:
            raise ShapeError("matrix: not a Plücker motion transform: expected [[R, 0], [[p]×R, R]]")
        px = x[..., 3:, :3] @ matrix_transpose(rot)
        if np.abs(px + matrix_transpose(px)).max(initial=0.0) > tol * scale:
            raise ShapeError("matrix: not a Plücker motion transform: lower-left block times Rᵀ is not skew-symmetric")
        return cls._wrap(np.array(rot), unskew_unchecked(px), source, target)

    @property
    def shape(self) -> tuple[int, ...]:
        """The batch shape."""
        return tuple(self.translation.shape[:-1])

    @property
    def dtype(self) -> np.dtype:
        return self.translation.dtype

    def __getitem__(self, idx: Any) -> PluckerTransform:
        idx = batch_index(self.translation, idx, 1)
        return PluckerTransform._wrap(np.array(self.rotation[idx]), np.array(self.translation[idx]), self.source, self.target)

    # action on spatial values ----------------------------------------------

    @overload
    def apply(self, x: SpatialMotion) -> SpatialMotion: ...
    @overload
    def apply(self, x: SpatialForce) -> SpatialForce: ...
    @overload
    def apply(self, x: SpatialInertia) -> SpatialInertia: ...

    def apply(self, x: _Transformable) -> _Transformable:
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
            rw = matvec(self.rotation, x.angular)
            rv = matvec(self.rotation, x.linear) + cross3(self.translation, rw)
            return SpatialMotion._wrap(np.concatenate(broadcast_batch(rw, rv), axis=-1), self.target, x.body, x.relative_to)
        if isinstance(x, SpatialForce):
            check_same_frame(x.frame, self.source, "X.apply(force): force frame vs X.source")
            rf = matvec(self.rotation, x.linear)
            rn = matvec(self.rotation, x.angular) + cross3(self.translation, rf)
            return SpatialForce._wrap(np.concatenate(broadcast_batch(rn, rf), axis=-1), self.target)
        if isinstance(x, SpatialInertia):
            check_same_frame(x.frame, self.source, "X.apply(inertia): inertia frame vs X.source")
            com = matvec(self.rotation, x.com) + self.translation
            ic = self.rotation @ x.inertia_com @ matrix_transpose(self.rotation)
            return SpatialInertia._wrap(*broadcast_inertia(x.mass, com, ic), self.target)
        raise _apply_type_error("X.apply", x)

    @overload
    def apply_inverse(self, x: SpatialMotion) -> SpatialMotion: ...
    @overload
    def apply_inverse(self, x: SpatialForce) -> SpatialForce: ...
    @overload
    def apply_inverse(self, x: SpatialInertia) -> SpatialInertia: ...

    def apply_inverse(self, x: _Transformable) -> _Transformable:
        """Transform from B back to A: ``X⁻¹ m``, ``X⁻¹* f = Xᵀ f``, ``Xᵀ I X`` (Pinocchio's ``actInv``).

        Equal to ``X.inverse().apply(x)`` without forming the inverse::

            X⁻¹ m:  ω = Rᵀ ω',  v = Rᵀ (v' − p × ω')
            Xᵀ f:   f = Rᵀ f',  n = Rᵀ (n' − p × f')
        """
        rt = matrix_transpose(self.rotation)
        if isinstance(x, SpatialMotion):
            check_same_frame(x.frame, self.target, "X.apply_inverse(motion): motion frame vs X.target")
            w = matvec(rt, x.angular)
            v = matvec(rt, x.linear - cross3(self.translation, x.angular))
            return SpatialMotion._wrap(np.concatenate(broadcast_batch(w, v), axis=-1), self.source, x.body, x.relative_to)
        if isinstance(x, SpatialForce):
            check_same_frame(x.frame, self.target, "X.apply_inverse(force): force frame vs X.target")
            f = matvec(rt, x.linear)
            n = matvec(rt, x.angular - cross3(self.translation, x.linear))
            return SpatialForce._wrap(np.concatenate(broadcast_batch(n, f), axis=-1), self.source)
        if isinstance(x, SpatialInertia):
            check_same_frame(x.frame, self.target, "X.apply_inverse(inertia): inertia frame vs X.target")
            com = matvec(rt, x.com - self.translation)
            ic = rt @ x.inertia_com @ self.rotation
            return SpatialInertia._wrap(*broadcast_inertia(x.mass, com, ic), self.source)
        raise _apply_type_error("X.apply_inverse", x)

    @overload
    def __matmul__(self, other: PluckerTransform) -> PluckerTransform: ...
    @overload
    def __matmul__(self, other: SpatialMotion) -> SpatialMotion: ...
    @overload
    def __matmul__(self, other: SpatialForce) -> SpatialForce: ...
    @overload
    def __matmul__(self, other: SpatialInertia) -> SpatialInertia: ...

    def __matmul__(self, other: PluckerTransform | _Transformable) -> PluckerTransform | _Transformable:
        """``X_CB @ X_BA = X_CA`` (composition); ``X @ value`` is ``X.apply(value)``.

        ::

            (R₁, p₁) ∘ (R₂, p₂) = (R₁ R₂,  R₁ p₂ + p₁)
        """
        if isinstance(other, PluckerTransform):
            check_same_frame(self.source, other.target, "X_CB @ X_BA: X_CB.source vs X_BA.target")
            rot = self.rotation @ other.rotation
            p = matvec(self.rotation, other.translation) + self.translation
            return PluckerTransform._wrap(*broadcast_rotation_translation(rot, p), other.source, self.target)
        return self.apply(other)

    def __rmatmul__(self, other: object) -> NoReturn:
        raise _apply_type_error("@", other)

    def inverse(self) -> PluckerTransform:
        """``ᴬX_B = (ᴮX_A)⁻¹``: the pose of B in A (source and target swap).

        ::

            (R, p)⁻¹ = (Rᵀ, −Rᵀ p)
        """
        rt = matrix_transpose(self.rotation)
        return PluckerTransform._wrap(np.array(rt), -matvec(rt, self.translation), self.target, self.source)

    # matrices ----------------------------------------------------------------

    def matrix(self) -> np.ndarray:
        """The `(..., 6, 6)` motion transform ``X = [[R, 0], [[p]×R, R]]``."""
        rot = self.rotation
        zero = np.zeros_like(rot)
        return np.concatenate(
            [np.concatenate([rot, zero], axis=-1), np.concatenate([skew_unchecked(self.translation) @ rot, rot], axis=-1)], axis=-2
        )

    def dual_matrix(self) -> np.ndarray:
        """The `(..., 6, 6)` force transform ``X* = X⁻ᵀ = [[R, [p]×R], [0, R]]`` (formed directly, not by inversion)."""
        rot = self.rotation
        zero = np.zeros_like(rot)
        return np.concatenate(
            [np.concatenate([rot, skew_unchecked(self.translation) @ rot], axis=-1), np.concatenate([zero, rot], axis=-1)], axis=-2
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
            raise SpatialTypeError(f"X.allclose needs a PluckerTransform, got a {type_name(other)}")
        check_same_frame(self.source, other.source, "X.allclose: source frames")
        check_same_frame(self.target, other.target, "X.allclose: target frames")
        return bool(
            np.allclose(self.rotation, other.rotation, rtol=rtol, atol=atol)
            and np.allclose(self.translation, other.translation, rtol=rtol, atol=atol)
        )

    def __repr__(self) -> str:
        return f"PluckerTransform(rotation={format_array(self.rotation)}, translation={format_array(self.translation)}{format_tags(self)})"


def _apply_type_error(what: str, x: object) -> SpatialTypeError:
    return SpatialTypeError(
        f"{what} needs a SpatialMotion, SpatialForce or SpatialInertia, got a {type_name(x)}: motions transform "
        "with X and forces with X* = X⁻ᵀ, so a raw 6-vector is ambiguous. Wrap it with "
        "SpatialMotion.from_vector(v) or SpatialForce.from_vector(f), or use X.matrix() @ v / X.dual_matrix() @ f"
    )


#: the slots' own setters: a frozen dataclass refuses ``obj.x = …``, and ``object.__setattr__`` costs
#: a type lookup per field (building the results of the compiled one-state calls is on the hot path)
_SET_ROTATION, _SET_TRANSLATION, _SET_SOURCE, _SET_TARGET = (
    PluckerTransform.__dict__[name].__set__ for name in ("rotation", "translation", "source", "target"))


def _init_x(obj: object, rot: np.ndarray, p: np.ndarray, source: Frame, target: Frame) -> None:
    rot.setflags(write=False)  # (readonly() inlined)
    p.setflags(write=False)
    _SET_ROTATION(obj, rot)
    _SET_TRANSLATION(obj, p)
    _SET_SOURCE(obj, source)
    _SET_TARGET(obj, target)


def rotx(theta: ArrayLike) -> PluckerTransform:
    """spatial_v2 ``rotx``: the coordinate transform to a frame rotated by ``theta`` about x.

    A coordinate transform (as in the book), so ``R = Rx(θ)ᵀ``::

        rotx(θ) = [[E, 0], [0, E]],   E = [[1, 0, 0], [0, c, s], [0, −s, c]]
    """
    return _rot_axis(theta, 0)


def roty(theta: ArrayLike) -> PluckerTransform:
    """spatial_v2 ``roty``: ``E = [[c, 0, −s], [0, 1, 0], [s, 0, c]]`` (``R = Ry(θ)ᵀ``)."""
    return _rot_axis(theta, 1)


def rotz(theta: ArrayLike) -> PluckerTransform:
    """spatial_v2 ``rotz``: ``E = [[c, s, 0], [−s, c, 0], [0, 0, 1]]`` (``R = Rz(θ)ᵀ``)."""
    return _rot_axis(theta, 2)


def _rot_axis(theta: ArrayLike, axis: int) -> PluckerTransform:
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


def xlt(r: ArrayLike) -> PluckerTransform:
    """spatial_v2 ``xlt``: the coordinate transform to a frame whose origin is at ``r``.

    ::

        xlt(r) = [[1, 0], [−[r]×, 1]]   ⇒   R = 1,  p = −r
    """
    rr = as_array(r, "r", (3,))
    rot = np.broadcast_to(np.eye(3, dtype=rr.dtype), rr.shape[:-1] + (3, 3)).copy()
    return PluckerTransform._wrap(rot, -rr, None, None)


def plux(E: ArrayLike, r: ArrayLike) -> PluckerTransform:
    """spatial_v2 ``plux(E, r) = rot(E) @ xlt(r)``; see :meth:`PluckerTransform.from_plux`."""
    return PluckerTransform.from_plux(E, r)
