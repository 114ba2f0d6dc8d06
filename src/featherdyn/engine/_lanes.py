"""Batched kernels that run ``LANES`` states at once in SIMD lanes (private).

The scalar cores of :mod:`._kernels` run one state at a time; these kernels run
a *block* of ``LANES`` states through the same recursions with every per-body
quantity held for all lanes side by side: the workspace is the scalar cores'
layout with each entry widened to a *row* of ``LANES`` doubles (entry ``o`` of
lane ``s`` at ``W[o * LANES + s]``), and every formula is written once on
values of type ``f64xL`` — an LLVM ``<LANES x double>`` vector — so that each
arithmetic operation is one SIMD instruction over the block.

Why an explicit vector type: Numba leaves LLVM's SLP vectoriser off, and a loop
``for s in range(LANES)`` over ``W[o * LANES + s]`` is not vectorised by the
loop vectoriser either (the signed indices wrap around, and the rows it reads
and writes could alias as far as LLVM can tell). The type here has only
element-wise ``+ - * /``, negation and square root — IEEE operations, correctly
rounded in every lane exactly as their scalar forms — and no fast-math flag, so
LLVM neither reassociates nor contracts them into FMAs. Every helper below
repeats its scalar twin in :mod:`._kernels` operation by operation, in the
same order (a scalar model parameter is broadcast, ``x * s`` equals ``s * x``
bit for bit), so each lane is bit-identical to the scalar core on its state.

Everything that is the same for all states (the tree, joint codes, model
parameters) stays scalar, so branches on the joint type are taken once per
block. ``sin``/``cos`` have no vector form without SVML: they run in a scalar
loop over the lanes into two scratch rows.

A block reads its states' inputs into rows of the workspace (a broadcast input
of length 1 fills every lane), and writes its lanes back into the output rows.
The last block of a batch whose length is not a multiple of ``LANES`` is padded
with copies of the batch's last state, whose results are computed and dropped.
ABA flags, lane by lane, the first joint whose pivot is singular (where the
scalar core returns) and computes on; the block reports its first flagged state.

CRBA's output is the bulk of its memory traffic (`nv²` entries a state): the
entries are stored as lane rows (one vector store each, into rows zeroed once
per thread — the tree fixes which entries are written), transposed by
``LANES × LANES`` shuffles into a state-major scratch, and copied out, with
non-temporal stores for large batches. (Scattering each vector's lanes straight
into the output took eight extracts and stores per entry: slower, and 30 %
slower still when loaded from Numba's disk cache than freshly compiled.)

``LANES = 8`` (one AVX-512 register; two AVX2 registers where there is no
AVX-512): measured against 4 and 16 on panda, solo12 and talos, 8 was fastest
or within noise for all three algorithms.
"""


from __future__ import annotations

import numpy as np
from numba import njit, prange

from ._flat_spatial import _IJIT, _JIT, _PJIT
from ._kernels import _chunks
from ._lane_helpers import (
    _aligned_empty,
    _compose,
    _cross_force_add,
    _cross_motion_add,
    _force_to_child,
    _force_to_parent,
    _gather,
    _inertia_matrix_model,
    _inertia_matrix_rows,
    _inertia_times_model,
    _inertia_times_rows,
    _inertia_to_parent_model,
    _inertia_to_parent_rows,
    _matrix6_to_parent_add,
    _motion_to_child,
    _motion_to_parent,
    _pose_in_parent,
    _rows,
    _S_col,
    _S_times,
    _scatter,
    _St_dot,
    lane_rows,
)
from ._lane_vector import (
    LANES,
    STREAM_MIN,
    _fence,
    _lane,
    _ld,
    _ldv,
    _line_offset,
    _sqrt,
    _st,
    _stream_line,
    _sts,
    _stv,
    _transpose_rows,
    _v,
)
from ._layout import (
    AX,
    FF,
    IV,
    JT,
    MASS,
    NBF,
    NBI,
    NV,
    PARENT,
    SINGULAR_RTOL,
    UNIT,
    WS_ABA,
    WS_CRBA,
    WS_RNEA,
)

__all__ = ["LANES", "lane_rows", "rnea_lanes", "crba_lanes", "aba_lanes"]

