"""The scalar kernels' joint and spatial-algebra helpers over lane rows, operation by operation (private).

Each helper here is the twin of the one-state helper of the same name in
:mod:`._flat_spatial`, applied to ``LANES`` states at once (see :mod:`._lanes`),
in the same order of operations so that every lane is bit-identical to the
one-state result; plus the gathering and scattering of a block's inputs and outputs.
"""


from __future__ import annotations

import math

import numpy as np
from numba import njit

# ---------------------------------------------------------------------------
# helpers: the scalar helpers of _kernels over lane rows, operation by operation
# ---------------------------------------------------------------------------
# the one-state kernels' compile options (no fastmath, no FMA contraction; helpers inlined at the IR level)
from ._flat_spatial import _IJIT
from ._lane_vector import LANES, _ld, _line_offset, _st, _v
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
    WS_TAIL,
    XP,
    XR,
)


@njit(**_IJIT)
def _compose(W, A, B, out):  # pragma: no cover - compiled
    """``W[out] = W[A] · W[B]`` for poses; ``out`` may be ``B``."""
    b0, b1, b2, b3, b4, b5, b6, b7, b8 = _ld(W, B), _ld(W, B + 1), _ld(W, B + 2), _ld(W, B + 3), _ld(W, B + 4), \
        _ld(W, B + 5), _ld(W, B + 6), _ld(W, B + 7), _ld(W, B + 8)
    q0, q1, q2 = _ld(W, B + 9), _ld(W, B + 10), _ld(W, B + 11)
    for r in range(3):
        a0, a1, a2 = _ld(W, A + 3 * r), _ld(W, A + 3 * r + 1), _ld(W, A + 3 * r + 2)
        _st(W, out + 3 * r, a0 * b0 + a1 * b3 + a2 * b6)
        _st(W, out + 3 * r + 1, a0 * b1 + a1 * b4 + a2 * b7)
        _st(W, out + 3 * r + 2, a0 * b2 + a1 * b5 + a2 * b8)
        _st(W, out + 9 + r, _ld(W, A + 9 + r) + a0 * q0 + a1 * q1 + a2 * q2)


@njit(**_IJIT)
def _cos_sin(W, qo, scale, T):  # pragma: no cover - compiled
    """Rows ``T``, ``T + 1`` = ``cos``, ``sin`` of ``θ = q · scale`` (``q`` the row ``qo``), lane by lane."""
    for s in range(LANES):
        th = W[qo * LANES + s] * scale
        W[T * LANES + s] = math.cos(th)
        W[(T + 1) * LANES + s] = math.sin(th)


@njit(**_IJIT)
def _cos_sin1(W, qo, T):  # pragma: no cover - compiled
    """Rows ``T``, ``T + 1`` = ``cos``, ``sin`` of the row ``qo``, lane by lane."""
    for s in range(LANES):
        th = W[qo * LANES + s]
        W[T * LANES + s] = math.cos(th)
        W[(T + 1) * LANES + s] = math.sin(th)


