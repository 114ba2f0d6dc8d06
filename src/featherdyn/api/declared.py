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
   returns ``None`` (or a non-zero status) for anything else, which goes on;
2. **Dask**: a Dask array among the state arguments hands the call to ``_dask.call``;
3. **checks**: ``f_ext`` and the state, worded by the public checks (``_state_checks``);
4. **backend**: ``select_backend`` — the core for float64, the reference otherwise;
5. **call**: the core's batch on the thread pool (``core.declared.run``: any batch shape;
   a failing row words the reference's error) or the reference function;
6. **out=**: the result written into the given arrays (an array for each output the call forms; a function
   whose result is a record returns it made of them). One rule for an ``out`` that shares
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
from ..errors import DTypeError, NotAModelError, ShapeError
from ..frames import LOCAL, LOCAL_WORLD_ALIGNED, WORLD, as_reference_frame
from ..model import Model
from ._backend import CORE, core_path, select_backend
from ._checks import (
    VECTORS,
    State,
    as_dtype,
    batch_with_f_ext,
    batch_with_point,
    check_f_ext,
    check_point,
    check_state,
    finite_result,
    quiet,
)

__all__ = ["Declaration", "Record", "AFTER_OPTIONS", "call", "public_function", "compiled_method", "kernel_options",
           "positional_parameters", "xla_ffi", "xla_entry", "operand_shapes"]

#: the state arguments a declaration may take, and how each is checked: a configuration (length nq, unit quaternions:
#: q, or q0 and q1), a vector of length nv (w: a cotangent, fd.rnea_vjp's), a matrix (nv, nv) (W: a cotangent,
#: fd.crba_vjp's), f_ext, or a point (3) in the frame's coordinates (fd.kinematics_derivatives')
STATE_ARGUMENTS = ("q", "q0", "q1", "v", "a", "tau", "w", "W", "f_ext", "point")
#: the inputs that come after the options in the public signatures (a point follows the frame it is in:
#: ``fd.kinematics_derivatives(model, q, v, a, frame, reference, point)``), as the core's operands say
#: (``Operand::after_options``, ``core/cpp/declare.hpp``); the reference function takes them by name
AFTER_OPTIONS = ("point",)
#: the options a declaration may take, and their defaults (``frame`` has none: it is required)
OPTIONS: dict[str, Any] = {"frame": inspect.Parameter.empty, "reference": LOCAL, "gravity": True}


@dataclass(frozen=True)
class Record:
    """The object a declaration's outputs make (``Declaration.result``): a new ``cls`` (``object.__new__``: its
    ``__init__`` is not called) with each of ``fields`` — ``(field, source)`` — set as ``object.__setattr__`` sets
    it to an output (``source`` its name; the array made read-only, as a record's arrays are), the model
    (``"model"``) or ``None``. Made in C for the one-state call (``core/cpp/bind_public_calls.cpp``), here for the
    others."""

    cls: type
    fields: tuple[tuple[str, str | None], ...]

    def make(self, model: Model, outputs: dict[str, Any]) -> Any:
        obj: Any = object.__new__(self.cls)
        for field, source in self.fields:
            value = model if source == "model" else None if source is None else outputs[source]
            if isinstance(value, np.ndarray):
                value.flags.writeable = False
            object.__setattr__(obj, field, value)
        return obj

    def constants(self, decl: Declaration, model: Model | None) -> tuple[Any, ...]:
        """The record as the core's public call reads it: ``(cls, (field, source), ...)``, each source an output's
        index, ``-1`` for the model argument (``model`` itself for a bound method) or ``None``."""
        index = {n: k for k, n in enumerate(decl.outputs)}
        return (self.cls, *((f, (-1 if model is None else model) if s == "model" else None if s is None else index[s])
                            for f, s in self.fields))


