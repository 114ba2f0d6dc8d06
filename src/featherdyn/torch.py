"""featherdyn's declared functions as PyTorch operators, with analytical gradients (docs/frameworks.md).

``import featherdyn.torch as ft``: ``ft.<name>(model, q, ...)`` takes and returns tensors, with the names,
arguments and results of ``fd.<name>``. Everything here is made from the declarations
(``api/declarations.py``, docs/architecture.md "The glue") and the Jacobians of ``api/jacobians.py`` (shared
with ``featherdyn.jax``); nothing is written per algorithm:

* **Operators.** Each declared function is a ``torch.library.custom_op`` ``featherdyn::<name>`` (no mutation):
  ``(int model, Tensor q, ..., Tensor? f_ext, <options>) -> Tensor or (Tensor, ...)``. The model is not a
  tensor: ``model`` is its key in this module's registry (:func:`model_key`; a model once registered stays
  registered for the life of the process). Options are arguments: ``gravity`` a bool, ``frame`` an index
  (names are resolved by the wrapper, ``Model.resolve_frame``), ``reference`` a code (``ReferenceFrame.code``).
  The operator calls the declared call of ``fd.<name>`` (``api.declared.call``: the same checks, errors and
  core) on the tensors' NumPy views; its fake implementation gives the shapes the core declares
  (``core.declared.SPECS``), so ``torch.compile(fullgraph=True)`` traces it without a graph break, and a vmap
  rule (one call on the mapped batch).
* **Functions.** ``ft.<name>`` calls the operator through a ``torch.autograd.Function`` made per declaration
  (:data:`FUNCTIONS`) with ``setup_context``, a backward, a forward-mode ``jvp`` and ``generate_vmap_rule``:
  what ``torch.func`` (grad, jacrev, jacfwd, vmap, hessian) needs, which PyTorch's custom operators alone do
  not give (their autograd has no ``setup_context`` for functorch). Under ``torch.compile`` the Function is a
  node of the graph (``torch.compiler.allow_in_graph``: Dynamo does not trace a Function with a ``jvp``), run by
  AOTAutograd on fake tensors. The operators keep the same backward (``register_autograd``):
  ``torch.ops.featherdyn.<name>`` alone differentiates under ``torch.autograd``.
* **Gradients** (api/jacobians.py: ``jacobians(fw, name, model, x, options)`` → ``{output: {input: J}}``, for
  every function with ``has_jacobians``). Backward: ``x̄ = Σ_o ȳ_o · J[o][x]`` (the output dimensions
  contracted), ``q``'s through ``T(q)ᵀ`` (``tangent_transpose``: the Jacobians in ``q`` are along
  ``fd.integrate``'s tangent, ``nv`` columns; featherdyn normalises the quaternions, so their radial direction
  has derivative zero), summed to the input's broadcast shape. Forward mode: ``ẏ_o = Σ_x J[o][x] · ẋ``, ``q̇``
  through ``T(q)``. The Jacobians are computed by calling the Functions themselves (the framework adapter
  ``_Torch``), so they have their own backward and ``jvp``: the double backward, ``jacfwd(jacrev)`` and
  ``hessian`` come from differentiating them (``rnea``'s through ``rnea_derivatives``, whose Jacobians are
  ``rnea_second_derivatives``'). An operator without Jacobians, or a derivative order that does not exist (the
  second-derivative functions' own), raises :class:`~featherdyn.FeatherdynError` naming it: never a silent
  zero. :func:`tangent_grad` turns a coordinate gradient into the tangent gradient (``E(q)ᵀ g``),
  :func:`tangent_to_coordinates` the other way (``T(q)ᵀ g``); :func:`normalize` divides the quaternions by
  their norms (differentiable: what finite differences in coordinates call first).
* **f_ext** (api/jacobians.py's ``generalized_force`` & co.): it enters ``rnea`` and ``aba`` as the generalized
  force ``Σ_b J_bᵀ f_b``; its gradient is ``J_b w`` (``fd.forward_kinematics(q, w).vel``), its tangent
  ``−RNEA(q, 0, 0, ḟ)``. First order
  only: a second derivative involving ``f_ext`` raises (with ``f_ext`` requiring grad, the double backward of
  ``rnea``/``aba`` raises even for ``q``: detach it).
* **Dtypes.** float64 CPU tensors go to NumPy without a copy (``Tensor.numpy()``); float32 tensors are
  converted to float64, computed by the core, and the results returned as float32 (where ``fd.<name>`` on
  float32 arrays uses the float32 reference). Results are float64 otherwise; other dtypes are handed to
  ``fd`` as NumPy arrays, which raises its own errors (``DTypeError`` for complex). The Jacobians of float32
  inputs are computed in float64 too; gradients and tangents are rounded once to the input's (output's) dtype.
* **Results.** One output: a tensor. Several: the NamedTuple ``fd.<name>`` returns when it is one
  (``RneaSecondDerivatives`` & co.), else a NamedTuple named by the declaration's outputs (records such as
  ``fd.forward_kinematics``'s ``Kinematics`` or ``fd.frame_placement``'s ``PluckerTransform`` become their
  arrays: ``ft.forward_kinematics(...)`` is ``(H, Hp, vel, acc)``); an output formed only with an absent
  optional input (``vel`` without ``v``) is ``None`` (an empty tensor from the operator itself).
"""

from __future__ import annotations

import inspect
from collections import namedtuple
from collections.abc import Callable, Sequence
from dataclasses import replace
from types import SimpleNamespace
from typing import Any, NamedTuple, cast

import numpy as np
import torch

from .api import jacobians as _jac
from .api.declarations import DECLARATIONS
from .api.declared import OPTIONS, REFERENCES, Declaration, call, positional_parameters
from .core.declared import SPECS, shape_of
from .errors import DTypeError, FeatherdynError, ShapeError
from .frames import as_reference_frame
from .model import Model

__all__ = ["model_key", "tangent_grad", "tangent_to_coordinates", "coordinates_of_tangent", "normalize",
           "OPERATORS", "FUNCTIONS"]

# --------------------------------------------------------------------------------------------------- models

