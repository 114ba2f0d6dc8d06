"""featherdyn's declared algorithms as JAX operations: XLA FFI calls into the compiled core (docs/frameworks.md).

::

    import featherdyn.jax as fj
    tau = fj.rnea(model, q, v, a)                  # the same names, arguments and results as fd.*
    jax.jit(jax.vmap(fj.aba, (None, 0, 0, 0)))     # vmap runs the core's batch (one call, the thread pool)
    jax.grad(lambda q: fj.rnea(model, q, v, a) @ w)(q)

Every function of ``fd`` that is declared once (``api/declarations.py``) is made here from its declaration:
an ``jax.ffi.ffi_call`` of the core's one handler (``core/cpp/bind_jax.cpp``) with the model and the options
as a registered entry; no Python runs when the compiled computation runs. Under ``vmap`` the handler gets the
batch and runs the core's batch path (``declare.hpp: run_rows``), as ``fd.<name>`` does on a batch.

**Gradients** come from ``api/jacobians.py``: each function's Jacobians made of declared functions (the
declaration's ``derivative``, or a rule there), computed by this module's operations, so a JVP rule
``ẏ = Σ ∂y/∂x_i · ẋ_i`` (``jvp``, ``jacfwd`` and, by JAX's transposition, ``grad``, ``vjp``, ``jacrev``) that is
itself differentiable where its Jacobians are (``jax.hessian`` of ``rnea``, ``aba``, …). A function without them
raises :class:`featherdyn.errors.FeatherdynError` when differentiated, never a zero; ``f_ext`` differentiates in
``rnea`` and ``aba`` (``∂τ/∂f_b = −J_bᵀ``) and raises elsewhere.
``constrained_dynamics`` and ``impulse_dynamics`` (contacts) are the core's contact kernels, differentiated by the
contact derivative kernels.

**The configuration's tangent.** featherdyn's ``∂/∂q`` is along ``fd.integrate``'s tangent (``nv`` columns);
JAX differentiates with respect to ``q``'s coordinates (``nq``). The JVP maps a coordinate direction ``q̇`` to
the tangent ``δ = T(q) q̇`` (:func:`tangent_of_coordinates`: identity on revolute and prismatic coordinates;
``ω = 2 vec(q̄ ⊗ q̇)/|q|²`` on a quaternion, ``Rᵀ ṗ`` on a free-flyer's position, ``[θ̇; Rz(θ)ᵀ (ẋ, ẏ)]`` on a
planar joint), so ``jax.grad``
with respect to ``q`` is ``T(q)ᵀ g`` — the gradient in coordinates, tangent to the unit quaternions. For the
gradient on the manifold (``nv`` entries, what ``fd.rnea_derivatives`` gives) use :func:`tangent_grad`.

float64 throughout: importing this module turns on ``jax_enable_x64``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from functools import partial
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np
from jax.core import ShapedArray
from jax.extend.core import Primitive
from jax.interpreters import ad, batching, mlir

from .api import jacobians as _jac
from .api.declarations import DECLARATIONS
from .api.declared import (
    REFERENCES,
    Declaration,
    kernel_options,
    operand_shapes,
    positional_parameters,
    xla_entry,
    xla_ffi,
)
from .core.declared import SPECS
from .errors import DTypeError, FeatherdynError, ShapeError
from .model import Model

jax.config.update("jax_enable_x64", True)

__all__ = ["tangent_of_coordinates", "coordinates_of_tangent", "normalize", "tangent_grad", "constrained_dynamics",
           "impulse_dynamics", "ConstrainedDynamics", "ImpulseDynamics", *DECLARATIONS]

_HANDLER = xla_ffi()
if _HANDLER is None:
    raise ImportError("featherdyn.jax: this build of featherdyn's core has no XLA FFI handler (jaxlib was not in "
                      "its build environment; `featherdyn info --build` says which); reinstall featherdyn with "
                      "jaxlib available, e.g. pip install --force-reinstall 'featherdyn[jax]'")
_TARGET = "featherdyn_declared"
jax.ffi.register_ffi_target(_TARGET, _HANDLER[0], platform="cpu")
_ORDER = _HANDLER[1]

#: the handler's entries: (model id, options) → (key, the model, held alive here); and the models by key
_ENTRIES: dict[tuple[int, tuple[tuple[str, Any], ...]], tuple[int, Model]] = {}
#: by key: the model, the options (as the public functions take them: the frame's index, the reference; a contact
#: plan's as the kernel does), and the constraint rows m
_MODELS: dict[int, tuple[Model, dict[str, Any], int]] = {}


def _entry(model: Model, options: dict[str, Any]) -> int:
    """The handler's key of (model, kernel options), registered once (the model, and a contact plan among the
    options, stay registered)."""
    ident = (id(model), tuple(sorted(options.items())))
    found = _ENTRIES.get(ident)
    if found is None:
        key = xla_entry(model, options)
        found = _ENTRIES[ident] = (key, model)
        _MODELS[key] = (model, {n: REFERENCES[v] if n == "reference" else v for n, v in options.items()},
                        int(options.get("rows", 0)))
    return found[0]


# --- the configuration's tangent (api/jacobians.py, shared with featherdyn.torch) -----------------------------------


class _Jax:
    """api/jacobians.py's :class:`~featherdyn.api.jacobians.Framework` in JAX: the operations of this module."""

    einsum = staticmethod(jnp.einsum)
    const = staticmethod(jnp.asarray)
    cos = staticmethod(jnp.cos)
    sin = staticmethod(jnp.sin)
    sqrt = staticmethod(jnp.sqrt)

    @staticmethod
    def isfinite(x: Any, /) -> Any:
        return jnp.isfinite(x)

    @staticmethod
    def where(condition: Any, x: Any, y: Any, /) -> Any:
        return jnp.where(condition, x, y)

    @staticmethod
    def call(name: str, model: Model, inputs: dict[str, Any], options: dict[str, Any]) -> tuple[Any, ...]:
        r = globals()[name](model, **{n: inputs.get(n) for n in DECLARATIONS[name].inputs}, **options)  # (by name)
        return tuple(r) if isinstance(r, tuple) else (r,)

    @staticmethod
    def concat(xs: Sequence[Any], axis: int) -> Any:
        return jnp.concatenate(list(xs), axis=axis)

    @staticmethod
    def stack(xs: Sequence[Any], axis: int) -> Any:
        return jnp.stack(list(xs), axis=axis)

    @staticmethod
    def zeros(shape: tuple[int, ...]) -> Any:
        return jnp.zeros(shape, dtype=jnp.float64)


