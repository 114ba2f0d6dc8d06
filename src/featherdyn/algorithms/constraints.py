"""Constrained dynamics by the tree-sparse LᵀL factorisation of M and the Schur complement (reference).

RBDA (Featherstone 2008) §6.5, table 6.3, and Carpentier, Budhiraja & Mansard,
"Proximal and sparse resolution of constrained dynamic equations" (RSS 2021).
The compiled core's ``core/cpp/ltl.hpp`` mirrors this file line for line.

**The factor.** ``M = Lᵀ L`` with ``L`` lower triangular and ``L_kj ≠ 0`` only for
``j = k`` or ``j`` an ancestor dof of ``k``; the dofs' parent array ``λ`` (:func:`dof_parents`)
is the only structure needed. Eliminating the dofs from the leaves inwards::

    for k = nv−1 … 0:   L_kk = √M_kk
                        L_ki = M_ki / L_kk               for i ∈ ancestors(k)
                        M_ij ← M_ij − L_ki L_kj          for i ∈ ancestors(k), j ∈ {i} ∪ ancestors(i)

costs Σ_k depth(k)² instead of nv³/3, and keeps M⁻¹ out of every formula below.

**The solves.** ``M x = b`` is ``Lᵀ y = b`` (:func:`solve_Lt`, leaves inwards) then
``L x = y`` (:func:`solve_L`, root outwards). The Delassus matrix of constraint rows ``J``::

    D = J M⁻¹ Jᵀ = Y Yᵀ,    Y = J L⁻¹   (row r of Y solves Lᵀ y = J_rᵀ)

**Constrained dynamics** ``M q̈ + h = τ + Jᵀ λ``, ``J q̈ = c`` (:func:`kkt_solve`)::

    q̈_f = M⁻¹ (τ − h),   D λ = c − J q̈_f,   q̈ = q̈_f + M⁻¹ Jᵀ λ

and with ``μ > 0`` the proximal iterations ``λ ← (D + μ 1)⁻¹ (c − J q̈_f + μ λ)``, which
converge to the minimum-norm ``λ`` when the rows are dependent; they stop when
``‖D λ − (c − J q̈_f)‖∞ ≤ tol · max(1, ‖c − J q̈_f‖∞)``.

Everything batches over leading axes (loops over dofs and rows, vectorised over
the batch) and keeps the input's floating dtype.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import Model

__all__ = ["dof_parents", "ltl_factor", "solve_Lt", "solve_L", "mass_solve", "delassus", "dense_cholesky",
           "KktSolution", "kkt_solve"]


def dof_parents(model: Model) -> list[int]:
    """``λ`` `(nv,)`: each dof's parent dof — the previous dof of its joint, or the last dof of the
    parent body's joint (``−1`` at a root)."""
    lam: list[int] = []
    for i, joint in enumerate(model.joints):
        iv, p = model.idx_v[i], model.parents[i]
        for c in range(joint.nv):
            lam.append(iv + c - 1 if c > 0 else -1 if p == -1 else model.idx_v[p] + model.joints[p].nv - 1)
    return lam


def _ancestors(lam: list[int], k: int) -> list[int]:
    out, i = [], lam[k]
    while i != -1:
        out.append(i)
        i = lam[i]
    return out


