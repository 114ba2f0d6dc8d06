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

Every method is a declared algorithm's (``rnea``, ``nle``, ``gravity``, ``crba``, ``aba``, ``fk`` and the others
of ``featherdyn/api/declarations.py``), added by ``fd.compile``; ``rnea_batch``, ``crba_batch``, ``aba_batch``,
``rnea_derivatives_batch``, ``aba_derivatives_batch``, ``frame_jacobian_batch`` and ``fk_batch`` are the same
methods under their former names. Each takes one state or any batch shape.

A one-state call hands its arguments to the core as they are: native-endian,
aligned, C-contiguous float64 arrays of the exact shapes go straight in;
anything else (lists, float32, strided, big-endian, masked arrays) takes the
declared call's general path, which converts it.
The core checks every state it computes on — lengths, finiteness, unit
quaternions — and a bad one raises the same featherdyn exception, with the
same message, as ``fd.rnea`` & co.

The core's scratch memory is per thread, so one :class:`CompiledModel` may be
used by several threads at once; the batched methods run on the core's pool
(``fd.set_num_threads``) with the GIL released.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import ModelError
from ..model import Model
from ..results import Kinematics
from . import _lib, _view

__all__ = ["CompiledModel", "compile_model"]


class CompiledModel:
    """A model bound to the compiled core (see the module docstring).

    Attributes:
        model: the :class:`~featherdyn.Model`.
        nq, nv, nb: sizes.
        compile_seconds: how long :func:`compile_model` took (copying the model's arrays; nothing is compiled).
    """

    # the declared algorithms' methods, set by fd.compile (api/declarations.py): the common ones typed by their results
    rnea: Callable[..., np.ndarray]
    crba: Callable[..., np.ndarray]
    aba: Callable[..., np.ndarray]
    fk: Callable[..., np.ndarray]
    frame_jacobian: Callable[..., np.ndarray]
    rnea_derivatives: Callable[..., tuple[np.ndarray, np.ndarray, np.ndarray]]
    aba_derivatives: Callable[..., tuple[np.ndarray, np.ndarray, np.ndarray]]
    forward_kinematics: Callable[..., Kinematics]

    if TYPE_CHECKING:  # every other declared algorithm's method (a new algorithm adds none here)
        def __getattr__(self, name: str) -> Callable[..., Any]: ...

    def __init__(self, model: Model, compile_seconds: float = 0.0) -> None:
        _lib()
        _view(model)  # the model's arrays in the core, made now (a model the core cannot take fails here)
        self.model = model
        self.nq, self.nv, self.nb = model.nq, model.nv, model.nbodies
        self.compile_seconds = compile_seconds

    def warmup(self) -> None:
        """Kept for compatibility: the core is compiled at install, so there is nothing to warm up."""

    def __repr__(self) -> str:
        return f"CompiledModel({self.model!r})"


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