_FW = _Jax()


def tangent_of_coordinates(model: Model, q: Any, dq: Any) -> Any:
    """``δ = T(q) q̇`` `(..., nv)`: the tangent (``fd.integrate``'s, ``v``'s layout) of a coordinate direction ``q̇``
    `(..., nq)` at ``q``, with the quaternions normalised as featherdyn does (the radial part of ``q̇`` has none)::

        revolute, prismatic: δ = q̇;   quaternion (u, w): ω = 2 vec(q̄ ⊗ q̇) / |q|²;
        free-flyer [p, quat]: [ω; v] with v = R(quat)ᵀ ṗ;   planar [x, y, θ]: [θ̇, Rz(θ)ᵀ (ẋ, ẏ)]
    """
    return _jac.tangent_of_coordinates(_FW, model, jnp.asarray(q), jnp.asarray(dq))


def coordinates_of_tangent(model: Model, q: Any, delta: Any) -> Any:
    """``q̇ = E(q) δ`` `(..., nq)`: the coordinate direction of ``q ⊕ ε δ`` at ε = 0 (``T(q) E(q) = 1``)::

        quaternion: q̇ = ½ q ⊗ [ω; 0];   free-flyer: ṗ = R(quat) v;   planar: (ẋ, ẏ) = Rz(θ) (v_x, v_y), θ̇ = ω
    """
    return _jac.coordinates_of_tangent(_FW, model, jnp.asarray(q), jnp.asarray(delta))


def normalize(model: Model, q: Any) -> Any:
    """``q`` `(..., nq)` with each quaternion divided by its norm (``fd.normalize`` in JAX): what a function
    differentiated in coordinates off the unit quaternions (finite differences, ``check_grads``) calls first;
    at a unit quaternion its Jacobian removes the radial direction, which ``T(q)`` ignores anyway."""
    return _jac.normalize(_FW, model, jnp.asarray(q, dtype=jnp.float64))


