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

**Gradients** come from the declaration's ``derivative`` (``rnea`` → ``fd.rnea_derivatives``, ``aba`` →
``fd.aba_derivatives``, ``generalized_gravity``, ``frame_velocity``, ``frame_acceleration``): a JVP rule
``ẏ = Σ ∂y/∂x_i · ẋ_i`` (so ``jvp``, ``jacfwd`` and, by JAX's transposition, ``grad``, ``vjp``, ``jacrev``).
A function without one raises :class:`featherdyn.errors.FeatherdynError` when differentiated, never a zero.
``f_ext`` has no derivative (differentiating with respect to it raises).

**The configuration's tangent.** featherdyn's ``∂/∂q`` is along ``fd.integrate``'s tangent (``nv`` columns);
JAX differentiates with respect to ``q``'s coordinates (``nq``). The JVP maps a coordinate direction ``q̇`` to
the tangent ``δ = T(q) q̇`` (:func:`tangent_of_coordinates`: identity on revolute, prismatic and planar
coordinates; ``ω = 2 vec(q̄ ⊗ q̇)`` on a quaternion, ``Rᵀ ṗ`` on a free-flyer's position), so ``jax.grad``
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

from .api.declarations import DECLARATIONS
from .api.declared import Declaration, kernel_options, operand_shapes, xla_entry, xla_ffi
from .errors import DTypeError, FeatherdynError, ShapeError
from .joints import FreeFlyerJoint, SphericalJoint
from .model import Model

jax.config.update("jax_enable_x64", True)

__all__ = ["tangent_of_coordinates", "coordinates_of_tangent", "normalize", "tangent_grad", *DECLARATIONS]

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
_MODELS: dict[int, Model] = {}


def _entry(model: Model, options: dict[str, Any]) -> int:
    """The handler's key of (model, kernel options), registered once (the model stays registered)."""
    ident = (id(model), tuple(sorted(options.items())))
    found = _ENTRIES.get(ident)
    if found is None:
        key = xla_entry(model, options)
        found = _ENTRIES[ident] = (key, model)
        _MODELS[key] = model
    return found[0]


# --- the configuration's tangent ---------------------------------------------------------------------------------


def _quat_mul(a: Any, b: Any) -> Any:
    """Hamilton product of (x, y, z, w) quaternions."""
    ax, ay, az, aw = a[..., 0], a[..., 1], a[..., 2], a[..., 3]
    bx, by, bz, bw = b[..., 0], b[..., 1], b[..., 2], b[..., 3]
    return jnp.stack([aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
                      aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz], axis=-1)


def _rotation(quat: Any) -> Any:
    x, y, z, w = quat[..., 0], quat[..., 1], quat[..., 2], quat[..., 3]
    return jnp.stack([jnp.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
                      jnp.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
                      jnp.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1)], -2)


def _conj(quat: Any) -> Any:
    return quat * jnp.array([-1.0, -1.0, -1.0, 1.0])


def tangent_of_coordinates(model: Model, q: Any, dq: Any) -> Any:
    """``δ = T(q) q̇`` `(..., nv)`: the tangent (``fd.integrate``'s, ``v``'s layout) of a coordinate direction ``q̇``
    `(..., nq)` at ``q``; the part of ``q̇`` off the unit quaternions has none::

        revolute, prismatic, planar: δ = q̇;   spherical: ω = 2 vec(q̄ ⊗ q̇);
        free-flyer [p, quat]: [ω; v] = [2 vec(q̄ ⊗ q̇_quat); R(quat)ᵀ ṗ]
    """
    parts = []
    for i, joint in enumerate(model.joints):
        iq, nq = model.idx_q[i], type(joint).nq
        if isinstance(joint, SphericalJoint):
            quat = q[..., iq:iq + 4]
            parts.append(2.0 * _quat_mul(_conj(quat), dq[..., iq:iq + 4])[..., :3])
        elif isinstance(joint, FreeFlyerJoint):
            quat = q[..., iq + 3:iq + 7]
            w = 2.0 * _quat_mul(_conj(quat), dq[..., iq + 3:iq + 7])[..., :3]
            v = jnp.einsum("...ji,...j->...i", _rotation(quat), dq[..., iq:iq + 3])
            parts += [w, v]
        elif nq:
            parts.append(dq[..., iq:iq + nq])
    return jnp.concatenate(parts, axis=-1) if parts else jnp.zeros(dq.shape[:-1] + (0,))


def coordinates_of_tangent(model: Model, q: Any, delta: Any) -> Any:
    """``q̇ = E(q) δ`` `(..., nq)`: the coordinate direction of ``q ⊕ ε δ`` at ε = 0 (``T(q) E(q) = 1``)::

        spherical: q̇ = ½ q ⊗ [ω; 0];   free-flyer: [ṗ; q̇_quat] = [R(quat) v; ½ quat ⊗ [ω; 0]]
    """
    parts = []
    for i, joint in enumerate(model.joints):
        iv, nv = model.idx_v[i], type(joint).nv
        if isinstance(joint, SphericalJoint):
            iq = model.idx_q[i]
            w = jnp.concatenate([delta[..., iv:iv + 3], jnp.zeros(delta.shape[:-1] + (1,))], -1)
            parts.append(0.5 * _quat_mul(q[..., iq:iq + 4], w))
        elif isinstance(joint, FreeFlyerJoint):
            iq = model.idx_q[i]
            quat = q[..., iq + 3:iq + 7]
            w = jnp.concatenate([delta[..., iv:iv + 3], jnp.zeros(delta.shape[:-1] + (1,))], -1)
            parts += [jnp.einsum("...ij,...j->...i", _rotation(quat), delta[..., iv + 3:iv + 6]),
                      0.5 * _quat_mul(quat, w)]
        elif nv:
            parts.append(delta[..., iv:iv + nv])
    return jnp.concatenate(parts, axis=-1) if parts else jnp.zeros(delta.shape[:-1] + (0,))


def normalize(model: Model, q: Any) -> Any:
    """``q`` `(..., nq)` with each quaternion divided by its norm (``fd.normalize`` in JAX): what a function
    differentiated in coordinates off the unit quaternions (finite differences, ``check_grads``) calls first;
    at a unit quaternion its Jacobian removes the radial direction, which ``T(q)`` ignores anyway."""
    q = jnp.asarray(q, dtype=jnp.float64)
    for i, joint in enumerate(model.joints):
        iq = model.idx_q[i] + (3 if isinstance(joint, FreeFlyerJoint) else 0)
        if isinstance(joint, (SphericalJoint, FreeFlyerJoint)):
            quat = q[..., iq:iq + 4]
            q = q.at[..., iq:iq + 4].set(quat / jnp.linalg.norm(quat, axis=-1, keepdims=True))
    return q


def tangent_grad(f: Callable[..., Any], model: Model) -> Callable[..., Any]:
    """``g(q, *args)`` `(..., nv)`: the gradient of the scalar ``f(q, *args)`` along ``fd.integrate``'s tangent at
    ``q`` — ``E(q)ᵀ ∇_q f`` (:func:`coordinates_of_tangent`), the row ``fd.rnea_derivatives`` & co. give."""
    grad = jax.grad(f)

    def g(q: Any, *args: Any) -> Any:
        gq = grad(q, *args)
        _, vjp = jax.vjp(lambda d: coordinates_of_tangent(model, q, d), jnp.zeros(q.shape[:-1] + (model.nv,)))
        return vjp(gq)[0]

    return g


# --- the operations --------------------------------------------------------------------------------------------


def _ffi(name: str, key: int, present: int, arrays: Sequence[Any]) -> tuple[Any, ...]:
    """The handler's outputs of kernel ``name``; the batch is the inputs' leading axes, broadcast (``vmap``
    broadcasts its unmapped inputs too: ``broadcast_all``)."""
    model = _MODELS[key]
    inputs, outputs = operand_shapes(name, model)
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
    decl = DECLARATIONS[name]
    out = _op(name, key, present, *primals)
    if decl.derivative is None:
        raise FeatherdynError(f"featherdyn.jax.{name}: no derivative is declared for it (api/declarations.py); "
                              "differentiate a function that has one (rnea, aba, generalized_gravity, …)")
    given = [n for k, n in enumerate(decl.inputs) if (present >> k) & 1]
    derivs = _op(decl.derivative, key, present, *primals)
    model = _MODELS[key]
    t_out = jnp.zeros_like(out[0])
    for k, (n, x, t) in enumerate(zip(given, primals, tangents, strict=True)):
        if isinstance(t, jax.custom_derivatives.SymbolicZero):
            continue
        if n == "f_ext":
            raise FeatherdynError(f"featherdyn.jax.{name}: no derivative with respect to f_ext (its declaration's "
                                  "derivative covers the state inputs); hold f_ext constant (jax.lax.stop_gradient)")
        direction = tangent_of_coordinates(model, x, t) if n == "q" else t
        t_out = t_out + jnp.einsum("...ij,...j->...i", derivs[k], direction)
    return out, (t_out,) + tuple(jnp.zeros_like(o) for o in out[1:])


_op.defjvp(_op_jvp, symbolic_zeros=True)


def _function(decl: Declaration) -> Callable[..., Any]:
    outputs = NamedTuple(f"{decl.name}_result", [(n, Any) for n in decl.outputs])  # type: ignore[misc]

    def f(model: Model, *inputs: Any, **options: Any) -> Any:
        if not isinstance(model, Model):
            raise ShapeError(f"model: expected a featherdyn Model, got {type(model).__name__}")
        positional = [o for o in ("frame", "reference") if o in decl.options]  # after the inputs, as in fd.*
        if len(inputs) > len(decl.inputs) + len(positional):
            raise ShapeError(f"featherdyn.jax.{decl.name}: at most {len(decl.inputs) + len(positional)} arguments "
                             f"after the model ({', '.join((*decl.inputs, *positional))}), got {len(inputs)}")
        options = {**dict(zip(positional, inputs[len(decl.inputs):], strict=False)), **options}
        inputs = inputs[:len(decl.inputs)]
        names = list(decl.inputs)
        padded = list(inputs) + [None] * (len(names) - len(inputs))
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
        return out[0] if len(out) == 1 else outputs(*out)

    f.__name__ = f.__qualname__ = decl.name
    f.__doc__ = (f"``fd.{decl.name}`` as a JAX operation (featherdyn.jax's module docstring): jit, vmap (the "
                 f"core's batch){', grad/jvp/vjp' if decl.derivative else ''}.\n\n" + decl.doc)
    return f


for _name, _decl in DECLARATIONS.items():
    globals()[_name] = _function(_decl)
