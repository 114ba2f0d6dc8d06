"""The algorithm cores and their batched forms (private; :mod:`._kernels` is the index).

One *core* per algorithm computes one state into caller-provided outputs using
a flat workspace (FK, RNEA, gravity, CRBA, ABA, frame Jacobian), mirroring the
reference algorithms' names and order (``docs/architecture.md``, "The mirror");
the batched FK / Jacobian forms run a core over rows with ``prange``.
"""


from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

from ._flat_spatial import (
    _IJIT,
    _JIT,
    _PJIT,
    _compose,
    _cross_force_add,
    _cross_motion_add,
    _force_to_child,
    _force_to_parent,
    _inertia_matrix,
    _inertia_times,
    _inertia_to_parent,
    _matrix6_to_parent_add,
    _motion_to_child,
    _motion_to_parent,
    _pose_in_parent,
    _S_col,
    _S_times,
    _St_dot,
)
from ._layout import (
    AX,
    FF,
    IV,
    JT,
    LWA_CODE,
    MASS,
    NBF,
    NBI,
    NV,
    PARENT,
    SINGULAR_RTOL,
    UNIT,
    WORLD_CODE,
)

# ---------------------------------------------------------------------------
# forward kinematics
# ---------------------------------------------------------------------------


@njit(**_IJIT)
def _homogeneous(W, X, H, h):  # pragma: no cover - compiled
    """``H[h:h+16] = [[R, p], [0, 1]]`` (row-major 4×4) of the pose ``W[X:X+12]``."""
    for r in range(3):
        H[h + 4 * r] = W[X + 3 * r]
        H[h + 4 * r + 1] = W[X + 3 * r + 1]
        H[h + 4 * r + 2] = W[X + 3 * r + 2]
        H[h + 4 * r + 3] = W[X + 9 + r]
    H[h + 12] = 0.0
    H[h + 13] = 0.0
    H[h + 14] = 0.0
    H[h + 15] = 1.0


@njit(**_JIT)
def fk_core(BI, BF, q, qd, qdd, oM, pM, vel, acc, W):  # pragma: no cover - compiled
    """World placements ``⁰M_i``, and optionally ``ᵖM_i``, ``v_i`` and ``a_i``, of every body.

    Args:
        q: `(nq,)`; qd, qdd: `(nv,)`, or empty when velocities / accelerations are not wanted.
        oM: `(nb, 4, 4)` out, homogeneous ``⁰M_i``; pM: `(nb, 4, 4)` out ``ᵖM_i`` or `(0, 4, 4)`.
        vel, acc: `(nb, 6)` out body velocities / spatial accelerations (no gravity), or `(0, 6)`.
        W: workspace (36 entries; `(WS_FK nb + WS_TAIL,)` as every kernel is given).

    ::

        ⁰M_i = ⁰M_λ(i) ᵖM_i,   v_i = X_up[i] v_λ(i) + S_i q̇_i,   a_i = X_up[i] a_λ(i) + S_i q̈_i + v_i × S_i q̇_i
    """
    nb = BI.shape[0] // NBI
    X_up = 0  # ᵖM_i of the current body only
    vJ = 12
    aJ = 18
    v = 24  # v_i, a_i of the current body (copied to vel, acc)
    a = 30
    want_parent = pM.shape[0] > 0
    want_v = vel.shape[0] > 0
    want_a = acc.shape[0] > 0
    # flat views: cheaper stores than 3-d indexing; ⁰M_i is composed in the output itself (row stride 4)
    oH = oM.reshape(oM.shape[0] * 16)
    pH = pM.reshape(pM.shape[0] * 16)
    for i in range(nb):
        lam = BI[NBI * i + PARENT]
        h = 16 * i
        _pose_in_parent(BI, BF, i, q, W, X_up)
        if lam == -1:
            _homogeneous(W, X_up, oH, h)
        else:
            # ⁰M_i = ⁰M_λ ᵖM_i: R = R_λ R, p = p_λ + R_λ p (the order of _compose)
            A = 16 * lam
            b0, b1, b2 = W[X_up], W[X_up + 1], W[X_up + 2]
            b3, b4, b5 = W[X_up + 3], W[X_up + 4], W[X_up + 5]
            b6, b7, b8 = W[X_up + 6], W[X_up + 7], W[X_up + 8]
            q0, q1, q2 = W[X_up + 9], W[X_up + 10], W[X_up + 11]
            for r in range(3):
                a0, a1, a2 = oH[A + 4 * r], oH[A + 4 * r + 1], oH[A + 4 * r + 2]
                oH[h + 4 * r] = a0 * b0 + a1 * b3 + a2 * b6
                oH[h + 4 * r + 1] = a0 * b1 + a1 * b4 + a2 * b7
                oH[h + 4 * r + 2] = a0 * b2 + a1 * b5 + a2 * b8
                oH[h + 4 * r + 3] = oH[A + 4 * r + 3] + a0 * q0 + a1 * q1 + a2 * q2
            oH[h + 12] = 0.0
            oH[h + 13] = 0.0
            oH[h + 14] = 0.0
            oH[h + 15] = 1.0
        if want_parent:
            _homogeneous(W, X_up, pH, h)
        if want_v:
            _S_times(BI, BF, i, qd, W, vJ)
            if lam == -1:
                for k in range(6):
                    W[v + k] = W[vJ + k]
            else:
                for k in range(6):
                    W[v + k] = vel[lam, k]
                _motion_to_child(W, X_up, v, v)
                for k in range(6):
                    W[v + k] += W[vJ + k]
            for k in range(6):
                vel[i, k] = W[v + k]
            if want_a:
                _S_times(BI, BF, i, qdd, W, aJ)
                if lam == -1:
                    for k in range(6):
                        W[a + k] = W[aJ + k]
                else:
                    for k in range(6):
                        W[a + k] = acc[lam, k]
                    _motion_to_child(W, X_up, a, a)
                    for k in range(6):
                        W[a + k] += W[aJ + k]
                _cross_motion_add(W, v, vJ, a)
                for k in range(6):
                    acc[i, k] = W[a + k]