def ltl_factor(model: Model, M: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(L, bad)``: ``L`` `(..., nv, nv)` lower triangular with ``M = Lᵀ L``; ``bad`` `(...)` the first dof
    (from the leaves) whose pivot is not positive, ``−1`` where M is positive definite.

    Where ``bad ≥ 0`` the factor is not usable (its pivots are NaN from there on).
    """
    lam = dof_parents(model)
    H = np.array(M, copy=True)
    bad = np.full(H.shape[:-2], -1, dtype=np.int64)
    for k in range(model.nv - 1, -1, -1):
        d = H[..., k, k]
        ok = d > 0
        bad = np.where((bad == -1) & ~ok, k, bad)
        a = np.sqrt(np.where(ok, d, np.nan))
        H[..., k, k] = a
        anc = _ancestors(lam, k)
        for i in anc:
            H[..., k, i] = H[..., k, i] / a
        for n, i in enumerate(anc):
            for j in anc[n:]:
                H[..., i, j] = H[..., i, j] - H[..., k, i] * H[..., k, j]
    return np.tril(H), bad


def solve_Lt(model: Model, L: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``L⁻ᵀ x`` `(..., nv)`: the solution ``y`` of ``Lᵀ y = x`` (leaves inwards)."""
    lam = dof_parents(model)
    y = np.array(x, dtype=np.result_type(L, x), copy=True)
    for k in range(model.nv - 1, -1, -1):
        y[..., k] = y[..., k] / L[..., k, k]
        for i in _ancestors(lam, k):
            y[..., i] = y[..., i] - L[..., k, i] * y[..., k]
    return y


def solve_L(model: Model, L: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``L⁻¹ x`` `(..., nv)`: the solution ``y`` of ``L y = x`` (root outwards)."""
    lam = dof_parents(model)
    y = np.array(x, dtype=np.result_type(L, x), copy=True)
    for k in range(model.nv):
        for i in _ancestors(lam, k):
            y[..., k] = y[..., k] - L[..., k, i] * y[..., i]
        y[..., k] = y[..., k] / L[..., k, k]
    return y


def mass_solve(model: Model, L: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``M⁻¹ b`` `(..., nv)` from the factor: ``Lᵀ y = b``, ``L x = y``."""
    return solve_L(model, L, solve_Lt(model, L, b))


def delassus(model: Model, L: np.ndarray, J: np.ndarray) -> np.ndarray:
    """``D = J M⁻¹ Jᵀ = Y Yᵀ`` `(..., m, m)` with ``Y = J L⁻¹`` (rows solved by :func:`solve_Lt`)."""
    Y = solve_Lt(model, L[..., None, :, :], J)
    return Y @ np.swapaxes(Y, -1, -2)


def dense_cholesky(A: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray]:
    """``(C, ok)``: the lower Cholesky factor of the symmetric ``A`` `(..., m, m)`; ``ok`` `(...)` False where
    a pivot is ``≤ tol · max_i |A_ii|`` (a singular or indefinite A)."""
    m = A.shape[-1]
    C = np.zeros_like(A)
    scale = np.max(np.abs(np.diagonal(A, axis1=-2, axis2=-1)), axis=-1) if m else np.zeros(A.shape[:-2])
    ok = np.ones(A.shape[:-2], dtype=bool)
    for j in range(m):
        d = A[..., j, j] - np.sum(C[..., j, :j] ** 2, axis=-1)
        ok &= d > tol * scale
        c = np.sqrt(np.where(d > 0, d, np.nan))
        C[..., j, j] = c
        for i in range(j + 1, m):
            C[..., i, j] = (A[..., i, j] - np.sum(C[..., i, :j] * C[..., j, :j], axis=-1)) / c
    return C, ok


def _cholesky_solve(C: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``A⁻¹ x`` for the factor of :func:`dense_cholesky` (forward, then backward substitution)."""
    y = np.array(x, copy=True)
    m = C.shape[-1]
    for i in range(m):
        y[..., i] = (y[..., i] - np.sum(C[..., i, :i] * y[..., :i], axis=-1)) / C[..., i, i]
    for i in range(m - 1, -1, -1):
        y[..., i] = (y[..., i] - np.sum(C[..., i + 1:, i] * y[..., i + 1:], axis=-1)) / C[..., i, i]
    return y


@dataclass(frozen=True)
class KktSolution:
    """``qdd`` `(..., nv)`, ``lam`` `(..., m)`, ``iterations`` `(...)` (``−1``: D singular with μ = 0;
    ``−2``: not converged), ``residual`` `(...)` ``max |J q̈ − c|``."""

    qdd: np.ndarray
    lam: np.ndarray
    iterations: np.ndarray
    residual: np.ndarray


def kkt_solve(model: Model, L: np.ndarray, tau_h: np.ndarray, J: np.ndarray, c: np.ndarray, *, mu: float,
              max_iter: int, tol: float, singular_tol: float) -> KktSolution:
    """Solve ``M q̈ = τ − h + Jᵀ λ``, ``J q̈ = c`` on the factor ``L`` of M (module docstring).

    Args:
        L: `(..., nv, nv)` from :func:`ltl_factor`; tau_h: ``τ − h`` `(..., nv)`;
        J: `(..., m, nv)`; c: `(..., m)`; mu: the proximal parameter (0: one direct solve);
        max_iter, tol: the proximal iterations and their stopping rule; singular_tol: with μ = 0,
            a pivot of D below ``singular_tol · max D_ii`` means dependent rows.
    """
    qf = mass_solve(model, L, tau_h)
    D0 = delassus(model, L, J)
    rhs = c - (J @ qf[..., None])[..., 0]
    m = J.shape[-2]
    rhs_size = np.maximum(1.0, np.max(np.abs(rhs), axis=-1)) if m else np.ones(rhs.shape[:-1])
    C, ok = dense_cholesky(D0 + mu * np.eye(m, dtype=D0.dtype), 0.0 if mu > 0 else singular_tol)
    iterations = np.where(ok, 0, -1)
    lam = np.zeros_like(rhs)
    active = ok.copy()
    for it in range(1, (max(1, max_iter) if mu > 0 else 1) + 1):
        lam = np.where(active[..., None], _cholesky_solve(C, rhs + mu * lam), lam)
        iterations = np.where(active, it, iterations)
        if mu <= 0:
            break
        dual = np.max(np.abs((D0 @ lam[..., None])[..., 0] - rhs), axis=-1)
        active &= ~(dual <= tol * rhs_size)
        if not active.any():
            break
    if mu > 0:
        iterations = np.where(active, -2, iterations)
    lam = np.where(ok[..., None], lam, np.nan)
    qdd = qf + mass_solve(model, L, (np.swapaxes(J, -1, -2) @ lam[..., None])[..., 0])
    residual = np.max(np.abs((J @ qdd[..., None])[..., 0] - c), axis=-1) if m else np.zeros(qdd.shape[:-1])
    return KktSolution(qdd, lam, iterations, residual)