@njit(**_IJIT)
def _pose_in_parent(BI, BF, i, Q, W, X, T):  # pragma: no cover - compiled
    """``W[X:X+12] = ᵖM_i(q_i)``, ``q`` in rows ``Q + k``; rows ``T``, ``T + 1`` are scratch."""
    jt = BI[NBI * i + JT]
    k = BI[NBI * i + IQ]
    b = NBF * i
    if jt >= REV_X and jt <= REV_Z:
        ax = jt - REV_X
        _cos_sin(W, Q + k, BF[b + AX + ax], T)
        c = _ld(W, T)
        s = _ld(W, T + 1)
        i1 = ax + 1 if ax < 2 else 0
        i2 = ax - 1 if ax > 0 else 2
        for r in range(3):
            x1 = BF[b + XR + 3 * r + i1]
            x2 = BF[b + XR + 3 * r + i2]
            _st(W, X + 3 * r + ax, BF[b + XR + 3 * r + ax])
            _st(W, X + 3 * r + i1, c * x1 + s * x2)
            _st(W, X + 3 * r + i2, c * x2 - s * x1)
        _st(W, X + 9, BF[b + XP])
        _st(W, X + 10, BF[b + XP + 1])
        _st(W, X + 11, BF[b + XP + 2])
        return
    p0 = _v(0.0)
    p1 = _v(0.0)
    p2 = _v(0.0)
    if jt == REV or jt == PLANAR:
        _cos_sin1(W, Q + k if jt == REV else Q + k + 2, T)
        kx, ky, kz = BF[b + AX], BF[b + AX + 1], BF[b + AX + 2]
        c = _ld(W, T)
        s = _ld(W, T + 1)
        t = 1.0 - c
        r00, r01, r02 = c + t * kx * kx, t * kx * ky - s * kz, t * kx * kz + s * ky
        r10, r11, r12 = t * kx * ky + s * kz, c + t * ky * ky, t * ky * kz - s * kx
        r20, r21, r22 = t * kx * kz - s * ky, t * ky * kz + s * kx, c + t * kz * kz
        if jt == PLANAR:
            x, y = _ld(W, Q + k), _ld(W, Q + k + 1)
            p0 = x * BF[b + PB] + y * BF[b + PB + 1]
            p1 = x * BF[b + PB + 3] + y * BF[b + PB + 4]
            p2 = x * BF[b + PB + 6] + y * BF[b + PB + 7]
    elif jt == PRIS:
        one = _v(1.0)
        zero = _v(0.0)
        r00, r01, r02 = one, zero, zero
        r10, r11, r12 = zero, one, zero
        r20, r21, r22 = zero, zero, one
        d = _ld(W, Q + k)
        p0, p1, p2 = d * BF[b + AX], d * BF[b + AX + 1], d * BF[b + AX + 2]
    else:
        o = k
        if jt == FF:
            p0, p1, p2 = _ld(W, Q + k), _ld(W, Q + k + 1), _ld(W, Q + k + 2)
            o = k + 3
        x, y, z, w = _ld(W, Q + o), _ld(W, Q + o + 1), _ld(W, Q + o + 2), _ld(W, Q + o + 3)
        two = 2.0 / (x * x + y * y + z * z + w * w)
        r00, r01, r02 = 1.0 - two * (y * y + z * z), two * (x * y - w * z), two * (x * z + w * y)
        r10, r11, r12 = two * (x * y + w * z), 1.0 - two * (x * x + z * z), two * (y * z - w * x)
        r20, r21, r22 = two * (x * z - w * y), two * (y * z + w * x), 1.0 - two * (x * x + y * y)
    for r in range(3):
        a0, a1, a2 = BF[b + XR + 3 * r], BF[b + XR + 3 * r + 1], BF[b + XR + 3 * r + 2]
        _st(W, X + 3 * r, a0 * r00 + a1 * r10 + a2 * r20)
        _st(W, X + 3 * r + 1, a0 * r01 + a1 * r11 + a2 * r21)
        _st(W, X + 3 * r + 2, a0 * r02 + a1 * r12 + a2 * r22)
        _st(W, X + 9 + r, BF[b + XP + r] + a0 * p0 + a1 * p1 + a2 * p2)


@njit(**_IJIT)
def _S_col(BI, BF, i, c, W, out):  # pragma: no cover - compiled
    """Rows ``out:out+6`` = ``S_i[:, c]`` in every lane."""
    jt = BI[NBI * i + JT]
    b = NBF * i
    for r in range(6):
        _st(W, out + r, 0.0)
    if jt <= REV_Z:
        _st(W, out, BF[b + AX])
        _st(W, out + 1, BF[b + AX + 1])
        _st(W, out + 2, BF[b + AX + 2])
    elif jt == PRIS:
        _st(W, out + 3, BF[b + AX])
        _st(W, out + 4, BF[b + AX + 1])
        _st(W, out + 5, BF[b + AX + 2])
    elif jt == SPH or jt == FF:
        _st(W, out + c, 1.0)
    elif c == 0:
        _st(W, out, BF[b + AX])
        _st(W, out + 1, BF[b + AX + 1])
        _st(W, out + 2, BF[b + AX + 2])
    else:
        e = c - 1
        _st(W, out + 3, BF[b + PB + e])
        _st(W, out + 4, BF[b + PB + 3 + e])
        _st(W, out + 5, BF[b + PB + 6 + e])