# ---------------------------------------------------------------------------
# RNEA
# ---------------------------------------------------------------------------


@njit(**_JIT)
def rnea_core(BI, BF, G, q, qd, qdd, fext, gravity, tau, W):  # pragma: no cover - compiled
    """Inverse dynamics of one state into ``tau`` `(nv,)`.

    Args:
        q: `(nq,)`; qd, qdd: `(nv,)`.
        fext: `(nb, 6)` body-frame external forces ``[n; f]``, or `(0, 6)` for none.
        gravity: whether to apply gravity as the base acceleration ``a₀ = −g``.
        W: workspace `(WS_RNEA nb + WS_TAIL,)`.

    ::

        v_i = X_up[i] v_λ(i) + S_i q̇_i
        a_i = X_up[i] a_λ(i) + S_i q̈_i + v_i × S_i q̇_i
        f_i = I_i a_i + v_i ×* I_i v_i − f_i^ext
        τ_i = S_iᵀ f_i,   f_λ(i) += X_up[i]ᵀ f_i        (i = nb−1 … 0)
    """
    nb = BI.shape[0] // NBI
    X_up = 0
    v = 12 * nb
    a = 18 * nb
    f = 24 * nb
    t = 30 * nb
    vJ = t
    aJ = t + 6
    Iv = t + 12
    a0 = t + 18
    g = 1.0 if gravity else 0.0
    W[a0], W[a0 + 1], W[a0 + 2] = 0.0, 0.0, 0.0
    W[a0 + 3], W[a0 + 4], W[a0 + 5] = -g * G[0], -g * G[1], -g * G[2]
    has_fext = fext.shape[0] > 0
    for i in range(nb):
        lam = BI[NBI * i + PARENT]
        Xi = X_up + 12 * i
        vi = v + 6 * i
        ai = a + 6 * i
        fi = f + 6 * i
        _pose_in_parent(BI, BF, i, q, W, Xi)
        _S_times(BI, BF, i, qd, W, vJ)
        _S_times(BI, BF, i, qdd, W, aJ)
        if lam == -1:
            for k in range(6):
                W[vi + k] = W[vJ + k]
            _motion_to_child(W, Xi, a0, ai)
        else:
            _motion_to_child(W, Xi, v + 6 * lam, vi)
            for k in range(6):
                W[vi + k] += W[vJ + k]
            _motion_to_child(W, Xi, a + 6 * lam, ai)
        for k in range(6):
            W[ai + k] += W[aJ + k]
        _cross_motion_add(W, vi, vJ, ai)
        I = NBF * i + MASS
        _inertia_times(BF, I, W, ai, fi)
        _inertia_times(BF, I, W, vi, Iv)
        _cross_force_add(W, vi, Iv, fi)
        if has_fext:
            for k in range(6):
                W[fi + k] -= fext[i, k]
    for i in range(nb - 1, -1, -1):
        lam = BI[NBI * i + PARENT]
        iv = BI[NBI * i + IV]
        fi = f + 6 * i
        for c in range(BI[NBI * i + NV]):
            tau[iv + c] = _St_dot(BI, BF, i, c, W, fi)
        if lam != -1:
            _force_to_parent(W, X_up + 12 * i, fi, f + 6 * lam, True)


