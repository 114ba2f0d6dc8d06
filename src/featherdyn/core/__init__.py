"""The compiled core: C++ kernels of the dynamics algorithms, built at install (no JIT).

Each kernel is written once, templated on the scalar type, in the reference's order and symbols
(``featherdyn/algorithms``; ``docs/architecture.md``), in body coordinates. This module is its Python side: one
function per kernel declared in ``core/cpp/declarations.hpp`` (made by ``_declared``: one state or any batch
shape, on the core's thread pool), and the constraint solves written below. Arguments are converted to what the
binding reads as it is — native-endian, aligned, C-contiguous float64 (lists, float32, big-endian, strided arrays
are copied; object arrays that cannot become float64 raise :class:`~featherdyn.errors.DTypeError`) — and a
status becomes the reference's exception and message. Results are float64; ``out=`` gives the arrays to write
into. Conventions: motion ``[ω; v]``, force ``[n; f]``, free-flyer ``q = [p, quat xyzw]`` and ``v = [ω; v]`` in
the base frame, gravity from ``model.gravity`` entered as a base acceleration ``−g``.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

import numpy as np

from ..errors import DTypeError, ShapeError
from ..frames import LOCAL, as_reference_frame
from ..model import Model
from ..spatial.validation import as_array
from . import _errors, declared
from ._model_view import CoreHandle, model_view

_core: Any
try:
    from . import _core  # the compiled extension (no stub: typed Any above)
except ImportError:  # pragma: no cover - a source checkout without the built extension
    _core = None

__all__ = [  # and one function per declared kernel (below)
    "available",
    "rnea_complex",
    "delassus",
    "constrained_solve",
    "contact_dynamics",
    "set_num_threads",
    "get_num_threads",
    *(name for name, spec in declared.SPECS.items() if not spec.constrained),
]

_F64 = np.dtype(np.float64)


def available() -> bool:
    """Whether the compiled extension ``featherdyn.core._core`` is importable."""
    return _core is not None


def _lib() -> Any:
    if _core is None:
        from ..errors import MissingDependencyError

        raise MissingDependencyError("featherdyn.core._core is not built; reinstall featherdyn with pip")
    return _core


def _view(model: Model) -> CoreHandle:
    if not isinstance(model, Model):
        raise ShapeError(f"model: expected a featherdyn Model, got {type(model).__name__}")
    return model_view(model, _lib())


def _f64(x: Any, name: str) -> np.ndarray:
    """``x`` as a native-endian, aligned, C-contiguous float64 array; no copy when it already is one."""
    if type(x) is np.ndarray and x.dtype == _F64 and x.dtype.isnative and x.flags.c_contiguous and x.flags.aligned:
        return x
    arr = as_array(x, name, check_finite=False)  # the reference's DTypeError / ShapeError for unreadable input
    try:
        return np.array(arr, dtype=np.float64, order="C")  # a fresh array: native, aligned, contiguous
    except (TypeError, ValueError) as exc:
        raise DTypeError(f"{name}: the compiled core computes in float64 and cannot convert this ({exc}); "
                         "use the reference algorithms for symbolic input") from None


def _batch_shape(model: Model, arrays: list[tuple[np.ndarray, int]], q: Any, vectors: list[tuple[str, Any]],
                 f_ext: Any, name: str = "q") -> tuple[int, ...]:
    """The broadcast batch shape of ``(array, trailing ndim)`` pairs; the reference's error when there is none."""
    try:
        return np.broadcast_shapes(*(a.shape[: a.ndim - k] for a, k in arrays))
    except ValueError:
        _errors.validate(model, q, vectors, f_ext, name)
        raise


# ---------------------------------------------------------------------------
# the declared algorithms (core/cpp/declarations.hpp): one generic function each
# ---------------------------------------------------------------------------