@njit(**_IJIT)
def _S_times(BI, BF, i, x, W, out):  # pragma: no cover - compiled
    """Rows ``out:out+6`` = ``S_i x_i``, the `(nv,)` vector ``x`` in rows ``x + k``."""
    jt = BI[NBI * i + JT]
    k = x + BI[NBI * i + IV]
    b = NBF * i
    if jt <= REV_Z:
        s = _ld(W, k)
        _st(W, out, s * BF[b + AX])
        _st(W, out + 1, s * BF[b + AX + 1])
        _st(W, out + 2, s * BF[b + AX + 2])
        _st(W, out + 3, 0.0)
        _st(W, out + 4, 0.0)
        _st(W, out + 5, 0.0)
    elif jt == PRIS:
        s = _ld(W, k)
        _st(W, out, 0.0)
        _st(W, out + 1, 0.0)
        _st(W, out + 2, 0.0)
        _st(W, out + 3, s * BF[b + AX])
        _st(W, out + 4, s * BF[b + AX + 1])
        _st(W, out + 5, s * BF[b + AX + 2])
    elif jt == SPH:
        _st(W, out, _ld(W, k))
        _st(W, out + 1, _ld(W, k + 1))
        _st(W, out + 2, _ld(W, k + 2))
        _st(W, out + 3, 0.0)
        _st(W, out + 4, 0.0)
        _st(W, out + 5, 0.0)
    elif jt == FF:
        for r in range(6):
            _st(W, out + r, _ld(W, k + r))
    else:
        w, vx, vy = _ld(W, k), _ld(W, k + 1), _ld(W, k + 2)
        _st(W, out, w * BF[b + AX])
        _st(W, out + 1, w * BF[b + AX + 1])
        _st(W, out + 2, w * BF[b + AX + 2])
        for r in range(3):
            _st(W, out + 3 + r, vx * BF[b + PB + 3 * r] + vy * BF[b + PB + 3 * r + 1])


@njit(**_IJIT)
def _St_dot(BI, BF, i, c, W, f):  # pragma: no cover - compiled
    """``S_i[:, c] · W[f:f+6]`` per lane."""
    jt = BI[NBI * i + JT]
    b = NBF * i
    if jt <= REV_Z:
        return BF[b + AX] * _ld(W, f) + BF[b + AX + 1] * _ld(W, f + 1) + BF[b + AX + 2] * _ld(W, f + 2)
    if jt == PRIS:
        return BF[b + AX] * _ld(W, f + 3) + BF[b + AX + 1] * _ld(W, f + 4) + BF[b + AX + 2] * _ld(W, f + 5)
    if jt == SPH or jt == FF:
        return _ld(W, f + c)
    if c == 0:
        return BF[b + AX] * _ld(W, f) + BF[b + AX + 1] * _ld(W, f + 1) + BF[b + AX + 2] * _ld(W, f + 2)
    e = c - 1
    return BF[b + PB + e] * _ld(W, f + 3) + BF[b + PB + 3 + e] * _ld(W, f + 4) + BF[b + PB + 6 + e] * _ld(W, f + 5)


@njit(**_IJIT)
def _motion_to_child(W, X, m, out):  # pragma: no cover - compiled
    """``W[out] = X_up W[m] = [Rᵀ ω; Rᵀ (v − p × ω)]``; ``out`` may be ``m``."""
    w0, w1, w2 = _ld(W, m), _ld(W, m + 1), _ld(W, m + 2)
    p0, p1, p2 = _ld(W, X + 9), _ld(W, X + 10), _ld(W, X + 11)
    t0 = _ld(W, m + 3) - (p1 * w2 - p2 * w1)
    t1 = _ld(W, m + 4) - (p2 * w0 - p0 * w2)
    t2 = _ld(W, m + 5) - (p0 * w1 - p1 * w0)
    for c in range(3):
        x0, x3, x6 = _ld(W, X + c), _ld(W, X + 3 + c), _ld(W, X + 6 + c)
        _st(W, out + c, x0 * w0 + x3 * w1 + x6 * w2)
        _st(W, out + 3 + c, x0 * t0 + x3 * t1 + x6 * t2)