@dataclass(frozen=True)
class Declaration:
    """An algorithm, declared once.

    Attributes:
        name: the public name (``fd.<name>``) and the name of the core's kernel.
        inputs: the state arguments in order, each one of ``q, q0, q1, v, a, tau, w, W, f_ext, point``, the first a
            configuration (``q``, or ``q0`` followed by ``q1``: two configurations, ``fd.difference``'s); those of
            :data:`AFTER_OPTIONS` last (the public signatures place them after the options).
        optional: the inputs that may be ``None``.
        outputs: the names of the results, in order (their shapes are the kernel's).
        reference: the reference function ``reference(model, *inputs) -> output or tuple of outputs`` on
            checked arrays (``featherdyn.algorithms``).
        doc: the public function's docstring (shapes and the defining equation).
        optional: the inputs that may be ``None``.
        options: the scalar parameters it takes besides the state (``gravity``: keyword-only, default ``True``),
            passed by name to the kernel and to the reference.
        method: the name of ``fd.compile(model)``'s method, when not ``name``.
        result: what the outputs make (``None``: the output, or the tuple of them): a :class:`Record`, or a function
            of the outputs (``None`` for one formed only with an absent input). With ``out=`` (an array for each
            output formed) it is made of the given arrays (:func:`_written`).
        needs: ``(x, y)`` pairs of optional inputs: ``x`` is only taken with ``y`` (``a`` needs ``v``).
        derivative: the declared function whose outputs are the derivatives of this one's output with respect to
            each of its state inputs but ``f_ext``, in order (``∂/∂q`` along the tangent of ``fd.integrate``, for
            every configuration input and for a configuration output: ``integrate`` → ``integrate_derivatives``), when
            there is one: ``rnea`` → ``rnea_derivatives`` (∂τ/∂q, ∂τ/∂q̇, ∂τ/∂q̈). The frameworks' operations take
            their gradients from it.
    """

    name: str
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    reference: Callable[..., Any]
    doc: str
    optional: tuple[str, ...] = ()
    options: tuple[str, ...] = ()
    method: str | None = None
    derivative: str | None = None
    result: Record | Callable[..., Any] | None = None
    needs: tuple[tuple[str, str], ...] = ()

    def __post_init__(self) -> None:
        unknown = [n for n in self.inputs if n not in STATE_ARGUMENTS]
        after = [n in AFTER_OPTIONS for n in self.inputs]
        if (unknown or self.inputs[:1] not in (("q",), ("q0",)) or ("q0" in self.inputs) != ("q1" in self.inputs)
                or not set(self.optional) <= set(self.inputs) or after != sorted(after)):
            raise ValueError(f"declaration {self.name!r}: inputs must be among {STATE_ARGUMENTS}, q or q0 (with q1) "
                             f"first, {AFTER_OPTIONS} last")
        if not set(self.options) <= set(OPTIONS):
            raise ValueError(f"declaration {self.name!r}: options must be among {tuple(OPTIONS)}")


def _result(decl: Declaration, model: Model, outs: tuple[Any, ...]) -> Any:
    if isinstance(decl.result, Record):
        return decl.result.make(model, dict(zip(decl.outputs, outs, strict=True)))
    if decl.result is not None:
        return decl.result(*outs)
    return outs[0] if len(decl.outputs) == 1 else outs


def _formed(decl: Declaration, given: dict[str, Any]) -> tuple[str, ...] | None:
    """The outputs a call forms: every one, but one formed only with an optional input that is not given (the
    kernel's declaration says which: ``fd.forward_kinematics``' ``vel`` needs ``v``). ``None`` without the core:
    the reference's results tell, after it ran (:func:`call`, step 6)."""
    spec = _declared.SPECS.get(decl.name)
    if spec is None:
        return None
    return tuple(name for name, _, when in spec.outputs if when is None or given.get(when) is not None)


def _out_arrays(decl: Declaration, out: Any, formed: tuple[str, ...] | None) -> tuple[np.ndarray | None, ...]:
    """``out`` — an array for each output the call forms, in the declared order (one array bare where it forms
    one) — as the tuple the kernel takes: one entry per declared output, ``None`` for one not formed. A result of
    the function whose fields are its outputs (a ``NamedTuple``: ``fd.RneaSecondDerivatives``) is such a tuple.
    With ``formed`` unknown (``None``), the arrays as given, checked but for their number."""
    names = decl.outputs if formed is None else formed
    arrays = tuple(out) if isinstance(out, (tuple, list)) else (out,)
    if formed is not None and len(arrays) != len(formed):
        raise ShapeError(f"out: expected {'an array' if len(names) == 1 else f'{len(names)} arrays'} "
                         f"for {', '.join(names)}, got {type(out).__name__}"
                         + (f" of {len(arrays)}" if isinstance(out, (tuple, list)) else ""))
    for k, a in enumerate(arrays):
        name = names[k] if k < len(names) else f"#{k}"
        if type(a) is not np.ndarray:
            raise ShapeError(f"out: expected a NumPy array for {name}, got {type(a).__name__}")
        if not a.flags.writeable:
            raise ShapeError(f"out: the array for {name} is read-only")
        for j, b in enumerate(arrays[:k]):
            if np.may_share_memory(a, b):
                raise ShapeError(f"out: the arrays for {names[j]} and {name} share memory")
    if formed is None:
        return arrays
    by_name = dict(zip(formed, arrays, strict=True))
    return tuple(by_name.get(name) for name in decl.outputs)