# ---------------------------------------------------------------------------
# RNEA
# ---------------------------------------------------------------------------


@njit(**_JIT)
def rnea_block(BI, BF, G, Q, QD, QDD, FEXT, gravity, TAU, s0, count, W):  # pragma: no cover - compiled
    """:func:`._kernels.rnea_core` on the states ``s0 … s0 + count − 1`` (``count ≤ LANES``) in lanes."""
    nb = BI.shape[0] // NBI
    nq = Q.shape[1]
    nv = TAU.shape[1]
    _n, q, qd, qdd, fx, tau, sc, _e = _rows(WS_RNEA, nb, nq, nv, 0)
    _gather(Q, s0, count, W, q)
    _gather(QD, s0, count, W, qd)
    _gather(QDD, s0, count, W, qdd)
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
    _st(W, a0, 0.0)
    _st(W, a0 + 1, 0.0)
    _st(W, a0 + 2, 0.0)
    _st(W, a0 + 3, -g * G[0])
    _st(W, a0 + 4, -g * G[1])
    _st(W, a0 + 5, -g * G[2])
    has_fext = FEXT.shape[1] > 0
    if has_fext:  # (N or 1, nb, 6) → rows fx + 6 i + k
        _gather(FEXT.reshape((FEXT.shape[0], 6 * nb)), s0, count, W, fx)
    for i in range(nb):
        lam = BI[NBI * i + PARENT]
        Xi = X_up + 12 * i
        vi = v + 6 * i
        ai = a + 6 * i
        fi = f + 6 * i
        _pose_in_parent(BI, BF, i, q, W, Xi, sc)
        _S_times(BI, BF, i, qd, W, vJ)
        _S_times(BI, BF, i, qdd, W, aJ)
        if lam == -1:
            for k in range(6):
                _st(W, vi + k, _ld(W, vJ + k))
            _motion_to_child(W, Xi, a0, ai)
        else:
            _motion_to_child(W, Xi, v + 6 * lam, vi)
            for k in range(6):
                _st(W, vi + k, _ld(W, vi + k) + _ld(W, vJ + k))
            _motion_to_child(W, Xi, a + 6 * lam, ai)
        for k in range(6):
            _st(W, ai + k, _ld(W, ai + k) + _ld(W, aJ + k))
        _cross_motion_add(W, vi, vJ, ai)
        I = NBF * i + MASS
        _inertia_times_model(BF, I, W, ai, fi)
        _inertia_times_model(BF, I, W, vi, Iv)
        _cross_force_add(W, vi, Iv, fi)
        if has_fext:
            for k in range(6):
                _st(W, fi + k, _ld(W, fi + k) - _ld(W, fx + 6 * i + k))
    for i in range(nb - 1, -1, -1):
        lam = BI[NBI * i + PARENT]
        iv = BI[NBI * i + IV]
        fi = f + 6 * i
        for c in range(BI[NBI * i + NV]):
            _st(W, tau + iv + c, _St_dot(BI, BF, i, c, W, fi))
        if lam != -1:
            _force_to_parent(W, X_up + 12 * i, fi, f + 6 * lam, True)
    _scatter(W, tau, TAU, s0, count)


@njit(**_PJIT)
def rnea_lanes(BI, BF, G, Q, QD, QDD, FEXT, gravity, TAU, threads):  # pragma: no cover - compiled
    """:func:`._kernels.rnea_core` over the rows of `(N or 1, ·)` inputs (``FEXT`` `(N or 1, nb, 6)` or
    `(1, 0, 6)`), into ``TAU`` `(N, nv)`, in blocks of ``LANES`` states, one chunk of blocks per thread."""
    n = TAU.shape[0]
    nb = BI.shape[0] // NBI
    rows = _rows(WS_RNEA, nb, Q.shape[1], TAU.shape[1], 0)[0]
    nblk = (n + LANES - 1) // LANES
    nt, chunk = _chunks(nblk, threads)
    for t in prange(nt):
        W = _aligned_empty(rows * LANES)
        for blk in range(t * chunk, min(nblk, (t + 1) * chunk)):
            s0 = blk * LANES
            rnea_block(BI, BF, G, Q, QD, QDD, FEXT, gravity, TAU, s0, min(LANES, n - s0), W)