@njit(**_JIT)
def gravity_core(BI, BF, G, q, tau, W):  # pragma: no cover - compiled
    """Generalized gravity ``g(q)`` of one state into ``tau`` `(nv,)`: :func:`rnea_core` with ``q̇ = q̈ = 0``.

    With no velocity the velocity-product terms vanish, so only the
    accelerations of gravity (entered as the base acceleration ``a₀ = −g``)
    travel out and the forces travel back::

        a_i = X_up[i] a_λ(i),   f_i = I_i a_i,   g_i = S_iᵀ f_i,   f_λ(i) += X_up[i]ᵀ f_i

    Every skipped term of :func:`rnea_core` is an exact zero, so the results
    are the same numbers (up to the sign of zeros).
    W: workspace `(WS_RNEA nb + WS_TAIL,)`.
    """
    nb = BI.shape[0] // NBI
    X_up = 0
    a = 18 * nb
    f = 24 * nb
    a0 = 30 * nb + 18
    W[a0], W[a0 + 1], W[a0 + 2] = 0.0, 0.0, 0.0
    W[a0 + 3], W[a0 + 4], W[a0 + 5] = -G[0], -G[1], -G[2]
    for i in range(nb):
        lam = BI[NBI * i + PARENT]
        Xi = X_up + 12 * i
        _pose_in_parent(BI, BF, i, q, W, Xi)
        _motion_to_child(W, Xi, a0 if lam == -1 else a + 6 * lam, a + 6 * i)
        _inertia_times(BF, NBF * i + MASS, W, a + 6 * i, f + 6 * i)
    for i in range(nb - 1, -1, -1):
        lam = BI[NBI * i + PARENT]
        iv = BI[NBI * i + IV]
        fi = f + 6 * i
        for c in range(BI[NBI * i + NV]):
            tau[iv + c] = _St_dot(BI, BF, i, c, W, fi)
        if lam != -1:
            _force_to_parent(W, X_up + 12 * i, fi, f + 6 * lam, True)


# ---------------------------------------------------------------------------
# CRBA
# ---------------------------------------------------------------------------


