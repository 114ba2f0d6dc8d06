"""featherdyn's declared functions as PyTorch custom operators, with analytical gradients (docs/frameworks.md).

``import featherdyn.torch as ft``: ``ft.<name>(model, q, ...)`` takes and returns tensors, with the names,
arguments and results of ``fd.<name>``. Everything here is made from the declarations
(``api/declarations.py``, docs/architecture.md "The glue"); nothing is written per algorithm but the three
small tables at the end of this docstring:

* **Operators.** Each declared function is a ``torch.library.custom_op`` ``featherdyn::<name>`` (no mutation):
  ``(int model, Tensor q, ..., Tensor? f_ext, <options>) -> Tensor or (Tensor, ...)``. The model is not a
  tensor: ``model`` is its key in this module's registry (:func:`model_key`; a model once registered stays
  registered for the life of the process). Options are arguments: ``gravity`` a bool, ``frame`` an index
  (names are resolved by the wrapper, ``Model.resolve_frame``), ``reference`` a code (``ReferenceFrame.code``).
  The operator calls the declared call of ``fd.<name>`` (``api.declared.call``: the same checks, errors and
  core) on the tensors' NumPy views; its fake implementation gives the shapes the core declares
  (``core.declared.SPECS``), so ``torch.compile(fullgraph=True)`` traces it without a graph break, and a vmap
  rule (one call on the mapped batch). ``torch.func.grad`` does not reach the backward of PyTorch's custom
  operators (docs/frameworks.md); ``torch.autograd`` does.
* **Dtypes.** float64 CPU tensors go to NumPy without a copy (``Tensor.numpy()``); float32 tensors are
  converted to float64, computed by the core, and the results returned as float32 (where ``fd.<name>`` on
  float32 arrays uses the float32 reference). Results are float64 otherwise; other dtypes are handed to
  ``fd`` as NumPy arrays, which raises its own errors (``DTypeError`` for complex).
* **Results.** One output: a tensor. Several: the NamedTuple ``fd.<name>`` returns when it is one
  (``RneaSecondDerivatives`` & co.), else a NamedTuple named by the declaration's outputs (records such as
  ``fd.forward_kinematics``'s ``Kinematics`` or ``fd.frame_placement``'s ``PluckerTransform`` become their
  arrays: ``ft.forward_kinematics(...)`` is ``(H, Hp, vel, acc)``); an output formed only with an absent
  optional input (``vel`` without ``v``) is ``None`` (an empty tensor from the operator itself).
* **Gradients.** An operator whose declaration names a ``derivative`` has a backward: the vector-Jacobian
  product of the derivative's outputs (operator ``featherdyn::<name>_vjp``, itself traced). The derivative
  with respect to ``q`` is along ``fd.integrate``'s tangent (``nv``); the backward maps it to ``q``'s
  coordinates with ``∂δ/∂q`` of the joints (:func:`tangent_to_coordinates`: unit quaternions are normalised by
  featherdyn, so the radial direction has derivative zero), which is what ``torch.autograd.gradcheck`` in
  coordinates measures. :func:`tangent_grad` turns any coordinate gradient back into the tangent gradient.
  Every other operator has a backward that raises :class:`~featherdyn.FeatherdynError` naming what is missing
  (never a silent zero).

The tables (hand-written, each a few lines): ``_EXTRA_JACOBIANS`` (``crba``: ``∂M/∂q`` is
``fd.rnea_second_derivatives(q, 0, 0).dM_dq``, which the declaration's ``derivative`` field — one output per
state input, of the same declared function — cannot state), ``_F_EXT`` (the generalized force of ``f_ext``
in ``rnea`` and ``aba``: its gradient is a body velocity, ``∂τ/∂f_b = −J_bᵀ``), and ``_SECOND`` (which
output of ``fd.rnea_second_derivatives`` / ``fd.aba_second_derivatives`` is which pair of inputs: the double
backward of ``rnea`` and ``aba``).
"""

from __future__ import annotations

import inspect
from collections import namedtuple
from collections.abc import Callable, Sequence
from dataclasses import replace
from types import SimpleNamespace
from typing import Any, cast

import numpy as np
import torch

from .api.declarations import DECLARATIONS
from .api.declared import OPTIONS, REFERENCES, Declaration, call
from .core.declared import SPECS, shape_of
from .errors import DTypeError, FeatherdynError, ShapeError
from .frames import as_reference_frame
from .model import Model

