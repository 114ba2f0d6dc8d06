"""One declaration per algorithm, and the front ends made from it (docs/architecture.md, "The glue").

A :class:`Declaration` states an algorithm once on the Python side: its public name (also
the name of its kernel in the core, ``core/cpp/declarations.hpp``, which declares the
operands' shapes), its state arguments in order, its outputs, its reference function
(``featherdyn/algorithms``) and its docstring. :func:`public_function` makes the public
function from it and :func:`compiled_method` ``fd.compile(model)``'s method; both go
through :func:`call`, the one path of a declared call, which does each thing once, in
this order:

1. **one state**: the core's kernel takes the arguments as they are (``Kernel.fresh`` /
   ``Kernel.into``: exact native float64 arrays of the declared shapes, a sound state); it
   returns ``None`` (or a status) or raises ``TypeError`` for anything else, which goes on;
2. **Dask**: a Dask array among the state arguments hands the call to ``_dask.call``;
3. **checks**: ``f_ext`` and the state, worded by the public checks (``_state_checks``);
4. **backend**: ``select_backend`` — the core for float64, the reference otherwise;
5. **call**: the core's batch on the thread pool (``core.declared.run``: any batch shape;
   a failing row words the reference's error) or the reference function;
6. **out=**: the result written into the given arrays. One rule for an ``out`` that shares
   memory with an input: the result is computed as if it did not (into fresh memory, then
   copied), so it is the same as without ``out``.
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, cast

import numpy as np

from .. import _dask
from ..core import declared as _declared
from ..core._model_view import CoreHandle
from ..errors import DTypeError, ShapeError
from ..model import Model
from ._backend import CORE, core_path, select_backend
from ._checks import as_dtype, batch_with_f_ext, check_f_ext, check_state, finite_result, quiet

__all__ = ["Declaration", "call", "public_function", "compiled_method"]

#: the state arguments a declaration may take, and how each is checked: a vector of length nq or nv, or f_ext
STATE_ARGUMENTS = ("q", "v", "a", "tau", "f_ext")


@dataclass(frozen=True)
class Declaration:
    """An algorithm, declared once.

    Attributes:
        name: the public name (``fd.<name>``) and the name of the core's kernel.
        inputs: the state arguments in order, each one of ``q, v, a, tau, f_ext``.
        optional: the inputs that may be ``None``.
        outputs: the names of the results, in order (their shapes are the kernel's).
        reference: the reference function ``reference(model, *inputs) -> output or tuple of outputs`` on
            checked arrays (``featherdyn.algorithms``).
        doc: the public function's docstring (shapes and the defining equation).
    """

    name: str
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    reference: Callable[..., Any]
    doc: str
    optional: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        unknown = [n for n in self.inputs if n not in STATE_ARGUMENTS]
        if unknown or "q" not in self.inputs or not set(self.optional) <= set(self.inputs):
            raise ValueError(f"declaration {self.name!r}: inputs must be among {STATE_ARGUMENTS}, with q")


def _result(decl: Declaration, outs: tuple[np.ndarray, ...]) -> Any:
    return outs[0] if len(decl.outputs) == 1 else outs


def _out_arrays(decl: Declaration, out: Any) -> tuple[np.ndarray, ...]:
    """``out`` as the tuple of arrays to write into (one array for a single output, else a tuple of them)."""
    arrays = (out,) if len(decl.outputs) == 1 and not isinstance(out, (tuple, list)) else tuple(out)
    if len(arrays) != len(decl.outputs) or not all(type(a) is np.ndarray for a in arrays):
        raise ShapeError(f"out: expected {'an array' if len(decl.outputs) == 1 else f'{len(decl.outputs)} arrays'} "
                         f"for {', '.join(decl.outputs)}, got {type(out).__name__}")
    for name, a in zip(decl.outputs, arrays, strict=True):
        if not a.flags.writeable:
            raise ShapeError(f"out: the array for {name} is read-only")
    return arrays


#: the core's kernel of each declaration, looked up once
_KERNELS: dict[str, Any] = {}
#: the public function of each declaration (Dask's blocks call it)
_PUBLIC: dict[str, Callable[..., Any]] = {}


def call(decl: Declaration, model: Model, args: tuple[Any, ...], out: Any = None, backend: str | None = None) -> Any:
    """The declared algorithm on ``args`` (its inputs in order): the one path of every front end (module docstring)."""
    # 1. one state: the core takes the arguments as they are, or declines
    h = core_path(model, backend)
    if h is not None:
        kernel = _KERNELS.get(decl.name) or _KERNELS.setdefault(decl.name, _declared.kernel(decl.name))
        try:
            if out is None:
                r = kernel.fresh(h.cm, args)
                if r is not None:
                    return r
            elif kernel.into(h.cm, args, _out_arrays(decl, out)) == 0:
                return out
        except TypeError:  # arguments the kernel does not take as they are: converted below
            pass
    # 2. Dask
    if _dask.lazy(*args):
        if out is not None:
            raise ShapeError("out: not supported with Dask arrays (the result is a Dask array)")
        return _dask.call(_PUBLIC[decl.name], model, dict(zip(decl.inputs, args, strict=True)), backend=backend)
    # 3. checks: the model, f_ext, then the state, as every public function words them
    if not isinstance(model, Model):
        raise ShapeError(f"model: expected a featherdyn Model, got {type(model).__name__}")
    given = dict(zip(decl.inputs, args, strict=True))
    fx = check_f_ext(model, given.get("f_ext")) if "f_ext" in given else None
    if "f_ext" in given and fx is None and "f_ext" not in decl.optional:
        raise ShapeError(f"f_ext: expected an array of shape (..., nb={model.nbodies}, 6), got None")
    vectors = {n: given[n] for n in decl.inputs if n in ("v", "a", "tau")}
    st = check_state(model, given["q"], optional=decl.optional, **vectors)
    batch, dtype = batch_with_f_ext(st, fx)
    checked = [fx if n == "f_ext" else st.q if n == "q" else st.arrays.get(n) for n in decl.inputs]
    # 4. backend, 5. call
    if select_backend(backend, dtype) == "compiled":
        f64 = [None if x is None else np.asarray(x, dtype=np.float64) for x in checked]
        outs = tuple(as_dtype(o, dtype) for o in _declared.run(decl.name, model, batch, f64))
    else:
        r = quiet(decl.reference, model, *checked)
        outs = tuple(finite_result(np.asarray(o), decl.name) for o in (r if isinstance(r, tuple) else (r,)))
    if out is None:
        return _result(decl, outs)
    # 6. out=: written after the computation (so an out sharing memory with an input changes nothing)
    arrays = _out_arrays(decl, out)
    for name, dst, src in zip(decl.outputs, arrays, outs, strict=True):
        if dst.shape != src.shape:
            raise ShapeError(f"out: expected shape {src.shape} for {name}, got {dst.shape}")
        if not np.can_cast(src.dtype, dst.dtype, casting="same_kind"):
            raise DTypeError(f"out: cannot write {src.dtype} results for {name} into a {dst.dtype} array")
        np.copyto(dst, src)
    return out


def _signature(decl: Declaration, bound: bool) -> inspect.Signature:
    P = inspect.Parameter
    params = [] if bound else [P("model", P.POSITIONAL_OR_KEYWORD, annotation="Model")]
    for n in decl.inputs:
        params.append(P(n, P.POSITIONAL_OR_KEYWORD, default=None if n in decl.optional else P.empty,
                        annotation="ArrayLike | None" if n in decl.optional else "ArrayLike"))
    params.append(P("out", P.KEYWORD_ONLY, default=None))
    if not bound:
        params.append(P("backend", P.KEYWORD_ONLY, default=None, annotation="str | None"))
    return inspect.Signature(params)


def _bind(decl: Declaration, sig: inspect.Signature, args: tuple[Any, ...], kwargs: dict[str, Any]) -> inspect.BoundArguments:
    try:
        ba = sig.bind(*args, **kwargs)
    except TypeError as exc:
        raise TypeError(f"{decl.name}(): {exc}") from None
    ba.apply_defaults()
    return ba


def _finished_in_c(general: Callable[..., Any], kernel: Any, extra: tuple[Any, ...], bound: Any) -> Any:
    """``general`` with its common one-state call (the inputs by position, nothing else) finished in the core.

    The core's public-call object (``core/cpp/public_calls.hpp``) binds the arguments and runs the kernel's
    ``fresh`` path in C; every other call — ``out=``, ``backend=``, conversions, a bad state, the reference
    as the default backend — goes to ``general`` with the same arguments. Without the core, ``general``.
    """
    if kernel is None:
        return general
    fast = CORE.declared_call(kernel, general, extra, bound)
    functools.update_wrapper(fast, general)
    return fast


def public_function(decl: Declaration) -> Callable[..., Any]:
    """``fd.<name>(model, *inputs, out=None, backend=None)``, made from ``decl``."""
    sig = _signature(decl, bound=False)

    def general(*args: Any, **kwargs: Any) -> Any:
        ba = _bind(decl, sig, args, kwargs)
        a = ba.arguments
        return call(decl, a["model"], tuple(a[k] for k in decl.inputs), a["out"], a["backend"])

    general.__name__ = general.__qualname__ = decl.name
    general.__module__ = "featherdyn"
    general.__doc__ = decl.doc
    general.__signature__ = sig  # type: ignore[attr-defined]
    kernel = _declared.kernel(decl.name)
    public = _PUBLIC[decl.name] = _finished_in_c(general, kernel, (CoreHandle, kernel), None)
    return cast(Callable[..., Any], public)


def compiled_method(decl: Declaration, model: Model) -> Callable[..., Any]:
    """``fd.compile(model).<name>(*inputs, out=None)``: the declared call bound to ``model``."""
    sig = _signature(decl, bound=True)

    def general(*args: Any, **kwargs: Any) -> Any:
        ba = _bind(decl, sig, args, kwargs)
        return call(decl, model, tuple(ba.arguments[k] for k in decl.inputs), ba.arguments["out"])

    general.__name__ = general.__qualname__ = decl.name
    general.__doc__ = decl.doc
    general.__signature__ = sig  # type: ignore[attr-defined]
    kernel = _declared.kernel(decl.name)
    h = core_path(model, None) if kernel is not None else None
    return cast(Callable[..., Any], _finished_in_c(general, kernel if h is not None else None, (kernel,),
                                                   h.cm if h is not None else None))