@njit(**_IJIT)
def _motion_to_parent(W, X, m, out):  # pragma: no cover - compiled
    """``W[out] = X_up⁻¹ W[m] = [R ω; R v + p × R ω]``; ``out`` may be ``m``."""
    w0, w1, w2 = _ld(W, m), _ld(W, m + 1), _ld(W, m + 2)
    v0, v1, v2 = _ld(W, m + 3), _ld(W, m + 4), _ld(W, m + 5)
    R0, R1, R2, R3, R4, R5, R6, R7, R8 = _ld(W, X), _ld(W, X + 1), _ld(W, X + 2), _ld(W, X + 3), _ld(W, X + 4), \
        _ld(W, X + 5), _ld(W, X + 6), _ld(W, X + 7), _ld(W, X + 8)
    a0 = R0 * w0 + R1 * w1 + R2 * w2
    a1 = R3 * w0 + R4 * w1 + R5 * w2
    a2 = R6 * w0 + R7 * w1 + R8 * w2
    p0, p1, p2 = _ld(W, X + 9), _ld(W, X + 10), _ld(W, X + 11)
    _st(W, out, a0)
    _st(W, out + 1, a1)
    _st(W, out + 2, a2)
    _st(W, out + 3, R0 * v0 + R1 * v1 + R2 * v2 + p1 * a2 - p2 * a1)
    _st(W, out + 4, R3 * v0 + R4 * v1 + R5 * v2 + p2 * a0 - p0 * a2)
    _st(W, out + 5, R6 * v0 + R7 * v1 + R8 * v2 + p0 * a1 - p1 * a0)


@njit(**_IJIT)
def _force_to_parent(W, X, f, out, accumulate):  # pragma: no cover - compiled
    """``W[out] (+)= X_upᵀ W[f] = [R n + p × R f; R f]``."""
    n0, n1, n2 = _ld(W, f), _ld(W, f + 1), _ld(W, f + 2)
    f0, f1, f2 = _ld(W, f + 3), _ld(W, f + 4), _ld(W, f + 5)
    R0, R1, R2, R3, R4, R5, R6, R7, R8 = _ld(W, X), _ld(W, X + 1), _ld(W, X + 2), _ld(W, X + 3), _ld(W, X + 4), \
        _ld(W, X + 5), _ld(W, X + 6), _ld(W, X + 7), _ld(W, X + 8)
    g0 = R0 * f0 + R1 * f1 + R2 * f2
    g1 = R3 * f0 + R4 * f1 + R5 * f2
    g2 = R6 * f0 + R7 * f1 + R8 * f2
    p0, p1, p2 = _ld(W, X + 9), _ld(W, X + 10), _ld(W, X + 11)
    m0 = R0 * n0 + R1 * n1 + R2 * n2 + p1 * g2 - p2 * g1
    m1 = R3 * n0 + R4 * n1 + R5 * n2 + p2 * g0 - p0 * g2
    m2 = R6 * n0 + R7 * n1 + R8 * n2 + p0 * g1 - p1 * g0
    if accumulate:
        _st(W, out, _ld(W, out) + m0)
        _st(W, out + 1, _ld(W, out + 1) + m1)
        _st(W, out + 2, _ld(W, out + 2) + m2)
        _st(W, out + 3, _ld(W, out + 3) + g0)
        _st(W, out + 4, _ld(W, out + 4) + g1)
        _st(W, out + 5, _ld(W, out + 5) + g2)
    else:
        _st(W, out, m0)
        _st(W, out + 1, m1)
        _st(W, out + 2, m2)
        _st(W, out + 3, g0)
        _st(W, out + 4, g1)
        _st(W, out + 5, g2)


@njit(**_IJIT)
def _force_to_child(W, X, f, out):  # pragma: no cover - compiled
    """``W[out] = X_up⁻ᵀ W[f] = [Rᵀ (n − p × f); Rᵀ f]``; ``out`` may be ``f``."""
    n0, n1, n2 = _ld(W, f), _ld(W, f + 1), _ld(W, f + 2)
    f0, f1, f2 = _ld(W, f + 3), _ld(W, f + 4), _ld(W, f + 5)
    p0, p1, p2 = _ld(W, X + 9), _ld(W, X + 10), _ld(W, X + 11)
    t0 = n0 - (p1 * f2 - p2 * f1)
    t1 = n1 - (p2 * f0 - p0 * f2)
    t2 = n2 - (p0 * f1 - p1 * f0)
    for c in range(3):
        x0, x3, x6 = _ld(W, X + c), _ld(W, X + 3 + c), _ld(W, X + 6 + c)
        _st(W, out + c, x0 * t0 + x3 * t1 + x6 * t2)
        _st(W, out + 3 + c, x0 * f0 + x3 * f1 + x6 * f2)


