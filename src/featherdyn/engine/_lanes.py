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

import math
import operator
from typing import Any

import numpy as np
from llvmlite import ir
from numba import njit, prange, types
from numba.core import cgutils
from numba.extending import intrinsic, lower_builtin, models, register_model, type_callable

from ._kernels import _chunks
from ._layout import (
    AX,
    FF,
    IQ,
    IV,
    JT,
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
    WS_ABA,
    WS_CRBA,
    WS_RNEA,
    WS_TAIL,
    XP,
    XR,
)

__all__ = ["LANES", "lane_rows", "rnea_lanes", "crba_lanes", "aba_lanes"]

#: states per block (SIMD lanes)
LANES = 8
#: CRBA writes its output with non-temporal stores from this many entries on (1 MiB): the stores skip reading
#: each line of the output from memory before writing it, the larger part of the memory traffic otherwise
STREAM_MIN = 1 << 17

# ---------------------------------------------------------------------------
# the lane vector type
# ---------------------------------------------------------------------------


class LaneVector(types.Type):
    """``n`` float64 lanes, an LLVM ``<n x double>``."""

    def __init__(self, n: int) -> None:
        self.n = n
        super().__init__(name=f"f64x{n}")


@register_model(LaneVector)
class _LaneVectorModel(models.PrimitiveModel):
    def __init__(self, dmm: Any, fe_type: LaneVector) -> None:
        super().__init__(dmm, fe_type, ir.VectorType(ir.DoubleType(), fe_type.n))


_VEC = LaneVector(LANES)
_I32 = ir.IntType(32)


def _splat_ir(context: Any, builder: Any, ty: Any, val: Any, n: int) -> Any:
    """``val`` (a number of type ``ty``, or already a vector) broadcast to ``<n x double>``."""
    if isinstance(ty, LaneVector):
        return val
    d = context.cast(builder, val, ty, types.float64)
    vt = ir.VectorType(ir.DoubleType(), n)
    v = builder.insert_element(ir.Constant(vt, ir.Undefined), d, ir.Constant(_I32, 0))
    return builder.shuffle_vector(v, ir.Constant(vt, ir.Undefined), ir.Constant(ir.VectorType(_I32, n), [0] * n))


