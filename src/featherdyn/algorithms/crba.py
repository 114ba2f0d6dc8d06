"""The joint-space mass matrix by the Composite Rigid Body Algorithm.

CRBA (chapter §5.3; RBDA table 6.2)::

    I^C_i = I_i + Σ_{children j} X_up[j]ᵀ I^C_j X_up[j]     (i = nb−1 … 0)
    F     = I^C_i S_i,   M_ii = S_iᵀ F
    j = i;  while λ(j) ≠ −1:  F = X_up[j]ᵀ F;  j = λ(j);  M_ji = S_jᵀ F;  M_ij = M_jiᵀ
    M += diag(armature)                                     (reflected rotor inertia)

The full symmetric matrix is returned (Pinocchio's C++ ``crba`` fills the
upper triangle only; its Python binding returns it full).
"""

from __future__ import annotations

import numpy as np

from ..model import Model
from ..spatial import PluckerTransform, SpatialInertia, SpatialMotion
from ._common import TreeData, batch_dtype, expand, expand_inertia, zeros

__all__ = ["crba", "composite_inertias"]


def composite_inertias(td: TreeData, q: np.ndarray) -> tuple[list[PluckerTransform], list[SpatialInertia]]:
    """``(X_up, IC)``: the parent-to-body transforms and composite inertias ``I^C_i`` (body frames)."""
    X_up = [td.pose_in_parent(q, i).inverse() for i in range(td.nb)]
    IC = list(td.I)
    for i in range(td.nb - 1, -1, -1):
        lam = td.parents[i]
        if lam != -1:
            IC[lam] = IC[lam] + X_up[i].apply_inverse(IC[i])
    return X_up, IC


def crba(model: Model, q: np.ndarray) -> np.ndarray:
    """The joint-space mass matrix ``M(q)`` `(..., nv, nv)`, full and symmetric, on a checked ``q`` `(..., nq)`.

    Public entry: :func:`featherdyn.crba`. ::

        T = ½ q̇ᵀ M(q) q̇,    M_ij = S_iᵀ ⁱX_j^* I^C_j S_j   (j in the subtree of i)
    """
    batch, dtype = batch_dtype(q)
    return mass_matrix_on(TreeData(model, dtype), batch, q)


def mass_matrix_on(td: TreeData, batch: tuple[int, ...], q: np.ndarray) -> np.ndarray:
    """:func:`crba` on the tree data ``td`` (its poses ``td.pose_in_parent``, its dtype) and ``batch``."""
    model = td.model
    X_up, IC = composite_inertias(td, q)
    M = zeros(batch, (model.nv, model.nv), td.dtype)
    for i in range(td.nb):
        si = slice(model.idx_v[i], model.idx_v[i] + model.nvs[i])
        # the columns of F = I^C_i S_i, as a batch of forces (..., nv_i, 6)
        F = expand_inertia(IC[i]) @ _columns(td.S[i], batch)
        M[..., si, si] = F.vector @ td.S[i]
        j = i
        while td.parents[j] != -1:
            F = expand(X_up[j]).apply_inverse(F)
            j = td.parents[j]
            sj = slice(model.idx_v[j], model.idx_v[j] + model.nvs[j])
            block = F.vector @ td.S[j]  # (..., nv_i, nv_j) = (S_jᵀ F)ᵀ
            M[..., si, sj] = block
            M[..., sj, si] = np.swapaxes(block, -1, -2)
    if np.any(model.armature != 0):
        k = np.arange(model.nv)
        M[..., k, k] = M[..., k, k] + model.armature.astype(td.dtype)
    return M


def _columns(S: np.ndarray, batch: tuple[int, ...]) -> SpatialMotion:
    """The columns of ``S`` `(6, k)` as a batch of motions `(..., k, 6)`."""
    cols = np.broadcast_to(S.T, batch + S.T.shape)
    return SpatialMotion._wrap(cols, None)