#: the registered models, by key (a model stays registered: the key is in compiled graphs)
_MODELS: list[Model] = []
_KEYS: dict[int, int] = {}  # id(model) -> key (the model is held above, so its id is not reused)


@torch.compiler.assume_constant_result
def model_key(model: Model) -> int:
    """The integer that stands for ``model`` in the operators (``torch.ops.featherdyn.<name>(key, q, ...)``),
    registering it on first use. Under ``torch.compile`` it is called when tracing and its result is a constant
    of the graph (the model is a guarded input of a compiled function: another model retraces)."""
    key = _KEYS.get(id(model))
    if key is None:
        if not isinstance(model, Model):
            raise ShapeError(f"model: expected a featherdyn Model, got {type(model).__name__}")
        key = _KEYS[id(model)] = len(_MODELS)
        _MODELS.append(model)
    return key


def _model(key: int) -> Model:
    if not 0 <= key < len(_MODELS):
        raise ShapeError(f"model: {key} is not the key of a registered model (featherdyn.torch.model_key)")
    return _MODELS[key]


# ------------------------------------------------------------------------------------------------- shapes

def _tail(model: Model, symbolic: tuple[Any, ...]) -> tuple[int, ...]:
    """A declared shape (``core.declared.SPECS``) with the model's lengths: ``("nv", "nv")`` → ``(nv, nv)``
    (``core.declared.shape_of``, which reads the lengths ``nq, nv, nb`` of the core's handle of a model)."""
    return shape_of(cast(Any, SimpleNamespace(nq=model.nq, nv=model.nv, nb=model.nbodies)), symbolic)


def _batch(model: Model, name: str, tensors: Sequence[torch.Tensor | None]) -> tuple[Any, ...]:
    """The broadcast batch shape of a declared function's inputs (checked against the declared trailing shapes)."""
    batches = []
    for t, (arg, shape, _) in zip(tensors, SPECS[name].inputs, strict=True):
        if t is None:
            continue
        tail = _tail(model, shape)
        if t.dim() < len(tail) or tuple(t.shape[t.dim() - len(tail):]) != tail:
            raise ShapeError(f"{arg}: expected an array of shape (..., {', '.join(map(str, tail))}), got shape "
                             f"{tuple(t.shape)}")
        batches.append(tuple(t.shape[: t.dim() - len(tail)]))
    try:
        return tuple(torch.broadcast_shapes(*batches))
    except RuntimeError:
        raise ShapeError(f"{name}: the inputs' batch shapes {batches} do not broadcast") from None


def _result_dtype(tensors: Sequence[torch.Tensor | None]) -> torch.dtype:
    """float32 when the floating inputs are all float32 (the float32 rule of the module docstring), else float64."""
    floats = {t.dtype for t in tensors if t is not None and t.is_floating_point()}
    return torch.float32 if floats == {torch.float32} else torch.float64


def _numpy(t: torch.Tensor | None) -> np.ndarray | None:
    """A tensor as the NumPy array featherdyn takes: float64 CPU without a copy, float32 converted to float64."""
    if t is None:
        return None
    t = t.detach()
    if t.dtype == torch.float32:
        t = t.to(torch.float64)
    return t.cpu().numpy()


def _tensor(a: np.ndarray | None, dtype: torch.dtype, device: torch.device) -> torch.Tensor:
    if a is None:  # an output formed only with an absent optional input
        return torch.empty(0, dtype=dtype, device=device)
    t = torch.from_numpy(np.asarray(a, dtype=np.float64))
    return t.to(dtype=dtype, device=device)


# --------------------------------------------------------------------------------------------- operators

_SCHEMA_TYPE = {"gravity": "bool", "frame": "int", "reference": "int"}


def _schema(decl: Declaration, n_out: int, extra: str = "") -> str:
    args = ["int model"] + [f"Tensor{'?' if n in decl.optional else ''} {n}" for n in decl.inputs]
    args += [f"{_SCHEMA_TYPE[n]} {n}" for n in decl.options]
    returns = "Tensor" if n_out == 1 else "(" + ", ".join(["Tensor"] * n_out) + ")"
    return f"({', '.join(args + ([extra] if extra else []))}) -> {returns}"


def _options(decl: Declaration, values: Sequence[Any]) -> dict[str, Any]:
    """The operator's option arguments as ``api.declared.call`` takes them (``reference``: the frame of its code)."""
    return {n: REFERENCES[v] if n == "reference" else v for n, v in zip(decl.options, values, strict=True)}


def _declared(decl: Declaration, model: Model, arrays: Sequence[np.ndarray | None],
              options: dict[str, Any]) -> tuple[np.ndarray | None, ...]:
    """The outputs of ``fd.<decl.name>`` (its declared call, without the record the outputs make)."""
    r = call(_RAW[decl.name], model, tuple(arrays), options=options)
    return tuple(r) if len(decl.outputs) > 1 else (r,)


def _device(tensors: Sequence[torch.Tensor | None]) -> torch.device:
    return next(t.device for t in tensors if t is not None)


def _make_operator(decl: Declaration) -> Any:
    n = len(decl.inputs)
    spec = SPECS.get(decl.name)

    def impl(key: int, *args: Any) -> Any:
        tensors = args[:n]
        outs = _declared(decl, _model(key), [_numpy(t) for t in tensors], _options(decl, args[n:]))
        dtype, device = _result_dtype(tensors), _device(tensors)
        r = tuple(_tensor(o, dtype, device) for o in outs)
        return r if len(r) > 1 else r[0]

    def fake(key: int, *args: Any) -> Any:
        if spec is None:
            raise FeatherdynError(f"featherdyn.torch.{decl.name}: tracing needs the compiled core's declared shapes")
        tensors = args[:n]
        dtype = _result_dtype(tensors)
        r = tuple(tensors[0].new_empty(s, dtype=dtype) for s in _output_shapes(decl, _model(key), tensors))
        return r if len(r) > 1 else r[0]

    op = torch.library.custom_op(f"featherdyn::{decl.name}", impl, mutates_args=(),
                                 schema=_schema(decl, len(decl.outputs)))
    op.register_fake(fake)
    if spec is not None:
        op.register_vmap(_vmap_rule(op, lambda model, _: {i: _tail(model, shape)
                                                          for i, (_, shape, _) in enumerate(spec.inputs)}))
    return op


