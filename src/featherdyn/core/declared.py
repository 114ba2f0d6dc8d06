"""The compiled core's declared algorithms, on checked arrays of any batch shape (docs/architecture.md, "The glue").

Each algorithm declared in ``core/cpp/declarations.hpp`` is one :class:`Kernel` of the
binding (``_core.kernels[name]``): its operands with symbolic shapes and three front
ends (``into``, ``fresh``, ``batch``). :func:`run` is the one Python path to its batch:
the inputs as rows, the outputs allocated (or ``out`` checked), the rows run on the
core's thread pool, a failing row turned into the reference's error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import ShapeError
from ..model import Model
from . import _errors
from ._model_view import CoreHandle, model_view
from ._result_pool import MIN_BYTES, result_array

__all__ = ["Spec", "SPECS", "kernel", "shape_of", "call_options", "run", "raise_singular", "arg_names"]

try:
    import featherdyn.core._core as _binding  # the compiled extension: a leaf, it imports no featherdyn module
    _binding.set_result_allocator(result_array, MIN_BYTES)  # (one state's large results reuse it too)
except ImportError:  # pragma: no cover - a source checkout without the built extension
    _binding = None


@dataclass(frozen=True)
class Spec:
    """A kernel's declaration as Python reads it, read once from the binding (its properties build new lists).

    Attributes:
        kernel: the binding's ``Kernel``.
        inputs: ``(name, symbolic shape, optional)`` each.
        outputs: ``(name, symbolic shape, when)`` each: ``when`` the input it is formed with (``None``: always).
        options: the options it takes (``frame``, ``reference``, ``gravity``), in their order.
        parameters: the public call's parameters after the model, in order (a point after the options).
    """

    kernel: Any
    inputs: tuple[tuple[str, tuple[Any, ...], bool], ...]
    outputs: tuple[tuple[str, tuple[Any, ...], str | None], ...]
    options: tuple[str, ...]
    input_names: tuple[str, ...]
    parameters: tuple[str, ...]

    @property
    def constrained(self) -> bool:
        """Whether its lengths include the call's constraint rows ``m`` (the constraint family: ``rows``, ``plan``)."""
        return "rows" in self.options or "plan" in self.options

    @classmethod
    def of(cls, k: Any) -> Spec:
        inputs = tuple(k.inputs)
        return cls(k, inputs, tuple(k.outputs), tuple(k.options), tuple(n for n, _, _ in inputs), k.parameters[1:])


#: every declared kernel's Spec, by name (empty without the built core)
SPECS: dict[str, Spec] = {} if _binding is None else {name: Spec.of(k) for name, k in _binding.kernels.items()}


def kernel(name: str) -> Any:
    """The core's declared algorithm ``name`` (``_core.kernels[name]``), or ``None`` without the built core."""
    return None if _binding is None else _binding.kernels[name]


def shape_of(h: CoreHandle, symbolic: tuple[Any, ...], rows: int = 0) -> tuple[int, ...]:
    """A declared shape with the model's lengths and the call's constraint rows ``m``: ``("nv", "nv")`` → `(nv, nv)`."""
    lengths = {"nq": h.nq, "nv": h.nv, "nb": h.nb, "np": 10 * h.nb, "m": rows}
    return tuple(lengths[d] if isinstance(d, str) else int(d) for d in symbolic)


def call_options(**given: Any) -> Any:
    """The binding's ``Options`` of a call (``core/cpp/declare.hpp``), ``None`` for the defaults: ``gravity``,
    ``frame`` (an index), ``reference`` (a code), ``rows`` (m), ``plan`` (a ``ContactPlan``: its contacts, and m),
    ``mu``, ``max_iter``, ``tol``, ``singular_tol``. Made once where a loop calls again (a contact plan's)."""
    return _binding.Options(**given) if given else None