@njit(**_JIT)
def crba_core(BI, BF, q, M, W):  # pragma: no cover - compiled
    """The joint-space mass matrix of one state into ``M`` `(nv, nv)`, full and symmetric.

    Args:
        q: `(nq,)`.
        W: workspace `(WS_CRBA nb + WS_TAIL,)`.

    The reference's recursion (RBDA table 6.2) carried out in world
    coordinates, as Pinocchio does: with ``⁰J_i = ⁰X_i S_i`` and the composite
    inertias ``⁰I^C_i`` in the world frame, the transforms up the support
    become 6-vector dot products::

        ⁰I^C_i = ⁰X_i* I_i ⁰X_i⁻¹ + Σ_children ⁰I^C_j          (i = nb−1 … 0)
        F = ⁰I^C_i ⁰J_i,   M_ji = ⁰J_jᵀ F   for j = i and every ancestor j of i

    A free-flyer joint ``j`` (``S_j = 1``) takes a shortcut: ``⁰J_jᵀ F`` is ``F``
    in body ``j``'s coordinates (one transform instead of six dot products),
    and its diagonal block is ``I^C_j`` in body coordinates.
    """
    nb = BI.shape[0] // NBI
    nv = M.shape[0]
    oX = 0  # ⁰M_i
    IC = 12 * nb  # ⁰I^C_i, 10 parameters
    J = 22 * nb  # columns of ⁰J_i, 6 apart (up to 6 per body)
    t = 58 * nb
    X = t  # ᵖM_i, then (⁰M_i)⁻¹
    F = t + 12
    Fj = t + 18
    Iloc = t + 24  # 10
    Ib = t + 34  # 36
    for i in range(nb):
        lam = BI[NBI * i + PARENT]
        Xi = oX + 12 * i
        if lam == -1:
            _pose_in_parent(BI, BF, i, q, W, Xi)
        else:
            _pose_in_parent(BI, BF, i, q, W, X)
            _compose(W, oX + 12 * lam, X, Xi)
        _inertia_to_parent(BF, NBF * i + MASS, W, Xi, IC + 10 * i, False)
        ki = BI[NBI * i + NV]
        if ki == 1:
            _S_col(BI, BF, i, 0, W, J + 36 * i)
            _motion_to_parent(W, Xi, J + 36 * i, J + 36 * i)
        elif lam == -1 and BI[NBI * i + JT] == FF:
            pass  # a free-flying root needs no columns (see the fill below)
        else:
            for c in range(ki):
                _S_col(BI, BF, i, c, W, J + 36 * i + 6 * c)
                _motion_to_parent(W, Xi, J + 36 * i + 6 * c, J + 36 * i + 6 * c)
    for i in range(nb - 1, -1, -1):
        lam = BI[NBI * i + PARENT]
        if lam != -1:
            for k in range(10):
                W[IC + 10 * lam + k] += W[IC + 10 * i + k]
    for r in range(nv):
        for c in range(nv):
            M[r, c] = 0.0
    for i in range(nb):
        iv = BI[NBI * i + IV]
        lam = BI[NBI * i + PARENT]
        first = i
        if BI[NBI * i + JT] == FF:
            # M_ii = I^C_i in body coordinates: transform by (⁰M_i)⁻¹ = (Rᵀ, −Rᵀ p)
            Xi = oX + 12 * i
            for r in range(3):
                for c in range(3):
                    W[X + 3 * r + c] = W[Xi + 3 * c + r]
            for r in range(3):
                W[X + 9 + r] = -(W[Xi + r] * W[Xi + 9] + W[Xi + 3 + r] * W[Xi + 10] + W[Xi + 6 + r] * W[Xi + 11])
            _inertia_to_parent(W, IC + 10 * i, W, X, Iloc, False)
            _inertia_matrix(W, Iloc, W, Ib)
            for r in range(6):
                for c in range(6):
                    M[iv + r, iv + c] = W[Ib + 6 * r + c]
            if lam == -1:
                continue
            first = lam
        for c in range(BI[NBI * i + NV]):
            _inertia_times(W, IC + 10 * i, W, J + 36 * i + 6 * c, F)
            # F in registers: the stores into M could alias W as far as the compiler knows
            f0, f1, f2, f3, f4, f5 = W[F], W[F + 1], W[F + 2], W[F + 3], W[F + 4], W[F + 5]
            j = first
            while j != -1:
                jv = BI[NBI * j + IV]
                kj = BI[NBI * j + NV]
                Jr = J + 36 * j
                if kj == 1:  # no loop for a single axis (short loops cost more than their work)
                    val = (W[Jr] * f0 + W[Jr + 1] * f1 + W[Jr + 2] * f2
                           + W[Jr + 3] * f3 + W[Jr + 4] * f4 + W[Jr + 5] * f5)
                    M[jv, iv + c] = val
                    M[iv + c, jv] = val
                elif BI[NBI * j + JT] == FF:
                    _force_to_child(W, oX + 12 * j, F, Fj)
                    for r in range(6):
                        M[jv + r, iv + c] = W[Fj + r]
                        M[iv + c, jv + r] = W[Fj + r]
                else:
                    for r in range(kj):
                        val = (W[Jr] * f0 + W[Jr + 1] * f1 + W[Jr + 2] * f2
                               + W[Jr + 3] * f3 + W[Jr + 4] * f4 + W[Jr + 5] * f5)
                        M[jv + r, iv + c] = val
                        M[iv + c, jv + r] = val
                        Jr += 6
                j = BI[NBI * j + PARENT]


