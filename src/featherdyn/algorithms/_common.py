"""Shared pieces of the reference algorithms (private): the model's constant data in the book's symbols.

The reference algorithms receive arrays the public layer (:mod:`featherdyn.api`)
has already checked — trailing lengths, finiteness, unit quaternions — and
compute in the dtype those arrays promote to (float64, float32 or SymPy
objects). :class:`TreeData` is the model's constant data (joint placements,
inertias, motion subspaces, gravity) cast to that dtype.
"""

from __future__ import annotations

import numpy as np

from ..model import Model
from ..spatial import PluckerTransform, SpatialInertia, SpatialMotion
from ..spatial.validation import result_dtype

__all__ = ["TreeData", "batch_dtype", "stack_motions", "stack_transforms", "expand", "expand_inertia", "zeros"]


def batch_dtype(*vectors: np.ndarray | None, f_ext: np.ndarray | None = None) -> tuple[tuple[int, ...], np.dtype]:
    """The common batch shape and computation dtype of ``vectors`` `(..., n)` and ``f_ext`` `(..., nb, 6)`."""
    given = [a for a in vectors if a is not None]
    shapes = [a.shape[:-1] for a in given]
    if f_ext is not None:
        given.append(f_ext)
        shapes.append(f_ext.shape[:-2])
    return np.broadcast_shapes(*shapes), result_dtype(*given)


class TreeData:
    """The model's constant data cast to one dtype, in the chapter's symbols.

    Attributes:
        parents: ``λ(i)``.
        joint_placement: ``ᵖM_J``, the pose of joint ``i``'s frame in its parent body (maps
            joint-frame to parent coordinates; Pinocchio's ``jointPlacements``). RBDA's ``Xtree``
            is its inverse ``ᴶX_p``; the passes use ``X_up[i] = pose_in_parent(q, i).inverse()``.
        I: body inertias, one :class:`SpatialInertia` per body (body frame).
        S: motion subspaces `(6, nv_i)`.
        a0: the base acceleration ``−g`` as a spatial motion (the RNEA gravity trick).
    """

    def __init__(self, model: Model, dtype: np.dtype) -> None:
        self.model = model
        self.dtype = dtype
        self.parents = model.parents
        self.nb = model.nbodies

        def cast(a: np.ndarray) -> np.ndarray:
            return np.asarray(a).astype(dtype)

        pl, inertias = model.joint_placements, model.inertias
        self.joint_placement = [PluckerTransform._wrap(cast(pl.rotation[i]), cast(pl.translation[i]), None, None)
                      for i in range(self.nb)]
        self.I = [SpatialInertia._wrap(cast(inertias.mass[i]), cast(inertias.com[i]), cast(inertias.inertia_com[i]),
                                       None) for i in range(self.nb)]
        self.S = [cast(j.S) for j in model.joints]
        g = cast(model.gravity)
        self.a0 = SpatialMotion._wrap(np.concatenate([np.zeros(3, dtype=dtype), -g]), None)

    def q_i(self, q: np.ndarray, i: int) -> np.ndarray:
        m = self.model
        return q[..., m.idx_q[i] : m.idx_q[i] + m.nqs[i]]

    def v_i(self, v: np.ndarray, i: int) -> np.ndarray:
        m = self.model
        return v[..., m.idx_v[i] : m.idx_v[i] + m.nvs[i]]

    def pose_in_parent(self, q: np.ndarray, i: int) -> PluckerTransform:
        """``ᵖM_i(q)``: the pose of body ``i`` in its parent = ``joint_placement[i] @ M_J(q_i)``."""
        XJ = self.model.joints[i].pose(self.q_i(q, i))
        XJ = PluckerTransform._wrap(XJ.rotation.astype(self.dtype), XJ.translation.astype(self.dtype), None, None)
        return self.joint_placement[i] @ XJ

    def vJ(self, qd: np.ndarray, i: int) -> SpatialMotion:
        """Joint velocity (or any joint-space rate) ``S_i q̇_i`` as a motion in body ``i``."""
        return SpatialMotion._wrap(self.v_i(qd, i) @ self.S[i].T, None)


def stack_motions(ms: list[SpatialMotion], batch: tuple[int, ...], dtype: np.dtype) -> SpatialMotion:
    """Stack per-body motions into one `(..., nb, 6)` motion (body axis last among batch axes)."""
    if not ms:
        return SpatialMotion._wrap(np.zeros(batch + (0, 6), dtype=dtype), None)
    return SpatialMotion._wrap(np.stack([np.broadcast_to(m.vector, batch + (6,)) for m in ms], axis=-2), None)


def stack_transforms(xs: list[PluckerTransform], batch: tuple[int, ...], dtype: np.dtype) -> PluckerTransform:
    """Stack per-body transforms into one with batch shape `(..., nb)`."""
    if not xs:
        return PluckerTransform._wrap(np.zeros(batch + (0, 3, 3), dtype), np.zeros(batch + (0, 3), dtype), None, None)
    rot = np.stack([np.broadcast_to(x.rotation, batch + (3, 3)) for x in xs], axis=-3)
    p = np.stack([np.broadcast_to(x.translation, batch + (3,)) for x in xs], axis=-2)
    return PluckerTransform._wrap(rot, p, None, None)


def expand(X: PluckerTransform) -> PluckerTransform:
    """Add a trailing batch axis to ``X`` (to act on a set of columns `(..., k, 6)`)."""
    return PluckerTransform._wrap(X.rotation[..., None, :, :], X.translation[..., None, :], X.source, X.target)


def expand_inertia(I: SpatialInertia) -> SpatialInertia:
    """Add a trailing batch axis to ``I`` (to act on a set of columns `(..., k, 6)`)."""
    return SpatialInertia._wrap(I.mass[..., None], I.com[..., None, :], I.inertia_com[..., None, :, :], I.frame)


def zeros(batch: tuple[int, ...], shape: tuple[int, ...], dtype: np.dtype) -> np.ndarray:
    if dtype.kind == "O":
        out = np.empty(batch + shape, dtype=object)
        out.fill(0)
        return out
    return np.zeros(batch + shape, dtype=dtype)