def _vmap_rule(op: Any, tails: Callable[[Model, int], dict[int, tuple[int, ...]]]) -> Callable[..., Any]:
    """``torch.vmap``'s rule of an operator. The operators take batch dimensions themselves: the mapped dimension
    of each mapped tensor goes first, followed by singleton dimensions up to the widest input's batch (unmapped
    tensors broadcast from the right), and the operator is called once. ``tails(model, len(args))``: the
    trailing (declared) shape of each tensor argument, by position."""

    def rule(info: Any, in_dims: tuple[int | None, ...], key: int, *args: Any) -> Any:
        shapes = tails(_model(key), len(args))
        args_ = list(args)
        mapped = {i: d for i, d in enumerate(in_dims[1:]) if d is not None and args[i] is not None}
        widest = max((args[i].dim() - (i in mapped) - len(tail) for i, tail in shapes.items() if args[i] is not None),
                     default=0)
        for i, d in mapped.items():
            t = args[i].movedim(d, 0)
            own = t.dim() - 1 - len(shapes[i])
            args_[i] = t.reshape(t.shape[:1] + (1,) * (widest - own) + t.shape[1:])
        out = op(key, *args_)
        if isinstance(out, tuple):  # (an absent optional output stays the empty tensor, unmapped)
            return out, tuple(None if o.dim() == 1 and o.shape[0] == 0 else 0 for o in out)
        return out, 0

    return rule


# ------------------------------------------------------------------------- api/jacobians.py in PyTorch

class _Torch:
    """api/jacobians.py's :class:`~featherdyn.api.jacobians.Framework` in PyTorch: the declared functions through
    their ``autograd.Function`` (:data:`FUNCTIONS`: a Jacobian is differentiable again, by ``torch.autograd``
    and ``torch.func`` alike), new arrays of one dtype and device."""

    cos = staticmethod(torch.cos)
    sin = staticmethod(torch.sin)
    sqrt = staticmethod(torch.sqrt)

    @staticmethod
    def isfinite(x: Any, /) -> Any:
        return torch.isfinite(x)

    @staticmethod
    def where(condition: Any, x: Any, y: Any, /) -> Any:
        return torch.where(condition, x, y)

    def __init__(self, dtype: torch.dtype, device: torch.device) -> None:
        self.dtype, self.device = dtype, device

    def call(self, name: str, model: Model, inputs: dict[str, Any], options: dict[str, Any]) -> tuple[Any, ...]:
        decl = DECLARATIONS[name]
        values = [as_reference_frame(options.get(k, OPTIONS[k])).code if k == "reference"
                  else options.get(k, OPTIONS[k]) for k in decl.options]
        r = _apply(name, model_key(model), *(inputs.get(n) for n in decl.inputs), *values)
        return tuple(r) if isinstance(r, tuple) else (r,)

    @staticmethod
    def einsum(spec: str, *xs: torch.Tensor) -> torch.Tensor:
        """``torch.einsum`` without opt_einsum's search of a contraction order: on these small operands the
        search (~0.2 ms a call) costs more than the contraction."""
        with torch.backends.opt_einsum.flags(enabled=False):
            return torch.einsum(spec, *xs)

    def const(self, a: np.ndarray) -> torch.Tensor:
        return torch.as_tensor(a, dtype=self.dtype, device=self.device)

    def concat(self, xs: Sequence[torch.Tensor], axis: int) -> torch.Tensor:
        return torch.cat(list(xs), dim=axis)

    def stack(self, xs: Sequence[torch.Tensor], axis: int) -> torch.Tensor:
        return torch.stack(list(xs), dim=axis)

    def zeros(self, shape: tuple[int, ...]) -> torch.Tensor:
        return torch.zeros(shape, dtype=self.dtype, device=self.device)


@torch.compiler.allow_in_graph
def _apply(name: str, *args: Any) -> Any:
    """``FUNCTIONS[name].apply(*args)``, a node of the graph under ``torch.compile`` (Dynamo does not trace an
    autograd.Function with a ``jvp``; AOTAutograd runs it on fake tensors, under ``torch.func`` transforms too)."""
    return FUNCTIONS[name].apply(*args)


def _fw(*tensors: torch.Tensor | None) -> _Torch:
    """The framework of these tensors: their promoted floating dtype (float64 from integers), their device."""
    given = [t for t in tensors if t is not None]
    dtype = torch.float64
    floats = [t.dtype for t in given if t.is_floating_point()]
    if floats:
        dtype = floats[0]
        for d in floats[1:]:
            dtype = torch.promote_types(dtype, d)
    return _Torch(dtype, given[0].device)


# ---------------------------------------------------------------------------------------- tangent of q

def tangent_to_coordinates(model: Model, q: torch.Tensor, g: torch.Tensor) -> torch.Tensor:
    """The gradient in ``q``'s coordinates `(..., nq)` of a gradient ``g`` `(..., nv)` along ``fd.integrate``'s
    tangent: ``T(q)ᵀ g`` (api/jacobians.py's ``tangent_transpose``), with ``δ = T(q) q̇`` the tangent of a
    coordinate direction (featherdyn normalises the quaternions: their radial direction has none)::

        quaternion (u, w): ω = 2 (w u̇ − ẇ u − u × u̇) / |q|²;   free-flyer [p, quat]: v = R(quat)ᵀ ṗ;
        planar [x, y, θ]: [ω, v_x, v_y] = [θ̇, Rz(θ)ᵀ (ẋ, ẏ)];   other joints: the identity

    What the backward of every operator does with ``q``'s Jacobians. Differentiable (torch operations)."""
    return _jac.tangent_transpose(_fw(q, g), model, q, g)


