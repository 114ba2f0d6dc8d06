"""The SIMD lane vector type of the batched kernels: ``<8 x double>`` for Numba, with its intrinsics (private).

:mod:`._lanes` describes why and how the batched RNEA, CRBA and ABA run eight
states at a time; this module holds the type (:class:`LaneVector`), its
arithmetic and the loads, stores, transposes and fences the kernels use.
"""


from __future__ import annotations

import operator
from typing import Any

from llvmlite import ir
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic, lower_builtin, models, register_model, type_callable

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
