"""Joint transforms and spatial algebra on the flat arrays of :mod:`._layout`, for the kernels (private).

Part of the compiled engine's kernels (:mod:`._kernels` is the index). The
representations (row-major, angular first) are described there; everything
here works on offsets into a flat float64 workspace ``W`` and never allocates.
"""


from __future__ import annotations

import math
from typing import Any

from numba import njit

from ._layout import (
    AX,
    FF,
    IQ,
    IV,
    JT,
    NBF,
    NBI,
    PB,
    PLANAR,
    PRIS,
    REV,
    REV_X,
    REV_Z,
    SPH,
    XP,
    XR,
)

# cores and helpers never allocate, so they are compiled without reference counting
# No fastmath, not even FMA contraction: LLVM would contract differently where a core is inlined
# into a batched kernel, and batched results would differ from single calls in the last bit.
_JIT: dict[str, Any] = {"cache": True, "nogil": True, "error_model": "numpy", "_nrt": False}
# small helpers are inlined into the cores at the Numba IR level (LLVM does not inline across Numba functions)
_IJIT: dict[str, Any] = {**_JIT, "inline": "always"}
_PJIT: dict[str, Any] = {"cache": True, "nogil": True, "error_model": "numpy", "parallel": True}

# ---------------------------------------------------------------------------
# joints: ᵖM_i(q) = Xtree_i · M_J(q_i), and the motion subspace S_i
# ---------------------------------------------------------------------------


@njit(**_IJIT)
def _compose(W, A, B, out):  # pragma: no cover - compiled
    """``W[out] = W[A] · W[B]`` for poses (``R = R_A R_B``, ``p = p_A + R_A p_B``); ``out`` may be ``B``."""
    b0, b1, b2, b3, b4, b5, b6, b7, b8 = W[B], W[B + 1], W[B + 2], W[B + 3], W[B + 4], W[B + 5], W[B + 6], \
        W[B + 7], W[B + 8]
    q0, q1, q2 = W[B + 9], W[B + 10], W[B + 11]
    for r in range(3):
        a0, a1, a2 = W[A + 3 * r], W[A + 3 * r + 1], W[A + 3 * r + 2]
        W[out + 3 * r] = a0 * b0 + a1 * b3 + a2 * b6
        W[out + 3 * r + 1] = a0 * b1 + a1 * b4 + a2 * b7
        W[out + 3 * r + 2] = a0 * b2 + a1 * b5 + a2 * b8
        W[out + 9 + r] = W[A + 9 + r] + a0 * q0 + a1 * q1 + a2 * q2