# ---------------------------------------------------------------------------
# ABA
# ---------------------------------------------------------------------------


@njit(**_IJIT)
def _spd_inverse(W, D, k, Dinv, L, tol):  # pragma: no cover - compiled
    """``W[Dinv] = W[D]⁻¹`` for a symmetric positive definite `(k, k)` matrix (row stride 6), by Cholesky.

    Returns the smallest pivot; one ``<= tol`` means singular (``W[Dinv]`` is then undefined).
    """
    if k == 1:
        d = W[D]
        if d > tol:
            W[Dinv] = 1.0 / d
        return d
    smallest = np.inf
    for j in range(k):  # L Lᵀ = D, L lower triangular (row stride 6)
        d = W[D + 7 * j]
        for m in range(j):
            d -= W[L + 6 * j + m] * W[L + 6 * j + m]
        if d <= tol:
            return d
        smallest = min(smallest, d)
        ljj = math.sqrt(d)
        W[L + 7 * j] = ljj
        for r in range(j + 1, k):
            x = W[D + 6 * r + j]
            for m in range(j):
                x -= W[L + 6 * r + m] * W[L + 6 * j + m]
            W[L + 6 * r + j] = x / ljj
    for j in range(k):  # L ← L⁻¹ in place, column by column
        W[L + 7 * j] = 1.0 / W[L + 7 * j]
        for r in range(j + 1, k):
            x = 0.0
            for m in range(j, r):
                x -= W[L + 6 * r + m] * W[L + 6 * m + j]
            W[L + 6 * r + j] = x / W[L + 7 * r]
    for r in range(k):  # D⁻¹ = L⁻ᵀ L⁻¹
        for c in range(r, k):
            x = 0.0
            for m in range(c, k):
                x += W[L + 6 * m + r] * W[L + 6 * m + c]
            W[Dinv + 6 * r + c] = x
            W[Dinv + 6 * c + r] = x
    return smallest