# ---------------------------------------------------------------------------
# CRBA
# ---------------------------------------------------------------------------


@njit(**_IJIT)
def _copy_out(S, n, A, o, stream):  # pragma: no cover - compiled
    """``A[o : o + n] = S[0 : n]``; with ``stream``, whole cache lines of ``A`` are written with non-temporal
    stores (no read of the line from memory before it is written, and no eviction of the cached data)."""
    k = 0
    if stream:
        while k < n and _line_offset(A, o + k) != 0:
            _sts(A, o + k, S[k])
            k += 1
        while k + 8 <= n:
            _stream_line(A, o + k, S, k)
            k += 8
    else:
        while k + LANES <= n:
            _stv(A, o + k, _ldv(S, k))
            k += LANES
    while k < n:
        _sts(A, o + k, S[k])
        k += 1


@njit(**_IJIT)
def _crba_extra(nv):  # pragma: no cover - compiled
    """Lane rows of CRBA's assembled entries: ``nv²``, padded to whole tiles of ``LANES``."""
    return (nv * nv + LANES - 1) // LANES * LANES


@njit(**_JIT)
def crba_block(BI, BF, Q, M, s0, count, W, S, stream):  # pragma: no cover - compiled
    """:func:`._kernels.crba_core` on the states ``s0 … s0 + count − 1`` (``count ≤ LANES``) in lanes.

    The entries of ``M`` are assembled in lane rows of ``W`` (entry ``(r, c)`` in row ``r nv + c`` of the
    :func:`_crba_extra` rows at the end of the workspace; the entries written are the same for every state, so
    the caller zeroes these rows once), transposed tile by tile into ``S`` (`(LANES nv² + LANES,)`,
    state-major) and copied to ``M`` (with ``stream``, by non-temporal stores).
    """
    nb = BI.shape[0] // NBI
    nq = Q.shape[1]
    nv = M.shape[1]
    nn = nv * nv
    _n, q, _i2, _i3, _fx, _out, sc, Mb = _rows(WS_CRBA, nb, nq, nv, _crba_extra(nv))
    _gather(Q, s0, count, W, q)
    oX = 0
    IC = 12 * nb
    J = 22 * nb
    t = 58 * nb
    X = t
    F = t + 12
    Fj = t + 18
    Iloc = t + 24
    Ib = t + 34
    for i in range(nb):
        lam = BI[NBI * i + PARENT]
        Xi = oX + 12 * i
        if lam == -1:
            _pose_in_parent(BI, BF, i, q, W, Xi, sc)
        else:
            _pose_in_parent(BI, BF, i, q, W, X, sc)
            _compose(W, oX + 12 * lam, X, Xi)
        _inertia_to_parent_model(BF, NBF * i + MASS, W, Xi, IC + 10 * i)
        ki = BI[NBI * i + NV]
        if ki == 1:
            _S_col(BI, BF, i, 0, W, J + 36 * i)
            _motion_to_parent(W, Xi, J + 36 * i, J + 36 * i)
        elif lam == -1 and BI[NBI * i + JT] == FF:
            pass
        else:
            for c in range(ki):
                _S_col(BI, BF, i, c, W, J + 36 * i + 6 * c)
                _motion_to_parent(W, Xi, J + 36 * i + 6 * c, J + 36 * i + 6 * c)
    for i in range(nb - 1, -1, -1):
        lam = BI[NBI * i + PARENT]
        if lam != -1:
            for k in range(10):
                _st(W, IC + 10 * lam + k, _ld(W, IC + 10 * lam + k) + _ld(W, IC + 10 * i + k))
    for i in range(nb):
        iv = BI[NBI * i + IV]
        lam = BI[NBI * i + PARENT]
        first = i
        if BI[NBI * i + JT] == FF:
            Xi = oX + 12 * i
            for r in range(3):
                for c in range(3):
                    _st(W, X + 3 * r + c, _ld(W, Xi + 3 * c + r))
            for r in range(3):
                _st(W, X + 9 + r, -(_ld(W, Xi + r) * _ld(W, Xi + 9) + _ld(W, Xi + 3 + r) * _ld(W, Xi + 10)
                                    + _ld(W, Xi + 6 + r) * _ld(W, Xi + 11)))
            _inertia_to_parent_rows(W, IC + 10 * i, X, Iloc)
            _inertia_matrix_rows(W, Iloc, Ib)
            for r in range(6):
                for c in range(6):
                    _st(W, Mb + (iv + r) * nv + iv + c, _ld(W, Ib + 6 * r + c))
            if lam == -1:
                continue
            first = lam
        for c in range(BI[NBI * i + NV]):
            _inertia_times_rows(W, IC + 10 * i, J + 36 * i + 6 * c, F)
            f0, f1, f2, f3, f4, f5 = _ld(W, F), _ld(W, F + 1), _ld(W, F + 2), _ld(W, F + 3), _ld(W, F + 4), \
                _ld(W, F + 5)
            j = first
            while j != -1:
                jv = BI[NBI * j + IV]
                kj = BI[NBI * j + NV]
                Jr = J + 36 * j
                if kj == 1:
                    val = (_ld(W, Jr) * f0 + _ld(W, Jr + 1) * f1 + _ld(W, Jr + 2) * f2
                           + _ld(W, Jr + 3) * f3 + _ld(W, Jr + 4) * f4 + _ld(W, Jr + 5) * f5)
                    _st(W, Mb + jv * nv + iv + c, val)
                    _st(W, Mb + (iv + c) * nv + jv, val)
                elif BI[NBI * j + JT] == FF:
                    _force_to_child(W, oX + 12 * j, F, Fj)
                    for r in range(6):
                        x = _ld(W, Fj + r)
                        _st(W, Mb + (jv + r) * nv + iv + c, x)
                        _st(W, Mb + (iv + c) * nv + jv + r, x)
                else:
                    for r in range(kj):
                        val = (_ld(W, Jr) * f0 + _ld(W, Jr + 1) * f1 + _ld(W, Jr + 2) * f2
                               + _ld(W, Jr + 3) * f3 + _ld(W, Jr + 4) * f4 + _ld(W, Jr + 5) * f5)
                        _st(W, Mb + (jv + r) * nv + iv + c, val)
                        _st(W, Mb + (iv + c) * nv + jv + r, val)
                        Jr += 6
                j = BI[NBI * j + PARENT]
    # tiles of LANES entries; the last one (read past nn into padding rows) first, since its lanes spill into
    # the first entries of the next state in S, which tile 0 then overwrites
    for t in range((nn + LANES - 1) // LANES - 1, -1, -1):
        _transpose_rows(W, Mb + t * LANES, S, t * LANES, nn)
    _copy_out(S, count * nn, M.reshape(M.shape[0] * nn), s0 * nn, stream)


@njit(**_PJIT)
def crba_lanes(BI, BF, Q, M, threads):  # pragma: no cover - compiled
    """:func:`._kernels.crba_core` over the rows of ``Q``, into ``M`` `(N, nv, nv)`, in blocks of ``LANES`` states."""
    n = M.shape[0]
    nb = BI.shape[0] // NBI
    nv = M.shape[1]
    rows, _q, _i2, _i3, _fx, _out, _sc, Mb = _rows(WS_CRBA, nb, Q.shape[1], nv, _crba_extra(nv))
    nblk = (n + LANES - 1) // LANES
    nn = nv * nv
    stream = n * nn >= STREAM_MIN
    nt, chunk = _chunks(nblk, threads)
    for t in prange(nt):
        W = _aligned_empty(rows * LANES)
        W[Mb * LANES : rows * LANES] = 0.0
        S = _aligned_empty(LANES * nn + LANES)
        for blk in range(t * chunk, min(nblk, (t + 1) * chunk)):
            s0 = blk * LANES
            crba_block(BI, BF, Q, M, s0, min(LANES, n - s0), W, S, stream)
        if stream:
            _fence()


# ---------------------------------------------------------------------------
# ABA
# ---------------------------------------------------------------------------


@njit(**_IJIT)
def _flag(W, d, tol, bad, i):  # pragma: no cover - compiled
    """Lanes whose pivot ``d`` is ``<= tol`` and have no singular joint yet get joint ``i`` in row ``bad``."""
    for s in range(LANES):
        if _lane(d, s) <= tol and W[bad * LANES + s] < 0.0:
            W[bad * LANES + s] = i


@njit(**_IJIT)
def _spd_inverse(W, D, k, Dinv, L, tol, bad, i):  # pragma: no cover - compiled
    """:func:`._kernels._spd_inverse` per lane: rows ``Dinv`` = rows ``D`` inverted; a lane with a pivot
    ``<= tol`` (where the scalar form returns) is flagged with joint ``i`` in row ``bad`` and computes on."""
    if k == 1:
        d = _ld(W, D)
        _st(W, Dinv, 1.0 / d)
        _flag(W, d, tol, bad, i)
        return
    for j in range(k):
        d = _ld(W, D + 7 * j)
        for m in range(j):
            d = d - _ld(W, L + 6 * j + m) * _ld(W, L + 6 * j + m)
        _flag(W, d, tol, bad, i)
        ljj = _sqrt(d)
        _st(W, L + 7 * j, ljj)
        for r in range(j + 1, k):
            x = _ld(W, D + 6 * r + j)
            for m in range(j):
                x = x - _ld(W, L + 6 * r + m) * _ld(W, L + 6 * j + m)
            _st(W, L + 6 * r + j, x / ljj)
    for j in range(k):
        _st(W, L + 7 * j, 1.0 / _ld(W, L + 7 * j))
        for r in range(j + 1, k):
            x = _v(0.0)
            for m in range(j, r):
                x = x - _ld(W, L + 6 * r + m) * _ld(W, L + 6 * m + j)
            _st(W, L + 6 * r + j, x / _ld(W, L + 7 * r))
    for r in range(k):
        for c in range(r, k):
            x = _v(0.0)
            for m in range(c, k):
                x = x + _ld(W, L + 6 * m + r) * _ld(W, L + 6 * m + c)
            _st(W, Dinv + 6 * r + c, x)
            _st(W, Dinv + 6 * c + r, x)


@njit(**_JIT)
def aba_block(BI, BF, G, Q, QD, TAU, FEXT, gravity, QDD, s0, count, W):  # pragma: no cover - compiled
    """:func:`._kernels.aba_core` on the states ``s0 … s0 + count − 1`` (``count ≤ LANES``) in lanes.

    Returns ``-1``, or ``state · nb + joint`` for the first of these states that is singular, with the joint
    :func:`._kernels.aba_core` reports for it.
    """
    nb = BI.shape[0] // NBI
    nq = Q.shape[1]
    nv = QDD.shape[1]
    _n, q, qd, tau, fx, qdd, sc, _e = _rows(WS_ABA, nb, nq, nv, 0)
    bad = sc + 2
    _gather(Q, s0, count, W, q)
    _gather(QD, s0, count, W, qd)
    _gather(TAU, s0, count, W, tau)
    _st(W, bad, -1.0)
    X_up = 0
    v = 12 * nb
    c = 18 * nb
    IA = 24 * nb
    pA = 60 * nb
    U = 66 * nb
    Dinv = 102 * nb
    u = 138 * nb
    a = 144 * nb
    t = 150 * nb
    vJ = t
    Iv = t + 6
    Ia = t + 12
    pa = t + 48
    UD = t + 54
    D = t + 90
    T = t + 126
    s = t + 153
    a0 = Iv
    L = Ia
    tol = SINGULAR_RTOL * G[3]
    has_fext = FEXT.shape[1] > 0
    if has_fext:  # (N or 1, nb, 6) → rows fx + 6 i + k
        _gather(FEXT.reshape((FEXT.shape[0], 6 * nb)), s0, count, W, fx)

    for i in range(nb):
        lam = BI[NBI * i + PARENT]
        Xi = X_up + 12 * i
        vi = v + 6 * i
        _pose_in_parent(BI, BF, i, q, W, Xi, sc)
        _S_times(BI, BF, i, qd, W, vJ)
        if lam == -1:
            for k in range(6):
                _st(W, vi + k, _ld(W, vJ + k))
        else:
            _motion_to_child(W, Xi, v + 6 * lam, vi)
            for k in range(6):
                _st(W, vi + k, _ld(W, vi + k) + _ld(W, vJ + k))
        for k in range(6):
            _st(W, c + 6 * i + k, 0.0)
            _st(W, pA + 6 * i + k, 0.0)
        _cross_motion_add(W, vi, vJ, c + 6 * i)
        I = NBF * i + MASS
        _inertia_matrix_model(BF, I, W, IA + 36 * i)
        _inertia_times_model(BF, I, W, vi, Iv)
        _cross_force_add(W, vi, Iv, pA + 6 * i)
        if has_fext:
            for k in range(6):
                _st(W, pA + 6 * i + k, _ld(W, pA + 6 * i + k) - _ld(W, fx + 6 * i + k))

    for i in range(nb - 1, -1, -1):
        lam = BI[NBI * i + PARENT]
        ki = BI[NBI * i + NV]
        iv = BI[NBI * i + IV]
        IAi = IA + 36 * i
        Ui = U + 36 * i
        unit = BI[NBI * i + UNIT]
        if unit >= 0:
            sg = BF[NBF * i + AX + (unit - 3 if unit >= 3 else unit)]
            for r in range(6):
                _st(W, Ui + r, sg * _ld(W, IAi + 6 * r + unit))
            _st(W, D, _ld(W, IAi + 7 * unit))
            _st(W, u + 6 * i, _ld(W, tau + iv) - sg * _ld(W, pA + 6 * i + unit))
        elif BI[NBI * i + JT] == FF:
            for r in range(6):
                for m in range(6):
                    x = _ld(W, IAi + 6 * r + m)
                    _st(W, Ui + 6 * m + r, x)
                    _st(W, D + 6 * r + m, x)
                _st(W, u + 6 * i + r, _ld(W, tau + iv + r) - _ld(W, pA + 6 * i + r))
        elif ki == 1:
            _S_col(BI, BF, i, 0, W, s)
            d = _v(0.0)
            for r in range(6):
                x = _v(0.0)
                for m in range(6):
                    x = x + _ld(W, IAi + 6 * r + m) * _ld(W, s + m)
                _st(W, Ui + r, x)
                d = d + _ld(W, s + r) * x
            _st(W, D, d)
            _st(W, u + 6 * i, _ld(W, tau + iv) - _St_dot(BI, BF, i, 0, W, pA + 6 * i))
        else:
            for j in range(ki):
                _S_col(BI, BF, i, j, W, s)
                for r in range(6):
                    x = _v(0.0)
                    for m in range(6):
                        x = x + _ld(W, IAi + 6 * r + m) * _ld(W, s + m)
                    _st(W, Ui + 6 * j + r, x)
            for r in range(ki):
                for j in range(ki):
                    _st(W, D + 6 * r + j, _St_dot(BI, BF, i, r, W, Ui + 6 * j))
                _st(W, u + 6 * i + r, _ld(W, tau + iv + r) - _St_dot(BI, BF, i, r, W, pA + 6 * i))
        Di = Dinv + 36 * i
        _spd_inverse(W, D, ki, Di, L, tol, bad, i)
        if lam == -1:
            continue
        if ki == 1:
            dinv = _ld(W, Di)
            uu = _ld(W, u + 6 * i)
            for r in range(6):
                _st(W, UD + r, _ld(W, Ui + r) * dinv)
            for r in range(6):
                ud = _ld(W, UD + r)
                for col in range(r, 6):
                    x = _ld(W, IAi + 6 * r + col) - ud * _ld(W, Ui + col)
                    _st(W, Ia + 6 * r + col, x)
                    _st(W, Ia + 6 * col + r, x)
            for r in range(6):
                x = _ld(W, pA + 6 * i + r) + _ld(W, UD + r) * uu
                for m in range(6):
                    x = x + _ld(W, Ia + 6 * r + m) * _ld(W, c + 6 * i + m)
                _st(W, pa + r, x)
        else:
            for j in range(ki):
                for r in range(6):
                    x = _v(0.0)
                    for m in range(ki):
                        x = x + _ld(W, Ui + 6 * m + r) * _ld(W, Di + 6 * m + j)
                    _st(W, UD + 6 * j + r, x)
            for r in range(6):
                for col in range(r, 6):
                    x = _ld(W, IAi + 6 * r + col)
                    for j in range(ki):
                        x = x - _ld(W, UD + 6 * j + r) * _ld(W, Ui + 6 * j + col)
                    _st(W, Ia + 6 * r + col, x)
                    _st(W, Ia + 6 * col + r, x)
            for r in range(6):
                x = _ld(W, pA + 6 * i + r)
                for m in range(6):
                    x = x + _ld(W, Ia + 6 * r + m) * _ld(W, c + 6 * i + m)
                for j in range(ki):
                    x = x + _ld(W, UD + 6 * j + r) * _ld(W, u + 6 * i + j)
                _st(W, pa + r, x)
        _matrix6_to_parent_add(W, X_up + 12 * i, Ia, IA + 36 * lam, T)
        _force_to_parent(W, X_up + 12 * i, pa, pA + 6 * lam, True)

    g = 1.0 if gravity else 0.0
    _st(W, a0, 0.0)
    _st(W, a0 + 1, 0.0)
    _st(W, a0 + 2, 0.0)
    _st(W, a0 + 3, -g * G[0])
    _st(W, a0 + 4, -g * G[1])
    _st(W, a0 + 5, -g * G[2])
    for i in range(nb):
        lam = BI[NBI * i + PARENT]
        ki = BI[NBI * i + NV]
        iv = BI[NBI * i + IV]
        ai = a + 6 * i
        _motion_to_child(W, X_up + 12 * i, a0 if lam == -1 else a + 6 * lam, ai)
        for k in range(6):
            _st(W, ai + k, _ld(W, ai + k) + _ld(W, c + 6 * i + k))
        Ui = U + 36 * i
        Di = Dinv + 36 * i
        if ki == 1:
            x = _ld(W, u + 6 * i)
            for r in range(6):
                x = x - _ld(W, Ui + r) * _ld(W, ai + r)
            _st(W, qdd + iv, _ld(W, Di) * x)
        else:
            for j in range(ki):
                x = _ld(W, u + 6 * i + j)
                for r in range(6):
                    x = x - _ld(W, Ui + 6 * j + r) * _ld(W, ai + r)
                _st(W, s + j, x)
            for r in range(ki):
                x = _v(0.0)
                for j in range(ki):
                    x = x + _ld(W, Di + 6 * r + j) * _ld(W, s + j)
                _st(W, qdd + iv + r, x)
        _S_times(BI, BF, i, qdd, W, vJ)
        for k in range(6):
            _st(W, ai + k, _ld(W, ai + k) + _ld(W, vJ + k))
    _scatter(W, qdd, QDD, s0, count)
    for ln in range(count):
        j = W[bad * LANES + ln]
        if j >= 0.0:
            return (s0 + ln) * nb + int(j)
    return -1


@njit(**_PJIT)
def aba_lanes(BI, BF, G, Q, QD, TAU, FEXT, gravity, QDD, threads):  # pragma: no cover - compiled
    """:func:`._kernels.aba_core` over rows, in blocks of ``LANES`` states; returns ``-1`` or
    ``state · nb + joint`` of the first singular state (where the per-state core would stop)."""
    n = QDD.shape[0]
    nb = BI.shape[0] // NBI
    rows = _rows(WS_ABA, nb, Q.shape[1], QDD.shape[1], 0)[0]
    nblk = (n + LANES - 1) // LANES
    nt, chunk = _chunks(nblk, threads)
    status = np.full(nt, -1, dtype=np.int64)
    for t in prange(nt):
        W = _aligned_empty(rows * LANES)
        for blk in range(t * chunk, min(nblk, (t + 1) * chunk)):
            s0 = blk * LANES
            bad = aba_block(BI, BF, G, Q, QD, TAU, FEXT, gravity, QDD, s0, min(LANES, n - s0), W)
            if bad >= 0:
                status[t] = bad
                break
    for t in range(nt):
        if status[t] >= 0:
            return status[t]
    return -1
