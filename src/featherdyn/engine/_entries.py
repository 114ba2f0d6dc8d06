"""Single-state entry points of ``fd.compile`` and the checked entry points of the public functions (private).

:mod:`._kernels` is the index of the engine's kernels.
"""


from __future__ import annotations

import math
from typing import Any

import numpy as np
from numba import njit, types

from ..tolerances import QUATERNION_NORM
from ._cores import aba_core, crba_core, fk_core, frame_jacobian_core, gravity_core, rnea_core
from ._flat_spatial import _IJIT, _JIT, _compose, _pose_in_parent
from ._layout import (
    FF,
    IQ,
    JT,
    NBF,
    NBI,
    PARENT,
    SPH,
    WS_ABA,
    WS_CRBA,
    WS_FK,
    WS_RNEA,
    WS_TAIL,
)

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
def _all_finite2(x):  # pragma: no cover - compiled
    for i in range(x.shape[0]):
        for k in range(x.shape[1]):
            if not math.isfinite(x[i, k]):
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
    return OK if _all_finite(tau) else NOT_FINITE  # finite input that overflowed: the general path words it


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
    return OK if _all_finite(h) else NOT_FINITE


@njit(**_GJIT)
def checked_gravity(MD, q, g):  # pragma: no cover - compiled
    """``g`` ← RNEA(q, 0, 0) if ``q`` is valid; returns the status."""
    BI, BF, G, _FB, _FR, W, _nb, nq, nv = _unpack(MD, WS_RNEA)
    st = _check_q(BI, q, nq)
    if st != OK or g.shape[0] != nv:
        return max(st, BAD_LENGTH)
    gravity_core(BI, BF, G, q, g, W)
    return OK if _all_finite(g) else NOT_FINITE


@njit(**_GJIT)
def checked_crba(MD, q, M):  # pragma: no cover - compiled
    """``M`` ← CRBA(q) if ``q`` is valid; returns the status."""
    BI, BF, _G, _FB, _FR, W, _nb, nq, nv = _unpack(MD, WS_CRBA)
    st = _check_q(BI, q, nq)
    if st != OK or M.shape[0] != nv or M.shape[1] != nv:
        return max(st, BAD_LENGTH)
    crba_core(BI, BF, q, M, W)
    return OK if _all_finite2(M) else NOT_FINITE


@njit(**_GJIT)
def checked_aba(MD, q, v, tau, gravity, qdd):  # pragma: no cover - compiled
    """``qdd`` ← ABA(q, v, τ) if the state is valid; returns ``-1`` (done), the index of a joint with a
    singular articulated inertia, or ``-1 − status`` for an invalid state."""
    BI, BF, G, _FB, _FR, W, _nb, nq, nv = _unpack(MD, WS_ABA)
    st = max(_check_q(BI, q, nq), _check_vec(v, nv), _check_vec(tau, nv))
    if st != OK or qdd.shape[0] != nv:
        return -1 - max(st, BAD_LENGTH)
    bad = aba_core(BI, BF, G, q, v, tau, W[:0].reshape((0, 6)), gravity, qdd, W)
    if bad == -1 and not _all_finite(qdd):
        return -1 - NOT_FINITE  # finite input that overflowed: the general path words it
    return bad


@njit(**_GJIT)
def checked_frame_jacobian(MD, q, frame, ref, J):  # pragma: no cover - compiled
    """``J`` ← the Jacobian of frame index ``frame`` in ``ref`` (0 LOCAL, 1 WORLD, 2 LWA) if valid; the status."""
    BI, BF, _G, FB, FR, W, _nb, nq, nv = _unpack(MD, 0)
    st = _check_q(BI, q, nq)
    if st != OK or J.shape[0] != 6 or J.shape[1] != nv or frame < 0 or frame >= FB.shape[0] or ref < 0 or ref > 2:
        return max(st, BAD_LENGTH)
    frame_jacobian_core(BI, BF, q, FB[frame], FR, 12 * frame, ref, J, W)
    return OK if _all_finite2(J) else NOT_FINITE


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
    for i in range(nb):
        if not _all_finite2(H[0, i]) or (want_v and not _all_finite(vel[i])) or (want_a and not _all_finite(acc[i])):
            return NOT_FINITE
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
    return OK if _all_finite(out) else NOT_FINITE


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