def tangent_grad(f: Callable[..., Any], model: Model) -> Callable[..., Any]:
    """``g(q, *args)`` `(..., nv)`: the gradient of the scalar ``f(q, *args)`` along ``fd.integrate``'s tangent at
    ``q`` — ``E(q)ᵀ ∇_q f`` (:func:`coordinates_of_tangent`), the row ``fd.rnea_derivatives`` & co. give."""
    grad = jax.grad(f)

    def g(q: Any, *args: Any) -> Any:
        q = jnp.asarray(q, dtype=jnp.float64)
        return _jac.coordinates_transpose(_FW, model, q, grad(q, *args))

    return g


# --- the operations --------------------------------------------------------------------------------------------


def _ffi(name: str, key: int, present: int, arrays: Sequence[Any]) -> tuple[Any, ...]:
    """The handler's outputs of kernel ``name``; the batch is the inputs' leading axes, broadcast (``vmap``
    broadcasts its unmapped inputs too: ``broadcast_all``)."""
    model, _, rows = _MODELS[key]
    inputs, outputs = operand_shapes(name, model, rows)
    shapes = [shape for k, shape in enumerate(inputs) if (present >> k) & 1]
    batch: tuple[int, ...] = ()
    for x, shape in zip(arrays, shapes, strict=True):
        if x.shape[x.ndim - len(shape):] != shape or x.ndim < len(shape):
            raise ShapeError(f"featherdyn.jax.{name}: an input of shape {x.shape}, expected (..., "
                             f"{', '.join(map(str, shape))})")
        batch = jnp.broadcast_shapes(batch, x.shape[:x.ndim - len(shape)])
    arrays = [jnp.broadcast_to(x, batch + shape) for x, shape in zip(arrays, shapes, strict=True)]
    results = [jax.ShapeDtypeStruct(batch + s, jnp.float64) for s in outputs]
    out = jax.ffi.ffi_call(_TARGET, results, vmap_method="broadcast_all")(
        *arrays, kernel=np.int64(_ORDER[name]), key=np.int64(key), present=np.int64(present))
    return tuple(out)


@partial(jax.custom_jvp, nondiff_argnums=(0, 1, 2))
def _op(name: str, key: int, present: int, *arrays: Any) -> tuple[Any, ...]:
    return _ffi(name, key, present, arrays)