@njit(**_IJIT)
def _cross_motion_add(W, v, m, out):  # pragma: no cover - compiled
    """``W[out] += W[v] × W[m]``."""
    w0, w1, w2, u0, u1, u2 = _ld(W, v), _ld(W, v + 1), _ld(W, v + 2), _ld(W, v + 3), _ld(W, v + 4), _ld(W, v + 5)
    a0, a1, a2, b0, b1, b2 = _ld(W, m), _ld(W, m + 1), _ld(W, m + 2), _ld(W, m + 3), _ld(W, m + 4), _ld(W, m + 5)
    _st(W, out, _ld(W, out) + (w1 * a2 - w2 * a1))
    _st(W, out + 1, _ld(W, out + 1) + (w2 * a0 - w0 * a2))
    _st(W, out + 2, _ld(W, out + 2) + (w0 * a1 - w1 * a0))
    _st(W, out + 3, _ld(W, out + 3) + (w1 * b2 - w2 * b1 + u1 * a2 - u2 * a1))
    _st(W, out + 4, _ld(W, out + 4) + (w2 * b0 - w0 * b2 + u2 * a0 - u0 * a2))
    _st(W, out + 5, _ld(W, out + 5) + (w0 * b1 - w1 * b0 + u0 * a1 - u1 * a0))


@njit(**_IJIT)
def _cross_force_add(W, v, f, out):  # pragma: no cover - compiled
    """``W[out] += W[v] ×* W[f]``."""
    w0, w1, w2, u0, u1, u2 = _ld(W, v), _ld(W, v + 1), _ld(W, v + 2), _ld(W, v + 3), _ld(W, v + 4), _ld(W, v + 5)
    n0, n1, n2, f0, f1, f2 = _ld(W, f), _ld(W, f + 1), _ld(W, f + 2), _ld(W, f + 3), _ld(W, f + 4), _ld(W, f + 5)
    _st(W, out, _ld(W, out) + (w1 * n2 - w2 * n1 + u1 * f2 - u2 * f1))
    _st(W, out + 1, _ld(W, out + 1) + (w2 * n0 - w0 * n2 + u2 * f0 - u0 * f2))
    _st(W, out + 2, _ld(W, out + 2) + (w0 * n1 - w1 * n0 + u0 * f1 - u1 * f0))
    _st(W, out + 3, _ld(W, out + 3) + (w1 * f2 - w2 * f1))
    _st(W, out + 4, _ld(W, out + 4) + (w2 * f0 - w0 * f2))
    _st(W, out + 5, _ld(W, out + 5) + (w0 * f1 - w1 * f0))


@njit(**_IJIT)
def _inertia_apply(mass, h0, h1, h2, xx, xy, xz, yy, yz, zz, W, m, out):  # pragma: no cover - compiled
    """``W[out] = I W[m] = [Ī ω + h × v; m v − h × ω]`` (parameters: numbers or vectors)."""
    w0, w1, w2, v0, v1, v2 = _ld(W, m), _ld(W, m + 1), _ld(W, m + 2), _ld(W, m + 3), _ld(W, m + 4), _ld(W, m + 5)
    _st(W, out, xx * w0 + xy * w1 + xz * w2 + h1 * v2 - h2 * v1)
    _st(W, out + 1, xy * w0 + yy * w1 + yz * w2 + h2 * v0 - h0 * v2)
    _st(W, out + 2, xz * w0 + yz * w1 + zz * w2 + h0 * v1 - h1 * v0)
    _st(W, out + 3, mass * v0 - (h1 * w2 - h2 * w1))
    _st(W, out + 4, mass * v1 - (h2 * w0 - h0 * w2))
    _st(W, out + 5, mass * v2 - (h0 * w1 - h1 * w0))


@njit(**_IJIT)
def _inertia_times_model(BF, I, W, m, out):  # pragma: no cover - compiled
    """``W[out] = I W[m]`` with the model's parameters ``BF[I:I+10]`` (the same in every lane)."""
    _inertia_apply(BF[I], BF[I + 1], BF[I + 2], BF[I + 3], BF[I + 4], BF[I + 5], BF[I + 6], BF[I + 7], BF[I + 8],
                   BF[I + 9], W, m, out)