@njit(**_IJIT)
def _pose_in_parent(BI, BF, i, q, W, X):  # pragma: no cover - compiled
    """``W[X:X+12] = ᵖM_i = Xtree_i · M_J(q_i)``: the pose of body ``i`` in its parent."""
    jt = BI[NBI * i + JT]
    k = BI[NBI * i + IQ]
    b = NBF * i
    if jt >= REV_X and jt <= REV_Z:
        # a rotation about ±e_ax mixes two columns of Xtree's rotation
        ax = jt - REV_X
        th = q[k] * BF[b + AX + ax]
        c = math.cos(th)
        s = math.sin(th)
        i1 = ax + 1 if ax < 2 else 0
        i2 = ax - 1 if ax > 0 else 2
        for r in range(3):
            x1 = BF[b + XR + 3 * r + i1]
            x2 = BF[b + XR + 3 * r + i2]
            W[X + 3 * r + ax] = BF[b + XR + 3 * r + ax]
            W[X + 3 * r + i1] = c * x1 + s * x2
            W[X + 3 * r + i2] = c * x2 - s * x1
        W[X + 9] = BF[b + XP]
        W[X + 10] = BF[b + XP + 1]
        W[X + 11] = BF[b + XP + 2]
        return
    # the other joints: M_J = (RJ, pJ), then R = R_tree RJ, p = p_tree + R_tree pJ
    p0 = 0.0
    p1 = 0.0
    p2 = 0.0
    if jt == REV or jt == PLANAR:
        # Rodrigues: RJ = c 1 + s [k]× + (1 − c) k kᵀ
        th = q[k] if jt == REV else q[k + 2]
        kx, ky, kz = BF[b + AX], BF[b + AX + 1], BF[b + AX + 2]
        c = math.cos(th)
        s = math.sin(th)
        t = 1.0 - c
        r00, r01, r02 = c + t * kx * kx, t * kx * ky - s * kz, t * kx * kz + s * ky
        r10, r11, r12 = t * kx * ky + s * kz, c + t * ky * ky, t * ky * kz - s * kx
        r20, r21, r22 = t * kx * kz - s * ky, t * ky * kz + s * kx, c + t * kz * kz
        if jt == PLANAR:  # pJ = x e1 + y e2, the first two columns of the plane basis
            x, y = q[k], q[k + 1]
            p0 = x * BF[b + PB] + y * BF[b + PB + 1]
            p1 = x * BF[b + PB + 3] + y * BF[b + PB + 4]
            p2 = x * BF[b + PB + 6] + y * BF[b + PB + 7]
    elif jt == PRIS:
        r00, r01, r02 = 1.0, 0.0, 0.0
        r10, r11, r12 = 0.0, 1.0, 0.0
        r20, r21, r22 = 0.0, 0.0, 1.0
        d = q[k]
        p0, p1, p2 = d * BF[b + AX], d * BF[b + AX + 1], d * BF[b + AX + 2]
    else:
        # spherical (quat xyzw) or free-flyer ([p, quat xyzw]): R = 1 + 2w[v]× + 2[v]×², with 2 → 2/|q|²
        o = k
        if jt == FF:
            p0, p1, p2 = q[k], q[k + 1], q[k + 2]
            o = k + 3
        x, y, z, w = q[o], q[o + 1], q[o + 2], q[o + 3]
        two = 2.0 / (x * x + y * y + z * z + w * w)
        r00, r01, r02 = 1.0 - two * (y * y + z * z), two * (x * y - w * z), two * (x * z + w * y)
        r10, r11, r12 = two * (x * y + w * z), 1.0 - two * (x * x + z * z), two * (y * z - w * x)
        r20, r21, r22 = two * (x * z - w * y), two * (y * z + w * x), 1.0 - two * (x * x + y * y)
    for r in range(3):
        a0, a1, a2 = BF[b + XR + 3 * r], BF[b + XR + 3 * r + 1], BF[b + XR + 3 * r + 2]
        W[X + 3 * r] = a0 * r00 + a1 * r10 + a2 * r20
        W[X + 3 * r + 1] = a0 * r01 + a1 * r11 + a2 * r21
        W[X + 3 * r + 2] = a0 * r02 + a1 * r12 + a2 * r22
        W[X + 9 + r] = BF[b + XP + r] + a0 * p0 + a1 * p1 + a2 * p2


@njit(**_IJIT)
def _S_col(BI, BF, i, c, W, out):  # pragma: no cover - compiled
    """``W[out:out+6] = S_i[:, c]``."""
    jt = BI[NBI * i + JT]
    b = NBF * i
    for r in range(6):
        W[out + r] = 0.0
    if jt <= REV_Z:
        W[out], W[out + 1], W[out + 2] = BF[b + AX], BF[b + AX + 1], BF[b + AX + 2]
    elif jt == PRIS:
        W[out + 3], W[out + 4], W[out + 5] = BF[b + AX], BF[b + AX + 1], BF[b + AX + 2]
    elif jt == SPH or jt == FF:
        W[out + c] = 1.0
    elif c == 0:  # planar: [n; 0], [0; e1], [0; e2]
        W[out], W[out + 1], W[out + 2] = BF[b + AX], BF[b + AX + 1], BF[b + AX + 2]
    else:
        e = c - 1
        W[out + 3], W[out + 4], W[out + 5] = BF[b + PB + e], BF[b + PB + 3 + e], BF[b + PB + 6 + e]


