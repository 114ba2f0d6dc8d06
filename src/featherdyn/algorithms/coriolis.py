"""The Coriolis matrix ``C(q, q̇)`` with ``Ṁ − 2C`` skew-symmetric.

Built body by body in world coordinates (Echeandia & Wensing 2021)::

    C = Σ_i ⁰J_iᵀ (⁰I_i ⁰J̇_i + B_i ⁰J_i),
    B_i = ½ (v_i ×* I_i − I_i v_i× + (I_i v_i)⊼),     (h⊼) m := m ×* h

so that ``C q̇`` is the Coriolis and centrifugal term of :func:`rnea` and
``C + Cᵀ = Ṁ`` (because ``B + Bᵀ = İ = v×* I − I v×``). This is the
Christoffel-consistent factorisation that Pinocchio's
``computeCoriolisMatrix`` returns.
"""

from __future__ import annotations

import numpy as np

from ..model import Model
from ..results import Kinematics
from ..spatial import crf, crm
from ..spatial.ops import crm_apply, skew_unchecked
from ._common import TreeData, zeros
from .jacobians import mask_support, world_columns
from .kinematics import body_at, motion_at

__all__ = ["coriolis_matrix"]


def _bar(h: np.ndarray) -> np.ndarray:
    """The `(..., 6, 6)` matrix ``h⊼`` with ``(h⊼) m = m ×* h`` for a force ``h = [n; f]``."""
    n, f = -skew_unchecked(h[..., :3]), -skew_unchecked(h[..., 3:])
    zero = np.zeros_like(n)
    return np.concatenate([np.concatenate([n, f], axis=-1), np.concatenate([f, zero], axis=-1)], axis=-2)


def coriolis_matrix(model: Model, kin: Kinematics) -> np.ndarray:
    """``C(q, q̇)`` `(..., nv, nv)` from the placements and body velocities of ``kin``.

    ``C q̇ = RNEA(q, q̇, 0) − g(q)`` and ``Ṁ − 2C`` is skew-symmetric.
    """
    assert kin.velocities is not None
    batch, dtype = kin.placements.shape[:-1], kin.placements.dtype
    td = TreeData(model, dtype)
    cols = world_columns(model, td, kin.placements, batch)  # (..., nv, 6) = ⁰X_k S_k
    v_world = [body_at(kin.placements, k).apply(motion_at(kin.velocities, k)).vector for k in range(model.nbodies)]
    dcols = zeros(batch, (model.nv, 6), dtype)
    for k in range(model.nbodies):
        sk = slice(model.idx_v[k], model.idx_v[k] + model.nvs[k])
        dcols[..., sk, :] = crm_apply(v_world[k][..., None, :], cols[..., sk, :])
    C = zeros(batch, (model.nv, model.nv), dtype)
    for i in range(model.nbodies):
        J = np.swapaxes(mask_support(cols, model, i), -1, -2)    # (..., 6, nv)
        dJ = np.swapaxes(mask_support(dcols, model, i), -1, -2)
        I_w = body_at(kin.placements, i).apply(td.I[i]).matrix()
        vw = v_world[i]
        h = (I_w @ vw[..., None])[..., 0]
        B = (crf(vw) @ I_w - I_w @ crm(vw) + _bar(h)) / 2
        C = C + np.swapaxes(J, -1, -2) @ (I_w @ dJ + B @ J)
    return C