@njit(**_JIT)
def aba_core(BI, BF, G, q, qd, tau, fext, gravity, qdd, W):  # pragma: no cover - compiled
    """Forward dynamics of one state into ``qdd`` `(nv,)`.

    Args:
        q: `(nq,)`; qd, tau: `(nv,)`.
        fext: `(nb, 6)` body-frame external forces, or `(0, 6)` for none.
        gravity: whether to apply ``a₀ = −g``.
        W: workspace `(WS_ABA nb + WS_TAIL,)`.

    Returns:
        ``-1``, or the first joint (from the leaves) whose articulated inertia
        ``D_i`` has a pivot below ``1e-14 ×`` the largest body-inertia entry;
        ``qdd`` is then undefined.

    In body coordinates, as the reference (a world-frame variant is cheaper but
    loses digits on robots with tiny link inertias far from the origin)::

        pass 1:  v_i = X_up[i] v_λ(i) + S_i q̇_i,  c_i = v_i × S_i q̇_i,  I^A_i = I_i,  p^A_i = v_i ×* I_i v_i − f_i^ext
        pass 2:  U_i = I^A_i S_i,  D_i = S_iᵀ U_i,  u_i = τ_i − S_iᵀ p^A_i
                 I^a = I^A_i − U_i D_i⁻¹ U_iᵀ,  p^a = p^A_i + I^a c_i + U_i D_i⁻¹ u_i
                 I^A_λ(i) += X_up[i]ᵀ I^a X_up[i],  p^A_λ(i) += X_up[i]ᵀ p^a
        pass 3:  a' = X_up[i] a_λ(i) + c_i,  q̈_i = D_i⁻¹ (u_i − U_iᵀ a'),  a_i = a' + S_i q̈_i

    Single-axis joints (``nv_i = 1``) take loop-free branches: in Numba a short
    loop costs more than its work.
    """
    nb = BI.shape[0] // NBI
    X_up = 0
    v = 12 * nb
    c = 18 * nb
    IA = 24 * nb
    pA = 60 * nb
    U = 66 * nb  # column j of U_i at U + 36 i + 6 j
    Dinv = 102 * nb  # (k, k), row stride 6
    u = 138 * nb
    a = 144 * nb
    t = 150 * nb
    vJ = t
    Iv = t + 6
    Ia = t + 12
    pa = t + 48
    UD = t + 54  # U D⁻¹, column j at UD + 6 j
    D = t + 90
    T = t + 126
    s = t + 153
    a0 = Iv  # reused in pass 3
    L = Ia  # reused by the Cholesky factorisation
    tol = SINGULAR_RTOL * G[3]
    has_fext = fext.shape[0] > 0

    for i in range(nb):
        lam = BI[NBI * i + PARENT]
        Xi = X_up + 12 * i
        vi = v + 6 * i
        _pose_in_parent(BI, BF, i, q, W, Xi)
        _S_times(BI, BF, i, qd, W, vJ)
        if lam == -1:
            for k in range(6):
                W[vi + k] = W[vJ + k]
        else:
            _motion_to_child(W, Xi, v + 6 * lam, vi)
            for k in range(6):
                W[vi + k] += W[vJ + k]
        for k in range(6):
            W[c + 6 * i + k] = 0.0
            W[pA + 6 * i + k] = 0.0
        _cross_motion_add(W, vi, vJ, c + 6 * i)
        I = NBF * i + MASS
        _inertia_matrix(BF, I, W, IA + 36 * i)
        _inertia_times(BF, I, W, vi, Iv)
        _cross_force_add(W, vi, Iv, pA + 6 * i)
        if has_fext:
            for k in range(6):
                W[pA + 6 * i + k] -= fext[i, k]

    for i in range(nb - 1, -1, -1):
        lam = BI[NBI * i + PARENT]
        ki = BI[NBI * i + NV]
        iv = BI[NBI * i + IV]
        IAi = IA + 36 * i
        Ui = U + 36 * i
        unit = BI[NBI * i + UNIT]
        if unit >= 0:  # S_i = ±e_unit: U_i is a column of I^A_i, D_i a diagonal entry
            sg = BF[NBF * i + AX + (unit - 3 if unit >= 3 else unit)]
            for r in range(6):
                W[Ui + r] = sg * W[IAi + 6 * r + unit]
            W[D] = W[IAi + 7 * unit]
            W[u + 6 * i] = tau[iv] - sg * W[pA + 6 * i + unit]
        elif BI[NBI * i + JT] == FF:  # S_i = 1: U_i = D_i = I^A_i, u_i = τ_i − p^A_i
            for r in range(6):
                for m in range(6):
                    W[Ui + 6 * m + r] = W[IAi + 6 * r + m]
                    W[D + 6 * r + m] = W[IAi + 6 * r + m]
                W[u + 6 * i + r] = tau[iv + r] - W[pA + 6 * i + r]
        elif ki == 1:
            _S_col(BI, BF, i, 0, W, s)
            d = 0.0
            for r in range(6):
                x = 0.0
                for m in range(6):
                    x += W[IAi + 6 * r + m] * W[s + m]
                W[Ui + r] = x
                d += W[s + r] * x
            W[D] = d
            W[u + 6 * i] = tau[iv] - _St_dot(BI, BF, i, 0, W, pA + 6 * i)
        else:
            for j in range(ki):
                _S_col(BI, BF, i, j, W, s)
                for r in range(6):
                    x = 0.0
                    for m in range(6):
                        x += W[IAi + 6 * r + m] * W[s + m]
                    W[Ui + 6 * j + r] = x
            for r in range(ki):
                for j in range(ki):
                    W[D + 6 * r + j] = _St_dot(BI, BF, i, r, W, Ui + 6 * j)
                W[u + 6 * i + r] = tau[iv + r] - _St_dot(BI, BF, i, r, W, pA + 6 * i)
        Di = Dinv + 36 * i
        if _spd_inverse(W, D, ki, Di, L, tol) <= tol:
            return i
        if lam == -1:
            continue
        if ki == 1:
            dinv = W[Di]
            uu = W[u + 6 * i]
            for r in range(6):
                W[UD + r] = W[Ui + r] * dinv
            for r in range(6):  # I^a = I^A − U D⁻¹ Uᵀ, symmetric: the upper triangle, mirrored
                ud = W[UD + r]
                for col in range(r, 6):
                    x = W[IAi + 6 * r + col] - ud * W[Ui + col]
                    W[Ia + 6 * r + col] = x
                    W[Ia + 6 * col + r] = x
            for r in range(6):  # p^a = p^A + I^a c + U D⁻¹ u
                x = W[pA + 6 * i + r] + W[UD + r] * uu
                for m in range(6):
                    x += W[Ia + 6 * r + m] * W[c + 6 * i + m]
                W[pa + r] = x
        else:
            for j in range(ki):
                for r in range(6):
                    x = 0.0
                    for m in range(ki):
                        x += W[Ui + 6 * m + r] * W[Di + 6 * m + j]
                    W[UD + 6 * j + r] = x
            for r in range(6):
                for col in range(r, 6):
                    x = W[IAi + 6 * r + col]
                    for j in range(ki):
                        x -= W[UD + 6 * j + r] * W[Ui + 6 * j + col]
                    W[Ia + 6 * r + col] = x
                    W[Ia + 6 * col + r] = x
            for r in range(6):
                x = W[pA + 6 * i + r]
                for m in range(6):
                    x += W[Ia + 6 * r + m] * W[c + 6 * i + m]
                for j in range(ki):
                    x += W[UD + 6 * j + r] * W[u + 6 * i + j]
                W[pa + r] = x
        _matrix6_to_parent_add(W, X_up + 12 * i, Ia, IA + 36 * lam, T)
        _force_to_parent(W, X_up + 12 * i, pa, pA + 6 * lam, True)

    g = 1.0 if gravity else 0.0
    W[a0], W[a0 + 1], W[a0 + 2] = 0.0, 0.0, 0.0
    W[a0 + 3], W[a0 + 4], W[a0 + 5] = -g * G[0], -g * G[1], -g * G[2]
    for i in range(nb):
        lam = BI[NBI * i + PARENT]
        ki = BI[NBI * i + NV]
        iv = BI[NBI * i + IV]
        ai = a + 6 * i
        _motion_to_child(W, X_up + 12 * i, a0 if lam == -1 else a + 6 * lam, ai)
        for k in range(6):
            W[ai + k] += W[c + 6 * i + k]
        Ui = U + 36 * i
        Di = Dinv + 36 * i
        if ki == 1:
            x = W[u + 6 * i]
            for r in range(6):
                x -= W[Ui + r] * W[ai + r]
            qdd[iv] = W[Di] * x
        else:
            for j in range(ki):
                x = W[u + 6 * i + j]
                for r in range(6):
                    x -= W[Ui + 6 * j + r] * W[ai + r]
                W[s + j] = x
            for r in range(ki):
                x = 0.0
                for j in range(ki):
                    x += W[Di + 6 * r + j] * W[s + j]
                qdd[iv + r] = x
        _S_times(BI, BF, i, qdd, W, vJ)
        for k in range(6):
            W[ai + k] += W[vJ + k]
    return -1