def _op_jvp(name: str, key: int, present: int, primals: tuple[Any, ...], tangents: tuple[Any, ...]
            ) -> tuple[tuple[Any, ...], tuple[Any, ...]]:
    """``ẏ_o = Σ_x J_ox · ẋ`` with the Jacobians of api/jacobians.py (``q̇`` mapped to the tangent first): made of this
    module's operations, so differentiated again by their own rules (``jax.hessian``)."""
    out = _op(name, key, present, *primals)
    decl = DECLARATIONS.get(name)
    if decl is None:  # a kernel without a public declaration (the contact derivatives): no derivatives of its own
        if any(not isinstance(t, jax.custom_derivatives.SymbolicZero) for t in tangents):
            raise FeatherdynError(f"featherdyn.jax.{name}: its derivatives are not available (a second derivative "
                                  "of constrained or impulse dynamics; docs/frameworks.md)")
        return out, tuple(jnp.zeros_like(o) for o in out)
    given = [n for k, n in enumerate(decl.inputs) if (present >> k) & 1]
    moving = {n: t for n, t in zip(given, tangents, strict=True)
              if not isinstance(t, jax.custom_derivatives.SymbolicZero)}
    zeros = tuple(jnp.zeros_like(o) for o in out)
    if not moving:
        return out, zeros
    model, options, _ = _MODELS[key]
    if not _jac.has_jacobians(name):
        raise FeatherdynError(f"featherdyn.jax.{name}: its derivatives are not available (docs/frameworks.md lists "
                              "the operations with first and second derivatives)")
    x = dict(zip(given, primals, strict=True))
    spec = SPECS[name]
    configuration = {n for n, shape, _ in (*spec.inputs, *spec.outputs) if shape == ("nq",)}  # (q, q0, q1, q')
    directions = {n: tangent_of_coordinates(model, x[n], t) if n in configuration else t for n, t in moving.items()}
    f_dot = directions.pop("f_ext", None)
    if f_dot is not None and name not in _jac.F_EXT:
        raise FeatherdynError(f"{name}: no derivative with respect to f_ext (rnea's and aba's only); hold f_ext "
                              "constant")
    if name in _jac.VJPS:  # the tangent as a primitive linear in the directions (_LINEAR), f_ext's through _FORCE
        u_dot = None if f_dot is None else _FORCE.bind(x["q"], f_dot, key=key)[0]
        into = _jac.F_EXT.get(name)
        if u_dot is not None and into is not None:  # (aba: q̈ = ABA(q, q̇, τ + u))
            directions[into] = directions[into] + u_dot if into in directions else u_dot
        known, linear = tuple(x), tuple(directions)
        t_out = _LINEAR.bind(*x.values(), *directions.values(), name=name, key=key, known=known, linear=linear)
        if u_dot is not None and into is None:  # (rnea: τ − u)
            t_out = [t_out[0] - u_dot, *t_out[1:]]
        return out, tuple(t + z for t, z in zip(t_out, zeros, strict=True))
    table = _jac.jacobians(_FW, name, model, x, options)
    for n in _jac.matrix_inputs(name) & set(directions):  # (a matrix's Jacobian is over its flattened entries)
        directions[n] = directions[n].reshape(directions[n].shape[:-2] + (-1,))
    t_out = []
    for o_name, o, zero, (_, shape, _) in zip(decl.outputs, out, zeros, spec.outputs, strict=True):
        t = None
        letters = "abcdefgh"[:len(shape)]
        for n, d in directions.items():
            J = table.get(o_name, {}).get(n)
            if J is not None:
                term = jnp.einsum(f"...{letters}z,...z->...{letters}", J, d)
                t = term if t is None else t + term
        if f_dot is not None and o_name == decl.outputs[0]:  # (f_ext: through the generalized force, _FORCE)
            term = _jac.f_ext_tangent(_FW, name, table, _FORCE.bind(x["q"], f_dot, key=key)[0])
            t = term if t is None else t + term
        if t is None:
            t_out.append(zero)
        else:  # (a configuration's Jacobians are along its tangent: its coordinates move by E(q') δ')
            t_out.append(coordinates_of_tangent(model, o, t) if o_name in configuration else t + zero)
    return out, tuple(t_out)


_op.defjvp(_op_jvp, symbolic_zeros=True)


# --- a tangent whose transpose contracts as it goes ----------------------------------------------------------------
# JAX differentiates in reverse by transposing the forward rule, ẏ = Σ J_x · δ_x: for crba that needs ∂M/∂q, nv³
# numbers a state, and for rnea and aba their Jacobians, nv² a state and O(nv·nb) to form. `_LINEAR` is that sum as
# a primitive that is linear in the directions δ (JAX's primitive interface: docs.jax.dev, "JAX Internals:
# primitives"), with the transpose rule api/jacobians.py's VJPS (crba: ⟨W, ∂M/∂q⟩ by fd.crba_vjp; rnea, aba:
# fd.rnea_vjp, fd.aba_vjp, O(nb)): `grad`, `vjp`, `jacrev` take it; forward mode and its own derivatives
# evaluate J · δ.

_LINEAR = Primitive("featherdyn_linear_tangent")
_LINEAR.multiple_results = True


def _tails(names: Sequence[str]) -> tuple[int, ...]:
    """The operands' own trailing dimensions (``f_ext`` `(nb, 6)` and ``W`` `(nv, nv)`, every other input a
    vector)."""
    return tuple(_jac.input_tail(n) for n in names)