def tangent_grad(model: Model, q: torch.Tensor, grad_q: torch.Tensor) -> torch.Tensor:
    """The gradient `(..., nv)` along ``fd.integrate``'s tangent of a function whose gradient in ``q``'s
    coordinates is ``grad_q`` `(..., nq)`: ``E(q)ᵀ grad_q`` (api/jacobians.py's ``coordinates_transpose``),
    ``E = ∂(q ⊕ δ)/∂δ`` at ``δ = 0`` `(nq, nv)`, i.e. ``d/dδ L(fd.integrate(q, δ))``. For the gradient of
    featherdyn's operators (``Tᵀ g``, ``T E = 1``) it is their tangent gradient ``g`` exactly. A step on the
    manifold: ``fd.integrate(model, q, -lr * g)``::

        quaternion: E = ½ [w 1 + [u]×; −uᵀ];  free-flyer's position: R(quat);  planar: Rz(θ) on (x, y), θ̇ = ω
    """
    return _jac.coordinates_transpose(_fw(q, grad_q), model, q, grad_q)


def coordinates_of_tangent(model: Model, q: torch.Tensor, delta: torch.Tensor) -> torch.Tensor:
    """``q̇ = E(q) δ`` `(..., nq)`: the coordinate direction of ``fd.integrate(q, ε δ)`` at ε = 0 (``T E = 1``;
    api/jacobians.py): ``q + coordinates_of_tangent(model, q, δ)`` is ``q ⊕ δ`` to first order, so a function of
    ``δ`` differentiated at 0 (``torch.func.hessian``) is differentiated along the tangent."""
    return _jac.coordinates_of_tangent(_fw(q, delta), model, q, delta)


def normalize(model: Model, q: torch.Tensor) -> torch.Tensor:
    """``q`` `(..., nq)` with each quaternion divided by its norm (``fd.normalize`` on tensors, differentiable):
    what a function differentiated in coordinates off the unit quaternions (finite differences,
    ``torch.autograd.gradcheck``) calls first; at a unit quaternion its Jacobian removes the radial direction,
    which ``T(q)`` ignores anyway."""
    return _jac.normalize(_fw(q), model, q)


def _sum_to(g: torch.Tensor, shape: torch.Size) -> torch.Tensor:
    """``g`` summed over the batch dimensions its input was broadcast along (to ``shape``)."""
    if tuple(g.shape) == tuple(shape):
        return g
    lead = g.dim() - len(shape)
    g = g.sum(dim=tuple(range(lead))) if lead else g
    dims = tuple(i for i, (a, b) in enumerate(zip(g.shape, shape, strict=True)) if b == 1 and a != 1)
    return g.sum(dim=dims, keepdim=True) if dims else g


# ------------------------------------------------------------------------------------------- gradients

def _no_derivative(what: str) -> FeatherdynError:
    return FeatherdynError(f"featherdyn.torch: {what} is not available (docs/frameworks.md lists the operators "
                           "with first and second derivatives)")


def _out_dims(decl: Declaration, output: str) -> int:
    """The number of trailing (declared) dimensions of ``output``."""
    return len(SPECS[decl.name].outputs[decl.outputs.index(output)][1])


def _row_times(ybar: torch.Tensor, J: torch.Tensor, d: int) -> torch.Tensor:
    """``ȳ · J`` `(..., n)`: ``ȳ`` `(..., *out)` against ``J`` `(..., *out, n)`, the ``d`` output dims contracted
    (one batched matmul: a fraction of einsum's time on small matrices)."""
    rows = ybar.reshape(ybar.shape[:ybar.dim() - d] + (1, -1))
    return (rows @ J.reshape(J.shape[:J.dim() - 1 - d] + (-1, J.shape[-1])))[..., 0, :]


def _times_column(J: torch.Tensor, x: torch.Tensor, d: int) -> torch.Tensor:
    """``J · ẋ`` `(..., *out)`: ``J`` `(..., *out, n)` against ``ẋ`` `(..., n)`."""
    out = J.shape[J.dim() - 1 - d: J.dim() - 1]
    y = J.reshape(J.shape[:J.dim() - 1 - d] + (-1, J.shape[-1])) @ x[..., None]
    return y.reshape(y.shape[:-2] + out)


def _jacobians(decl: Declaration, key: int, option_values: Sequence[Any], ins: Sequence[torch.Tensor | None]
               ) -> tuple[Model, _Torch, dict[str, torch.Tensor | None], dict[str, dict[str, Any]]]:
    """``(model, framework, inputs, {output: {input: J}})`` of api/jacobians.py, computed in float64 (float32 inputs
    cast: the Jacobians are the float64 computation's, the gradients rounded once to the input's dtype)."""
    if not _jac.has_jacobians(decl.name):
        raise _no_derivative(f"the derivative of {decl.name}")
    model, fw, x = _float64_inputs(decl, key, ins)
    return model, fw, x, _jac.jacobians(fw, decl.name, model, x, _options(decl, option_values))


def _float64_inputs(decl: Declaration, key: int, ins: Sequence[torch.Tensor | None]
                    ) -> tuple[Model, _Torch, dict[str, torch.Tensor | None]]:
    """``(model, framework, inputs by name)``, float32 inputs cast to float64 (the derivatives' computation)."""
    x = {n: t.to(torch.float64) if t is not None and t.dtype == torch.float32 else t
         for n, t in zip(decl.inputs, ins, strict=True)}
    return _model(key), _fw(*x.values()), x


def _configurations(decl: Declaration) -> set[str]:
    """The inputs and outputs of ``decl`` that are configurations (declared shape ``(nq,)``: ``q``, ``q0``, ``q1``,
    ``integrate``'s result): their Jacobians are along ``fd.integrate``'s tangent."""
    spec = SPECS[decl.name]
    return {n for n, shape, _ in (*spec.inputs, *spec.outputs) if shape == ("nq",)}


def _configuration_outputs(decl: Declaration, key: int, option_values: Sequence[Any],
                           ins: Sequence[torch.Tensor | None]) -> dict[str, torch.Tensor]:
    """The outputs of ``decl`` that are configurations, recomputed (their tangent maps need them: ``E(y)``)."""
    wanted = [o for o in decl.outputs if o in _configurations(decl)]
    if not wanted:
        return {}
    with torch.no_grad():
        r = _apply(decl.name, key, *(t.detach() if t is not None else None for t in ins), *option_values)
    r = r if isinstance(r, tuple) else (r,)
    return {o: y for o, y in zip(decl.outputs, r, strict=True) if o in wanted}