@njit(**_IJIT)
def _S_times(BI, BF, i, x, W, out):  # pragma: no cover - compiled
    """``W[out:out+6] = S_i x_i``, with ``x_i`` joint ``i``'s slice of the `(nv,)` vector ``x``."""
    jt = BI[NBI * i + JT]
    k = BI[NBI * i + IV]
    b = NBF * i
    if jt <= REV_Z:
        s = x[k]
        W[out], W[out + 1], W[out + 2] = s * BF[b + AX], s * BF[b + AX + 1], s * BF[b + AX + 2]
        W[out + 3], W[out + 4], W[out + 5] = 0.0, 0.0, 0.0
    elif jt == PRIS:
        s = x[k]
        W[out], W[out + 1], W[out + 2] = 0.0, 0.0, 0.0
        W[out + 3], W[out + 4], W[out + 5] = s * BF[b + AX], s * BF[b + AX + 1], s * BF[b + AX + 2]
    elif jt == SPH:
        W[out], W[out + 1], W[out + 2] = x[k], x[k + 1], x[k + 2]
        W[out + 3], W[out + 4], W[out + 5] = 0.0, 0.0, 0.0
    elif jt == FF:
        for r in range(6):
            W[out + r] = x[k + r]
    else:
        w, vx, vy = x[k], x[k + 1], x[k + 2]
        W[out], W[out + 1], W[out + 2] = w * BF[b + AX], w * BF[b + AX + 1], w * BF[b + AX + 2]
        for r in range(3):
            W[out + 3 + r] = vx * BF[b + PB + 3 * r] + vy * BF[b + PB + 3 * r + 1]


@njit(**_IJIT)
def _St_dot(BI, BF, i, c, W, f):  # pragma: no cover - compiled
    """``S_i[:, c] · W[f:f+6]``: a force's component along joint ``i``'s axis ``c``."""
    jt = BI[NBI * i + JT]
    b = NBF * i
    if jt <= REV_Z:
        return BF[b + AX] * W[f] + BF[b + AX + 1] * W[f + 1] + BF[b + AX + 2] * W[f + 2]
    if jt == PRIS:
        return BF[b + AX] * W[f + 3] + BF[b + AX + 1] * W[f + 4] + BF[b + AX + 2] * W[f + 5]
    if jt == SPH or jt == FF:
        return W[f + c]
    if c == 0:
        return BF[b + AX] * W[f] + BF[b + AX + 1] * W[f + 1] + BF[b + AX + 2] * W[f + 2]
    e = c - 1
    return BF[b + PB + e] * W[f + 3] + BF[b + PB + 3 + e] * W[f + 4] + BF[b + PB + 6 + e] * W[f + 5]


# ---------------------------------------------------------------------------
# spatial algebra on 6-vectors in W
# ---------------------------------------------------------------------------


@njit(**_IJIT)
def _motion_to_child(W, X, m, out):  # pragma: no cover - compiled
    """``W[out] = X_up W[m] = [Rᵀ ω; Rᵀ (v − p × ω)]``; ``out`` may be ``m``."""
    w0, w1, w2 = W[m], W[m + 1], W[m + 2]
    p0, p1, p2 = W[X + 9], W[X + 10], W[X + 11]
    t0 = W[m + 3] - (p1 * w2 - p2 * w1)
    t1 = W[m + 4] - (p2 * w0 - p0 * w2)
    t2 = W[m + 5] - (p0 * w1 - p1 * w0)
    for c in range(3):
        W[out + c] = W[X + c] * w0 + W[X + 3 + c] * w1 + W[X + 6 + c] * w2
        W[out + 3 + c] = W[X + c] * t0 + W[X + 3 + c] * t1 + W[X + 6 + c] * t2