def _linear(*args: Any, name: str, key: int, known: tuple[str, ...], linear: tuple[str, ...]) -> list[Any]:
    """``[Σ_x J_ox · δ_x for each output o]`` with api/jacobians.py's Jacobians of ``fd.<name>`` at the inputs
    ``known`` (``args``' first values), ``δ_x`` the directions of the inputs ``linear`` (the rest)."""
    model, options, rows = _MODELS[key]
    x = dict(zip(known, args[:len(known)], strict=True))
    table = _jac.jacobians(_FW, name, model, x, options)
    batch = jnp.broadcast_shapes(*(a.shape[:a.ndim - k] for a, k in zip(args, _tails(known + linear), strict=True)))
    out = []
    for o, shape in zip(DECLARATIONS[name].outputs, operand_shapes(name, model, rows)[1], strict=True):
        t = None
        for n, delta in zip(linear, args[len(known):], strict=True):
            J = table.get(o, {}).get(n)
            if J is None:
                continue
            d = delta.reshape(delta.shape[:-1] + (1,) * len(shape) + delta.shape[-1:])  # (against J's output dims)
            term = jnp.sum(J * d, axis=-1)
            t = term if t is None else t + term
        out.append(jnp.zeros(batch + shape, jnp.float64) if t is None else jnp.broadcast_to(t, batch + shape))
    return out


def _linear_shapes(*args: Any, name: str, key: int, known: tuple[str, ...], linear: tuple[str, ...]
                   ) -> list[ShapedArray]:
    model, _, rows = _MODELS[key]
    batch = jnp.broadcast_shapes(*(x.shape[:x.ndim - k] for x, k in zip(args, _tails(known + linear), strict=True)))
    return [ShapedArray(batch + shape, jnp.float64) for shape in operand_shapes(name, model, rows)[1]]


def _linear_transpose(cts: Sequence[Any], *args: Any, name: str, key: int, known: tuple[str, ...],
                      linear: tuple[str, ...]) -> tuple[Any, ...]:
    """``δ̄_x = ȳᵀ J_x`` for each linear input by api/jacobians.py's ``VJPS[name]`` (the known inputs are values
    here, the directions undefined)."""
    assert all(ad.is_undefined_primal(d) for d in args[len(known):])
    assert not any(ad.is_undefined_primal(x) for x in args[:len(known)])
    model, options, _ = _MODELS[key]
    avals = [d.aval for d in args[len(known):]]
    given = {o: ct for o, ct in zip(DECLARATIONS[name].outputs, cts, strict=True) if type(ct) is not ad.Zero}
    if not given:
        return (None,) * len(known) + tuple(ad.Zero(a) for a in avals)
    bars = _jac.VJPS[name](_FW, model, dict(zip(known, args[:len(known)], strict=True)), given, options)
    grads = []
    for n, aval in zip(linear, avals, strict=True):
        g = bars.get(n)
        grads.append(ad.Zero(aval) if g is None else g if g.shape == aval.shape else _sum_to(g, aval.shape))
    return (None,) * len(known) + tuple(grads)


def _sum_to(g: Any, shape: tuple[int, ...]) -> Any:
    """``g`` summed over the leading axes it has beyond ``shape`` (``δ`` broadcast against a batch of ``q``)."""
    g = jnp.sum(g, axis=tuple(range(g.ndim - len(shape))))
    return jnp.sum(g, axis=tuple(k for k, n in enumerate(shape) if n == 1 and g.shape[k] != 1), keepdims=True)


def _batch_rule(primitive: Primitive, tails: Callable[..., tuple[int, ...]]) -> Callable[..., Any]:
    """vmap of a primitive whose operands take any leading batch axes (``tails(**params)``: each operand's own
    trailing dimensions): the mapped axis first, then singletons up to the widest operand's own batch, so that every
    operand broadcasts against the others (an unmapped operand from the right); the results mapped on axis 0."""

    def rule(args: Sequence[Any], dims: Sequence[int | None], **params: Any) -> tuple[list[Any], list[int]]:
        own = [x.ndim - (d is not None) - n for x, d, n in zip(args, dims, tails(**params), strict=True)]
        widest = max(own)
        moved = []
        for x, d, k in zip(args, dims, own, strict=True):
            x = x[None] if d is None else jnp.moveaxis(x, d, 0)
            moved.append(x.reshape(x.shape[:1] + (1,) * (widest - k) + x.shape[1:]))
        out = primitive.bind(*moved, **params)
        return out, [0] * len(out)

    return rule