@njit(**_IJIT)
def _inertia_times_rows(W, I, m, out):  # pragma: no cover - compiled
    """``W[out] = I W[m]`` with the parameters in rows ``I:I+10``."""
    _inertia_apply(_ld(W, I), _ld(W, I + 1), _ld(W, I + 2), _ld(W, I + 3), _ld(W, I + 4), _ld(W, I + 5),
                   _ld(W, I + 6), _ld(W, I + 7), _ld(W, I + 8), _ld(W, I + 9), W, m, out)


@njit(**_IJIT)
def _inertia_to_parent_apply(mass, h0, h1, h2, xx, xy, xz, yy, yz, zz, W, X, out):  # pragma: no cover - compiled
    """``W[out] = X_upᵀ I X_up`` on 10 parameters (see :func:`._kernels._inertia_to_parent`)."""
    p0, p1, p2 = _ld(W, X + 9), _ld(W, X + 10), _ld(W, X + 11)
    R0, R1, R2, R3, R4, R5, R6, R7, R8 = _ld(W, X), _ld(W, X + 1), _ld(W, X + 2), _ld(W, X + 3), _ld(W, X + 4), \
        _ld(W, X + 5), _ld(W, X + 6), _ld(W, X + 7), _ld(W, X + 8)
    y0 = R0 * h0 + R1 * h1 + R2 * h2
    y1 = R3 * h0 + R4 * h1 + R5 * h2
    y2 = R6 * h0 + R7 * h1 + R8 * h2
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
    _st(W, out, mass)
    _st(W, out + 1, y0 + mass * p0)
    _st(W, out + 2, y1 + mass * p1)
    _st(W, out + 3, y2 + mass * p2)
    _st(W, out + 4, t00 * R0 + t01 * R1 + t02 * R2 - 2.0 * p0 * y0 - mass * p0 * p0 + d)
    _st(W, out + 5, t00 * R3 + t01 * R4 + t02 * R5 - p0 * y1 - y0 * p1 - mass * p0 * p1)
    _st(W, out + 6, t00 * R6 + t01 * R7 + t02 * R8 - p0 * y2 - y0 * p2 - mass * p0 * p2)
    _st(W, out + 7, t10 * R3 + t11 * R4 + t12 * R5 - 2.0 * p1 * y1 - mass * p1 * p1 + d)
    _st(W, out + 8, t10 * R6 + t11 * R7 + t12 * R8 - p1 * y2 - y1 * p2 - mass * p1 * p2)
    _st(W, out + 9, t20 * R6 + t21 * R7 + t22 * R8 - 2.0 * p2 * y2 - mass * p2 * p2 + d)


@njit(**_IJIT)
def _inertia_matrix_apply(mass, h0, h1, h2, xx, xy, xz, yy, yz, zz, W, o):  # pragma: no cover - compiled
    """Rows ``o:o+36`` = ``[[Ī, [h]×], [[h]×ᵀ, m 1]]`` (parameters: numbers or vectors)."""
    _st(W, o, xx)
    _st(W, o + 1, xy)
    _st(W, o + 2, xz)
    _st(W, o + 3, 0.0)
    _st(W, o + 4, -h2)
    _st(W, o + 5, h1)
    _st(W, o + 6, xy)
    _st(W, o + 7, yy)
    _st(W, o + 8, yz)
    _st(W, o + 9, h2)
    _st(W, o + 10, 0.0)
    _st(W, o + 11, -h0)
    _st(W, o + 12, xz)
    _st(W, o + 13, yz)
    _st(W, o + 14, zz)
    _st(W, o + 15, -h1)
    _st(W, o + 16, h0)
    _st(W, o + 17, 0.0)
    _st(W, o + 18, 0.0)
    _st(W, o + 19, h2)
    _st(W, o + 20, -h1)
    _st(W, o + 21, mass)
    _st(W, o + 22, 0.0)
    _st(W, o + 23, 0.0)
    _st(W, o + 24, -h2)
    _st(W, o + 25, 0.0)
    _st(W, o + 26, h0)
    _st(W, o + 27, 0.0)
    _st(W, o + 28, mass)
    _st(W, o + 29, 0.0)
    _st(W, o + 30, h1)
    _st(W, o + 31, -h0)
    _st(W, o + 32, 0.0)
    _st(W, o + 33, 0.0)
    _st(W, o + 34, 0.0)
    _st(W, o + 35, mass)


