"""The compiled core's declared algorithms, on checked arrays of any batch shape (docs/architecture.md, "The glue").

Each algorithm declared in ``core/cpp/declarations.hpp`` is one :class:`Kernel` of the
binding (``_core.kernels[name]``): its operands with symbolic shapes and three front
ends (``into``, ``fresh``, ``batch``). :func:`run` is the one Python path to its batch:
the inputs as rows, the outputs allocated (or ``out`` checked), the rows run on the
core's thread pool, a failing row turned into the reference's error.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..model import Model
from . import _errors
from ._model_view import CoreHandle, model_view
from ._result_pool import result_array

__all__ = ["kernel", "shape_of", "run"]


def kernel(name: str) -> Any:
    """The core's declared algorithm ``name`` (``_core.kernels[name]``), or ``None`` without the built core."""
    from . import _core  # (the package imports the binding; None when it is not built)

    return None if _core is None else _core.kernels[name]


def shape_of(h: CoreHandle, symbolic: tuple[Any, ...]) -> tuple[int, ...]:
    """A declared shape with the model's lengths: ``("nv", "nv")`` → `(nv, nv)`."""
    lengths = {"nq": h.nq, "nv": h.nv, "nb": h.nb}
    return tuple(lengths[d] if isinstance(d, str) else int(d) for d in symbolic)


def run(name: str, model: Model, batch: tuple[int, ...], inputs: list[np.ndarray | None],
        out: tuple[np.ndarray, ...] | None = None) -> tuple[np.ndarray, ...]:
    """The outputs `(*batch, *shape)` of the declared algorithm ``name`` on checked float64 inputs.

    ``inputs`` are in the declaration's order, each broadcastable to ``batch`` plus its declared shape
    (``None`` for an absent optional one); ``out``, when given, holds the outputs to write into (checked
    C-contiguous float64 of the right shapes by the caller). A failing row raises the reference's error
    for the whole batch (``_errors.raise_for``), naming the row as NumPy would.
    """
    from . import _core

    k = _core.kernels[name]
    h = model_view(model, _core)
    N = math.prod(batch)
    rows: list[np.ndarray | None] = []
    for x, (_, shape, _) in zip(inputs, k.inputs, strict=True):
        if x is None:
            rows.append(None)
            continue
        tail = shape_of(h, shape)
        n = math.prod(tail)
        bx = x.shape[: x.ndim - len(tail)]
        if bx == batch:
            rows.append(np.ascontiguousarray(x).reshape(N, n))
        elif math.prod(bx) == 1:
            rows.append(np.ascontiguousarray(x).reshape(1, n))
        else:
            rows.append(np.ascontiguousarray(np.broadcast_to(x, batch + tail)).reshape(N, n))
    outs = out if out is not None else tuple(result_array(batch + shape_of(h, s)) for _, s, _ in k.outputs)
    _row, status = k.batch(h.cm, rows, [o.reshape(N, -1) for o in outs])
    if status:
        names = [n for n, _, _ in k.inputs]
        q = inputs[names.index("q")]
        vectors = [(n, x) for n, x in zip(names, inputs, strict=True) if n in ("v", "a", "tau")]
        f_ext = inputs[names.index("f_ext")] if "f_ext" in names else None
        _errors.raise_for(status, model, q, vectors, f_ext, what=name)
    return tuple(outs)