@njit(**_IJIT)
def _motion_to_parent(W, X, m, out):  # pragma: no cover - compiled
    """``W[out] = X_up⁻¹ W[m] = [R ω; R v + p × R ω]``; ``out`` may be ``m``."""
    w0, w1, w2 = W[m], W[m + 1], W[m + 2]
    v0, v1, v2 = W[m + 3], W[m + 4], W[m + 5]
    a0 = W[X] * w0 + W[X + 1] * w1 + W[X + 2] * w2
    a1 = W[X + 3] * w0 + W[X + 4] * w1 + W[X + 5] * w2
    a2 = W[X + 6] * w0 + W[X + 7] * w1 + W[X + 8] * w2
    p0, p1, p2 = W[X + 9], W[X + 10], W[X + 11]
    W[out], W[out + 1], W[out + 2] = a0, a1, a2
    W[out + 3] = W[X] * v0 + W[X + 1] * v1 + W[X + 2] * v2 + p1 * a2 - p2 * a1
    W[out + 4] = W[X + 3] * v0 + W[X + 4] * v1 + W[X + 5] * v2 + p2 * a0 - p0 * a2
    W[out + 5] = W[X + 6] * v0 + W[X + 7] * v1 + W[X + 8] * v2 + p0 * a1 - p1 * a0


@njit(**_IJIT)
def _force_to_parent(W, X, f, out, accumulate):  # pragma: no cover - compiled
    """``W[out] (+)= X_upᵀ W[f] = [R n + p × R f; R f]``; ``out`` may be ``f`` when not accumulating."""
    n0, n1, n2 = W[f], W[f + 1], W[f + 2]
    f0, f1, f2 = W[f + 3], W[f + 4], W[f + 5]
    g0 = W[X] * f0 + W[X + 1] * f1 + W[X + 2] * f2
    g1 = W[X + 3] * f0 + W[X + 4] * f1 + W[X + 5] * f2
    g2 = W[X + 6] * f0 + W[X + 7] * f1 + W[X + 8] * f2
    p0, p1, p2 = W[X + 9], W[X + 10], W[X + 11]
    m0 = W[X] * n0 + W[X + 1] * n1 + W[X + 2] * n2 + p1 * g2 - p2 * g1
    m1 = W[X + 3] * n0 + W[X + 4] * n1 + W[X + 5] * n2 + p2 * g0 - p0 * g2
    m2 = W[X + 6] * n0 + W[X + 7] * n1 + W[X + 8] * n2 + p0 * g1 - p1 * g0
    if accumulate:
        W[out] += m0
        W[out + 1] += m1
        W[out + 2] += m2
        W[out + 3] += g0
        W[out + 4] += g1
        W[out + 5] += g2
    else:
        W[out], W[out + 1], W[out + 2], W[out + 3], W[out + 4], W[out + 5] = m0, m1, m2, g0, g1, g2


@njit(**_IJIT)
def _force_to_child(W, X, f, out):  # pragma: no cover - compiled
    """``W[out] = X_up⁻ᵀ W[f] = [Rᵀ (n − p × f); Rᵀ f]`` (a force from the parent to the body); ``out`` may be ``f``."""
    n0, n1, n2 = W[f], W[f + 1], W[f + 2]
    f0, f1, f2 = W[f + 3], W[f + 4], W[f + 5]
    p0, p1, p2 = W[X + 9], W[X + 10], W[X + 11]
    t0 = n0 - (p1 * f2 - p2 * f1)
    t1 = n1 - (p2 * f0 - p0 * f2)
    t2 = n2 - (p0 * f1 - p1 * f0)
    for c in range(3):
        W[out + c] = W[X + c] * t0 + W[X + 3 + c] * t1 + W[X + 6 + c] * t2
        W[out + 3 + c] = W[X + c] * f0 + W[X + 3 + c] * f1 + W[X + 6 + c] * f2