def _declared(name: str, doc: str) -> Callable[..., Any]:
    """``featherdyn.core.<name>(model, *inputs, *options, out=None)`` of the declared kernel ``name``.

    The inputs in the declaration's order (optional ones may be omitted or ``None``), then its options
    (``frame`` a name or index, ``reference`` a code or ``fd.LOCAL`` & co., ``gravity``), then ``out``; one state or
    any batch shape (leading axes, broadcast), converted as the module docstring says. One state is first handed
    to the kernel as it is (``Kernel.fresh`` / ``into``).
    """
    spec = declared.SPECS[name]
    P = inspect.Parameter
    required = {n for n, _, opt in spec.inputs if not opt} | {"frame"}  # (in the order of the public call's)
    sig = inspect.Signature([P("model", P.POSITIONAL_OR_KEYWORD)] + [
        P(n, P.POSITIONAL_OR_KEYWORD, **({} if n in required else {"default": None})) for n in spec.parameters])

    def function(*args: Any, **kwargs: Any) -> Any:
        _lib()
        try:
            given = sig.bind(*args, **kwargs).arguments
        except TypeError as exc:
            raise TypeError(f"{name}(): {exc}") from None
        model, out = given["model"], given.get("out")
        h = _view(model)  # a Model (ShapeError otherwise)
        options: dict[str, Any] = {}
        if "frame" in spec.options:
            options["frame"] = model.resolve_frame(given["frame"])
        if "reference" in spec.options:
            ref = given.get("reference") or LOCAL
            options["reference"] = ref if type(ref) is int and 0 <= ref <= 2 else as_reference_frame(ref).code
        if "gravity" in spec.options:
            options["gravity"] = bool(given.get("gravity", True))
        inputs = [given.get(n) for n in spec.input_names]
        xs = [None if x is None else _f64(x, n) for x, n in zip(inputs, spec.input_names, strict=True)]
        outs = None if out is None else tuple(out) if isinstance(out, (tuple, list)) else (out,)
        # one state as the kernel takes it (out=: arrays of the exact shapes); anything else: the batch below
        if outs is None:
            r = spec.kernel.fresh(h.cm, xs, declared.call_options(**options))
            if r is not None:
                return r
        elif spec.kernel.into(h.cm, xs, list(outs), declared.call_options(**options)) == 0:
            return out
        vectors = [(n, x) for n, x in zip(spec.input_names, inputs, strict=True) if n in _errors.VECTORS]  # (q1 too)
        tails = [len(s) for _, s, _ in spec.inputs]
        batch = _batch_shape(model, [(x, t) for x, t in zip(xs, tails, strict=True) if x is not None],
                             given[spec.input_names[0]], vectors, given.get("f_ext"), spec.input_names[0])
        r = declared.run(name, model, batch, xs, outs, options)  # (out over an input: declared.run's one rule)
        return out if out is not None else r[0] if len(r) == 1 else r

    function.__name__ = function.__qualname__ = name
    function.__doc__ = doc
    function.__signature__ = sig  # type: ignore[attr-defined]
    return function


def _signature_doc(spec: declared.Spec) -> str:
    """The declared kernel's call and shapes, from its declaration: the function's docstring."""
    def shape(s: tuple[Any, ...]) -> str:
        return "(..., " + ", ".join(str(d) for d in s) + ")" if s else "(...)"

    inputs = {n: f"{n} {shape(s)}" + (" | None" if opt else "") for n, s, opt in spec.inputs}
    args = [inputs.get(n, f"{n}=...") for n in spec.parameters]
    outs = [f"{n} {shape(s)}" + ("" if when is None else f" (with {when}, else None)") for n, s, when in spec.outputs]
    return (f"``{spec.kernel.name}(model, {', '.join(args)})`` → {', '.join(outs)}: the compiled core's kernel "
            f"declared in ``core/cpp/declarations.hpp`` (its equation there and at ``featherdyn.{spec.kernel.name}``).")


#: (typed here for the modules that call them; made below as every declared kernel's function is)
mass_solve: Callable[..., Any]