# ---------------------------------------------------------------------------
# frame Jacobian
# ---------------------------------------------------------------------------


@njit(**_JIT)
def frame_jacobian_core(BI, BF, q, body, FR, fo, ref, J, W):  # pragma: no cover - compiled
    """The Jacobian `(6, nv)` of the frame placed at ``FR[fo:fo+12]`` in ``body`` (``-1`` = world), into ``J``.

    Walks the support from ``body`` to the root carrying ``T = ʲM_f``, the frame's
    pose in body ``j``; joint ``j``'s LOCAL column is ``ᶠX_j S_j``::

        ᶠJ[:, j] = (ʲM_f)⁻¹ S_j,     T ← ᵖM_j T

    then re-expresses the support columns with ``⁰M_f`` for ``ref`` = 1 (WORLD:
    ``⁰X_f ᶠJ``) or 2 (LOCAL_WORLD_ALIGNED: ``[R ω; R v]``); 0 is LOCAL.
    ``W`` needs `(WS_TAIL,)` entries. Only the support is visited (O(depth)).
    """
    nv = J.shape[1]
    for r in range(6):
        for col in range(nv):
            J[r, col] = 0.0
    if body < 0:
        return
    T = 0
    X = 12
    s = 24
    col6 = 30
    for k in range(12):
        W[T + k] = FR[fo + k]
    j = body
    while j != -1:
        jv = BI[NBI * j + IV]
        for cc in range(BI[NBI * j + NV]):
            _S_col(BI, BF, j, cc, W, s)
            _motion_to_child(W, T, s, col6)
            for r in range(6):
                J[r, jv + cc] = W[col6 + r]
        _pose_in_parent(BI, BF, j, q, W, X)
        _compose(W, X, T, T)
        j = BI[NBI * j + PARENT]
    if ref == WORLD_CODE or ref == LWA_CODE:
        if ref == LWA_CODE:  # rotate only: [R ω; R v]
            W[T + 9], W[T + 10], W[T + 11] = 0.0, 0.0, 0.0
        j = body
        while j != -1:
            jv = BI[NBI * j + IV]
            for cc in range(BI[NBI * j + NV]):
                for r in range(6):
                    W[col6 + r] = J[r, jv + cc]
                _motion_to_parent(W, T, col6, col6)
                for r in range(6):
                    J[r, jv + cc] = W[col6 + r]
            j = BI[NBI * j + PARENT]