def _register_binary(op: Any, inst: str) -> None:
    """``op`` on (vector, vector), (vector, number), (number, vector): the IEEE instruction ``inst`` per lane."""

    @type_callable(op)
    def _typer(context: Any) -> Any:
        def typer(a: Any, b: Any) -> Any:
            if isinstance(a, LaneVector) and (isinstance(b, LaneVector) or isinstance(b, types.Number)):
                return a
            if isinstance(b, LaneVector) and isinstance(a, types.Number):
                return b
            return None

        return typer

    def lower(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        n = sig.return_type.n
        a = _splat_ir(context, builder, sig.args[0], args[0], n)
        b = _splat_ir(context, builder, sig.args[1], args[1], n)
        return getattr(builder, inst)(a, b)

    lower_builtin(op, LaneVector, LaneVector)(lower)
    lower_builtin(op, LaneVector, types.Number)(lower)
    lower_builtin(op, types.Number, LaneVector)(lower)


for _op, _inst in ((operator.add, "fadd"), (operator.sub, "fsub"), (operator.mul, "fmul"),
                   (operator.truediv, "fdiv"), (operator.iadd, "fadd"), (operator.isub, "fsub"),
                   (operator.imul, "fmul"), (operator.itruediv, "fdiv")):
    _register_binary(_op, _inst)


@type_callable(operator.neg)
def _neg_typer(context: Any) -> Any:
    def typer(a: Any) -> Any:
        return a if isinstance(a, LaneVector) else None

    return typer


@lower_builtin(operator.neg, LaneVector)
def _neg_lower(context: Any, builder: Any, sig: Any, args: Any) -> Any:
    return builder.fneg(args[0])


def _row_pointer(context: Any, builder: Any, arrty: Any, arr: Any, idxty: Any, idx: Any) -> Any:
    """A ``<LANES x double>*`` to row ``idx`` of the flat float64 array ``arr`` (no wraparound, no bounds check)."""
    ary = context.make_array(arrty)(context, builder, arr)
    o = context.cast(builder, idx, idxty, types.intp)
    p = builder.gep(ary.data, [builder.mul(o, ir.Constant(o.type, LANES))], inbounds=True)
    return builder.bitcast(p, ir.PointerType(ir.VectorType(ir.DoubleType(), LANES)))


@intrinsic
def _ld(typingctx: Any, W: Any, o: Any) -> Any:
    """Row ``o`` of the lane workspace ``W``: ``W[o L : o L + L]`` as a vector."""
    sig = _VEC(W, o)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        p = _row_pointer(context, builder, signature.args[0], args[0], signature.args[1], args[1])
        return builder.load(p, align=8)

    return sig, codegen


@intrinsic
def _st(typingctx: Any, W: Any, o: Any, x: Any) -> Any:
    """``W[o L : o L + L] = x``; a number ``x`` is broadcast."""
    sig = types.void(W, o, x)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        p = _row_pointer(context, builder, signature.args[0], args[0], signature.args[1], args[1])
        builder.store(_splat_ir(context, builder, signature.args[2], args[2], LANES), p, align=8)
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def _v(typingctx: Any, x: Any) -> Any:
    """``x`` as a vector: a number broadcast to every lane, a vector unchanged."""
    sig = _VEC(x)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return _splat_ir(context, builder, signature.args[0], args[0], LANES)

    return sig, codegen


@intrinsic
def _lane(typingctx: Any, x: Any, s: Any) -> Any:
    """Lane ``s`` of the vector ``x``."""
    sig = types.float64(x, s)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return builder.extract_element(args[0], context.cast(builder, args[1], signature.args[1], types.intp))

    return sig, codegen


@intrinsic
def _sqrt(typingctx: Any, x: Any) -> Any:
    """``√x`` per lane (``llvm.sqrt``, correctly rounded like the scalar ``math.sqrt``)."""
    sig = _VEC(x)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        vt = ir.VectorType(ir.DoubleType(), LANES)
        fn = cgutils.get_or_insert_function(builder.module, ir.FunctionType(vt, [vt]), f"llvm.sqrt.v{LANES}f64")
        return builder.call(fn, [args[0]])

    return sig, codegen


@intrinsic
def _stv(typingctx: Any, A: Any, i: Any, x: Any) -> Any:
    """``A[i : i + L] = x`` at any element offset ``i``; a number ``x`` is broadcast."""
    sig = types.void(A, i, x)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        ary = context.make_array(signature.args[0])(context, builder, args[0])
        o = context.cast(builder, args[1], signature.args[1], types.intp)
        p = builder.bitcast(builder.gep(ary.data, [o], inbounds=True),
                            ir.PointerType(ir.VectorType(ir.DoubleType(), LANES)))
        builder.store(_splat_ir(context, builder, signature.args[2], args[2], LANES), p, align=8)
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def _sts(typingctx: Any, A: Any, i: Any, x: Any) -> Any:
    """``A[i] = x`` for a float64 ``x`` (no wraparound: Numba's ``A[i] = x`` costs a select on the index)."""
    sig = types.void(A, i, types.float64)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        ary = context.make_array(signature.args[0])(context, builder, args[0])
        o = context.cast(builder, args[1], signature.args[1], types.intp)
        builder.store(args[2], builder.gep(ary.data, [o], inbounds=True))
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def _ldv(typingctx: Any, A: Any, i: Any) -> Any:
    """``A[i : i + L]`` as a vector, at any element offset ``i``."""
    sig = _VEC(A, i)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        ary = context.make_array(signature.args[0])(context, builder, args[0])
        o = context.cast(builder, args[1], signature.args[1], types.intp)
        p = builder.bitcast(builder.gep(ary.data, [o], inbounds=True),
                            ir.PointerType(ir.VectorType(ir.DoubleType(), LANES)))
        return builder.load(p, align=8)

    return sig, codegen


@intrinsic
def _stream_line(typingctx: Any, A: Any, i: Any, S: Any, j: Any) -> Any:
    """``A[i : i + 8] = S[j : j + 8]`` (one cache line) with a non-temporal store; ``A + i`` is 64-byte aligned."""
    sig = types.void(A, i, S, j)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        vt = ir.PointerType(ir.VectorType(ir.DoubleType(), 8))
        a = context.make_array(signature.args[0])(context, builder, args[0])
        b = context.make_array(signature.args[2])(context, builder, args[2])
        pa = builder.gep(a.data, [context.cast(builder, args[1], signature.args[1], types.intp)], inbounds=True)
        pb = builder.gep(b.data, [context.cast(builder, args[3], signature.args[3], types.intp)], inbounds=True)
        st = builder.store(builder.load(builder.bitcast(pb, vt), align=8), builder.bitcast(pa, vt), align=64)
        st.set_metadata("nontemporal", builder.module.add_metadata([ir.Constant(_I32, 1)]))
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def _line_offset(typingctx: Any, A: Any, i: Any) -> Any:
    """``(address of A[i] / 8) mod 8``: the position of ``A[i]`` in its 64-byte cache line."""
    sig = types.intp(A, i)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        a = context.make_array(signature.args[0])(context, builder, args[0])
        p = builder.gep(a.data, [context.cast(builder, args[1], signature.args[1], types.intp)], inbounds=True)
        addr = builder.ptrtoint(p, ir.IntType(64))
        return builder.and_(builder.lshr(addr, ir.Constant(ir.IntType(64), 3)), ir.Constant(ir.IntType(64), 7))

    return sig, codegen


def _transpose_ir(builder: Any, rows: list[Any]) -> list[Any]:
    """The ``L × L`` transpose of ``L`` vectors (``L`` a power of two): ``log2 L`` stages of two-vector shuffles,
    stage ``b`` interleaving blocks of ``b`` lanes of rows ``i`` and ``i + b``."""
    n = len(rows)
    v = list(rows)
    b = 1
    while b < n:
        lo = []
        hi = []
        for g in range(n // (2 * b)):
            lo += [g * 2 * b + k for k in range(b)] + [n + g * 2 * b + k for k in range(b)]
            hi += [g * 2 * b + b + k for k in range(b)] + [n + g * 2 * b + b + k for k in range(b)]
        mlo = ir.Constant(ir.VectorType(_I32, n), lo)
        mhi = ir.Constant(ir.VectorType(_I32, n), hi)
        w = list(v)
        for i in range(n):
            if (i // b) % 2 == 0:
                w[i] = builder.shuffle_vector(v[i], v[i + b], mlo)
                w[i + b] = builder.shuffle_vector(v[i], v[i + b], mhi)
        v = w
        b *= 2
    return v


@intrinsic
def _transpose_rows(typingctx: Any, W: Any, row: Any, S: Any, o: Any, stride: Any) -> Any:
    """``S[o + s · stride + k] = W[(row + k) L + s]`` for lanes ``s`` and ``k`` in ``0 … L − 1``: the tile of
    ``L`` rows, transposed, each lane's ``L`` entries stored contiguously."""
    sig = types.void(W, row, S, o, stride)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        vt = ir.PointerType(ir.VectorType(ir.DoubleType(), LANES))
        w = context.make_array(signature.args[0])(context, builder, args[0])
        t = context.make_array(signature.args[2])(context, builder, args[2])
        r0 = context.cast(builder, args[1], signature.args[1], types.intp)
        o = context.cast(builder, args[3], signature.args[3], types.intp)
        st = context.cast(builder, args[4], signature.args[4], types.intp)
        rows = []
        for k in range(LANES):
            idx = builder.mul(builder.add(r0, ir.Constant(r0.type, k)), ir.Constant(r0.type, LANES))
            rows.append(builder.load(builder.bitcast(builder.gep(w.data, [idx], inbounds=True), vt), align=8))
        cols = _transpose_ir(builder, rows)
        for k in range(LANES):
            idx = builder.add(o, builder.mul(st, ir.Constant(st.type, k)))
            builder.store(cols[k], builder.bitcast(builder.gep(t.data, [idx], inbounds=True), vt), align=8)
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def _fence(typingctx: Any) -> Any:
    """A full memory fence (orders the non-temporal stores before what follows)."""
    sig = types.void()

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        builder.fence("seq_cst")
        return context.get_dummy_value()

    return sig, codegen


# ---------------------------------------------------------------------------
# helpers: the scalar helpers of _kernels over lane rows, operation by operation
# ---------------------------------------------------------------------------

# no fastmath, no FMA contraction (see _kernels); helpers are inlined at the Numba IR level
_JIT: dict[str, Any] = {"cache": True, "nogil": True, "error_model": "numpy", "_nrt": False}
_IJIT: dict[str, Any] = {**_JIT, "inline": "always"}
_PJIT: dict[str, Any] = {"cache": True, "nogil": True, "error_model": "numpy", "parallel": True}


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