for _name, _spec in declared.SPECS.items():  # one function per declared kernel (rnea, crba, aba, ...)
    if not _spec.constrained:  # (the constraint family's are written below: their rows m come from J or specs)
        globals()[_name] = _declared(_name, _signature_doc(_spec))


def rnea_complex(model: Model, q: Any, v: Any, a: Any, f_ext: Any = None, gravity: bool = True) -> np.ndarray:
    """:func:`rnea` of one state in complex arithmetic `(nv,)` complex128 — the same template as the float64 kernel.

    For complex-step derivatives: ``Im rnea(q + i h δq) / h ≈ ∂τ/∂q δq`` (joint angles;
    quaternions must stay unit to first order). No finiteness or quaternion checks.
    """
    h = _view(model)

    def c128(x: Any) -> np.ndarray:
        return np.array(x, dtype=np.complex128, order="C")

    tau = np.empty(h.nv, dtype=np.complex128)
    s = _core.rnea_complex(h.cm, c128(q), c128(v), c128(a), None if f_ext is None else c128(f_ext), bool(gravity),
                           tau)
    if s:
        _errors.raise_for(s, model, np.real(q), [("v", np.real(v)), ("a", np.real(a))],
                          None if f_ext is None else np.real(f_ext))
    return tau


def _rows_of(J: Any, nv: int) -> tuple[np.ndarray, int]:
    """``J`` `(..., m, nv)` as float64 and its rows ``m``."""
    J_ = _f64(J, "J")
    if J_.ndim < 2 or J_.shape[-1] != nv:
        raise ShapeError(f"J: expected shape (..., m, {nv}), got {J_.shape}")
    return J_, J_.shape[-2]


