"""``fd.compile(model)``: the compiled core bound to one model, with the cheapest calls for control loops.

::

    cm = fd.compile(model)            # the model's arrays copied into the core once (nothing is compiled)
    tau = cm.rnea(q, v, a)            # (nv,)      inverse dynamics, with gravity
    M = cm.crba(q)                    # (nv, nv)   mass matrix
    ddq = cm.aba(q, v, tau)           # (nv,)      forward dynamics
    oMi = cm.fk(q)                    # (nb, 4, 4) world placements of the bodies
    J = cm.frame_jacobian(q, "tool", fd.LOCAL)   # (6, nv)
    cm.rnea(q, v, a, out=tau)         # writes into tau: no allocation at all
    TAU = cm.rnea_batch(Q, V, A)      # (N, nv), on the core's threads
    cm.rnea_derivatives_batch(Q, V, A, out=(DQ, DV, M))   # three (N, nv, nv), reused: no page faults

The declared algorithms' methods (``rnea``, ``nle``, ``gravity``, ``crba``, ``aba`` and the
others of ``featherdyn/api/declarations.py``; ``rnea_batch``, ``crba_batch`` and ``aba_batch``
``rnea_derivatives_batch``, ``aba_derivatives_batch``, ``frame_jacobian_batch`` are the same methods under their
former names) are added by ``fd.compile`` from the
declarations; the rest are below.

The single-state methods hand their arguments to the core's binding as they
are: native-endian, aligned, C-contiguous float64 arrays of the exact shapes
go straight in; anything else (lists, float32, strided, big-endian, masked
arrays) takes the general path of :mod:`featherdyn.core`, which converts it.
The core checks every state it computes on — lengths, finiteness, unit
quaternions — and a bad one raises the same featherdyn exception, with the
same message, as ``fd.rnea`` & co.

The core's scratch memory is per thread, so one :class:`CompiledModel` may be
used by several threads at once; the batched methods run on the core's pool
(``fd.set_num_threads``) with the GIL released.
"""

from __future__ import annotations

import functools
import time
from typing import Any

import numpy as np

from .._state_checks import check_f_ext, check_state
from ..errors import ModelError
from ..model import Model
from . import _lib, _view, fk_batch
from . import fk as _fk

__all__ = ["CompiledModel", "compile_model"]


class CompiledModel:
    """A model bound to the compiled core (see the module docstring).

    Attributes:
        model: the :class:`~featherdyn.Model`.
        nq, nv, nb: sizes.
        compile_seconds: how long :func:`compile_model` took (copying the model's arrays; nothing is compiled).
    """

    def __init__(self, model: Model, compile_seconds: float = 0.0) -> None:
        core = _lib()
        handle = _view(model)
        self.model = model
        self.nq, self.nv, self.nb = model.nq, model.nv, model.nbodies
        self.compile_seconds = compile_seconds
        cm, nb = handle.cm, self.nb
        shape_H = (nb, 4, 4)  # built once, not per call

        # The methods' general paths: featherdyn.core's wrappers, which convert, compute or word the error. A
        # native float64 state never reaches them: it is finished in C (below).

        def lengths_first(q: Any, f_ext: Any = None, **vectors: Any) -> None:
            # the public checks, in the public functions' order and words, before the wrappers convert: a wrong
            # length is a ShapeError at once, not the MemoryError of copying a huge zero-stride view
            check_f_ext(model, f_ext)
            check_state(model, q, **vectors)

        def fk(q: Any, out: Any = None) -> np.ndarray:
            """World placements of the bodies, homogeneous `(nb, 4, 4)`."""
            lengths_first(q)
            return _fk(model, q, out=_one_state_out(out, shape_H))

        # Each method: the closure above, with its one-state call finished in C when the arguments are as the
        # binding takes them (core/cpp/public_calls.hpp); anything else goes to the closure unchanged.
        def finished_in_c(name: str, closure: Any, constants: tuple[Any, ...] = ()) -> Any:
            method = core.public_call("fk" if name == "fk" else f"cm_{name}", closure, constants, cm)
            functools.update_wrapper(method, closure)
            method.__qualname__ = f"CompiledModel.{name}"
            return method

        self.fk = finished_in_c("fk", fk)

    # batched forms: any batch shape (leading axes broadcast), on the core's threads

    def fk_batch(self, q: Any, out: Any = None) -> np.ndarray:
        """World placements `(..., nb, 4, 4)` for a batch of configurations."""
        return fk_batch(self.model, q, out)

    def __getattr__(self, name: str) -> Any:
        """(Only for names not found: the declared algorithms' methods are set by ``fd.compile``.)"""
        raise AttributeError(f"'CompiledModel' object has no attribute {name!r}")

    def warmup(self) -> None:
        """Kept for compatibility: the core is compiled at install, so there is nothing to warm up."""

    def __repr__(self) -> str:
        return f"CompiledModel({self.model!r})"


def _one_state_out(out: Any, shape: tuple[int, ...]) -> Any:
    """``out`` for the general path of a single-state method: ``None``, or an array of exactly ``shape``.

    (The general path takes batches too; a single-state method refuses to write a batch into ``out``.)
    """
    if out is not None and getattr(out, "shape", None) != shape:
        from ..errors import ShapeError

        raise ShapeError(f"out: expected shape {shape}, got {getattr(out, 'shape', type(out).__name__)}")
    return out


def compile_model(model: Model, *, warmup: bool = True) -> CompiledModel:
    """The compiled core bound to ``model`` (see :class:`CompiledModel`).

    Nothing is compiled (the core is built at install): the model's flat arrays
    are copied into the core once, and kept on the model for the public
    functions too. ``warmup`` is accepted for compatibility and does nothing.

    Raises:
        ModelError: ``model`` is not a featherdyn Model.
    """
    if not isinstance(model, Model):
        raise ModelError(f"compile: expected a featherdyn Model, got {type(model).__name__}")
    del warmup
    t0 = time.perf_counter()
    cm = CompiledModel(model)
    cm.compile_seconds = time.perf_counter() - t0
    return cm