def _vjp(name: str, key: int, option_values: Sequence[Any], ins: Sequence[torch.Tensor | None],
         ybars: Sequence[torch.Tensor | None], needs: Sequence[bool]) -> tuple[torch.Tensor | None, ...]:
    """The gradients of the inputs (``None`` where not needed): ``x̄ = Σ_o ȳ_o · J[o][x]`` (the output dims
    contracted), ``q``'s through ``T(q)ᵀ``, ``f_ext``'s through the generalized force's transpose (api/jacobians.py:
    ``f_ext_cotangent``, ``generalized_force_transpose``), each summed to its input's shape."""
    decl = DECLARATIONS[name]
    given = dict(zip(decl.inputs, ins, strict=True))
    wanted = {n for n, need in zip(decl.inputs, needs, strict=True) if need and given[n] is not None}
    if not wanted or all(y is None for y in ybars):  # (no cotangent came: the gradients are undefined)
        return (None,) * len(decl.inputs)
    if "f_ext" in wanted and decl.name not in _jac.F_EXT:
        raise _no_derivative(f"the derivative of {decl.name} with respect to f_ext")
    table: dict[str, dict[str, Any]] = {}
    tangent: dict[str, torch.Tensor] = {}
    if name in _jac.VJPS and not torch.is_grad_enabled():  # first order only: contracted as it goes (VJPS)
        model, fw, x = _float64_inputs(decl, key, ins)
        given_ybars = {o: y.to(fw.dtype) for o, y in zip(decl.outputs, ybars, strict=True) if y is not None}
        tangent = _jac.VJPS[name](fw, model, x, given_ybars, _options(decl, option_values))
    else:
        model, fw, x, table = _jacobians(decl, key, option_values, ins)
        outs = _configuration_outputs(decl, key, option_values, ins)
        # a configuration output's cotangent as the tangent's: Eᵀ ȳ (its Jacobians are along its tangent)
        ybars = [_jac.coordinates_transpose(fw, model, outs[o].to(fw.dtype), y.to(fw.dtype))
                 if o in outs and y is not None else y for o, y in zip(decl.outputs, ybars, strict=True)]
        for n in decl.inputs:
            if n == "f_ext" or x[n] is None:
                continue
            terms = []
            for o, ybar in zip(decl.outputs, ybars, strict=True):
                J = table.get(o, {}).get(n)
                if J is not None and ybar is not None:
                    terms.append(_row_times(ybar.to(J.dtype), J, _out_dims(decl, o)))
            if terms:
                tangent[n] = sum(terms[1:], terms[0])
    q = cast(torch.Tensor, x.get("q"))
    configurations = _configurations(decl)
    out: list[torch.Tensor | None] = []
    for n in decl.inputs:
        t = given[n]
        if n not in wanted or t is None:
            out.append(None)
            continue
        if n == "f_ext":
            ybar = ybars[0]
            assert ybar is not None
            w = _jac.f_ext_cotangent(decl.name, ybar.to(fw.dtype), tangent)
            g = _jac.generalized_force_transpose(fw, model, q, w)
        elif n not in tangent:  # the input enters none of the outputs whose cotangent came
            g = torch.zeros_like(t)
        elif n in configurations:
            g = _jac.tangent_transpose(fw, model, cast(torch.Tensor, x[n]), tangent[n])
        elif n in _jac.matrix_inputs(decl.name):  # (its gradient over the flattened entries, shaped back)
            g = tangent[n].reshape(tangent[n].shape[:-1] + t.shape[-2:])
        else:
            g = tangent[n]
        out.append(_sum_to(g, t.shape).to(t.dtype))
    return tuple(out)


def _jvp(name: str, key: int, option_values: Sequence[Any], ins: Sequence[torch.Tensor | None],
         dots: Sequence[torch.Tensor | None]) -> tuple[torch.Tensor, ...]:
    """The outputs' tangents: ``ẏ_o = Σ_x J[o][x] · ẋ``, ``q̇`` mapped to the tangent ``T(q) q̇`` first, ``ḟ_ext``
    through the generalized force (api/jacobians.py's ``f_ext_tangent``); each output's shape and dtype (an absent
    output: its empty tensor)."""
    decl = DECLARATIONS[name]
    model = _model(key)
    moving = {n: d for n, d, t in zip(decl.inputs, dots, ins, strict=True) if d is not None and t is not None}
    dtype = _result_dtype(ins)
    shapes = _output_shapes(decl, model, ins)
    ref = next(t for t in ins if t is not None)
    if not moving:
        return tuple(ref.new_zeros(s, dtype=dtype) for s in shapes)
    if "f_ext" in moving and decl.name not in _jac.F_EXT:
        raise _no_derivative(f"the derivative of {decl.name} with respect to f_ext")
    _, fw, x, table = _jacobians(decl, key, option_values, ins)
    q = cast(torch.Tensor, x.get("q"))
    configurations = _configurations(decl)
    outs = _configuration_outputs(decl, key, option_values, ins)
    directions = {n: d.to(fw.dtype) for n, d in moving.items() if n != "f_ext"}
    for n in _jac.matrix_inputs(decl.name) & set(directions):  # (a matrix's Jacobian is over its flattened entries)
        directions[n] = directions[n].reshape(directions[n].shape[:-2] + (-1,))
    for n in configurations & set(directions):
        directions[n] = _jac.tangent_of_coordinates(fw, model, cast(torch.Tensor, x[n]), directions[n])
    out = []
    for o, shape in zip(decl.outputs, shapes, strict=True):
        terms = [_times_column(J, directions[n], _out_dims(decl, o))
                 for n, J in table.get(o, {}).items() if n in directions]
        if o == decl.outputs[0] and "f_ext" in moving:
            u = _jac.generalized_force(fw, model, q, moving["f_ext"].to(fw.dtype))
            terms.append(_jac.f_ext_tangent(fw, decl.name, table, u))
        if not terms or shape == (0,):  # (an output that no moving input enters; an absent output)
            out.append(ref.new_zeros(shape, dtype=dtype))
            continue
        t = sum(terms[1:], terms[0])
        if o in outs:  # a configuration's tangent as its coordinates' direction: E(y) δ
            t = _jac.coordinates_of_tangent(fw, model, outs[o].to(fw.dtype), t)
        out.append(torch.broadcast_to(t.to(dtype), shape))
    return tuple(out)