@njit(**_IJIT)
def _cross_motion_add(W, v, m, out):  # pragma: no cover - compiled
    """``W[out] += W[v] × W[m] = [ω × ω_m; ω × v_m + v × ω_m]``."""
    w0, w1, w2, u0, u1, u2 = W[v], W[v + 1], W[v + 2], W[v + 3], W[v + 4], W[v + 5]
    a0, a1, a2, b0, b1, b2 = W[m], W[m + 1], W[m + 2], W[m + 3], W[m + 4], W[m + 5]
    W[out] += w1 * a2 - w2 * a1
    W[out + 1] += w2 * a0 - w0 * a2
    W[out + 2] += w0 * a1 - w1 * a0
    W[out + 3] += w1 * b2 - w2 * b1 + u1 * a2 - u2 * a1
    W[out + 4] += w2 * b0 - w0 * b2 + u2 * a0 - u0 * a2
    W[out + 5] += w0 * b1 - w1 * b0 + u0 * a1 - u1 * a0


@njit(**_IJIT)
def _cross_force_add(W, v, f, out):  # pragma: no cover - compiled
    """``W[out] += W[v] ×* W[f] = [ω × n + v × f; ω × f]``."""
    w0, w1, w2, u0, u1, u2 = W[v], W[v + 1], W[v + 2], W[v + 3], W[v + 4], W[v + 5]
    n0, n1, n2, f0, f1, f2 = W[f], W[f + 1], W[f + 2], W[f + 3], W[f + 4], W[f + 5]
    W[out] += w1 * n2 - w2 * n1 + u1 * f2 - u2 * f1
    W[out + 1] += w2 * n0 - w0 * n2 + u2 * f0 - u0 * f2
    W[out + 2] += w0 * n1 - w1 * n0 + u0 * f1 - u1 * f0
    W[out + 3] += w1 * f2 - w2 * f1
    W[out + 4] += w2 * f0 - w0 * f2
    W[out + 5] += w0 * f1 - w1 * f0


@njit(**_IJIT)
def _inertia_times(P, I, W, m, out):  # pragma: no cover - compiled
    """``W[out] = I W[m] = [Ī ω + h × v; m v − h × ω]``, the 10 parameters at ``P[I:I+10]``."""
    mass, h0, h1, h2 = P[I], P[I + 1], P[I + 2], P[I + 3]
    xx, xy, xz, yy, yz, zz = P[I + 4], P[I + 5], P[I + 6], P[I + 7], P[I + 8], P[I + 9]
    w0, w1, w2, v0, v1, v2 = W[m], W[m + 1], W[m + 2], W[m + 3], W[m + 4], W[m + 5]
    W[out] = xx * w0 + xy * w1 + xz * w2 + h1 * v2 - h2 * v1
    W[out + 1] = xy * w0 + yy * w1 + yz * w2 + h2 * v0 - h0 * v2
    W[out + 2] = xz * w0 + yz * w1 + zz * w2 + h0 * v1 - h1 * v0
    W[out + 3] = mass * v0 - (h1 * w2 - h2 * w1)
    W[out + 4] = mass * v1 - (h2 * w0 - h0 * w2)
    W[out + 5] = mass * v2 - (h0 * w1 - h1 * w0)