def _solved(name: str, model: Model, q: Any, v: Any, tau: Any, f_ext: Any, extra: list[tuple[np.ndarray, int]],
            options: dict[str, Any], max_iter: int, tol: float, check: bool = True
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(q̈, λ, info)`` of the declared KKT solve ``name`` on the state and the ``extra`` inputs (array, trailing
    ndim); ``check``: a state whose rows are dependent (``mu = 0``) or did not converge raises."""
    from ..constraints import solver_settings
    from ..errors import ConstraintError
    from ..tolerances import DELASSUS_PIVOT_RTOL

    mu, max_iter, tol = solver_settings(options.pop("mu"), max_iter, tol)
    xs = [_f64(q, "q"), _f64(v, "v"), _f64(tau, "tau"), None if f_ext is None else _f64(f_ext, "f_ext")]
    state = [(x, k) for x, k in zip(xs, (1, 1, 1, 2), strict=True) if x is not None]
    batch = _batch_shape(model, state, q, [("v", v), ("tau", tau)], f_ext)
    try:
        batch = np.broadcast_shapes(batch, *(x.shape[: x.ndim - k] for x, k in extra))
    except ValueError:
        raise ShapeError(f"the rows {[x.shape for x, _ in extra]} and the state {batch}: batch shapes that do not "
                         "broadcast") from None
    qdd, lam, info = declared.run(name, model, batch, xs + [x for x, _ in extra],
                                  options={**options, "mu": mu, "max_iter": max_iter, "tol": tol,
                                           "singular_tol": DELASSUS_PIVOT_RTOL})
    if check:
        ConstraintError.check_iterations(info[..., 0], lam.shape[-1], max_iter, tol)
    return qdd, lam, info


def delassus(model: Model, q: Any, J: Any) -> np.ndarray:
    """``J M(q)⁻¹ Jᵀ`` `(..., m, m)` for ``J`` `(..., m, nv)`, without forming M⁻¹ (the declared ``delassus``)::

        J M⁻¹ Jᵀ = (J L⁻¹)(J L⁻¹)ᵀ,   M = Lᵀ L
    """
    J_, m = _rows_of(J, model.nv)
    q_ = _f64(q, "q")
    batch = _batch_shape(model, [(q_, 1), (J_, 2)], q, [], None)
    return declared.run("delassus", model, batch, [q_, J_], options={"rows": m})[0]


def constrained_solve(model: Model, q: Any, v: Any, tau: Any, J: Any, c: Any, f_ext: Any = None, *, mu: float = 0.0,
                      max_iter: int = 50, tol: float = 1e-12) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(q̈, λ, residual)`` of ``M q̈ + h = τ + Jᵀ λ`` and ``J q̈ = c`` for ``J`` `(..., m, nv)`, ``c`` `(..., m)`.

    By the Schur complement on M's tree-sparse factor (M is never inverted; the declared ``constrained_solve``)::

        q̈_f = M⁻¹ (τ − h),   D = J M⁻¹ Jᵀ,   D λ = c − J q̈_f,   q̈ = q̈_f + M⁻¹ Jᵀ λ

    ``mu > 0``: proximal iterations ``λ ← (D + μ1)⁻¹ (c − J q̈_f + μ λ)`` (Carpentier, Budhiraja & Mansard,
    RSS 2021), which converge to the minimum-norm λ when rows are dependent. ``residual`` `(...)`:
    ``max |J q̈ − c|``.

    Raises:
        ConstraintError: dependent rows with ``mu = 0`` (the message suggests ``mu``), or no convergence
            in ``max_iter`` proximal iterations.
    """
    J_, m = _rows_of(J, model.nv)
    c_ = _f64(c, "c")
    if c_.shape[-1:] != (m,):
        raise ShapeError(f"c: expected shape (..., {m}) for J with {m} rows, got {c_.shape}")
    qdd, lam, info = _solved("constrained_solve", model, q, v, tau, f_ext, [(J_, 2), (c_, 1)], {"rows": m, "mu": mu},
                             max_iter, tol)
    return qdd, lam, info[..., 1]


def contact_dynamics(model: Model, q: Any, v: Any, tau: Any, specs: np.ndarray, f_ext: Any = None, *,
                     mu: float = 0.0, max_iter: int = 50, tol: float = 1e-12
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(q̈, λ, iterations, residual)`` under point and frame contacts, rows and solve in one core call.

    ``specs`` `(nc, 4)` float64 rows ``[rows (3 | 6), frame index, reference code, K_d]`` (``contacts.hpp``; the
    declared ``contact_dynamics``)::

        point: J = linear rows of the frame Jacobian, γ = classical acceleration of the origin at q̈ = 0
        frame: J = the frame Jacobian, γ = its spatial acceleration at q̈ = 0;   c = −γ − K_d J q̇
        M q̈ + h = τ + Jᵀ λ,  J q̈ = c    (Schur complement on M's LᵀL factor)

    ``iterations`` `(...)`: −1 dependent rows (with ``mu = 0``; q̈ and λ are then zero), −2 not converged; the
    caller raises.
    """
    h = _view(model)
    try:
        plan = _lib().ContactPlan(h.cm, np.ascontiguousarray(specs, dtype=np.float64))
    except (TypeError, ValueError) as exc:  # (the binding's words: the specs' shape or a row out of range)
        raise ShapeError(f"specs: {exc}; got {np.shape(specs)} for a model with {len(model.frames)} frames") from None
    qdd, lam, info = _solved("contact_dynamics", model, q, v, tau, f_ext, [], {"plan": plan, "mu": mu}, max_iter, tol,
                             check=False)
    return qdd, lam, info[..., 0], info[..., 1]


# ---------------------------------------------------------------------------
# threads
# ---------------------------------------------------------------------------


def set_num_threads(n: int) -> None:
    """Threads of the batched calls (the calling thread included); ``n <= 0``: the cores available to the process.

    After a batch the pool's threads poll for the next one for about 100 µs (yielding their core to any other
    runnable thread) before they sleep, so that batches called back to back start on every thread at once
    instead of waiting for a sleeping thread to be woken (tens of µs in a virtual machine).
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
        raise TypeError(f"n: expected an integer, got {type(n).__name__}")
    _lib().set_num_threads(int(n))


def get_num_threads() -> int:
    """The number of threads of the batched calls."""
    return int(_lib().get_num_threads())