# ---------------------------------------------------------------------------
# batched forms: prange over thread chunks, one workspace per thread
# ---------------------------------------------------------------------------
#
# Every batched input has a leading axis of length N or 1 (broadcast); an
# absent optional input is passed with length 1 and an empty trailing axis
# (``(1, 0)``, ``(1, 0, 6)``), an unwanted output with zero bodies
# (``(N, 0, 4, 4)``), so every row lookup is valid and the cores see empty
# arrays.


@njit(cache=True, nogil=True)
def _row(X, s):  # pragma: no cover - compiled
    """Row ``s`` of a batched input, or row 0 when it is broadcast (length 1)."""
    return X[s if X.shape[0] > 1 else 0]


@njit(cache=True, nogil=True)
def _chunks(n, threads):  # pragma: no cover - compiled
    """``(chunks, states per chunk)``: one chunk per thread (threads is passed in: Numba cannot cache a
    function that calls ``get_num_threads``)."""
    nt = max(1, min(threads, n))
    return nt, (n + nt - 1) // nt


@njit(**_PJIT)
def fk_batch(BI, BF, Q, QD, QDD, OM, PM, VEL, ACC, wsize, threads):  # pragma: no cover - compiled
    """:func:`fk_core` over rows: ``OM``, ``PM`` `(N, nb, 4, 4)`, ``VEL``, ``ACC`` `(N, nb, 6)`."""
    n = OM.shape[0]
    nt, chunk = _chunks(n, threads)
    for t in prange(nt):
        W = np.empty(wsize)
        for s in range(t * chunk, min(n, (t + 1) * chunk)):
            fk_core(BI, BF, _row(Q, s), _row(QD, s), _row(QDD, s), OM[s], PM[s], VEL[s], ACC[s], W)


@njit(**_PJIT)
def frame_jacobian_batch(BI, BF, Q, body, FR, fo, ref, J, wsize, threads):  # pragma: no cover - compiled
    """:func:`frame_jacobian_core` over rows: ``J`` `(N, 6, nv)`."""
    n = J.shape[0]
    nt, chunk = _chunks(n, threads)
    for t in prange(nt):
        W = np.empty(wsize)
        for s in range(t * chunk, min(n, (t + 1) * chunk)):
            frame_jacobian_core(BI, BF, _row(Q, s), body, FR, fo, ref, J[s], W)