_FORWARD_SIGNATURE = inspect.Signature([inspect.Parameter("key", inspect.Parameter.POSITIONAL_ONLY),
                                        inspect.Parameter("args", inspect.Parameter.VAR_POSITIONAL)])


def _function(decl: Declaration) -> type[torch.autograd.Function]:
    """``featherdyn.torch.FUNCTIONS[name]``: the operator as a ``torch.autograd.Function`` with ``setup_context``
    (what ``torch.func`` needs), the backward :func:`_vjp`, the forward-mode ``jvp`` :func:`_jvp`, and vmap by
    ``generate_vmap_rule`` (the operator's own vmap rule: the batch in one call). Its methods close over the name
    and counts only (what Dynamo traces)."""
    name, n, n_options = decl.name, len(decl.inputs), len(decl.options)

    def forward(key: int, *args: Any) -> Any:
        return getattr(torch.ops.featherdyn, name)(key, *args)

    # (Function.apply binds the arguments to forward's signature at every call: given, it is not re-read)
    forward.__signature__ = _FORWARD_SIGNATURE  # type: ignore[attr-defined]

    def setup_context(ctx: Any, inputs: tuple[Any, ...], output: Any) -> None:
        ctx.key, ctx.options = inputs[0], inputs[1 + n:]
        ctx.set_materialize_grads(False)  # (an input without a tangent: None, not zeros; f_ext's raises where none)
        ctx.save_for_backward(*inputs[1: 1 + n])
        ctx.save_for_forward(*inputs[1: 1 + n])

    def backward(ctx: Any, *ybars: Any) -> Any:
        grads = _vjp(name, ctx.key, ctx.options, ctx.saved_tensors, ybars, ctx.needs_input_grad[1: 1 + n])
        return (None, *grads, *(None,) * n_options)

    def jvp(ctx: Any, *dots: Any) -> Any:
        r = _jvp(name, ctx.key, ctx.options, ctx.saved_tensors, dots[1: 1 + n])
        return r if len(r) > 1 else r[0]

    body = {"forward": staticmethod(forward), "setup_context": staticmethod(setup_context),
            "backward": staticmethod(backward), "jvp": staticmethod(jvp), "generate_vmap_rule": True,
            "__doc__": f"``featherdyn::{name}`` as an autograd.Function (featherdyn.torch._function)."}
    return cast(type[torch.autograd.Function], type(f"_{name}_function", (torch.autograd.Function,), body))


def _output_shapes(decl: Declaration, model: Model, tensors: Sequence[torch.Tensor | None]) -> list[tuple[int, ...]]:
    """The outputs' shapes (the declared trailing shapes on the inputs' batch; ``(0,)`` for an output formed only
    with an absent optional input)."""
    batch = _batch(model, decl.name, tensors)
    given = dict(zip(decl.inputs, tensors, strict=True))
    return [(0,) if when is not None and given[when] is None else tuple(batch) + _tail(model, shape)
            for _, shape, when in SPECS[decl.name].outputs]

# ------------------------------------------------------------------------------------------- the front

#: the declarations as the operators call them: their outputs, without the record they make
_RAW: dict[str, Declaration] = {name: replace(d, result=None) for name, d in DECLARATIONS.items()}


def _result_type(decl: Declaration) -> type | None:
    """What ``ft.<name>`` returns: ``None`` (the tensor) for one output; the declaration's own NamedTuple (as
    ``fd.<name>``: ``RneaSecondDerivatives`` & co.); else a NamedTuple named by the outputs."""
    if len(decl.outputs) == 1:
        return None
    own = decl.result
    if isinstance(own, type) and issubclass(own, tuple) and getattr(own, "_fields", ()) == decl.outputs:
        return own
    return namedtuple("".join(p.title() for p in decl.name.split("_")), decl.outputs)


def _front(decl: Declaration) -> Callable[..., Any]:
    """``ft.<name>(model, *inputs, frame, reference, point, *, gravity=True)`` (``fd.<name>``'s order): the operator on
    ``model``'s key, through its ``autograd.Function`` (:data:`FUNCTIONS`)."""
    P = inspect.Parameter
    params = [P("model", P.POSITIONAL_OR_KEYWORD)]
    params += [P(n, P.POSITIONAL_OR_KEYWORD, default=OPTIONS[n]) if n in OPTIONS else
               P(n, P.POSITIONAL_OR_KEYWORD, default=None if n in decl.optional else P.empty)
               for n in positional_parameters(decl)]
    if "gravity" in decl.options:
        params.append(P("gravity", P.KEYWORD_ONLY, default=True))
    sig = inspect.Signature(params)
    result = _result_type(decl)
    when = {o: w for o, _, w in SPECS[decl.name].outputs} if decl.name in SPECS else {}

    def front(*args: Any, **kwargs: Any) -> Any:
        try:
            a = sig.bind(*args, **kwargs).arguments
        except TypeError as exc:
            raise TypeError(f"{decl.name}(): {exc}") from None
        model = a["model"]
        options = []
        for name in decl.options:
            value = a.get(name, OPTIONS[name])
            if name == "frame":
                value = model.resolve_frame(value)
            elif name == "reference":
                value = as_reference_frame(value).code
            elif not (isinstance(value, (bool, np.bool_)) or (type(value) is int and value in (0, 1))):
                raise DTypeError(f"gravity: expected True or False, got {type(value).__name__} {value!r}")
            else:
                value = bool(value)
            options.append(value)
        args = (model_key(model), *(a.get(n) for n in decl.inputs), *options)
        # (Dynamo does not trace an autograd.Function with a jvp: under torch.compile the operator itself, whose
        # registered backward AOTAutograd traces)
        r = _apply(decl.name, *args)
        if result is None:
            return r
        absent = {n for n in decl.inputs if a.get(n) is None}
        return result(*(None if when.get(o) in absent else t for o, t in zip(decl.outputs, r, strict=True)))

    front.__name__ = front.__qualname__ = decl.name
    front.__doc__ = f"``fd.{decl.name}`` on tensors (operator ``featherdyn::{decl.name}``).\n\n{decl.doc}"
    front.__signature__ = sig  # type: ignore[attr-defined]
    return front