def _register(primitive: Primitive, impl: Callable[..., list[Any]], shapes: Callable[..., list[ShapedArray]],
              transpose: Callable[..., tuple[Any, ...]], tails: Callable[..., tuple[int, ...]]) -> None:
    """A primitive ``(*known, *linear) → outputs``, linear in its last operands: evaluated (and lowered to XLA) by
    ``impl``, a function of this module's operations, which its forward mode differentiates; reversed by
    ``transpose``; batched by :func:`_batch_rule`."""

    def jvp(primals: Sequence[Any], tangents: Sequence[Any], **params: Any) -> tuple[Any, Any]:
        moving = [k for k, t in enumerate(tangents) if type(t) is not ad.Zero]  # (the others held: f_ext, say)
        if not moving:
            out = impl(*primals, **params)
            return out, [jnp.zeros_like(o) for o in out]

        def of_moving(*xs: Any) -> list[Any]:
            args = list(primals)
            for k, x in zip(moving, xs, strict=True):
                args[k] = x
            return impl(*args, **params)

        return jax.jvp(of_moving, tuple(primals[k] for k in moving), tuple(tangents[k] for k in moving))

    primitive.def_impl(impl)
    primitive.def_abstract_eval(shapes)
    mlir.register_lowering(primitive, mlir.lower_fun(impl, multiple_results=True))
    ad.primitive_jvps[primitive] = jvp
    ad.primitive_transposes[primitive] = transpose
    batching.primitive_batchers[primitive] = _batch_rule(primitive, tails)


_register(_LINEAR, _linear, _linear_shapes, _linear_transpose,
          lambda known, linear, **_: _tails(known + linear))


# f_ext enters rnea and aba as the generalized force u = Σ_b J_bᵀ f_b (api/jacobians.py: generalized_force); `_FORCE`
# is u̇ = u(ḟ) as a primitive linear in ḟ whose transpose is J_b w per body (generalized_force_transpose): reverse
# mode never forms ∂u/∂f (nv × nb × 6 a state).

_FORCE = Primitive("featherdyn_generalized_force")
_FORCE.multiple_results = True


def _force(q: Any, f: Any, *, key: int) -> list[Any]:
    return [_jac.generalized_force(_FW, _MODELS[key][0], q, f)]


def _force_shapes(q: Any, f: Any, *, key: int) -> list[ShapedArray]:
    return [ShapedArray(jnp.broadcast_shapes(q.shape[:-1], f.shape[:-2]) + (_MODELS[key][0].nv,), jnp.float64)]


def _force_transpose(cts: Sequence[Any], q: Any, f: Any, *, key: int) -> tuple[None, Any]:
    """``f̄_b = J_b ū`` (``q`` known, ``f`` the linear input)."""
    assert ad.is_undefined_primal(f) and not ad.is_undefined_primal(q)
    aval = f.aval
    if type(cts[0]) is ad.Zero:
        return None, ad.Zero(aval)
    g = _jac.generalized_force_transpose(_FW, _MODELS[key][0], q, cts[0])
    return None, g if g.shape == aval.shape else _sum_to(g, aval.shape)


_register(_FORCE, _force, _force_shapes, _force_transpose, lambda **_: (1, 2))


