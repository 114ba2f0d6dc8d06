"""The compiled kernels: Numba, one state at a time, over the flat arrays of :mod:`._layout` (private).

Each algorithm has a *core* that computes one state into caller-provided
outputs using a flat float64 workspace ``W`` (nothing is allocated inside),
and a *batched* form that runs the core over the rows of `(N, ·)` inputs with
``prange``, one workspace per thread. The cores follow the reference
algorithms (:mod:`featherdyn.algorithms`) line by line and keep their names:
``X_up``, ``v``, ``a``, ``f``, ``IC``, ``IA``, ``pA``, ``U``, ``D``, ``u`` are
*offsets* of per-body blocks in ``W`` (block of body ``i`` at
``X_up + 12 i``, ``v + 6 i``, ...) and ``S`` is applied by joint code. Working
with offsets instead of array views is deliberate: a view costs two atomic
reference-count updates in Numba, which is half the run time of a small model.

Representations (row-major, angular first):

* a pose `(12,)` = ``(R (9), p (3))``; ``X_up[i]`` stores the pose ``ᵖM_i`` of
  body ``i`` in its parent and is applied as its inverse, with ``m = [ω; v]``::

      X_up m      = [Rᵀ ω; Rᵀ (v − p × ω)]            (motion, parent → body)
      X_upᵀ f     = [R n + p × R f; R f]              (force,  body → parent)

* a rigid-body inertia `(10,)` = ``(m, h = m c (3), Ī (6: xx xy xz yy yz zz))``
  about the body origin::

      I [ω; v] = [Ī ω + h × v;  m v − h × ω]

* an articulated inertia `(36,)`: a full 6×6 matrix.

Inputs are trusted: the callers check shapes, dtypes and finiteness.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import njit, prange, types

from ..tolerances import QUATERNION_NORM
from ._layout import (
    AX,
    FF,
    IQ,
    IV,
    JT,
    LWA_CODE,
    MASS,
    NBF,
    NBI,
    NV,
    PARENT,
    PB,
    PLANAR,
    PRIS,
    REV,
    REV_X,
    REV_Z,
    SINGULAR_RTOL,
    SPH,
    UNIT,
    WORLD_CODE,
    WS_ABA,
    WS_CRBA,
    WS_FK,
    WS_RNEA,
    WS_TAIL,
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


# ---------------------------------------------------------------------------
# single-state entry points: the model and a workspace packed in one array
# ---------------------------------------------------------------------------
#
# Each array argument of a call from Python costs about 0.08 µs (type check
# and unboxing) and every array view made with reference counting on another
# 0.01 µs, so fd.compile's methods call these: the model *and* a workspace are
# one argument (``MD``, see _layout.pack / with_workspace), and they are
# compiled without reference counting. A workspace in the argument makes a
# CompiledModel unsafe to share between threads (like Pinocchio's Data).
# Lengths are checked (a wrong one would read out of bounds) and raise
# ValueError with a constant message (the Python wrapper words the error).


@njit(**_JIT)
def _unpack(MD, need):  # pragma: no cover - compiled
    """``(BI, BF, G, FB, FR, W, nb, nq, nv)``: views of the packed model ``MD`` and its workspace."""
    I = MD.view(np.int64)
    nb, nq, nv, nf = I[0], I[1], I[2], I[3]
    oBI, oBF, oG, oFB, oFR, oW = I[4], I[5], I[6], I[7], I[8], I[9]
    if MD.shape[0] < oW + need * nb + WS_TAIL + nv:
        raise ValueError("packed model without a workspace (use CompiledModel.packed)")
    return (I[oBI : oBI + NBI * nb], MD[oBF : oBF + NBF * nb], MD[oG : oG + 4], I[oFB : oFB + nf],
            MD[oFR : oFR + 12 * nf], MD[oW:], nb, nq, nv)


@njit(**_JIT)
def entry_fk(MD, q, oM):  # pragma: no cover - compiled
    """``oM`` `(nb, 4, 4)` ← world placements at ``q``."""
    BI, BF, _G, _FB, _FR, W, nb, nq, _nv = _unpack(MD, WS_FK)
    if q.shape[0] != nq or oM.shape[0] != nb or oM.shape[1] != 4 or oM.shape[2] != 4:
        raise ValueError("fk: wrong length of q or shape of out")
    none = W[:0].reshape((0, 6))
    fk_core(BI, BF, q, W[:0], W[:0], oM, oM[:0], none, none, W)


@njit(**_JIT)
def entry_rnea(MD, q, v, a, tau):  # pragma: no cover - compiled
    """``tau`` `(nv,)` ← RNEA(q, v, a) with gravity."""
    BI, BF, G, _FB, _FR, W, _nb, nq, nv = _unpack(MD, WS_RNEA)
    if q.shape[0] != nq or v.shape[0] != nv or a.shape[0] != nv or tau.shape[0] != nv:
        raise ValueError("rnea: wrong length of q, v, a or out")
    rnea_core(BI, BF, G, q, v, a, W[:0].reshape((0, 6)), True, tau, W)


@njit(**_JIT)
def entry_rnea_fext(MD, q, v, a, fext, tau):  # pragma: no cover - compiled
    """``tau`` `(nv,)` ← RNEA(q, v, a, f_ext) with gravity; ``fext`` `(nb, 6)` body-frame forces."""
    BI, BF, G, _FB, _FR, W, nb, nq, nv = _unpack(MD, WS_RNEA)
    if (q.shape[0] != nq or v.shape[0] != nv or a.shape[0] != nv or tau.shape[0] != nv
            or fext.shape[0] != nb or fext.shape[1] != 6):
        raise ValueError("rnea: wrong length of q, v, a or out, or shape of f_ext")
    rnea_core(BI, BF, G, q, v, a, fext, True, tau, W)


@njit(**_JIT)
def entry_nle(MD, q, v, h):  # pragma: no cover - compiled
    """``h`` `(nv,)` ← RNEA(q, v, 0)."""
    BI, BF, G, _FB, _FR, W, nb, nq, nv = _unpack(MD, WS_RNEA)
    if q.shape[0] != nq or v.shape[0] != nv or h.shape[0] != nv:
        raise ValueError("nle: wrong length of q, v or out")
    z = WS_RNEA * nb + WS_TAIL
    zero = W[z : z + nv]
    zero[:] = 0.0
    rnea_core(BI, BF, G, q, v, zero, W[:0].reshape((0, 6)), True, h, W)


@njit(**_JIT)
def entry_gravity(MD, q, g):  # pragma: no cover - compiled
    """``g`` `(nv,)` ← RNEA(q, 0, 0)."""
    BI, BF, G, _FB, _FR, W, _nb, nq, nv = _unpack(MD, WS_RNEA)
    if q.shape[0] != nq or g.shape[0] != nv:
        raise ValueError("gravity: wrong length of q or out")
    gravity_core(BI, BF, G, q, g, W)


@njit(**_JIT)
def entry_crba(MD, q, M):  # pragma: no cover - compiled
    """``M`` `(nv, nv)` ← CRBA(q)."""
    BI, BF, _G, _FB, _FR, W, _nb, nq, nv = _unpack(MD, WS_CRBA)
    if q.shape[0] != nq or M.shape[0] != nv or M.shape[1] != nv:
        raise ValueError("crba: wrong length of q or shape of out")
    crba_core(BI, BF, q, M, W)


@njit(**_JIT)
def entry_aba(MD, q, v, tau, qdd):  # pragma: no cover - compiled
    """``qdd`` `(nv,)` ← ABA(q, v, τ) with gravity; returns ``-1`` or the singular joint."""
    BI, BF, G, _FB, _FR, W, _nb, nq, nv = _unpack(MD, WS_ABA)
    if q.shape[0] != nq or v.shape[0] != nv or tau.shape[0] != nv or qdd.shape[0] != nv:
        raise ValueError("aba: wrong length of q, v, tau or out")
    return aba_core(BI, BF, G, q, v, tau, W[:0].reshape((0, 6)), True, qdd, W)


@njit(**_JIT)
def entry_frame_jacobian(MD, q, frame, ref, J):  # pragma: no cover - compiled
    """``J`` `(6, nv)` ← the Jacobian of frame index ``frame`` in ``ref`` (0 LOCAL, 1 WORLD, 2 LWA)."""
    BI, BF, _G, FB, FR, W, _nb, nq, nv = _unpack(MD, 0)
    if q.shape[0] != nq or J.shape[0] != 6 or J.shape[1] != nv:
        raise ValueError("frame_jacobian: wrong length of q or shape of out")
    if frame < 0 or frame >= FB.shape[0] or ref < 0 or ref > 2:
        raise ValueError("frame_jacobian: frame index or reference code out of range")
    frame_jacobian_core(BI, BF, q, FB[frame], FR, 12 * frame, ref, J, W)


_V = types.Array(types.float64, 1, "C")
_MD = _V
_M = types.Array(types.float64, 2, "C")
_H = types.Array(types.float64, 3, "C")
#: the one signature of each entry point (locked by :func:`lock_entries`)
ENTRY_SIGNATURES = {
    entry_fk: types.void(_MD, _V, _H),
    entry_rnea: types.void(_MD, _V, _V, _V, _V),
    entry_rnea_fext: types.void(_MD, _V, _V, _V, _M, _V),
    entry_nle: types.void(_MD, _V, _V, _V),
    entry_gravity: types.void(_MD, _V, _V),
    entry_crba: types.void(_MD, _V, _M),
    entry_aba: types.int64(_MD, _V, _V, _V, _V),
    entry_frame_jacobian: types.void(_MD, _V, types.int64, types.int64, _M),
}


def lock_entries() -> None:
    """Compile (or load from the disk cache) each entry point for its one signature, then forbid others.

    A call with other types (float32, a list, a strided view) then raises
    ``TypeError`` at once instead of compiling a new specialisation.
    """
    for fn, sig in ENTRY_SIGNATURES.items():
        if not fn.signatures:
            fn.compile(sig)
            fn.disable_compile()


# ---------------------------------------------------------------------------
# checked entry points of the public functions (fd.rnea & co. on one state)
# ---------------------------------------------------------------------------
#
# ``fd.rnea(model, q, v, a)`` on one float64 state calls these directly: they
# check everything the reference's input validation checks (lengths,
# finiteness, unit quaternions) inside the kernel and return a status instead
# of raising, and on any non-zero status the public function takes its
# general path, which raises the reference's worded error. They hold the GIL
# (no ``nogil``), so the per-model workspace in ``MD`` cannot be used by two
# Python threads at once.

#: status codes of the checked entry points
OK, BAD_LENGTH, NOT_FINITE, NOT_UNIT_QUATERNION = 0, 1, 2, 3

_GJIT: dict[str, Any] = {"cache": True, "nogil": False, "error_model": "numpy", "_nrt": False}

#: a quaternion is accepted when | ‖quat‖ − 1 | ≤ this (float64; defined in :mod:`featherdyn.tolerances`)
QUAT_TOL = QUATERNION_NORM.float64


@njit(**_IJIT)
def _all_finite(x):  # pragma: no cover - compiled
    for k in range(x.shape[0]):
        if not math.isfinite(x[k]):
            return False
    return True


@njit(**_IJIT)
def _check_q(BI, q, nq):  # pragma: no cover - compiled
    """Status of ``q``: its length, finiteness and the norm of every quaternion (spherical, free-flyer)."""
    if q.shape[0] != nq:
        return BAD_LENGTH
    if not _all_finite(q):
        return NOT_FINITE
    for i in range(BI.shape[0] // NBI):
        jt = BI[NBI * i + JT]
        if jt == SPH or jt == FF:
            o = BI[NBI * i + IQ] + (3 if jt == FF else 0)
            n = math.sqrt(q[o] * q[o] + q[o + 1] * q[o + 1] + q[o + 2] * q[o + 2] + q[o + 3] * q[o + 3])
            if abs(n - 1.0) > QUAT_TOL:
                return NOT_UNIT_QUATERNION
    return OK


@njit(**_IJIT)
def _check_vec(x, n):  # pragma: no cover - compiled
    if x.shape[0] != n:
        return BAD_LENGTH
    if not _all_finite(x):
        return NOT_FINITE
    return OK


@njit(**_GJIT)
def checked_rnea(MD, q, v, a, gravity, tau):  # pragma: no cover - compiled
    """``tau`` ← RNEA(q, v, a) if the state is valid; returns the status (``OK`` = 0)."""
    BI, BF, G, _FB, _FR, W, _nb, nq, nv = _unpack(MD, WS_RNEA)
    st = max(_check_q(BI, q, nq), _check_vec(v, nv), _check_vec(a, nv))
    if st != OK or tau.shape[0] != nv:
        return max(st, BAD_LENGTH)
    rnea_core(BI, BF, G, q, v, a, W[:0].reshape((0, 6)), gravity, tau, W)
    return OK


@njit(**_GJIT)
def checked_nle(MD, q, v, h):  # pragma: no cover - compiled
    """``h`` ← RNEA(q, v, 0) if the state is valid; returns the status."""
    BI, BF, G, _FB, _FR, W, nb, nq, nv = _unpack(MD, WS_RNEA)
    st = max(_check_q(BI, q, nq), _check_vec(v, nv))
    if st != OK or h.shape[0] != nv:
        return max(st, BAD_LENGTH)
    z = WS_RNEA * nb + WS_TAIL
    zero = W[z : z + nv]
    zero[:] = 0.0
    rnea_core(BI, BF, G, q, v, zero, W[:0].reshape((0, 6)), True, h, W)
    return OK


@njit(**_GJIT)
def checked_gravity(MD, q, g):  # pragma: no cover - compiled
    """``g`` ← RNEA(q, 0, 0) if ``q`` is valid; returns the status."""
    BI, BF, G, _FB, _FR, W, _nb, nq, nv = _unpack(MD, WS_RNEA)
    st = _check_q(BI, q, nq)
    if st != OK or g.shape[0] != nv:
        return max(st, BAD_LENGTH)
    gravity_core(BI, BF, G, q, g, W)
    return OK


@njit(**_GJIT)
def checked_crba(MD, q, M):  # pragma: no cover - compiled
    """``M`` ← CRBA(q) if ``q`` is valid; returns the status."""
    BI, BF, _G, _FB, _FR, W, _nb, nq, nv = _unpack(MD, WS_CRBA)
    st = _check_q(BI, q, nq)
    if st != OK or M.shape[0] != nv or M.shape[1] != nv:
        return max(st, BAD_LENGTH)
    crba_core(BI, BF, q, M, W)
    return OK


@njit(**_GJIT)
def checked_aba(MD, q, v, tau, gravity, qdd):  # pragma: no cover - compiled
    """``qdd`` ← ABA(q, v, τ) if the state is valid; returns ``-1`` (done), the index of a joint with a
    singular articulated inertia, or ``-1 − status`` for an invalid state."""
    BI, BF, G, _FB, _FR, W, _nb, nq, nv = _unpack(MD, WS_ABA)
    st = max(_check_q(BI, q, nq), _check_vec(v, nv), _check_vec(tau, nv))
    if st != OK or qdd.shape[0] != nv:
        return -1 - max(st, BAD_LENGTH)
    return aba_core(BI, BF, G, q, v, tau, W[:0].reshape((0, 6)), gravity, qdd, W)


@njit(**_GJIT)
def checked_frame_jacobian(MD, q, frame, ref, J):  # pragma: no cover - compiled
    """``J`` ← the Jacobian of frame index ``frame`` in ``ref`` (0 LOCAL, 1 WORLD, 2 LWA) if valid; the status."""
    BI, BF, _G, FB, FR, W, _nb, nq, nv = _unpack(MD, 0)
    st = _check_q(BI, q, nq)
    if st != OK or J.shape[0] != 6 or J.shape[1] != nv or frame < 0 or frame >= FB.shape[0] or ref < 0 or ref > 2:
        return max(st, BAD_LENGTH)
    frame_jacobian_core(BI, BF, q, FB[frame], FR, 12 * frame, ref, J, W)
    return OK


@njit(**_GJIT)
def checked_fk(MD, q, v, a, H, vel, acc):  # pragma: no cover - compiled
    """``H`` `(2, nb, 4, 4)` ← ``⁰M_i`` and ``ᵖM_i``; ``vel`` `(nb, 6)` ← ``v_i`` unless it is empty `(0, 6)`
    (then ``v`` is not read), ``acc`` likewise ← ``a_i`` (needs ``vel``). Returns the status."""
    BI, BF, _G, _FB, _FR, W, nb, nq, nv = _unpack(MD, WS_FK)
    st = _check_q(BI, q, nq)
    want_v = vel.shape[0] > 0
    want_a = acc.shape[0] > 0
    if want_v:
        st = max(st, _check_vec(v, nv))
    if want_a:
        st = max(st, _check_vec(a, nv))
    if (st != OK or H.shape[0] != 2 or H.shape[1] != nb or H.shape[2] != 4 or H.shape[3] != 4
            or (want_v and (vel.shape[0] != nb or vel.shape[1] != 6))
            or (want_a and (acc.shape[0] != nb or acc.shape[1] != 6)) or (want_a and not want_v) or nb == 0):
        return max(st, BAD_LENGTH)
    fk_core(BI, BF, q, v, a, H[0], H[1], vel, acc, W)
    return OK


@njit(**_GJIT)
def checked_frame_placement(MD, q, frame, out):  # pragma: no cover - compiled
    """``out`` `(12,)` ← ``⁰M_f`` = ``(R row-major, p)`` of frame index ``frame``, walking its support to the root::

        ⁰M_f = ᵖM_root ⋯ ᵖM_body(f) · placement_f

    Returns the status."""
    BI, BF, _G, FB, FR, W, _nb, nq, _nv = _unpack(MD, 0)
    st = _check_q(BI, q, nq)
    if st != OK or out.shape[0] != 12 or frame < 0 or frame >= FB.shape[0]:
        return max(st, BAD_LENGTH)
    T = 0
    X = 12
    for k in range(12):
        W[T + k] = FR[12 * frame + k]
    j = FB[frame]
    while j != -1:
        _pose_in_parent(BI, BF, j, q, W, X)
        _compose(W, X, T, T)
        j = BI[NBI * j + PARENT]
    for k in range(12):
        out[k] = W[T + k]
    return OK


_I64 = types.int64
_B = types.boolean
_A4 = types.Array(types.float64, 4, "C")
#: the one signature of each checked entry point (locked by :func:`lock_checked`)
CHECKED_SIGNATURES = {
    checked_rnea: _I64(_MD, _V, _V, _V, _B, _V),
    checked_nle: _I64(_MD, _V, _V, _V),
    checked_gravity: _I64(_MD, _V, _V),
    checked_crba: _I64(_MD, _V, _M),
    checked_aba: _I64(_MD, _V, _V, _V, _B, _V),
    checked_frame_jacobian: _I64(_MD, _V, _I64, _I64, _M),
    checked_fk: _I64(_MD, _V, _V, _V, _A4, _M, _M),
    checked_frame_placement: _I64(_MD, _V, _I64, _V),
}


def lock_checked() -> None:
    """Compile (or load from the disk cache) each checked entry point for its one signature, then forbid others."""
    for fn, sig in CHECKED_SIGNATURES.items():
        if not fn.signatures:
            fn.compile(sig)
            fn.disable_compile()