#: the operators (``torch.ops.featherdyn.<name>``), by name
OPERATORS: dict[str, Any] = {}
#: the operators as ``torch.autograd.Function`` classes (what ``ft.<name>`` calls), by name
FUNCTIONS: dict[str, type[torch.autograd.Function]] = {}

for _decl in DECLARATIONS.values():
    OPERATORS[_decl.name] = _make_operator(_decl)
    FUNCTIONS[_decl.name] = _function(_decl)
    # the operator's own backward (torch.ops.featherdyn.<name> under torch.autograd alone): the same
    OPERATORS[_decl.name].register_autograd(FUNCTIONS[_decl.name].backward,
                                            setup_context=FUNCTIONS[_decl.name].setup_context)
    globals()[_decl.name] = _front(_decl)
    __all__.append(_decl.name)
del _decl


# ----------------------------------------------------------------- constrained and impulse dynamics (contacts)

class ConstrainedDynamics(NamedTuple):
    """``fd.constrained_dynamics``' result on tensors: ``ddq`` `(..., nv)`, ``forces`` (one tensor per constraint),
    ``lagrange`` `(..., m)`, ``residual`` `(...)`."""

    ddq: torch.Tensor
    forces: tuple[torch.Tensor, ...]
    lagrange: torch.Tensor
    residual: torch.Tensor


class ImpulseDynamics(NamedTuple):
    """``fd.impulse_dynamics``' result on tensors: ``v_plus`` `(..., nv)`, ``impulses``, ``lagrange`` `(..., m)`."""

    v_plus: torch.Tensor
    impulses: tuple[torch.Tensor, ...]
    lagrange: torch.Tensor


#: the contact problems the operator ``featherdyn::contact_solve`` solves, by key: (kind, model, constraints,
#: settings); registered once each (the key is a graph constant, like a model's)
_CONTACT_SETS: list[tuple[str, Model, Any, dict[str, Any]]] = []
_CONTACT_KEYS: dict[Any, int] = {}


def _contact_key(kind: str, model: Model, constraints: Any, settings: dict[str, Any]) -> int:
    from .constraints import as_constraints

    items = tuple(as_constraints(constraints))
    ident: Any = (kind, model_key(model), items, tuple(sorted(settings.items())))
    try:
        key = _CONTACT_KEYS.get(ident)
    except TypeError:  # (an unhashable setting: registered anew)
        key, ident = None, None
    if key is None:
        key = len(_CONTACT_SETS)
        _CONTACT_SETS.append((kind, model, list(items), dict(settings)))
        if ident is not None:
            _CONTACT_KEYS[ident] = key
    return key


@torch.library.custom_op("featherdyn::contact_solve", mutates_args=())
def _contact_solve(key: int, q: torch.Tensor, v: torch.Tensor, tau: torch.Tensor | None, f_ext: torch.Tensor | None,
                   derivatives: bool) -> list[torch.Tensor]:
    """The contact problem ``key``'s values ``[q̈ or v⁺, λ, residual]`` (``fd.constrained_dynamics`` /
    ``fd.impulse_dynamics``), or with ``derivatives`` the blocks of their ``_derivatives`` (``∂q̈/∂(q, v, τ)``,
    ``∂λ/∂(q, v, τ)``; impulses: ``∂v⁺/∂(q, v)``, ``∂Λ/∂(q, v)``)."""
    from .api.constraint_derivatives import constrained_dynamics_derivatives, impulse_dynamics_derivatives
    from .api.constraints import constrained_dynamics, impulse_dynamics

    kind, model, constraints, settings = _CONTACT_SETS[key]
    tensors = (q, v, tau, f_ext)
    a: list[Any] = [_numpy(t) for t in tensors]
    dtype, device = _result_dtype(tensors), _device(tensors)
    r: Any
    if kind == "constrained":
        f: Callable[..., Any] = constrained_dynamics_derivatives if derivatives else constrained_dynamics
        r = f(model, a[0], a[1], a[2], constraints, f_ext=a[3], **settings)
        out = ([r.ddq_dq, r.ddq_dv, r.ddq_dtau, r.forces_dq, r.forces_dv, r.forces_dtau] if derivatives
               else [r.ddq, r.lagrange, r.residual])
    else:
        f = impulse_dynamics_derivatives if derivatives else impulse_dynamics
        r = f(model, a[0], a[1], constraints, **settings)
        out = ([r.dv_plus_dq, r.dv_plus_dv, r.impulses_dq, r.impulses_dv] if derivatives
               else [r.v_plus, r.lagrange, np.zeros(np.shape(r.v_plus)[:-1])])
    return [_tensor(np.asarray(x), dtype, device) for x in out]


@_contact_solve.register_vmap
def _contact_solve_vmap(info: Any, in_dims: tuple[Any, ...], key: int, *args: Any) -> Any:
    """One call on the mapped batch: each mapped tensor's dimension first, then singletons up to the widest
    input's own batch (unmapped tensors broadcast from the right), as the declared operators' rule."""
    tensors, derivatives = args[:4], args[4]
    tails = (1, 1, 1, 2)  # q, v, τ vectors; f_ext (nb, 6)
    dims = in_dims[1:5]
    own = [t.dim() - (d is not None) - n for t, d, n in zip(tensors, dims, tails, strict=True) if t is not None]
    widest = max(own, default=0)
    moved = []
    for t, d, n in zip(tensors, dims, tails, strict=True):
        if t is None or d is None:
            moved.append(t)
            continue
        m = t.movedim(d, 0)
        moved.append(m.reshape(m.shape[:1] + (1,) * (widest - (m.dim() - 1 - n)) + m.shape[1:]))
    out = _contact_solve(key, *moved, derivatives)
    return out, [0] * len(out)