@njit(**_IJIT)
def _inertia_to_parent_model(BF, I, W, X, out):  # pragma: no cover - compiled
    """``W[out] = X_upᵀ I X_up`` with the model's parameters ``BF[I:I+10]``."""
    _inertia_to_parent_apply(BF[I], BF[I + 1], BF[I + 2], BF[I + 3], BF[I + 4], BF[I + 5], BF[I + 6], BF[I + 7],
                             BF[I + 8], BF[I + 9], W, X, out)


@njit(**_IJIT)
def _inertia_to_parent_rows(W, I, X, out):  # pragma: no cover - compiled
    """``W[out] = X_upᵀ I X_up`` with the parameters in rows ``I:I+10``."""
    _inertia_to_parent_apply(_ld(W, I), _ld(W, I + 1), _ld(W, I + 2), _ld(W, I + 3), _ld(W, I + 4), _ld(W, I + 5),
                             _ld(W, I + 6), _ld(W, I + 7), _ld(W, I + 8), _ld(W, I + 9), W, X, out)


@njit(**_IJIT)
def _inertia_matrix_model(BF, I, W, out):  # pragma: no cover - compiled
    """Rows ``out:out+36`` = the 6×6 inertia matrix of the model's parameters ``BF[I:I+10]``."""
    _inertia_matrix_apply(BF[I], BF[I + 1], BF[I + 2], BF[I + 3], BF[I + 4], BF[I + 5], BF[I + 6], BF[I + 7],
                          BF[I + 8], BF[I + 9], W, out)


@njit(**_IJIT)
def _inertia_matrix_rows(W, I, out):  # pragma: no cover - compiled
    """Rows ``out:out+36`` = the 6×6 inertia matrix of the parameters in rows ``I:I+10``."""
    _inertia_matrix_apply(_ld(W, I), _ld(W, I + 1), _ld(W, I + 2), _ld(W, I + 3), _ld(W, I + 4), _ld(W, I + 5),
                          _ld(W, I + 6), _ld(W, I + 7), _ld(W, I + 8), _ld(W, I + 9), W, out)


@njit(**_IJIT)
def _matrix6_to_parent_add(W, X, Ia, out, T):  # pragma: no cover - compiled
    """``W[out] += X_upᵀ W[Ia] X_up`` for a symmetric 6×6 ``Ia`` (scratch rows ``T:T+27``)."""
    for blk in range(3):
        top = Ia + (18 if blk == 2 else 0) + (0 if blk == 0 else 3)
        for r in range(3):
            x0, x1, x2 = _ld(W, X + 3 * r), _ld(W, X + 3 * r + 1), _ld(W, X + 3 * r + 2)
            m0 = x0 * _ld(W, top) + x1 * _ld(W, top + 6) + x2 * _ld(W, top + 12)
            m1 = x0 * _ld(W, top + 1) + x1 * _ld(W, top + 7) + x2 * _ld(W, top + 13)
            m2 = x0 * _ld(W, top + 2) + x1 * _ld(W, top + 8) + x2 * _ld(W, top + 14)
            for s in range(3):
                _st(W, T + 9 * blk + 3 * r + s,
                    m0 * _ld(W, X + 3 * s) + m1 * _ld(W, X + 3 * s + 1) + m2 * _ld(W, X + 3 * s + 2))
    p0, p1, p2 = _ld(W, X + 9), _ld(W, X + 10), _ld(W, X + 11)
    for r in range(3):
        for s in range(3):
            o = out + 21 + 6 * r + s
            _st(W, o, _ld(W, o) + _ld(W, T + 18 + 3 * r + s))
    for s in range(3):
        c0, c1, c2 = _ld(W, T + 18 + s), _ld(W, T + 21 + s), _ld(W, T + 24 + s)
        b0 = _ld(W, T + 9 + s) + p1 * c2 - p2 * c1
        b1 = _ld(W, T + 12 + s) + p2 * c0 - p0 * c2
        b2 = _ld(W, T + 15 + s) + p0 * c1 - p1 * c0
        _st(W, out + 3 + s, _ld(W, out + 3 + s) + b0)
        _st(W, out + 9 + s, _ld(W, out + 9 + s) + b1)
        _st(W, out + 15 + s, _ld(W, out + 15 + s) + b2)
        _st(W, out + 18 + 6 * s, _ld(W, out + 18 + 6 * s) + b0)
        _st(W, out + 19 + 6 * s, _ld(W, out + 19 + 6 * s) + b1)
        _st(W, out + 20 + 6 * s, _ld(W, out + 20 + 6 * s) + b2)
    for r in range(3):
        c = T + 18 + 3 * r
        c0, c1, c2 = _ld(W, c), _ld(W, c + 1), _ld(W, c + 2)
        _st(W, c, c1 * p2 - c2 * p1)
        _st(W, c + 1, c2 * p0 - c0 * p2)
        _st(W, c + 2, c0 * p1 - c1 * p0)
        q = T + 9 + 3 * r
        b0, b1, b2 = _ld(W, q), _ld(W, q + 1), _ld(W, q + 2)
        _st(W, q, b1 * p2 - b2 * p1)
        _st(W, q + 1, b2 * p0 - b0 * p2)
        _st(W, q + 2, b0 * p1 - b1 * p0)
    for s in range(3):
        c0, c1, c2 = _ld(W, T + 18 + s), _ld(W, T + 21 + s), _ld(W, T + 24 + s)
        _st(W, out + s, _ld(W, out + s)
            + (_ld(W, T + s) - _ld(W, T + 9 + s) - _ld(W, T + 9 + 3 * s) - (p1 * c2 - p2 * c1)))
        _st(W, out + 6 + s, _ld(W, out + 6 + s)
            + (_ld(W, T + 3 + s) - _ld(W, T + 12 + s) - _ld(W, T + 10 + 3 * s) - (p2 * c0 - p0 * c2)))
        _st(W, out + 12 + s, _ld(W, out + 12 + s)
            + (_ld(W, T + 6 + s) - _ld(W, T + 15 + s) - _ld(W, T + 11 + 3 * s) - (p0 * c1 - p1 * c0)))