__all__ = ["model_key", "tangent_grad", "tangent_to_coordinates", "OPERATORS", "VJP_OPERATORS"]

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
        model, tensors = _model(key), args[:n]
        batch, dtype = _batch(model, decl.name, tensors), _result_dtype(tensors)
        given = dict(zip(decl.inputs, tensors, strict=True))
        r = tuple(tensors[0].new_empty((0,) if when is not None and given[when] is None
                                       else batch + _tail(model, shape), dtype=dtype)
                  for _, shape, when in spec.outputs)
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


# ---------------------------------------------------------------------------------------- tangent of q

def _joint_blocks(model: Model) -> list[tuple[str, int, int]]:
    """``(kind, index in q, index in v)`` of each joint whose ``q`` is not its tangent's coordinates."""
    return [(j.kind, iq, iv) for j, iq, iv in zip(model.joints, model.idx_q, model.idx_v, strict=True)
            if j.kind in ("spherical", "free_flyer", "planar")]


def _cross(a: torch.Tensor, b: torch.Tensor) -> torch.Tensor:
    """``a × b`` on the last dimension, broadcasting (componentwise: vmap has no rule for broadcast_tensors)."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return torch.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], dim=-1)


def _rotate(quat: torch.Tensor, x: torch.Tensor, transpose: bool = False) -> torch.Tensor:
    """``R(q/|q|) x`` (or ``Rᵀ x``) for quaternions ``(x, y, z, w)``: ``x + 2w (u × x) + 2 u × (u × x)``."""
    u = quat / torch.linalg.vector_norm(quat, dim=-1, keepdim=True)
    vec, w = u[..., :3], u[..., 3:]
    if transpose:
        vec = -vec
    t = _cross(vec, x)
    return x + 2 * w * t + 2 * _cross(vec, t)


def _planar_rotate(theta: torch.Tensor, xy: torch.Tensor, transpose: bool = False) -> torch.Tensor:
    c, s = torch.cos(theta), torch.sin(theta)
    if transpose:
        s = -s
    return torch.stack([c * xy[..., 0] - s * xy[..., 1], s * xy[..., 0] + c * xy[..., 1]], dim=-1)


def tangent_to_coordinates(model: Model, q: torch.Tensor, g: torch.Tensor) -> torch.Tensor:
    """The gradient in ``q``'s coordinates `(..., nq)` of a gradient ``g`` `(..., nv)` along ``fd.integrate``'s
    tangent: ``Tᵀ g`` with ``T = ∂δ/∂q`` `(nv, nq)`, ``δ = fd.difference(q, q')`` at ``q' = q``. Per joint (others
    the identity): a quaternion ``q = (u, w)`` (featherdyn normalises it, ``R = R(q/|q|)``) has
    ``T = 2/|q|² [w 1 − [u]×, −u]`` (``δq = ½ q ⊗ (ω, 0)``); a free-flyer's position ``δv = Rᵀ δp``; a planar
    joint's ``ω = δθ``, ``(v_x, v_y) = Rz(θ)ᵀ (δx, δy)``. Differentiable (torch operations)."""
    blocks = _joint_blocks(model)
    if not blocks:
        return g
    pieces: list[torch.Tensor] = []
    done_q = done_v = 0
    for kind, iq, iv in blocks:
        if iq > done_q:  # the vector joints before this one
            pieces.append(g[..., done_v: iv])
        quat_at = {"spherical": iq, "free_flyer": iq + 3}.get(kind)
        if kind == "planar":
            th = q[..., iq + 2]
            pieces += [_planar_rotate(th, g[..., iv + 1: iv + 3]), g[..., iv: iv + 1]]
        else:
            assert quat_at is not None
            quat = q[..., quat_at: quat_at + 4]
            gw = g[..., iv: iv + 3]
            if kind == "free_flyer":
                pieces.append(_rotate(quat, g[..., iv + 3: iv + 6]))
            c = 2 / torch.sum(quat * quat, dim=-1, keepdim=True)
            u, w = quat[..., :3], quat[..., 3:]
            pieces += [c * (w * gw + _cross(u, gw)), -c * torch.sum(u * gw, dim=-1, keepdim=True)]
        done_q, done_v = iq + {"spherical": 4, "free_flyer": 7, "planar": 3}[kind], iv + (6 if kind == "free_flyer"
                                                                                          else 3)
    if done_v < g.shape[-1]:
        pieces.append(g[..., done_v:])
    batch = torch.broadcast_shapes(q.shape[:-1], g.shape[:-1])
    return torch.cat([p.expand(*batch, p.shape[-1]) for p in pieces], dim=-1)


def tangent_grad(model: Model, q: torch.Tensor, grad_q: torch.Tensor) -> torch.Tensor:
    """The gradient `(..., nv)` along ``fd.integrate``'s tangent of a function whose gradient in ``q``'s
    coordinates is ``grad_q`` `(..., nq)`: ``Eᵀ grad_q``, ``E = ∂(q ⊕ δ)/∂δ`` at ``δ = 0`` `(nq, nv)`, i.e.
    ``d/dδ L(fd.integrate(q, δ))``. For the gradient of featherdyn's operators (``Tᵀ g``, ``T E = 1``) it is
    their tangent gradient ``g`` exactly. A step on the manifold: ``fd.integrate(model, q, -lr * g)``.
    Per joint: a quaternion ``E = ½ [w 1 + [u]×; −uᵀ]``, a free-flyer's position ``R``, a planar joint's
    ``(δx, δy) = Rz(θ) (v_x, v_y)``, ``δθ = ω``."""
    blocks = _joint_blocks(model)
    if not blocks:
        return grad_q
    pieces: list[torch.Tensor] = []
    done_q = 0
    for kind, iq, _iv in blocks:
        if iq > done_q:
            pieces.append(grad_q[..., done_q: iq])
        if kind == "planar":
            pieces += [grad_q[..., iq + 2: iq + 3],
                       _planar_rotate(q[..., iq + 2], grad_q[..., iq: iq + 2], transpose=True)]
            done_q = iq + 3
            continue
        at = iq if kind == "spherical" else iq + 3
        quat, gq = q[..., at: at + 4], grad_q[..., at: at + 4]
        u, w = quat[..., :3], quat[..., 3:]
        pieces.append(0.5 * (w * gq[..., :3] - _cross(u, gq[..., :3]) - u * gq[..., 3:]))
        if kind == "free_flyer":
            pieces.append(_rotate(quat, grad_q[..., iq: iq + 3], transpose=True))
        done_q = at + 4
    if done_q < grad_q.shape[-1]:
        pieces.append(grad_q[..., done_q:])
    batch = torch.broadcast_shapes(q.shape[:-1], grad_q.shape[:-1])
    return torch.cat([p.expand(*batch, p.shape[-1]) for p in pieces], dim=-1)


def _sum_to(g: torch.Tensor, shape: torch.Size) -> torch.Tensor:
    """``g`` summed over the batch dimensions its input was broadcast along (to ``shape``)."""
    if tuple(g.shape) == tuple(shape):
        return g
    lead = g.dim() - len(shape)
    g = g.sum(dim=tuple(range(lead))) if lead else g
    dims = tuple(i for i, (a, b) in enumerate(zip(g.shape, shape, strict=True)) if b == 1 and a != 1)
    return g.sum(dim=dims, keepdim=True) if dims else g


# ------------------------------------------------------------------------------------------- gradients

def _jacobians_declared(decl: Declaration) -> Callable[..., tuple[np.ndarray, ...]]:
    """The Jacobians of ``decl``'s output, one per state input but ``f_ext``: its declared derivative's outputs."""
    deriv = DECLARATIONS[str(decl.derivative)]

    def jacobians(model: Model, arrays: dict[str, np.ndarray | None], options: dict[str, Any]) -> tuple[Any, ...]:
        outs = _declared(deriv, model, [arrays[n] for n in deriv.inputs],
                         {k: v for k, v in options.items() if k in deriv.options})
        return outs[: len(_differentiated(decl))]

    return jacobians


def _crba_jacobians(model: Model, arrays: dict[str, np.ndarray | None], options: dict[str, Any]) -> tuple[Any, ...]:
    """``∂M/∂q`` `(..., nv, nv, nv)` (``[i, j, k] = ∂M_ij/∂q_k``): ``fd.rnea_second_derivatives(q, 0, 0).dM_dq``
    (it does not depend on ``q̇, q̈``)."""
    q = arrays["q"]
    assert q is not None
    zero = np.zeros(q.shape[:-1] + (model.nv,))
    return (_declared(DECLARATIONS["rnea_second_derivatives"], model, [q, zero, zero, None], {"gravity": False})[3],)


#: the Jacobians of the operators without a declared ``derivative`` that have one anyway (module docstring)
_EXTRA_JACOBIANS: dict[str, Callable[..., tuple[np.ndarray, ...]]] = {"crba": _crba_jacobians}


def _jacobian_source(decl: Declaration) -> Callable[..., tuple[np.ndarray, ...]] | None:
    if decl.derivative is not None:
        return _jacobians_declared(decl)
    return _EXTRA_JACOBIANS.get(decl.name)


def _differentiated(decl: Declaration) -> tuple[str, ...]:
    """The inputs whose Jacobians the derivative gives (the state inputs but ``f_ext``)."""
    return tuple(n for n in decl.inputs if n != "f_ext")


#: ``f_ext`` enters ``rnea`` and ``aba`` as the generalized force ``Σ_b J_bᵀ f_b`` (body-frame ``J_b``, ``f_b``):
#: the gradient ``w`` with respect to that force, from the output's cotangent and the other inputs' gradients;
#: ``f_ext``'s gradient is then ``J_b w`` for each body: the bodies' velocities at ``q̇ = w``
#: (``fd.forward_kinematics(q, w).vel``, body coordinates)
_F_EXT: dict[str, Callable[[torch.Tensor, dict[str, torch.Tensor]], torch.Tensor]] = {
    "rnea": lambda ybar, grads: -ybar,           # τ = RNEA(q, q̇, q̈) − Σ J_bᵀ f_b
    "aba": lambda ybar, grads: grads["tau"],     # q̈ = ABA(q, q̇, τ + Σ J_bᵀ f_b)
}

#: the second derivatives of ``rnea`` and ``aba``: ``(x, z)`` → the output ``[i, x_j, z_k] = ∂²y_i/∂x_j∂z_k`` of
#: the declared function (pairs not listed, either way round, are zero: ``∂²τ/∂q̈², ∂²τ/∂q̇∂q̈, ∂²q̈/∂τ², ...``)
_SECOND: dict[str, tuple[str, dict[tuple[str, str], str]]] = {
    "rnea": ("rnea_second_derivatives", {("q", "q"): "d2tau_dq2", ("v", "v"): "d2tau_dv2",
                                         ("q", "v"): "d2tau_dqdv", ("a", "q"): "dM_dq"}),
    "aba": ("aba_second_derivatives", {("q", "q"): "d2ddq_dq2", ("v", "v"): "d2ddq_dv2",
                                       ("q", "v"): "d2ddq_dqdv", ("q", "tau"): "d2ddq_dqdtau"}),
}


def _make_vjp(decl: Declaration, jacobians: Callable[..., tuple[np.ndarray, ...]]) -> Any:
    """``featherdyn::<name>_vjp(model, inputs..., options..., ybar)``: ``ȳ · ∂y/∂x`` for each differentiated
    input ``x`` (``q`` along the tangent, `(..., nv)`), batch shape that of ``y``."""
    n = len(decl.inputs)
    xs = _differentiated(decl)

    def impl(key: int, *args: Any) -> Any:
        model, tensors, ybar = _model(key), args[:n], args[-1]
        arrays = dict(zip(decl.inputs, (_numpy(t) for t in tensors), strict=True))
        Js = jacobians(model, arrays, _options(decl, args[n:-1]))
        yb = _numpy(ybar)
        assert yb is not None
        dtype, device = _result_dtype((*tensors, ybar)), ybar.device
        out = []
        ybf = yb.reshape(yb.shape[: yb.ndim - _y_dims(decl)] + (1, -1))  # ȳ as a row (its output dims flat)
        for J in Js:  # (..., *y, nx): ȳ J (matmul: a third of einsum's time on batches)
            Jf = J.reshape(J.shape[: yb.ndim - _y_dims(decl)] + (-1, J.shape[-1]))
            out.append(_tensor(np.matmul(ybf, Jf)[..., 0, :], dtype, device))
        return tuple(out) if len(out) > 1 else out[0]

    def fake(key: int, *args: Any) -> Any:
        model, tensors, ybar = _model(key), args[:n], args[-1]
        batch = torch.broadcast_shapes(_batch(model, decl.name, tensors), ybar.shape[: ybar.dim() - _y_dims(decl)])
        dtype = _result_dtype((*tensors, ybar))
        r = tuple(ybar.new_empty(tuple(batch) + (model.nv,), dtype=dtype) for _ in xs)
        return r if len(r) > 1 else r[0]

    return torch.library.custom_op(f"featherdyn::{decl.name}_vjp", impl, mutates_args=(),
                                   schema=_schema(decl, len(xs), "Tensor ybar")), fake


def _vjp_tails(decl: Declaration) -> Callable[[Model, int], dict[int, tuple[int, ...]]]:
    """The trailing shapes of a VJP operator's tensors by position: the inputs', and the output's (``ȳ``, last)."""
    def tails(model: Model, n_args: int) -> dict[int, tuple[int, ...]]:
        spec = SPECS[decl.name]
        out = {i: _tail(model, shape) for i, (_, shape, _) in enumerate(spec.inputs)}
        out[n_args - 1] = _tail(model, spec.outputs[0][1])
        return out

    return tails


def _y_dims(decl: Declaration) -> int:
    """The number of trailing dimensions of the (one) output."""
    return len(SPECS[decl.name].outputs[0][1])


def _no_derivative(what: str) -> FeatherdynError:
    return FeatherdynError(f"featherdyn.torch: {what} is not available (docs/frameworks.md lists the operators "
                           "with first and second derivatives)")


def _saved(ctx: Any, inputs: tuple[Any, ...], n: int) -> None:
    ctx.key = inputs[0]
    ctx.options = inputs[1 + n:]
    ctx.save_for_backward(*inputs[1: 1 + n])


def _q_and_vectors(decl: Declaration, model: Model, ins: Sequence[torch.Tensor | None],
                   tangent: dict[str, torch.Tensor], needs: Sequence[bool]) -> dict[str, torch.Tensor | None]:
    """The gradients of the inputs from their tangent gradients: ``q`` mapped to its coordinates, each summed to
    its input's shape (``None`` where not needed)."""
    given = dict(zip(decl.inputs, ins, strict=True))
    out: dict[str, torch.Tensor | None] = {}
    for name, need in zip(decl.inputs, needs, strict=True):
        t = given[name]
        if not need or t is None or name not in tangent:
            out[name] = None
            continue
        g = tangent[name]
        if name == "q":
            g = tangent_to_coordinates(model, t, g)
        out[name] = _sum_to(g, t.shape).to(t.dtype)
    return out


def _register_gradient(decl: Declaration, op: Any, vjp: Any | None) -> None:
    n = len(decl.inputs)
    xs = _differentiated(decl)

    def backward(ctx: Any, *grads: Any) -> Any:
        needs = ctx.needs_input_grad[1: 1 + n]
        if vjp is None:
            if any(needs):
                raise _no_derivative(f"the derivative of {decl.name}")
            return (None,) * (1 + n + len(decl.options))
        model, ins, ybar = _model(ctx.key), ctx.saved_tensors, grads[0]
        r = vjp(ctx.key, *ins, *ctx.options, ybar)
        tangent = dict(zip(xs, r if len(xs) > 1 else (r,), strict=True))
        out = _q_and_vectors(decl, model, ins, tangent, needs)
        if "f_ext" in decl.inputs and needs[decl.inputs.index("f_ext")]:
            f_ext = ins[decl.inputs.index("f_ext")]
            if decl.name not in _F_EXT:
                raise _no_derivative(f"the derivative of {decl.name} with respect to f_ext")
            w = _F_EXT[decl.name](ybar, tangent)
            q = ins[decl.inputs.index("q")]
            vel = torch.ops.featherdyn.forward_kinematics(ctx.key, q, w.to(q.dtype), None)[2]
            out["f_ext"] = _sum_to(vel, f_ext.shape).to(f_ext.dtype)
        return (None, *(out[k] for k in decl.inputs), *(None for _ in decl.options))

    op.register_autograd(backward, setup_context=lambda ctx, inputs, output: _saved(ctx, inputs, n))


def _register_second(decl: Declaration, vjp: Any) -> None:
    """The backward of ``<name>_vjp``: ``ȳ`` gets ``Σ_x J_x h_x``, each input ``z`` ``Σ_x ȳ_i h_x,j ∂²y_i/∂x_j∂z_k``
    (``_SECOND``)."""
    n = len(decl.inputs)
    xs = _differentiated(decl)
    second = _SECOND.get(decl.name)
    deriv = decl.derivative

    def backward(ctx: Any, *hs: Any) -> Any:
        needs = ctx.needs_input_grad[1: 1 + n]
        need_ybar = ctx.needs_input_grad[-1]
        if not (any(needs) or need_ybar):
            return (None,) * (2 + n + len(decl.options))
        if second is None or deriv is None:
            raise _no_derivative(f"the second derivative of {decl.name}")
        if "f_ext" in decl.inputs and needs[decl.inputs.index("f_ext")]:
            raise _no_derivative(f"the second derivative of {decl.name} with respect to f_ext")
        model, (*ins, ybar) = _model(ctx.key), ctx.saved_tensors
        h = dict(zip(xs, hs, strict=True))
        ybar_grad = None
        if need_ybar:
            Js = getattr(torch.ops.featherdyn, deriv)(ctx.key, *ins, *ctx.options)
            terms = [torch.einsum("...ij,...j->...i", J, h[x]) for J, x in zip(Js[: len(xs)], xs, strict=True)]
            ybar_grad = sum(terms[1:], terms[0])
        tangent: dict[str, torch.Tensor] = {}
        if any(needs):
            name, table = second
            sdecl = DECLARATIONS[name]
            S = dict(zip(sdecl.outputs, getattr(torch.ops.featherdyn, name)(ctx.key, *ins, *ctx.options),
                         strict=True))
            for z in xs:
                terms = []
                for x in xs:
                    if (x, z) in table:
                        terms.append(torch.einsum("...i,...j,...ijk->...k", ybar, h[x], S[table[x, z]]))
                    elif (z, x) in table:
                        terms.append(torch.einsum("...i,...j,...ikj->...k", ybar, h[x], S[table[z, x]]))
                if terms:
                    tangent[z] = sum(terms[1:], terms[0])
                else:
                    tangent[z] = torch.zeros_like(h[z])
        out = _q_and_vectors(decl, model, ins, tangent, needs)
        if ybar_grad is not None:
            ybar_grad = _sum_to(ybar_grad, ybar.shape).to(ybar.dtype)
        return (None, *(out[k] for k in decl.inputs), *(None for _ in decl.options), ybar_grad)

    def setup(ctx: Any, inputs: tuple[Any, ...], output: Any) -> None:
        ctx.key = inputs[0]
        ctx.options = inputs[1 + n: -1]
        ctx.save_for_backward(*inputs[1: 1 + n], inputs[-1])

    vjp.register_autograd(backward, setup_context=setup)


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


def _front(decl: Declaration, op: Any) -> Callable[..., Any]:
    """``ft.<name>(model, *inputs, frame, reference, *, gravity=True)``: the operator on ``model``'s key."""
    P = inspect.Parameter
    params = [P("model", P.POSITIONAL_OR_KEYWORD)]
    params += [P(n, P.POSITIONAL_OR_KEYWORD, default=None if n in decl.optional else P.empty) for n in decl.inputs]
    params += [P(n, P.POSITIONAL_OR_KEYWORD, default=OPTIONS[n]) for n in ("frame", "reference") if n in decl.options]
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
        r = op(model_key(model), *(a.get(n) for n in decl.inputs), *options)
        if result is None:
            return r
        absent = {n for n in decl.inputs if a.get(n) is None}
        return result(*(None if when.get(o) in absent else t for o, t in zip(decl.outputs, r, strict=True)))

    front.__name__ = front.__qualname__ = decl.name
    front.__doc__ = f"``fd.{decl.name}`` on tensors (operator ``featherdyn::{decl.name}``).\n\n{decl.doc}"
    front.__signature__ = sig  # type: ignore[attr-defined]
    return front


def _is_state_function(decl: Declaration) -> bool:
    return all(n in ("q", "v", "a", "tau", "f_ext") for n in decl.inputs)


#: the operators (``torch.ops.featherdyn.<name>``), by name
OPERATORS: dict[str, Any] = {}
#: the vector-Jacobian operators (``torch.ops.featherdyn.<name>_vjp``) of the operators with a derivative
VJP_OPERATORS: dict[str, Any] = {}

for _decl in DECLARATIONS.values():
    if not _is_state_function(_decl):
        continue
    OPERATORS[_decl.name] = _make_operator(_decl)
for _decl in DECLARATIONS.values():
    if _decl.name not in OPERATORS:
        continue
    _source = _jacobian_source(_decl)
    _vjp = None
    if _source is not None:
        _vjp, _vjp_fake = _make_vjp(_decl, _source)
        _vjp.register_fake(_vjp_fake)
        _vjp.register_vmap(_vmap_rule(_vjp, _vjp_tails(_decl)))
        _register_second(_decl, _vjp)
        VJP_OPERATORS[_decl.name] = _vjp
    _register_gradient(_decl, OPERATORS[_decl.name], _vjp)
    globals()[_decl.name] = _front(_decl, OPERATORS[_decl.name])
    __all__.append(_decl.name)
del _decl
