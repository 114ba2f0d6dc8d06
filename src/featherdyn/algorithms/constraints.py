"""Constraints (reference): their rows J, drift γ and Baumgarte terms; constrained dynamics on M's LᵀL factor.

RBDA (Featherstone 2008) §6.5, table 6.3; Carpentier, Budhiraja & Mansard, "Proximal and
sparse resolution of constrained dynamic equations" (RSS 2021); Khatib (1987) for the
operational space. The compiled core mirrors this file: ``core/cpp/contacts.hpp`` (the
contacts' rows in one pass) and ``core/cpp/ltl.hpp`` (the factor and the solves), line for line.

**The rows** (:func:`constraint_rows`), from the forward kinematics ``kin`` at ``(q, q̇, q̈ = 0)``::

    M q̈ + h = τ + Jᵀ λ,        J q̈ + γ = c = −γ − K_p e − K_d J q̇   (then J q̈ = c)

* point contact (3 rows): the linear rows of the frame Jacobian ``ᶠJ`` in ``reference``;
  γ the classical acceleration of the frame's origin; e = 0;
* frame contact (6 rows): ``ᶠJ``; γ the frame's spatial acceleration; e = 0;
* loop (the chosen axes of ``[ω; v]``): the velocity of a relative to b in a's coordinates,
  then in ``reference`` (``B``: 1 in LOCAL, ``⁰X_a`` in WORLD, ``blkdiag(⁰R_a, ⁰R_a)`` in LWA)::

      J = B (J_a − ᵃX_b J_b),     r = v_a − ᵃX_b v_b,     e = B log(ᵃM_b)
      γ = B (a_a − ᵃX_b a_b + r × ᵃX_b v_b)  (+ B-rate terms:  WORLD v_a × r,  LWA [ω_a × r_ω; ω_a × r_v])

  (``d(ᵃX_b)/dt = −(r ×) ᵃX_b``; ``d(⁰X_a y)/dt = ⁰X_a (ẏ + v_a × y)``).

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
``‖D λ − (c − J q̈_f)‖∞ ≤ tol · max(1, ‖c − J q̈_f‖∞)``. **Impulses** are the same system
(:func:`impulse_system`); the **operational space** (:func:`operational_space`) is Λ = D⁻¹ and
its companions.

Everything batches over leading axes (loops over dofs and rows, vectorised over
the batch) and keeps the input's floating dtype.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from ..constraints import Constraint, LoopConstraint, PointContact
from ..frames import LOCAL, LOCAL_WORLD_ALIGNED, WORLD, ReferenceFrame
from ..model import Model
from ..results import Kinematics
from ..rotation import se3_log
from ..spatial.ops import crm_apply
from ..spatial_algebra import PluckerTransform
from .aba import aba
from .crba import crba
from .jacobians import frame_jacobian
from .kinematics import frame_acceleration, frame_classical_acceleration, frame_pose, frame_velocity

__all__ = ["selected_rows", "contact_rows", "loop_rows", "constraint_rows", "frames_jacobian", "impulse_system",
           "operational_space", "dof_parents", "ltl_factor", "mass_factor", "solve_Lt", "solve_L", "mass_solve", "delassus",
           "dense_cholesky", "KktSolution", "kkt_solve"]

#: the rows of ``[ω; v]`` a point contact keeps, and all six (read-only: shared by every call)
_LINEAR, _ALL = np.arange(3, 6), np.arange(6)
_LINEAR.flags.writeable = _ALL.flags.writeable = False


def selected_rows(c: Constraint) -> np.ndarray:
    """The rows of ``[ω; v]`` that ``c`` constrains: the linear three (point), all six (frame), the chosen axes (loop)."""
    if isinstance(c, PointContact):
        return _LINEAR
    if isinstance(c, LoopConstraint):
        return np.flatnonzero(np.array(c.axes))
    return _ALL


#: a frame's Jacobian `(..., 6, nv)` by frame index and reference (the caller's backend), or ``None``: the reference's
FrameJacobian = Callable[[int, ReferenceFrame], np.ndarray] | None


def _jacobian(model: Model, kin: Kinematics, jacobian: FrameJacobian, fid: int, ref: ReferenceFrame) -> np.ndarray:
    return frame_jacobian(model, kin, fid, ref) if jacobian is None else jacobian(fid, ref)


def contact_rows(model: Model, kin: Kinematics, c: Constraint, jacobian: FrameJacobian = None
                 ) -> tuple[np.ndarray, np.ndarray | None]:
    """``(ᶠJ, γ)`` of a point or frame contact, all six rows: ᶠJ `(..., 6, nv)` in ``c.reference``; γ `(..., 6)`
    the frame's classical (point) or spatial (frame) acceleration at q̈ = 0 (``None`` when ``kin`` has no velocities)::

        point: γ = [ω̇; a_origin] = ᶠa + [0; ω × v];     frame: γ = ᶠa        (ᶠa: the frame's spatial acceleration)
    """
    fid = model.resolve_frame(c.frame)  # type: ignore[union-attr]
    J = _jacobian(model, kin, jacobian, fid, c.reference)
    if kin.velocities is None:
        return J, None
    acc = frame_classical_acceleration if isinstance(c, PointContact) else frame_acceleration
    return J, acc(model, kin, fid, c.reference).vector


def loop_rows(model: Model, kin: Kinematics, c: LoopConstraint, jacobian: FrameJacobian = None
              ) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """``(J, γ, e)`` of a loop, all six rows (module docstring): J `(..., 6, nv)`, γ and e `(..., 6)` (``None``
    when ``kin`` has no velocities)."""
    a, b = model.resolve_frame(c.frame_a), model.resolve_frame(c.frame_b)
    oMa, oMb = frame_pose(model, kin, a), frame_pose(model, kin, b)
    aMb = oMa.inverse() @ oMb
    aXb = aMb.matrix()
    J = _jacobian(model, kin, jacobian, a, LOCAL) - aXb @ _jacobian(model, kin, jacobian, b, LOCAL)
    B = None if c.reference is LOCAL else oMa.matrix() if c.reference is WORLD else \
        PluckerTransform._wrap(oMa.rotation, np.zeros_like(oMa.translation), None, None).matrix()
    if B is not None:
        J = B @ J
    if kin.velocities is None:
        return J, None, None
    v_a = frame_velocity(model, kin, a, LOCAL).vector
    Xv_b = (aXb @ frame_velocity(model, kin, b, LOCAL).vector[..., None])[..., 0]
    r = v_a - Xv_b
    Xa_b = (aXb @ frame_acceleration(model, kin, b, LOCAL).vector[..., None])[..., 0]
    gamma = frame_acceleration(model, kin, a, LOCAL).vector - Xa_b + crm_apply(r, Xv_b)
    e = se3_log(aMb).vector
    if c.reference is WORLD:
        gamma = gamma + crm_apply(v_a, r)
    elif c.reference is LOCAL_WORLD_ALIGNED:
        w = v_a[..., :3]
        gamma = gamma + np.concatenate([np.cross(w, r[..., :3]), np.cross(w, r[..., 3:])], axis=-1)
    if B is not None:
        gamma, e = (B @ gamma[..., None])[..., 0], (B @ e[..., None])[..., 0]
    return J, gamma, e


def constraint_rows(model: Model, kin: Kinematics, constraints: Sequence[Constraint], qd: np.ndarray | None = None,
                    jacobian: FrameJacobian = None) -> tuple[np.ndarray, np.ndarray | None, np.ndarray | None]:
    """The constraints' rows stacked: ``(J, γ, c)``, J `(..., m, nv)`, γ and c `(..., m)` (``None`` without ``qd``)::

        J q̈ = c = −γ − K_p e − K_d J q̇        (each constraint's selected rows, in order)

    Args:
        kin: forward kinematics at ``(q, q̇, q̈ = 0)`` (placements only when ``qd`` is ``None``).
        qd: `(..., nv)` the joint velocity of ``kin``, or ``None`` for J alone.
        jacobian: the frames' Jacobians by another backend (the compiled core's), ``None``: :func:`frame_jacobian`.
    """
    Js, gammas, cs = [], [], []
    for con in constraints:
        rows = selected_rows(con)
        if isinstance(con, LoopConstraint):
            J6, gamma6, e6 = loop_rows(model, kin, con, jacobian)
        else:
            J6, gamma6 = contact_rows(model, kin, con, jacobian)
            e6 = None
        J = J6[..., rows, :]
        Js.append(J)
        if qd is not None and gamma6 is not None:
            kp, kd = con.baumgarte
            gamma = gamma6[..., rows]
            gammas.append(gamma)
            Jv = (J @ qd[..., None])[..., 0]
            cs.append(-gamma - kd * Jv if e6 is None else -gamma - kp * e6[..., rows] - kd * Jv)
    if qd is None:
        return np.concatenate(Js, axis=-2), None, None
    return np.concatenate(Js, axis=-2), np.concatenate(gammas, axis=-1), np.concatenate(cs, axis=-1)


def frames_jacobian(model: Model, kin: Kinematics, frames: Sequence[int], reference: ReferenceFrame,
                    jacobian: FrameJacobian = None) -> np.ndarray:
    """The frame Jacobians stacked, `(..., 6k, nv)` (the operational space's task rows)."""
    return np.concatenate([_jacobian(model, kin, jacobian, f, reference) for f in frames], axis=-2)


def impulse_system(M: np.ndarray, g: np.ndarray, J: np.ndarray, v_minus: np.ndarray, restitution: float
                   ) -> tuple[np.ndarray, np.ndarray]:
    """``(τ, c)``: an impact as the constrained dynamics at zero velocity, with ``q̈ := v⁺``::

        M (v⁺ − v⁻) = Jᵀ Λ,  J v⁺ = −e J v⁻    ⇔    M v⁺ + g = τ + Jᵀ Λ,  J v⁺ = c
        with τ = M v⁻ + g,  c = −e J v⁻         (h = g at zero velocity, so τ − h = M v⁻)

    M `(..., nv, nv)`, g `(..., nv)` the generalized gravity, J `(..., m, nv)`, v⁻ `(..., nv)`; τ `(..., nv)`, c `(..., m)`.
    """
    return (M @ v_minus[..., None])[..., 0] + g, -restitution * (J @ v_minus[..., None])[..., 0]


def operational_space(D: np.ndarray, Minv_Jt: np.ndarray, J: np.ndarray, Minv_h: np.ndarray, Jdot_v: np.ndarray,
                      g: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(Λ, J̄, μ, p)`` of Khatib (1987), from ``D = J M⁻¹ Jᵀ`` `(..., m, m)`, ``M⁻¹ Jᵀ`` `(..., nv, m)`,
    J `(..., m, nv)`, ``M⁻¹ h`` `(..., nv)`, ``J̇ q̇`` `(..., m)` and the generalized gravity g `(..., nv)`::

        Λ = D⁻¹,   J̄ = M⁻¹ Jᵀ Λ,   μ = Λ (J M⁻¹ h − J̇ q̇),   p = J̄ᵀ g
    """
    Lambda = np.linalg.inv(D)
    J_bar = Minv_Jt @ Lambda
    mu = (Lambda @ ((J @ Minv_h[..., None])[..., 0] - Jdot_v)[..., None])[..., 0]
    p = (np.swapaxes(J_bar, -1, -2) @ g[..., None])[..., 0]
    return Lambda, J_bar, mu, p


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


def mass_factor(model: Model, q: np.ndarray) -> np.ndarray:
    """``L`` `(..., nv, nv)` with ``M(q) = Lᵀ L`` (:func:`crba`, then :func:`ltl_factor`) on a checked ``q``; where
    M is singular, ABA's :class:`SingularMassMatrixError` for the first such state (the error ``fd.aba`` raises)."""
    L, bad = ltl_factor(model, crba(model, q))
    if np.any(bad >= 0):
        row = q[np.unravel_index(int(np.flatnonzero(bad.ravel() >= 0)[0]), bad.shape)] if bad.ndim else q
        zero = np.zeros(model.nv, dtype=row.dtype)
        aba(model, row, zero, zero, gravity=False)  # raises SingularMassMatrixError
    return L


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