def run(name: str, model: Model, batch: tuple[int, ...], inputs: list[np.ndarray | None],
        out: tuple[np.ndarray | None, ...] | None = None,
        options: dict[str, Any] | None = None) -> tuple[Any, ...]:
    """The outputs `(*batch, *shape)` of the declared algorithm ``name`` on checked float64 inputs (``None`` for an
    output formed only with an input that is absent).

    ``inputs`` are in the declaration's order, each broadcastable to ``batch`` plus its declared shape
    (``None`` for an absent optional one); ``out``, when given, holds the outputs to write into (C-contiguous
    float64, checked by the caller; their shapes are checked here, and an ``out`` that may share memory with an
    input gets the results through fresh memory); ``options`` its parameters by name (:func:`call_options`). A failing row
    raises the reference's error for the whole batch (``_errors.raise_for``; an overflow names the state's batch index); ``SINGULAR``, ABA's, as the reference words it
    (:func:`raise_singular`).
    """
    spec = SPECS[name]
    k = spec.kernel
    h = model_view(model, _binding)
    N = math.prod(batch)
    opts = call_options(**(options or {}))
    rows_m = 0 if opts is None else opts.rows
    rows: list[np.ndarray | None] = []
    for x, (_, shape, _) in zip(inputs, spec.inputs, strict=True):
        if x is None:
            rows.append(None)
            continue
        x = np.require(x, np.float64, ("C", "A"))  # native, C-contiguous and aligned: as the kernel reads rows
        tail = shape_of(h, shape, rows_m)
        n = math.prod(tail)
        if x.ndim < len(tail) or x.shape[x.ndim - len(tail):] != tail:
            rows.append(x.reshape(-1, max(x.shape[-1] if x.ndim else 1, 1)))  # wrong length: the core reports it
            continue
        bx = x.shape[: x.ndim - len(tail)]
        if bx == batch:
            rows.append(x.reshape(N, n))
        elif math.prod(bx) == 1:
            rows.append(x.reshape(1, n))
        else:
            rows.append(np.ascontiguousarray(np.broadcast_to(x, batch + tail)).reshape(N, n))
    given = dict(zip(spec.input_names, inputs, strict=True))
    shapes: list[tuple[int, ...] | None] = [None if when is not None and given[when] is None
                                            else batch + shape_of(h, s, rows_m) for _, s, when in spec.outputs]
    if out is not None and len(out) != len(shapes):
        raise ShapeError(f"out: expected {len(shapes)} arrays, got {len(out)}")
    for i, (o, expected) in enumerate(zip(out, shapes, strict=True) if out is not None else ()):
        if getattr(o, "shape", None) != expected:
            raise ShapeError(f"out: expected shape {expected}, got {getattr(o, 'shape', type(o).__name__)}")
        if o is not None and any(p is not None and np.may_share_memory(o, p) for p in out[:i]):  # type: ignore[index]
            raise ShapeError("out: the arrays must not overlap")
    if out is not None and any(x is not None and o is not None and np.may_share_memory(x, o)
                               for x in inputs for o in out):
        # the one rule for out= (docs/architecture.md): the result is the call's without out — a kernel writing
        # its rows while it reads the inputs' would read what it wrote, so it writes into fresh memory first
        for o, r in zip(out, run(name, model, batch, inputs, None, options), strict=True):
            if o is not None:
                np.copyto(o, r)
        return tuple(out)
    outs = out if out is not None else tuple(None if shape is None else result_array(shape) for shape in shapes)
    if N == 0:  # an empty batch: empty results
        return tuple(outs)
    row, status = k.batch(h.cm, rows, [None if o is None else o.reshape(N, -1) for o in outs], opts)
    if status:
        q = inputs[0]  # (q, or q0 and then q1 among the vectors)
        vectors = [(n, x) for n, x in given.items() if n in _errors.VECTORS and x is not None]
        f_ext = given.get("f_ext")
        if _errors.decode(status)[0] == _errors.SINGULAR:
            _errors.validate(model, q, vectors, f_ext)
            raise_singular(spec, model, h, rows, opts)
        state = f" (state {tuple(map(int, np.unravel_index(row, batch)))} of the batch)" if batch and row >= 0 else ""
        _errors.raise_for(status, model, q, vectors, f_ext, arg_names=arg_names(spec), what=name + state)
    return tuple(outs)


def raise_singular(spec: Spec, model: Model, h: CoreHandle, rows: list[np.ndarray | None], opts: Any) -> None:
    """The reference's error for a batch whose rows a kernel found singular: the singular joint nearest the
    leaves in any row, with the smallest eigenvalue of its ``D = Sᵀ Iᴬ S`` over those rows (the kernel's
    ``singular_block``, row by row: the error path)."""
    found: dict[int, float] = {}
    D = np.empty(36)
    N = max(x.shape[0] for x in rows if x is not None)
    for r in range(N):
        state = [None if x is None else x[0 if x.shape[0] == 1 else r].reshape(
                     shape_of(h, shape, 0 if opts is None else opts.rows))
                 for x, (_, shape, _) in zip(rows, spec.inputs, strict=True)]
        joint = spec.kernel.singular_block(h.cm, state, D, opts)
        if joint >= 0:
            e = _errors.eig_min(D, model.nvs[joint])
            found[joint] = min(found.get(joint, e), e)
    if found:
        joint = max(found)
        raise _errors.singular_error(model, joint, found[joint])


def arg_names(spec: Spec) -> tuple[str, ...]:
    """The names of a kernel's status arguments (``q`` or ``q0``, ``v``, ``a``, ``tau`` or ``b``, ``f_ext``, ``out``,
    ``frame``, ``q1``, ``w``, ``point``) as its declaration names them."""
    names = list(_errors.ARG_NAMES)
    for n in spec.input_names:  # q, v, f_ext by their names; the other vector (q̈, τ, b) is the third argument
        names[{"q": 0, "q0": 0, "v": 1, "f_ext": 3, "J": 6, "c": 7, "q1": 8, "w": 9, "W": 9, "point": 10}.get(n, 2)] = n
    return tuple(names)
