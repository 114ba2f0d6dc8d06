"""Inverse dynamics by the Recursive Newton–Euler Algorithm, and its special cases.

RNEA (chapter §8.1, appendix F.5; RBDA table 5.1), gravity entered as a base
acceleration ``a₀ = −g``::

    v_i = X_up[i] v_λ(i) + S_i q̇_i
    a_i = X_up[i] a_λ(i) + S_i q̈_i + v_i × S_i q̇_i
    f_i = I_i a_i + v_i ×* I_i v_i − f_i^ext
    τ_i = S_iᵀ f_i,        f_λ(i) += X_up[i]ᵀ f_i      (i = nb−1 … 0)
    τ  += armature ∘ q̈                                   (reflected rotor inertia)
"""

from __future__ import annotations

import numpy as np

from ..model import Model
from ..spatial import SpatialForce, SpatialMotion, cross_force, cross_motion
from ._common import TreeData, batch_dtype, zeros

__all__ = ["rnea", "nonlinear_effects", "generalized_gravity", "forward_pass"]


def forward_pass(td: TreeData, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, f_ext: np.ndarray | None,
                 a0: SpatialMotion) -> tuple[list, list[SpatialMotion], list[SpatialMotion], list[SpatialMotion],
                                             list[SpatialForce]]:
    """RNEA's forward pass: ``(X_up, S q̇, v, a, f)`` per body (f before the backward accumulation)::

        v_i = X_up[i] v_λ(i) + S_i q̇_i,   a_i = X_up[i] a_λ(i) + S_i q̈_i + v_i × S_i q̇_i
        f_i = I_i a_i + v_i ×* I_i v_i − f_i^ext
    """
    X_up: list = []  # ⁱX_λ(i), parent → body i
    vJs: list[SpatialMotion] = []
    vel: list[SpatialMotion] = []
    acc: list[SpatialMotion] = []
    f: list[SpatialForce] = []
    for i in range(td.nb):
        lam = td.parents[i]
        X_up.append(td.pose_in_parent(q, i).inverse())
        vJ = td.vJ(qd, i)
        v_i = vJ if lam == -1 else X_up[i].apply(vel[lam]) + vJ
        a_i = X_up[i].apply(a0 if lam == -1 else acc[lam]) + td.vJ(qdd, i) + cross_motion(v_i, vJ)
        f_i = td.I[i] @ a_i + cross_force(v_i, td.I[i] @ v_i)
        if f_ext is not None:
            f_i = f_i - SpatialForce._wrap(f_ext[..., i, :], None)
        vJs.append(vJ)
        vel.append(v_i)
        acc.append(a_i)
        f.append(f_i)
    return X_up, vJs, vel, acc, f


def rnea(model: Model, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, f_ext: np.ndarray | None = None,
         gravity: bool = True) -> np.ndarray:
    """Joint forces ``τ`` `(..., nv)` by RNEA, on checked arrays (public entry: :func:`featherdyn.rnea`).

    Args:
        model: the tree (gravity from ``model.gravity``).
        q: `(..., nq)`; qd, qdd: `(..., nv)` — ``q̇``, ``q̈``.
        f_ext: optional `(..., nb, 6)` external forces ``[n; f]`` on each body, body coordinates.
        gravity: ``False`` leaves gravity out (``a₀ = 0``).

    ::

        τ = M(q) q̈ + C(q, q̇) q̇ + g(q) − Σ_i J_iᵀ f_i^ext      (M includes diag(armature))
    """
    batch, dtype = batch_dtype(q, qd, qdd, f_ext=f_ext)
    td = TreeData(model, dtype)
    a0 = td.a0 if gravity else SpatialMotion._wrap(np.zeros(6, dtype=td.dtype), None)
    X_up, _, _, _, f = forward_pass(td, q, qd, qdd, f_ext, a0)

    tau = zeros(batch, (model.nv,), td.dtype)
    for i in range(td.nb - 1, -1, -1):
        lam = td.parents[i]
        tau[..., model.idx_v[i] : model.idx_v[i] + model.nvs[i]] = f[i].vector @ td.S[i]
        if lam != -1:
            f[lam] = f[lam] + X_up[i].apply_inverse(f[i])
    if np.any(model.armature != 0):
        tau = tau + model.armature.astype(td.dtype) * qdd
    return tau


def nonlinear_effects(model: Model, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """Coriolis, centrifugal and gravity forces `(..., nv)` on checked arrays (public: :func:`featherdyn.nonlinear_effects`)::

        h(q, q̇) = C(q, q̇) q̇ + g(q) = RNEA(q, q̇, 0)
    """
    return rnea(model, q, qd, np.zeros(qd.shape, dtype=qd.dtype))


def generalized_gravity(model: Model, q: np.ndarray) -> np.ndarray:
    """Gravity forces `(..., nv)` on checked arrays (public: :func:`featherdyn.generalized_gravity`)::

        g(q) = RNEA(q, 0, 0)
    """
    zero = np.zeros(q.shape[:-1] + (model.nv,), dtype=q.dtype)
    return rnea(model, q, zero, zero)