# ---------------------------------------------------------------------------
# inputs and outputs of a block
# ---------------------------------------------------------------------------


@njit(**_IJIT)
def _gather(X, s0, count, W, o):  # pragma: no cover - compiled
    """Rows ``o + k`` = column ``k`` of the block's input rows ``X[s0 : s0 + count]`` (or of ``X[0]`` when it
    is broadcast); lanes past ``count`` repeat the last state."""
    n = X.shape[1]
    for s in range(LANES):
        r = 0 if X.shape[0] == 1 else s0 + (s if s < count else count - 1)
        for k in range(n):
            W[(o + k) * LANES + s] = X[r, k]


@njit(**_IJIT)
def _scatter(W, o, Y, s0, count):  # pragma: no cover - compiled
    """``Y[s0 + s, k]`` = lane ``s`` of row ``o + k``, for the block's ``count`` states."""
    n = Y.shape[1]
    for s in range(count):
        for k in range(n):
            Y[s0 + s, k] = W[(o + k) * LANES + s]


@njit(cache=True, nogil=True)
def _aligned_empty(n):  # pragma: no cover - compiled
    """``np.empty(n)`` starting on a 64-byte boundary: rows of the workspace then never straddle two cache lines."""
    buf = np.empty(n + 8)
    o = (8 - _line_offset(buf, 0)) & 7
    return buf[o : o + n]


def lane_rows(width: int, nb: int, nq: int, nv: int, extra: int = 0) -> int:
    """Rows (of ``LANES`` doubles) of a block's workspace: the scalar core's entries as rows, then the inputs,
    external forces, outputs, four rows of scratch and ``extra`` rows."""
    return width * nb + WS_TAIL + nq + 3 * nv + 6 * nb + 4 + extra


@njit(**_IJIT)
def _rows(width, nb, nq, nv, extra):  # pragma: no cover - compiled
    """:func:`lane_rows` in compiled code, and the offsets ``(in1, in2, in3, fext, out, scratch, extra)`` of the
    rows."""
    o = width * nb + WS_TAIL
    e = o + nq + 3 * nv + 6 * nb + 4
    return e + extra, o, o + nq, o + nq + nv, o + nq + 2 * nv, o + nq + 2 * nv + 6 * nb, e - 4, e