def _written(decl: Declaration, model: Model, out: Any, arrays: tuple[np.ndarray | None, ...]) -> Any:
    """What a call with ``out=`` returns: ``out`` itself, or the result the declaration makes of the arrays (a
    :class:`Record` of read-only views of them, as a record's arrays are read-only; a ``NamedTuple`` of them)."""
    if decl.result is None:
        return out
    if isinstance(decl.result, Record):
        arrays = tuple(None if a is None else a.view() for a in arrays)
    return _result(decl, model, arrays)


def _options(decl: Declaration, model: Model, given: dict[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """The declaration's options as the kernel takes them and as the reference function does: ``gravity``
    ``True`` or ``False`` (or 1, 0) for both; ``frame`` (a name or an index) its index for both; ``reference``
    (``fd.LOCAL`` & co. or their names) its code for the kernel, the :class:`ReferenceFrame` for the reference."""
    kernel: dict[str, Any] = {}
    reference: dict[str, Any] = {}
    for name in decl.options:
        value = given.get(name, OPTIONS[name])
        if name == "gravity":
            if not (isinstance(value, (bool, np.bool_)) or (type(value) is int and value in (0, 1))):
                raise DTypeError(f"gravity: expected True or False, got {type(value).__name__} {value!r}")
            kernel[name] = reference[name] = bool(value)
        elif name == "frame":
            kernel[name] = reference[name] = model.resolve_frame(value)
        else:
            ref = as_reference_frame(value)
            kernel[name], reference[name] = ref.code, ref
    return kernel, reference


def kernel_options(decl: Declaration, model: Model, given: dict[str, Any]) -> dict[str, Any]:
    """The declaration's options as the core's kernels take them (``frame`` its index, ``reference`` its code),
    checked as the public functions check them: for the other front ends (``featherdyn.jax``)."""
    return _options(decl, model, given)[0]


def xla_ffi() -> tuple[Any, dict[str, int]] | None:
    """The core's XLA FFI handler of every declared algorithm (a capsule: ``core/cpp/bind_jax.cpp``) and each
    kernel's index for it; ``None`` when the core was built without XLA's FFI headers (or is not built)."""
    if CORE is None or not hasattr(CORE, "jax_handler"):
        return None
    return CORE.jax_handler(), {name: k for k, name in enumerate(CORE.kernel_order)}


def xla_entry(model: Model, options: dict[str, Any]) -> int:
    """Register ``model`` and a call's kernel options (:func:`kernel_options`) for the XLA FFI handler: its key.
    The caller keeps ``model`` alive (the entry holds the core's view of it, not the model)."""
    from ..core import _view

    return int(CORE.jax_entry(_view(model).cm, _declared.call_options(**options)))


def operand_shapes(name: str, model: Model, rows: int = 0) -> tuple[list[tuple[int, ...]], list[tuple[int, ...]]]:
    """The declared kernel ``name``'s input and output shapes for ``model`` (one state; ``rows``: the constraint rows
    ``m`` of a contact kernel)."""
    from ..core import _view

    spec, h = _declared.SPECS[name], _view(model)
    return ([_declared.shape_of(h, shape, rows) for _, shape, _ in spec.inputs],
            [_declared.shape_of(h, shape, rows) for _, shape, _ in spec.outputs])


def _writable_as_is(arrays: tuple[np.ndarray | None, ...] | None) -> bool:
    """Whether the core may write a batch into ``out``'s arrays as they are (C-contiguous, aligned, native
    float64); else the results are computed into fresh memory and copied (``call``, step 6)."""
    return arrays is not None and all(a is None or (a.dtype == np.float64 and a.dtype.isnative
                                                    and a.flags.c_contiguous and a.flags.aligned) for a in arrays)


#: the reference frames by their codes (the core's public calls read them by identity)
REFERENCES = (LOCAL, WORLD, LOCAL_WORLD_ALIGNED)

#: the public function of each declaration (Dask's blocks call it)
_PUBLIC: dict[str, Callable[..., Any]] = {}


def call(decl: Declaration, model: Model, args: tuple[Any, ...], out: Any = None, backend: str | None = None,
         options: dict[str, Any] | None = None, float64: bool = False) -> Any:
    """The declared algorithm on ``args`` (its inputs in order) with ``options`` (by name): the one path of every
    front end (module docstring). ``float64``: the core on any input that has float64 values, results in float64
    (``fd.compile``'s methods), where ``backend="compiled"`` returns float32 results for float32 input."""
    if not isinstance(model, Model):
        raise NotAModelError(f"model: expected a featherdyn Model, got {type(model).__name__}")
    given_options = options or {}
    opts, ref_opts = _options(decl, model, given_options)
    # (which outputs the call forms matters only to an out=; None there without the core: known after step 5)
    formed = None if out is None else _formed(decl, dict(zip(decl.inputs, args, strict=True)))
    arrays = None if out is None else _out_arrays(decl, out, formed)
    # 1. one state: the core takes the arguments as they are, or declines (None, or a non-zero status)
    h = core_path(model, backend)
    if h is not None:
        kernel = _declared.kernel(decl.name)
        core_opts = _declared.call_options(**opts)
        if arrays is None:
            r = kernel.fresh(h.cm, args, core_opts)
            if r is not None:
                return r if decl.result is None else _result(decl, model, r if len(decl.outputs) > 1 else (r,))
        elif kernel.into(h.cm, args, arrays, core_opts) == 0:
            return _written(decl, model, out, arrays)
    given = dict(zip(decl.inputs, args, strict=True))
    for x, y in decl.needs:
        if given[x] is not None and given[y] is None:
            raise ShapeError(f"{x}: needs {y} as well (got {y}=None)")
    # 2. Dask
    if _dask.lazy(*args):
        if out is not None:
            raise ShapeError("out: not supported with Dask arrays (the result is a Dask array)")
        return _dask.call(_PUBLIC[decl.name], model, dict(zip(decl.inputs, args, strict=True)), backend=backend,
                          **given_options)
    # 3. checks: f_ext, then the state, as every public function words them (their values only where the core
    # does not check them itself: it checks every state, and its error path words what it finds as these do)
    first = decl.inputs[0]  # the configuration q (or q0; a second one, q1, is checked among the vectors, as q is)
    vectors = {n: given[n] for n in decl.inputs if n in VECTORS}

    def checked_state(values: bool) -> tuple[np.ndarray | None, State, np.ndarray | None]:
        fx = check_f_ext(model, given.get("f_ext"), values) if "f_ext" in given else None
        if "f_ext" in given and fx is None and "f_ext" not in decl.optional:
            raise ShapeError(f"f_ext: expected an array of shape (..., nb={model.nbodies}, 6), got None")
        st = check_state(model, given[first], optional=decl.optional, values=values, name=first, **vectors)
        return fx, st, check_point(given.get("point"), values)

    fx, st, point = checked_state(False)
    batch, dtype = batch_with_point(*batch_with_f_ext(st, fx), point)
    # 4. backend, 5. call
    compiled = float64 or select_backend(backend, dtype) == "compiled"
    if not compiled:
        fx, st, point = checked_state(True)
    checked = [fx if n == "f_ext" else point if n == "point" else st.q if n == first else st.arrays.get(n)
               for n in decl.inputs]
    if compiled:
        dtype = np.dtype(np.float64) if float64 else dtype
        f64 = [None if x is None else np.asarray(x, dtype=np.float64) for x in checked]
        into = arrays if dtype == np.float64 and _writable_as_is(arrays) else None
        outs = _declared.run(decl.name, model, batch, f64, out=into, options=opts)
        if into is not None:  # written by the core (an out over an input: through fresh memory, declared.run's rule)
            return _written(decl, model, out, into)
        outs = tuple(None if o is None else as_dtype(o, dtype) for o in outs)
    else:
        after = {n: x for n, x in zip(decl.inputs, checked, strict=True) if n in AFTER_OPTIONS}  # (by name)
        leading = checked[:len(checked) - len(after)]
        reference = functools.partial(decl.reference, **ref_opts, **after) if ref_opts or after else decl.reference
        r = quiet(reference, model, *leading)
        outs = tuple(None if o is None else
                     finite_result(as_dtype(np.asarray(o), dtype) if dtype.kind == "f" else np.asarray(o), decl.name)
                     for o in (r if isinstance(r, tuple) else (r,)))
    if out is None:
        return _result(decl, model, outs)
    # 6. out=: written after the computation (so an out sharing memory with an input changes nothing)
    assert arrays is not None
    return _copied_into(decl, model, out, arrays, formed, outs)


def _copied_into(decl: Declaration, model: Model, out: Any, arrays: tuple[np.ndarray | None, ...],
                 formed: tuple[str, ...] | None, outs: tuple[Any, ...]) -> Any:
    """:func:`call`'s step 6: the results ``outs`` copied into ``out``'s arrays (:func:`_out_arrays`), and what the
    call then returns."""
    if formed is None:  # without the core: the outputs formed are those the reference returned
        formed = tuple(name for name, o in zip(decl.outputs, outs, strict=True) if o is not None)
        if len(arrays) != len(formed):
            raise ShapeError(f"out: expected {len(formed)} array(s) for {', '.join(formed)}, got {len(arrays)}")
        by_name = dict(zip(formed, arrays, strict=True))
        arrays = tuple(by_name.get(name) for name in decl.outputs)
    for name, dst, src in zip(decl.outputs, arrays, outs, strict=True):
        if dst is None or src is None:
            continue
        if dst.shape != src.shape:
            raise ShapeError(f"out: expected shape {src.shape} for {name}, got {dst.shape}")
        if not np.can_cast(src.dtype, dst.dtype, casting="safe"):
            raise DTypeError(f"out: cannot write {src.dtype} results for {name} into a {dst.dtype} array")
        np.copyto(dst, src)
    return _written(decl, model, out, arrays)


def positional_parameters(decl: Declaration) -> tuple[str, ...]:
    """The names a declared function takes by position after the model, in order: its inputs, ``frame`` and
    ``reference`` where it takes them, then the inputs of :data:`AFTER_OPTIONS` (the core's public calls bind the
    same order: ``core/cpp/declare.hpp``, ``Slots``)."""
    after = tuple(n for n in decl.inputs if n in AFTER_OPTIONS)
    return (tuple(n for n in decl.inputs if n not in AFTER_OPTIONS)
            + tuple(n for n in ("frame", "reference") if n in decl.options) + after)


def _signature(decl: Declaration, bound: bool) -> inspect.Signature:
    P = inspect.Parameter
    params = [] if bound else [P("model", P.POSITIONAL_OR_KEYWORD, annotation="Model")]
    for n in positional_parameters(decl):
        if n in decl.inputs:
            params.append(P(n, P.POSITIONAL_OR_KEYWORD, default=None if n in decl.optional else P.empty,
                            annotation="ArrayLike | None" if n in decl.optional else "ArrayLike"))
        else:
            params.append(P(n, P.POSITIONAL_OR_KEYWORD, default=OPTIONS[n],
                            annotation="str | int" if n == "frame" else "ReferenceFrame | str"))
    if bound:  # fd.compile's methods take out by position too (as the core binds them)
        params.append(P("out", P.POSITIONAL_OR_KEYWORD, default=None))
    if "gravity" in decl.options:
        params.append(P("gravity", P.KEYWORD_ONLY, default=True, annotation="bool"))
    if not bound:
        params.append(P("out", P.KEYWORD_ONLY, default=None))
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


def _constants(decl: Declaration, model: Model | None) -> Any:
    """The record's constants for the core's public call (``None``, the function, or :meth:`Record.constants`)."""
    return decl.result.constants(decl, model) if isinstance(decl.result, Record) else decl.result


def public_function(decl: Declaration) -> Callable[..., Any]:
    """``fd.<name>(model, *inputs, out=None, backend=None)``, made from ``decl``."""
    sig = _signature(decl, bound=False)

    def general(*args: Any, **kwargs: Any) -> Any:
        ba = _bind(decl, sig, args, kwargs)
        a = ba.arguments
        return call(decl, a["model"], tuple(a[k] for k in decl.inputs), a.get("out"), a["backend"],
                    {n: a[n] for n in decl.options})

    general.__name__ = general.__qualname__ = decl.name
    general.__module__ = "featherdyn"
    general.__doc__ = decl.doc
    general.__signature__ = sig  # type: ignore[attr-defined]
    kernel = _declared.kernel(decl.name)
    public = _PUBLIC[decl.name] = _finished_in_c(general, kernel, (CoreHandle, kernel, *REFERENCES,
                                                                   _constants(decl, None)), None)
    return cast(Callable[..., Any], public)


def compiled_method(decl: Declaration, model: Model) -> Callable[..., Any]:
    """``fd.compile(model).<name>(*inputs, out=None)``: the declared call bound to ``model``."""
    sig = _signature(decl, bound=True)

    def general(*args: Any, **kwargs: Any) -> Any:
        a = _bind(decl, sig, args, kwargs).arguments
        return call(decl, model, tuple(a[k] for k in decl.inputs), a.get("out"), None, {n: a[n] for n in decl.options},
                    float64=True)

    general.__name__ = decl.method or decl.name
    general.__qualname__ = f"CompiledModel.{general.__name__}"
    general.__doc__ = decl.doc
    general.__signature__ = sig  # type: ignore[attr-defined]
    kernel = _declared.kernel(decl.name)
    h = core_path(model, None) if kernel is not None else None
    return cast(Callable[..., Any], _finished_in_c(general, kernel if h is not None else None,
                                                   (kernel, h.frames if h is not None else {}, *REFERENCES,
                                                    _constants(decl, model)),
                                                   h.cm if h is not None else None))