def _function(decl: Declaration) -> Callable[..., Any]:
    outputs = NamedTuple(f"{decl.name}_result", [(n, Any) for n in decl.outputs])  # type: ignore[misc]

    when = {o: w for o, _, w in SPECS[decl.name].outputs} if decl.name in SPECS else {}

    def f(model: Model, *args: Any, **options: Any) -> Any:
        if not isinstance(model, Model):
            raise ShapeError(f"model: expected a featherdyn Model, got {type(model).__name__}")
        positional = positional_parameters(decl)  # (inputs, frame and reference, a point: as in fd.*)
        if len(args) > len(positional):
            raise ShapeError(f"featherdyn.jax.{decl.name}: at most {len(positional)} arguments after the model "
                             f"({', '.join(positional)}), got {len(args)}")
        given = dict(zip(positional, args, strict=False))
        if set(given) & set(options):
            raise TypeError(f"{decl.name}(): multiple values for {sorted(set(given) & set(options))}")
        given.update(options)
        names = list(decl.inputs)
        padded = [given.pop(n, None) for n in names]
        options = given
        if set(options) - set(decl.options):  # (as fd.<name> refuses an unknown keyword)
            raise TypeError(f"{decl.name}(): unexpected keyword arguments {sorted(set(options) - set(decl.options))}")
        for k, x in enumerate(padded):
            if x is None and names[k] not in decl.optional:
                raise ShapeError(f"featherdyn.jax.{decl.name}: {names[k]} is required")
        present = sum(1 << k for k, x in enumerate(padded) if x is not None)
        try:
            arrays = [jnp.asarray(x, dtype=jnp.float64) for x in padded if x is not None]
        except (TypeError, ValueError) as exc:
            raise DTypeError(f"featherdyn.jax.{decl.name}: inputs must be real numbers (float64): {exc}") from None
        key = _entry(model, kernel_options(decl, model, options))
        out = _op(decl.name, key, present, *arrays)
        if len(out) == 1:
            return out[0]
        absent = {names[k] for k, x in enumerate(padded) if x is None}  # (an output formed only with one: None)
        return outputs(*(None if when.get(o) in absent else r for o, r in zip(decl.outputs, out, strict=True)))

    f.__name__ = f.__qualname__ = decl.name
    f.__doc__ = (f"``fd.{decl.name}`` as a JAX operation (featherdyn.jax's module docstring): jit, vmap (the "
                 f"core's batch){', grad/jvp/vjp' if decl.derivative else ''}.\n\n" + decl.doc)
    return f


for _name, _decl in DECLARATIONS.items():
    globals()[_name] = _function(_decl)


# --- constrained and impulse dynamics (contacts: the core's contact kernels, core/cpp/declarations_constraints.hpp) --


class ConstrainedDynamics(NamedTuple):
    """``fd.constrained_dynamics``' result in JAX: ``ddq`` `(..., nv)`, ``forces`` (one array per constraint),
    ``lagrange`` `(..., m)`, ``residual`` `(...)`."""

    ddq: Any
    forces: tuple[Any, ...]
    lagrange: Any
    residual: Any


class ImpulseDynamics(NamedTuple):
    """``fd.impulse_dynamics``' result in JAX: ``v_plus`` `(..., nv)`, ``impulses`` (one per constraint),
    ``lagrange`` `(..., m)`."""

    v_plus: Any
    impulses: tuple[Any, ...]
    lagrange: Any


def _contact_key(model: Model, constraints: Any, options: dict[str, Any], caller: str) -> tuple[int, Any]:
    """The handler's key of the contact set's plan (cached on the model, as ``fd.constrained_dynamics`` caches it) and
    the solver's options; the plan."""
    from .api.constraints import core_contact_plan
    from .constraints import as_constraints, cached_contact_plan
    from .tolerances import DELASSUS_PIVOT_RTOL

    if not isinstance(model, Model):
        raise ShapeError(f"model: expected a featherdyn Model, got {type(model).__name__}")
    as_constraints(constraints)  # (its errors: not constraints, unknown frames)
    found = cached_contact_plan(model, constraints, core_contact_plan)
    if found is None or found[1] is None:
        raise FeatherdynError(f"featherdyn.jax.{caller}: point and frame contacts only (fd.PointContact, "
                              "fd.FrameContact); a loop closure runs in the NumPy function")
    plan = found[0]
    return _entry(model, {"plan": found[1][0], "rows": plan.size, "singular_tol": DELASSUS_PIVOT_RTOL, **options}), plan


def _floats(name: str, *xs: Any) -> list[Any]:
    try:
        return [jnp.asarray(x, dtype=jnp.float64) for x in xs]
    except (TypeError, ValueError) as exc:
        raise DTypeError(f"featherdyn.jax.{name}: inputs must be real numbers (float64): {exc}") from None


@partial(jax.custom_jvp, nondiff_argnums=(0, 1, 2, 3))
def _solved(kernel: str, derivative: str, key: int, present: int, *arrays: Any) -> tuple[Any, ...]:
    """The outputs of a contact ``kernel``; differentiated by its ``derivative`` kernel (``∂/∂x`` of each state
    input in order, per output; the derivatives are operations without derivatives of their own)."""
    return _op(kernel, key, present, *arrays)