@njit(**_IJIT)
def _inertia_to_parent(P, I, W, X, out, accumulate):  # pragma: no cover - compiled
    """``W[out] (+)= X_upᵀ P[I] X_up`` on 10 parameters: ``m' = m``, ``h' = y + m p`` with ``y = R h``, and::

        Ī' = R Ī Rᵀ − p yᵀ − y pᵀ + 2 (y·p) 1 − m (p pᵀ − |p|² 1)

    (``P`` holds the parameters: the model's ``BF`` or the workspace; ``W[X]`` is the pose.)
    """
    mass = P[I]
    p0, p1, p2 = W[X + 9], W[X + 10], W[X + 11]
    h0, h1, h2 = P[I + 1], P[I + 2], P[I + 3]
    R0, R1, R2, R3, R4, R5, R6, R7, R8 = W[X], W[X + 1], W[X + 2], W[X + 3], W[X + 4], W[X + 5], W[X + 6], \
        W[X + 7], W[X + 8]
    y0 = R0 * h0 + R1 * h1 + R2 * h2
    y1 = R3 * h0 + R4 * h1 + R5 * h2
    y2 = R6 * h0 + R7 * h1 + R8 * h2
    xx, xy, xz, yy, yz, zz = P[I + 4], P[I + 5], P[I + 6], P[I + 7], P[I + 8], P[I + 9]
    # T = R Ī, then (T Rᵀ)[r, s] = T[r, :] · R[s, :]
    t00 = R0 * xx + R1 * xy + R2 * xz
    t01 = R0 * xy + R1 * yy + R2 * yz
    t02 = R0 * xz + R1 * yz + R2 * zz
    t10 = R3 * xx + R4 * xy + R5 * xz
    t11 = R3 * xy + R4 * yy + R5 * yz
    t12 = R3 * xz + R4 * yz + R5 * zz
    t20 = R6 * xx + R7 * xy + R8 * xz
    t21 = R6 * xy + R7 * yy + R8 * yz
    t22 = R6 * xz + R7 * yz + R8 * zz
    d = 2.0 * (y0 * p0 + y1 * p1 + y2 * p2) + mass * (p0 * p0 + p1 * p1 + p2 * p2)
    r0 = mass
    r1 = y0 + mass * p0
    r2 = y1 + mass * p1
    r3 = y2 + mass * p2
    r4 = t00 * R0 + t01 * R1 + t02 * R2 - 2.0 * p0 * y0 - mass * p0 * p0 + d
    r5 = t00 * R3 + t01 * R4 + t02 * R5 - p0 * y1 - y0 * p1 - mass * p0 * p1
    r6 = t00 * R6 + t01 * R7 + t02 * R8 - p0 * y2 - y0 * p2 - mass * p0 * p2
    r7 = t10 * R3 + t11 * R4 + t12 * R5 - 2.0 * p1 * y1 - mass * p1 * p1 + d
    r8 = t10 * R6 + t11 * R7 + t12 * R8 - p1 * y2 - y1 * p2 - mass * p1 * p2
    r9 = t20 * R6 + t21 * R7 + t22 * R8 - 2.0 * p2 * y2 - mass * p2 * p2 + d
    if accumulate:
        W[out] += r0
        W[out + 1] += r1
        W[out + 2] += r2
        W[out + 3] += r3
        W[out + 4] += r4
        W[out + 5] += r5
        W[out + 6] += r6
        W[out + 7] += r7
        W[out + 8] += r8
        W[out + 9] += r9
    else:
        W[out], W[out + 1], W[out + 2], W[out + 3], W[out + 4] = r0, r1, r2, r3, r4
        W[out + 5], W[out + 6], W[out + 7], W[out + 8], W[out + 9] = r5, r6, r7, r8, r9


@njit(**_IJIT)
def _inertia_matrix(P, I, W, out):  # pragma: no cover - compiled
    """``W[out:out+36]`` = the 6×6 matrix ``[[Ī, [h]×], [[h]×ᵀ, m 1]]`` of the parameters ``P[I:I+10]``."""
    mass, h0, h1, h2 = P[I], P[I + 1], P[I + 2], P[I + 3]
    xx, xy, xz, yy, yz, zz = P[I + 4], P[I + 5], P[I + 6], P[I + 7], P[I + 8], P[I + 9]
    o = out
    W[o], W[o + 1], W[o + 2], W[o + 3], W[o + 4], W[o + 5] = xx, xy, xz, 0.0, -h2, h1
    W[o + 6], W[o + 7], W[o + 8], W[o + 9], W[o + 10], W[o + 11] = xy, yy, yz, h2, 0.0, -h0
    W[o + 12], W[o + 13], W[o + 14], W[o + 15], W[o + 16], W[o + 17] = xz, yz, zz, -h1, h0, 0.0
    W[o + 18], W[o + 19], W[o + 20], W[o + 21], W[o + 22], W[o + 23] = 0.0, h2, -h1, mass, 0.0, 0.0
    W[o + 24], W[o + 25], W[o + 26], W[o + 27], W[o + 28], W[o + 29] = -h2, 0.0, h0, 0.0, mass, 0.0
    W[o + 30], W[o + 31], W[o + 32], W[o + 33], W[o + 34], W[o + 35] = h1, -h0, 0.0, 0.0, 0.0, mass