class _Contacts(torch.autograd.Function):
    """The contact solves as one autograd node (``featherdyn::contact_solve``: the NumPy functions, the core's
    contact kernels), the backward and forward mode from their ``_derivatives`` (``q`` through ``T(q)``); first
    order only (:class:`_ContactJacobians`)."""

    generate_vmap_rule = True

    @staticmethod
    def forward(key: int, *tensors: Any) -> Any:
        return tuple(_contact_solve(key, *tensors, False))

    @staticmethod
    def setup_context(ctx: Any, inputs: tuple[Any, ...], output: Any) -> None:
        ctx.key = inputs[0]
        ctx.kind, ctx.model = _CONTACT_SETS[ctx.key][:2]
        ctx.given = [t is not None for t in inputs[1:]]
        given = [t for t in inputs[1:] if t is not None]
        ctx.save_for_backward(*given)
        ctx.save_for_forward(*given)  # (the jvp reads them too)
        ctx.mark_non_differentiable(output[2])

    @staticmethod
    def _jacobians(ctx: Any) -> tuple[list[torch.Tensor | None], list[list[torch.Tensor]]]:
        it = iter(ctx.saved_tensors)
        ins = [next(it) if g else None for g in ctx.given]
        ins += [None] * (4 - len(ins))
        d = _ContactJacobians.apply(ctx.key, *ins)
        n = 3 if ctx.kind == "constrained" else 2
        return ins, [list(d[:n]), list(d[n:])]

    @staticmethod
    def backward(ctx: Any, *ybars: Any) -> Any:
        needs = ctx.needs_input_grad[1:]
        if len(needs) > 3 and needs[3]:
            raise _no_derivative(f"the derivative of {ctx.kind} dynamics with respect to f_ext")
        ins, blocks = _Contacts._jacobians(ctx)
        grads: list[torch.Tensor | None] = []
        for k, t in enumerate(ins):
            if t is None or k >= len(blocks[0]) or not needs[k]:
                grads.append(None)
                continue
            terms = [torch.einsum("...i,...ij->...j", ybars[o].to(blocks[o][k].dtype), blocks[o][k])
                     for o in (0, 1) if ybars[o] is not None]
            if not terms:
                grads.append(None)
                continue
            g = sum(terms[1:], terms[0])
            g = tangent_to_coordinates(ctx.model, t, g) if k == 0 else g
            grads.append(_sum_to(g, t.shape).to(t.dtype))
        return (None, *grads[:len(ctx.given)])

    @staticmethod
    def jvp(ctx: Any, *dots: Any) -> Any:
        tangents = dots[1:]  # (the key's tangent is None)
        if len(tangents) > 3 and tangents[3] is not None:
            raise _no_derivative(f"the derivative of {ctx.kind} dynamics with respect to f_ext")
        ins, blocks = _Contacts._jacobians(ctx)
        outs: list[torch.Tensor | None] = []
        for row in blocks:
            t = None
            for k, (J, dx) in enumerate(zip(row, tangents, strict=False)):
                if dx is None:
                    continue
                q = ins[0]
                assert q is not None
                d = _jac.tangent_of_coordinates(_fw(q, dx), ctx.model, q, dx) if k == 0 else dx
                term = torch.einsum("...ij,...j->...i", J, d.to(J.dtype))
                t = term if t is None else t + term
            outs.append(t)
        return (*outs, None)


class _ContactJacobians(torch.autograd.Function):
    """The contact derivative blocks (``featherdyn::contact_solve`` with ``derivatives``) as an autograd node whose
    own derivative raises: the contact derivatives have none, so a double backward or ``hessian`` through the
    contact solves is refused rather than a silent zero (a gradient's derivative in the cotangent is fine)."""

    generate_vmap_rule = True

    @staticmethod
    def forward(key: int, *tensors: Any) -> Any:
        return tuple(_contact_solve(key, *tensors, True))

    @staticmethod
    def setup_context(ctx: Any, inputs: tuple[Any, ...], output: Any) -> None:
        ctx.kind = _CONTACT_SETS[inputs[0]][0]

    @staticmethod
    def backward(ctx: Any, *grads: Any) -> Any:
        raise _no_derivative(f"the second derivative of {ctx.kind} dynamics (its first derivatives are the "
                             "contact derivative functions', which have none)")

    @staticmethod
    def jvp(ctx: Any, *dots: Any) -> Any:
        raise _no_derivative(f"the second derivative of {ctx.kind} dynamics")


@torch.compiler.disable  # (Dynamo cannot take the constraint objects into a graph: eager, a graph break)
def constrained_dynamics(model: Model, q: torch.Tensor, v: torch.Tensor, tau: torch.Tensor, constraints: Any,
                         f_ext: torch.Tensor | None = None, *, mu: float = 0.0, max_iter: int = 50,
                         tol: float = 1e-12) -> ConstrainedDynamics:
    """``fd.constrained_dynamics`` on tensors (the core's contact kernels; loops too, through the NumPy
    function), differentiable once in ``q, v, τ`` (``fd.constrained_dynamics_derivatives``)::

        M q̈ + h = τ + Jᵀ λ,     J q̈ + γ = −K_p e − K_d J v
    """
    from .constraints import as_constraints

    items = as_constraints(constraints)
    key = _contact_key("constrained", model, constraints, {"mu": mu, "max_iter": max_iter, "tol": tol})
    ddq, lam, residual = _Contacts.apply(key, q, v, tau, f_ext)
    return ConstrainedDynamics(ddq, _split(lam, items), lam, residual)


@torch.compiler.disable  # (as constrained_dynamics)
def impulse_dynamics(model: Model, q: torch.Tensor, v: torch.Tensor, constraints: Any, *,
                     restitution: float = 0.0, mu: float = 0.0) -> ImpulseDynamics:
    """``fd.impulse_dynamics`` on tensors, differentiable once in ``q, v`` (``fd.impulse_dynamics_derivatives``)::

        M (v⁺ − v⁻) = Jᵀ Λ,     J v⁺ = −e J v⁻
    """
    from .constraints import as_constraints

    items = as_constraints(constraints)
    key = _contact_key("impulse", model, constraints, {"restitution": restitution, "mu": mu})
    v_plus, lam, _ = _Contacts.apply(key, q, v, None, None)
    return ImpulseDynamics(v_plus, _split(lam, items), lam)


def _split(lam: torch.Tensor, items: Sequence[Any]) -> tuple[torch.Tensor, ...]:
    sizes = [c.size for c in items]
    return tuple(torch.split(lam, sizes, dim=-1))


__all__ += ["constrained_dynamics", "impulse_dynamics", "ConstrainedDynamics", "ImpulseDynamics"]