def _solved_jvp(kernel: str, derivative: str, key: int, present: int, primals: tuple[Any, ...],
                tangents: tuple[Any, ...]) -> tuple[tuple[Any, ...], tuple[Any, ...]]:
    out = _solved(kernel, derivative, key, present, *primals)
    model = _MODELS[key][0]
    names = [n for k, n in enumerate(("q", "v", "tau", "f_ext")) if (present >> k) & 1]
    if any(n == "f_ext" and not isinstance(t, jax.custom_derivatives.SymbolicZero)
           for n, t in zip(names, tangents, strict=True)):
        raise FeatherdynError(f"featherdyn.jax.{kernel}: no derivative with respect to f_ext; hold it constant")
    d = _op(derivative, key, present, *primals)
    # the derivative's blocks: (q, v, τ) per output of q̈, λ (outputs 0, 1; the solve's info has none), or (q, v)
    # per output of v⁺, Λ
    n_in = 3 if kernel == "contact_dynamics" else 2
    t_out = []
    for o in range(len(out)):
        t = jnp.zeros_like(out[o])
        if o < 2:
            for k, (n, dx) in enumerate(zip(names, tangents, strict=False)):
                if k >= n_in or isinstance(dx, jax.custom_derivatives.SymbolicZero):
                    continue
                direction = tangent_of_coordinates(model, primals[0], dx) if n == "q" else dx
                t = t + jnp.einsum("...ij,...j->...i", d[o * n_in + k], direction)
        t_out.append(t)
    return out, tuple(t_out)


_solved.defjvp(_solved_jvp, symbolic_zeros=True)


def constrained_dynamics(model: Model, q: Any, v: Any, tau: Any, constraints: Any, f_ext: Any = None, *,
                         mu: float = 0.0, max_iter: int = 50, tol: float = 1e-12) -> ConstrainedDynamics:
    """``fd.constrained_dynamics`` with contacts as a JAX operation (the core's contact kernel; loops: the NumPy
    function)::

        M q̈ + h = τ + Jᵀ λ,     J q̈ + γ = −K_p e − K_d J v

    Differentiable in ``q, v, τ`` (``fd.constrained_dynamics_derivatives``' kernel). Under ``jit`` a solve that
    does not converge (``mu > 0``) is not an error: read ``residual``.
    """
    from .constraints import solver_settings

    mu, max_iter, tol = solver_settings(mu, max_iter, tol)
    key, plan = _contact_key(model, constraints, {"mu": mu, "max_iter": max_iter, "tol": tol},
                             "constrained_dynamics")
    arrays = _floats("constrained_dynamics", *(x for x in (q, v, tau, f_ext) if x is not None))
    qdd, lam, info = _solved("contact_dynamics", "contact_dynamics_derivatives", key, 7 | (8 if f_ext is not None
                                                                                         else 0), *arrays)
    return ConstrainedDynamics(qdd, tuple(lam[..., s] for s in plan.slices), lam, info[..., 1])


def impulse_dynamics(model: Model, q: Any, v: Any, constraints: Any, *, restitution: float = 0.0,
                     mu: float = 0.0) -> ImpulseDynamics:
    """``fd.impulse_dynamics`` with contacts as a JAX operation (the core's impulse kernel)::

        M (v⁺ − v⁻) = Jᵀ Λ,     J v⁺ = −e J v⁻

    Differentiable in ``q, v`` (``fd.impulse_dynamics_derivatives``' kernel).
    """
    from .constraints import solver_settings
    from .errors import ModelError

    try:
        e = float(restitution)
    except (TypeError, ValueError):
        e = float("nan")
    if not 0.0 <= e <= 1.0:
        raise ModelError(f"restitution: expected a number in [0, 1], got {restitution!r}")
    mu = solver_settings(mu, 1, 1.0)[0]
    key, plan = _contact_key(model, constraints, {"mu": mu, "restitution": e}, "impulse_dynamics")
    v_plus, lam = _solved("impulse_dynamics", "impulse_dynamics_derivatives", key, 3, *_floats("impulse_dynamics", q, v))
    return ImpulseDynamics(v_plus, tuple(lam[..., s] for s in plan.slices), lam)
