"""Forward dynamics by the Articulated-Body Algorithm.

ABA (RBDA table 7.1; chapter §8 and appendix F.5), gravity as ``a₀ = −g``::

    pass 1 (i = 0 … nb−1):   v_i = X_up[i] v_λ(i) + S_i q̇_i,   c_i = v_i × S_i q̇_i
                             I^A_i = I_i,   p^A_i = v_i ×* I_i v_i − f_i^ext
    pass 2 (i = nb−1 … 0):   U_i = I^A_i S_i,   D_i = S_iᵀ U_i + diag(armature_i),   u_i = τ_i − S_iᵀ p^A_i
                             I^a = I^A_i − U_i D_i⁻¹ U_iᵀ,   p^a = p^A_i + I^a c_i + U_i D_i⁻¹ u_i
                             I^A_λ(i) += X_up[i]ᵀ I^a X_up[i],   p^A_λ(i) += X_up[i]ᵀ p^a
    pass 3 (i = 0 … nb−1):   a' = X_up[i] a_λ(i) + c_i
                             q̈_i = D_i⁻¹ (u_i − U_iᵀ a'),   a_i = a' + S_i q̈_i
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ..errors import SingularMassMatrixError
from ..model import Model
from ..spatial import PluckerTransform, SpatialMotion, cross_force, cross_motion
from ..spatial.ops import matrix_transpose
from ..tolerances import SINGULAR_PIVOT_RTOL
from ._common import TreeData, batch_dtype, zeros

__all__ = ["aba"]


def _inv_small(D: np.ndarray, model: Model, i: int, scale: Any) -> np.ndarray:
    """``D⁻¹`` for the `(..., k, k)` joint-space articulated inertia of joint ``i``; singular → error."""
    if D.dtype.kind == "O":
        import sympy

        if D.shape[-1] == 1:
            return 1 / D
        flat = D.reshape(-1, *D.shape[-2:])
        out = np.empty_like(flat)
        for n, block in enumerate(flat):
            out[n] = np.array(sympy.Matrix(block).inv(), dtype=object)
        return out.reshape(D.shape)
    eig_min = np.linalg.eigvalsh((D + matrix_transpose(D)) / 2)[..., 0]
    if np.any(eig_min <= SINGULAR_PIVOT_RTOL * scale):
        raise SingularMassMatrixError.for_joint(model.joint_names[i], model.body_names[i], float(np.min(eig_min)))
    return np.linalg.inv(D)


def aba(model: Model, q: np.ndarray, qd: np.ndarray, tau: np.ndarray, f_ext: np.ndarray | None = None,
        gravity: bool = True) -> np.ndarray:
    """Joint accelerations ``q̈`` `(..., nv)` by ABA, on checked arrays (public entry: :func:`featherdyn.aba`).

    Args:
        model: the tree.
        q: `(..., nq)`; qd, tau: `(..., nv)` — ``q̇``, ``τ``.
        f_ext: optional `(..., nb, 6)` body-frame external forces ``[n; f]``.
        gravity: ``False`` leaves gravity out.

    ::

        q̈ = M(q)⁻¹ (τ − C(q, q̇) q̇ − g(q) + Σ_i J_iᵀ f_i^ext)

    Raises:
        SingularMassMatrixError: naming the joint, when ``M(q)`` is singular
            (:data:`featherdyn.tolerances.SINGULAR_PIVOT_RTOL`).
    """
    batch, dtype = batch_dtype(q, qd, tau, f_ext=f_ext)
    td = TreeData(model, dtype)
    a0 = td.a0 if gravity else SpatialMotion._wrap(np.zeros(6, dtype=td.dtype), None)

    nb = td.nb
    X_up: list[PluckerTransform] = []
    vel: list[SpatialMotion] = []
    Xm: list[np.ndarray] = []
    c: list[np.ndarray] = []
    IA: list[np.ndarray] = []
    pA: list[np.ndarray] = []
    for i in range(nb):
        lam = td.parents[i]
        X_up.append(td.pose_in_parent(q, i).inverse())
        Xm.append(X_up[i].matrix())
        vJ = td.vJ(qd, i)
        v_i = vJ if lam == -1 else X_up[i].apply(vel[lam]) + vJ
        vel.append(v_i)
        c.append(cross_motion(v_i, vJ).vector)
        IA.append(np.broadcast_to(td.I[i].matrix(), batch + (6, 6)).copy())
        p = cross_force(v_i, td.I[i] @ v_i).vector
        if f_ext is not None:
            p = p - f_ext[..., i, :]
        pA.append(np.broadcast_to(p, batch + (6,)).copy())

    scale = max((float(np.max(np.abs(m), initial=0.0)) for m in IA), default=1.0) if td.dtype.kind != "O" else 1.0
    U: list[np.ndarray] = [np.empty(0)] * nb
    Dinv: list[np.ndarray] = [np.empty(0)] * nb
    u: list[np.ndarray] = [np.empty(0)] * nb
    has_armature = bool(np.any(model.armature != 0))
    for i in range(nb - 1, -1, -1):
        lam = td.parents[i]
        S = td.S[i]
        U[i] = IA[i] @ S                                   # (..., 6, k)
        sv = slice(model.idx_v[i], model.idx_v[i] + model.nvs[i])
        D = matrix_transpose(S) @ U[i]                                  # (..., k, k)
        if has_armature:
            D = D + np.diag(model.armature[sv]).astype(td.dtype)
        u[i] = tau[..., sv] - pA[i] @ S                   # (..., k)
        Dinv[i] = _inv_small(D, model, i, scale)
        if lam != -1:
            Ia = IA[i] - U[i] @ Dinv[i] @ matrix_transpose(U[i])
            pa = pA[i] + (Ia @ c[i][..., None])[..., 0] + (U[i] @ (Dinv[i] @ u[i][..., None]))[..., 0]
            IA[lam] = IA[lam] + matrix_transpose(Xm[i]) @ Ia @ Xm[i]
            pA[lam] = pA[lam] + (matrix_transpose(Xm[i]) @ pa[..., None])[..., 0]

    qdd = zeros(batch, (model.nv,), td.dtype)
    acc: list[np.ndarray] = []
    for i in range(nb):
        lam = td.parents[i]
        a_parent = a0.vector if lam == -1 else acc[lam]
        a_prime = (Xm[i] @ a_parent[..., None])[..., 0] + c[i]
        qdd_i = (Dinv[i] @ (u[i] - (a_prime[..., None, :] @ U[i])[..., 0, :])[..., None])[..., 0]
        qdd[..., model.idx_v[i] : model.idx_v[i] + model.nvs[i]] = qdd_i
        acc.append(a_prime + qdd_i @ td.S[i].T)
    return qdd