@njit(**_IJIT)
def _matrix6_to_parent_add(W, X, Ia, out, T):  # pragma: no cover - compiled
    """``W[out] += X_upᵀ W[Ia] X_up`` for a symmetric 6×6 ``Ia`` (scratch ``W[T:T+27]``).

    With ``Ia = [[A, B], [Bᵀ, C]]``, primes denoting ``R (·) Rᵀ`` and ``P = [p]×``::

        C_λ += C',   B_λ += B' + P C',   A_λ += A' − Q − Qᵀ − P C' P,   Q = B' P
    """
    # T[0:9] = A', T[9:18] = B', T[18:27] = C'
    for blk in range(3):
        top = Ia + (18 if blk == 2 else 0) + (0 if blk == 0 else 3)  # first entry of the 3×3 block
        for r in range(3):
            x0, x1, x2 = W[X + 3 * r], W[X + 3 * r + 1], W[X + 3 * r + 2]
            m0 = x0 * W[top] + x1 * W[top + 6] + x2 * W[top + 12]
            m1 = x0 * W[top + 1] + x1 * W[top + 7] + x2 * W[top + 13]
            m2 = x0 * W[top + 2] + x1 * W[top + 8] + x2 * W[top + 14]
            for s in range(3):
                W[T + 9 * blk + 3 * r + s] = m0 * W[X + 3 * s] + m1 * W[X + 3 * s + 1] + m2 * W[X + 3 * s + 2]
    p0, p1, p2 = W[X + 9], W[X + 10], W[X + 11]
    for r in range(3):
        for s in range(3):
            W[out + 21 + 6 * r + s] += W[T + 18 + 3 * r + s]
    # B_new = B' + P C' (column s: p × C'[:, s]), into the B and Bᵀ blocks
    for s in range(3):
        c0, c1, c2 = W[T + 18 + s], W[T + 21 + s], W[T + 24 + s]
        b0 = W[T + 9 + s] + p1 * c2 - p2 * c1
        b1 = W[T + 12 + s] + p2 * c0 - p0 * c2
        b2 = W[T + 15 + s] + p0 * c1 - p1 * c0
        W[out + 3 + s] += b0
        W[out + 9 + s] += b1
        W[out + 15 + s] += b2
        W[out + 18 + 6 * s] += b0
        W[out + 19 + 6 * s] += b1
        W[out + 20 + 6 * s] += b2
    # rows of C'P (C'[r, :] × p) and of Q = B'P (B'[r, :] × p), in place
    for r in range(3):
        c = T + 18 + 3 * r
        c0, c1, c2 = W[c], W[c + 1], W[c + 2]
        W[c], W[c + 1], W[c + 2] = c1 * p2 - c2 * p1, c2 * p0 - c0 * p2, c0 * p1 - c1 * p0
        q = T + 9 + 3 * r
        b0, b1, b2 = W[q], W[q + 1], W[q + 2]
        W[q], W[q + 1], W[q + 2] = b1 * p2 - b2 * p1, b2 * p0 - b0 * p2, b0 * p1 - b1 * p0
    # A_new = A' − Q − Qᵀ − P (C'P), column s of P (C'P) = p × (C'P)[:, s]
    for s in range(3):
        c0, c1, c2 = W[T + 18 + s], W[T + 21 + s], W[T + 24 + s]
        W[out + s] += W[T + s] - W[T + 9 + s] - W[T + 9 + 3 * s] - (p1 * c2 - p2 * c1)
        W[out + 6 + s] += W[T + 3 + s] - W[T + 12 + s] - W[T + 10 + 3 * s] - (p2 * c0 - p0 * c2)
        W[out + 12 + s] += W[T + 6 + s] - W[T + 15 + s] - W[T + 11 + 3 * s] - (p0 * c1 - p1 * c0)
