"""The compiled core: C++ kernels of the dynamics algorithms, built at install (no JIT).

Each kernel is written once, templated on the scalar type, in the reference's
order and symbols (``featherdyn/algorithms``; see ``docs/architecture.md``), in
body coordinates. This module is its Python side: it converts arguments to
what the binding accepts — native-endian, aligned, C-contiguous float64 —
(lists, integers, float32, big-endian, strided and unaligned arrays are
copied; object arrays that cannot become float64 raise
:class:`~featherdyn.errors.DTypeError`), calls one kernel, and turns the
core's status into the reference's exception and message.

Every function takes one state (1-D ``q`` etc.) or a batch (leading axes,
broadcast; the batch runs on the core's thread pool with the GIL released).
A one-state call first hands its arguments to the binding as they are; only
when the binding refuses them (a ``TypeError``: not a native-endian, aligned,
C-contiguous float64 array of the exact shape) or reports a status (a batch,
a bad value) does the wrapper take its general path, which converts,
dispatches batches and raises the reference's errors. The general path never
changes what a call returns, only how long it takes.
Results are float64; ``out=`` gives an array to write into (float64,
C-contiguous, the result's shape). The functions of the declared algorithms
(``rnea`` & co., the Jacobians, the energies, the derivatives: one per kernel of
``core/cpp/declarations.hpp``) are made by ``_declared`` from the kernel's
declaration; the kinematics records and the constraints are written below. Conventions: motion ``[ω; v]``, force
``[n; f]``, free-flyer ``q = [p, quat xyzw]`` and ``v = [ω; v]`` in the base
frame, gravity from ``model.gravity`` entered as a base acceleration ``−g``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ..errors import DTypeError, ModelError, ShapeError
from ..frames import LOCAL, as_reference_frame
from ..model import Model
from ..spatial.validation import as_array
from . import _errors, declared
from ._model_view import CoreHandle, model_view
from ._result_pool import result_array

_core: Any
try:
    from . import _core  # the compiled extension (no stub: typed Any above)
except ImportError:  # pragma: no cover - a source checkout without the built extension
    _core = None

__all__ = [
    "contact_dynamics",
    "available",
    "rnea",
    "nonlinear_effects",
    "generalized_gravity",
    "generalized_gravity_derivatives",
    "static_torque_derivatives",
    "crba",
    "aba",
    "fk",
    "kinematics",
    "frame_placement",
    "frame_jacobian",
    "rnea_complex",
    "fk_batch",
    "frame_placement_batch",
    "kinetic_energy",
    "potential_energy",
    "center_of_mass",
    "centroidal_momentum_matrix",
    "centroidal_momentum",
    "joint_jacobians",
    "frame_jacobian_time_variation",
    "rnea_derivatives",
    "aba_derivatives",
    "mass_matrix_inverse",
    "frame_velocity_derivatives",
    "frame_acceleration_derivatives",
    "joint_torque_regressor",
    "mass_matrix_factor",
    "mass_solve",
    "delassus",
    "constrained_solve",
    "set_num_threads",
    "get_num_threads",
]

_F64 = np.dtype(np.float64)
_empty = np.empty


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


def _out(out: Any, shape: tuple[int, ...]) -> np.ndarray:
    if out is None:
        return np.empty(shape)
    if not (isinstance(out, np.ndarray) and out.dtype == _F64 and out.dtype.isnative and out.flags.c_contiguous
            and out.flags.aligned and out.flags.writeable):
        raise TypeError("out: expected a writable, aligned, C-contiguous float64 array")
    if out.shape != shape:
        raise ShapeError(f"out: expected shape {shape}, got {out.shape}")
    return out


def _into(out: Any, shape: tuple[int, ...], call: Callable[[np.ndarray], int]) -> tuple[np.ndarray, int]:
    """``(result, status)`` of a one-state ``call(o)`` writing into ``out`` (checked by :func:`_out`) or a fresh array.

    The one rule for ``out=`` (docs/architecture.md, "One declaration per algorithm"): an ``out`` that shares
    memory with an input is refused by the core (status ``OVERLAP``); the result is then computed into fresh
    memory and copied, so it is the call's result without ``out``.
    """
    o = _out(out, shape)
    s = call(o)
    if s and _errors.decode(s)[0] == _errors.OVERLAP:
        fresh = np.empty(shape)
        s = call(fresh)
        if not s:
            np.copyto(o, fresh)
    return o, s


def _apart(out: Any, *inputs: np.ndarray | None) -> tuple[Any, ...]:
    """The inputs of a batch, each copied first if it may share memory with ``out`` (an array or a tuple of them).

    The one rule for ``out=`` (docs/architecture.md, "One declaration per algorithm"): the result is the call's
    result without ``out``. A kernel writes its rows while it reads its inputs' rows, so an output over an input's
    memory (``cm.rnea_batch(Q, V, A, out=A)``) would read what it has written: the input is read from a copy.
    ``np.may_share_memory`` compares the bounds only: no scan.
    """
    if out is None:
        return inputs
    outs = tuple(out) if isinstance(out, (tuple, list)) else (out,)
    return tuple(x if x is None or not any(isinstance(o, np.ndarray) and np.may_share_memory(x, o) for o in outs)
                 else x.copy() for x in inputs)


def _batch_out(out: Any, shape: tuple[int, ...]) -> np.ndarray:
    """A batch's result: ``out`` after :func:`_out`'s checks, or a fresh array (reused memory when large)."""
    return result_array(shape) if out is None else _out(out, shape)


def _outs(out: Any, n: int, shape: tuple[int, ...]) -> tuple[np.ndarray, ...]:
    """``n`` result arrays of ``shape``: fresh, or the ``n`` arrays of ``out`` after :func:`_out`'s checks."""
    if out is None:
        return tuple(result_array(shape) for _ in range(n))
    if not isinstance(out, (tuple, list)) or len(out) != n:
        raise TypeError(f"out: expected a tuple of {n} arrays")
    arrays = tuple(_out(o, shape) for o in out)
    if len({id(a) for a in arrays}) != n or any(np.shares_memory(a, b) for i, a in enumerate(arrays)
                                                   for b in arrays[i + 1:]):
        raise ValueError("out: the arrays must not overlap")
    return arrays


def _reference_code(reference: Any) -> int:
    """The kernel's code of ``fd.LOCAL`` & co. (or their names), or the code itself (0, 1, 2)."""
    if isinstance(reference, (int, np.integer)) and not isinstance(reference, bool) and 0 <= reference <= 2:
        return int(reference)
    return as_reference_frame(reference).code


# ---------------------------------------------------------------------------
# batching: leading axes → rows
# ---------------------------------------------------------------------------


def _batch_shape(model: Model, arrays: list[tuple[np.ndarray, int]], q: Any, vectors: list[tuple[str, Any]],
                 f_ext: Any) -> tuple[int, ...]:
    """The broadcast batch shape of ``(array, trailing ndim)`` pairs; the reference's error when there is none."""
    try:
        return np.broadcast_shapes(*(a.shape[: a.ndim - k] for a, k in arrays))
    except ValueError:
        _errors.validate(model, q, vectors, f_ext)
        raise


def _rows(x: np.ndarray | None, batch: tuple[int, ...], tail: tuple[int, ...]) -> np.ndarray | None:
    """``x`` with batch shape broadcastable to ``batch`` as `(N or 1, prod(tail))` rows (a copy only to broadcast)."""
    if x is None:
        return None
    n = math.prod(tail)
    if x.ndim < len(tail) or x.shape[x.ndim - len(tail):] != tail:
        return x.reshape(-1, max(x.shape[-1] if x.ndim else 1, 1))  # wrong length: the core reports it
    bx = x.shape[: x.ndim - len(tail)]
    if bx == batch:
        return x.reshape(math.prod(batch), n)
    if math.prod(bx) == 1:
        return x.reshape(1, n)
    return np.ascontiguousarray(np.broadcast_to(x, batch + tail)).reshape(math.prod(batch), n)


def _check_batch(status: tuple[int, int], model: Model, q: Any, vectors: list[tuple[str, Any]],
                 f_ext: Any = None, what: str = "featherdyn.core") -> None:
    _, s = status
    if s:
        _errors.raise_for(s, model, q, vectors, f_ext, what=what)


# ---------------------------------------------------------------------------
# the declared algorithms (core/cpp/declarations.hpp): one generic function each
# ---------------------------------------------------------------------------


def _declared(name: str, doc: str) -> Callable[..., Any]:
    """``featherdyn.core.<name>(model, *inputs, *options, out=None)`` of the declared kernel ``name``.

    The inputs in the declaration's order (optional ones may be omitted or ``None``), then its options
    (``gravity``), then ``out``; one state or any batch shape (leading axes, broadcast), converted as the
    module docstring says. One state is first handed to the kernel as it is (``Kernel.fresh``).
    """

    def function(model: Model, *args: Any, **kwargs: Any) -> Any:
        _lib()
        spec = declared.SPECS[name]
        h = _view(model)  # a Model (ShapeError otherwise)
        params = spec.input_names + spec.options + ("out",)
        if len(args) > len(params) or set(kwargs) - set(params):
            raise TypeError(f"{name}() takes the arguments (model, {', '.join(params)})")
        given = dict(zip(params, args, strict=False))
        for key, x in kwargs.items():
            if key in given:
                raise TypeError(f"{name}() got multiple values for argument {key!r}")
            given[key] = x
        missing = [n for n, _, opt in spec.inputs if not opt and n not in given]
        missing += [n for n in spec.options if n == "frame" and n not in given]
        if missing:
            raise TypeError(f"{name}() missing required arguments: {', '.join(missing)}")
        options: dict[str, Any] = {}
        if "frame" in spec.options:
            options["frame"] = model.resolve_frame(given["frame"])
        if "reference" in spec.options:
            options["reference"] = _reference_code(given.get("reference", LOCAL))
        if "gravity" in spec.options:
            options["gravity"] = bool(given.get("gravity", True))
        return _run_declared(spec, h, model, [given.get(n) for n in spec.input_names], options, given.get("out"))

    function.__name__ = function.__qualname__ = name
    function.__doc__ = doc
    return function


def _run_declared(spec: declared.Spec, h: CoreHandle, model: Model, inputs: list[Any], options: dict[str, Any],
                  out: Any) -> Any:
    k = spec.kernel
    xs = [None if x is None else _f64(x, n) for x, n in zip(inputs, spec.input_names, strict=True)]
    # one state as the kernel takes it (out=: arrays of the exact shapes); anything else: the batch path below
    if out is None:
        r = k.fresh(h.cm, xs, **options)
        if r is not None:
            return r
    elif k.into(h.cm, xs, list(out) if isinstance(out, tuple) else [out], **options) == 0:
        return out
    tails = [declared.shape_of(h, s) for _, s, _ in spec.inputs]
    names = spec.input_names
    vectors = [(n, x) for n, x in zip(names, inputs, strict=True) if n in ("v", "a", "tau")]
    f_ext = inputs[names.index("f_ext")] if "f_ext" in names else None
    q = inputs[names.index("q")]
    batch = _batch_shape(model, [(x, len(t)) for x, t in zip(xs, tails, strict=True) if x is not None], q, vectors,
                         f_ext)
    shapes = [batch + declared.shape_of(h, s) for _, s, _ in spec.outputs]
    name = spec.kernel.name
    if out is None:
        return _result(declared.run(name, model, batch, xs, None, options))
    outs = _outs(out, len(shapes), shapes[0]) if len(shapes) > 1 else (_out(out, shapes[0]),)
    declared.run(name, model, batch, xs, outs, options)  # (out over an input: declared.run's one rule)
    return out


def _result(outs: tuple[np.ndarray, ...]) -> Any:
    return outs[0] if len(outs) == 1 else outs


rnea = _declared("rnea", """Joint forces ``τ`` `(..., nv)` for ``q`` `(..., nq)`, ``v``, ``a`` `(..., nv)` (RNEA).

    Args:
        f_ext: optional `(..., nb, 6)` external forces ``[n; f]`` on each body, in body coordinates.
        gravity: set ``False`` to leave gravity out.
        out: an array of the result's shape to write into.

    ::

        τ = M(q) q̈ + C(q, q̇) q̇ + g(q) − Σ_i J_iᵀ f_i^ext
    """)
nonlinear_effects = _declared("nonlinear_effects", """``h(q, q̇) = C(q, q̇) q̇ + g(q) = RNEA(q, q̇, 0)`` `(..., nv)`.""")
generalized_gravity = _declared("generalized_gravity", """``g(q) = RNEA(q, 0, 0)`` `(..., nv)`.""")
crba = _declared("crba", """The mass matrix ``M(q)`` `(..., nv, nv)`, full and exactly symmetric (CRBA)::

        T = ½ q̇ᵀ M(q) q̇,    M_ij = S_iᵀ ⁱX_j^* I^C_j S_j   (j in the subtree of i)
    """)
aba = _declared("aba", """Joint accelerations ``q̈`` `(..., nv)` for joint forces ``τ`` in state ``(q, v)`` (ABA)::

        q̈ = M(q)⁻¹ (τ − C(q, q̇) q̇ − g(q) + Σ_i J_iᵀ f_i^ext)

    Raises:
        SingularMassMatrixError: naming the joint.
    """)
generalized_gravity_derivatives = _declared("generalized_gravity_derivatives", """``∂g/∂q`` `(..., nv, nv)`.""")
frame_jacobian = _declared("frame_jacobian", """The geometric Jacobian `(..., 6, nv)` of a frame (name or index), rows ``[ω; v]``,
    in ``reference`` (``fd.LOCAL`` & co., their names, or the codes 0, 1, 2)::

        frame_velocity(model, q, v, frame, reference) = J v
    """)
joint_jacobians = _declared("joint_jacobians", """Every joint's columns in world coordinates `(..., 6, nv)`: ``J[:, k] = ⁰X_k S_k``.""")
frame_jacobian_time_variation = _declared("frame_jacobian_time_variation", """``J̇`` `(..., 6, nv)` of a frame's Jacobian
    along ``q̇ = v`` in ``reference``.""")
kinetic_energy = _declared("kinetic_energy", """Kinetic energy `(...)`: ``T = Σ_i ½ v_iᵀ I_i v_i = ½ q̇ᵀ M(q) q̇``.""")
potential_energy = _declared("potential_energy", """Potential energy `(...)`, zero at the world origin: ``U = −Σ_i m_i gᵀ ⁰c_i``.""")
centroidal_momentum_matrix = _declared("centroidal_momentum_matrix", """``A_G(q)`` `(..., 6, nv)`, ``h_G = A_G q̇`` (rows
    ``[k_G; p]``, world axes, about the centre of mass).""")
rnea_derivatives = _declared("rnea_derivatives", """``(∂τ/∂q, ∂τ/∂q̇, ∂τ/∂q̈ = M)``, each `(..., nv, nv)`, of
    ``τ = RNEA(q, q̇, q̈)``, ∂/∂q along the tangent of ``fd.integrate``; ``out``: a tuple of three arrays.""")
aba_derivatives = _declared("aba_derivatives", """``(∂q̈/∂q, ∂q̈/∂q̇, M⁻¹)``, each `(..., nv, nv)`, of ``q̈ = ABA(q, q̇, τ)``::

        ∂q̈/∂q = −M⁻¹ ∂τ/∂q,   ∂q̈/∂q̇ = −M⁻¹ ∂τ/∂q̇   (∂τ of RNEA at q̈ = ABA(q, q̇, τ))
    """)
mass_matrix_inverse = _declared("mass_matrix_inverse", """``M(q)⁻¹`` `(..., nv, nv)` from M's tree-sparse factor::

        M = Lᵀ L,   M⁻¹ = Zᵀ Z,   Z = L⁻ᵀ   (column a of Z nonzero only on a's ancestor dofs)
    """)
joint_torque_regressor = _declared("joint_torque_regressor", """``Y`` `(..., nv, 10 nb)` with ``RNEA(q, q̇, q̈) = Y π``.""")
frame_velocity_derivatives = _declared("frame_velocity_derivatives", """``(∂v_f/∂q, ∂v_f/∂q̇)`` `(..., 6, nv)` of a
    frame's velocity in ``reference``.""")
frame_acceleration_derivatives = _declared("frame_acceleration_derivatives", """``(∂a_f/∂q, ∂a_f/∂q̇, ∂a_f/∂q̈)``
    `(..., 6, nv)` of a frame's spatial acceleration in ``reference``.""")
static_torque_derivatives = _declared("static_torque_derivatives", """``∂τ_s/∂q`` `(..., nv, nv)`, ``τ_s = RNEA(q, 0, 0, f_ext)``.""")


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


# ---------------------------------------------------------------------------
# kinematics
# ---------------------------------------------------------------------------


def fk(model: Model, q: Any, v: Any = None, a: Any = None, out: Any = None) -> Any:
    """World placements of the bodies as homogeneous matrices ``⁰M_i`` `(..., nb, 4, 4)`.

    With ``v`` (one state only), returns ``(H, vel)``, and with ``a`` also,
    ``(H, vel, acc)``: body velocities and spatial accelerations (without
    gravity) in body coordinates `(nb, 6)`::

        ⁰M_i = ⁰M_λ(i) · Xtree_i · M_J(q_i)
        v_i = X_up[i] v_λ(i) + S_i q̇_i,   a_i = X_up[i] a_λ(i) + S_i q̈_i + v_i × S_i q̇_i
    """
    if v is None and a is None:
        try:
            h = model._core
            H = _empty((h.nb, 4, 4)) if out is None else out
            if _core.placements(h.cm, q, H) == 0:
                return H
        except (AttributeError, TypeError):
            pass
    h = _view(model)
    if a is not None and v is None:
        raise ShapeError("a: joint accelerations need joint velocities v as well")
    q_ = _f64(q, "q")
    if q_.ndim != 1:
        if v is not None:
            raise ShapeError("fk: velocities and accelerations are computed for one state at a time")
        return fk_batch(model, q_, out)
    v_ = None if v is None else _f64(v, "v")
    a_ = None if a is None else _f64(a, "a")
    vel = None if v is None else np.empty((h.nb, 6))
    acc = None if a is None else np.empty((h.nb, 6))
    H, s = _into(out, (h.nb, 4, 4), lambda o: _core.fk(h.cm, q_, v_, a_, o, None, vel, acc))
    if s:
        _errors.raise_for(s, model, q, [(n, x) for n, x in (("v", v), ("a", a)) if x is not None],
                          what="forward kinematics")
    if v is None:
        return H
    return (H, vel) if a is None else (H, vel, acc)


def kinematics(model: Model, q: Any, v: Any = None,
               a: Any = None) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None]:
    """Every body's world placement, placement in its parent, velocity and acceleration, any batch shape.

    Returns ``(⁰M, ᵖM, vel, acc)``: `(..., nb, 4, 4)` twice, then `(..., nb, 6)` body-frame
    velocities (``None`` without ``v``) and spatial accelerations without gravity (``None``
    without ``a``; ``a`` needs ``v``)::

        ᵖM_i = Xtree_i · M_J(q_i),   ⁰M_i = ⁰M_λ(i) · ᵖM_i
        v_i = X_up[i] v_λ(i) + S_i q̇_i,   a_i = X_up[i] a_λ(i) + S_i q̈_i + v_i × S_i q̇_i
    """
    h = _view(model)
    if a is not None and v is None:
        raise ShapeError("a: joint accelerations need joint velocities v as well")
    q_ = _f64(q, "q")
    v_ = None if v is None else _f64(v, "v")
    a_ = None if a is None else _f64(a, "a")
    vectors = [(name, x) for name, x in (("v", v), ("a", a)) if x is not None]
    parts = [(x, 1) for x in (q_, v_, a_) if x is not None]
    batch = _batch_shape(model, parts, q, vectors, None)
    nb = h.nb
    H, Hp = np.empty(batch + (nb, 4, 4)), np.empty(batch + (nb, 4, 4))
    vel = None if v_ is None else np.empty(batch + (nb, 6))
    acc = None if a_ is None else np.empty(batch + (nb, 6))
    if batch == ():
        s = _core.fk(h.cm, q_, v_, a_, H, Hp, vel, acc)
        if s:
            _errors.raise_for(s, model, q, vectors, what="forward kinematics")
        return H, Hp, vel, acc
    N = math.prod(batch)
    st = _core.kinematics_batch(
        h.cm, _rows(q_, batch, (h.nq,)), _rows(v_, batch, (h.nv,)), _rows(a_, batch, (h.nv,)),
        H.reshape(N, 16 * nb), Hp.reshape(N, 16 * nb), None if vel is None else vel.reshape(N, 6 * nb),
        None if acc is None else acc.reshape(N, 6 * nb))
    _check_batch(st, model, q, vectors, what="forward kinematics")
    return H, Hp, vel, acc


def fk_batch(model: Model, q: Any, out: Any = None) -> np.ndarray:
    """:func:`fk` placements over batch axes `(..., nb, 4, 4)`, on the core's threads."""
    h = _view(model)
    (q_,) = _apart(out, _f64(q, "q"))
    batch = _batch_shape(model, [(q_, 1)], q, [], None)
    result = _batch_out(out, batch + (h.nb, 4, 4))
    st = _core.fk_batch(h.cm, _rows(q_, batch, (h.nq,)), result.reshape(math.prod(batch), 16 * h.nb))
    _check_batch(st, model, q, [], what="forward kinematics")
    return result


def frame_placement(model: Model, q: Any, frame: Any, out: Any = None) -> np.ndarray:
    """The world placement of a frame (name or index) as a homogeneous matrix `(..., 4, 4)`::

        ⁰M_f = ⁰M_body(f) · placement_f = [[R, p], [0, 1]]
    """
    try:
        h = model._core
        fid = h.frames.get(frame, frame) if frame.__class__ is str else frame
        if fid.__class__ is int:
            H = _empty((4, 4)) if out is None else out
            if _core.frame_placement(h.cm, q, fid, H) == 0:
                return H
    except (AttributeError, TypeError):
        pass
    h = _view(model)
    fid = model.resolve_frame(frame)
    q_ = _f64(q, "q")
    if q_.ndim != 1:
        return frame_placement_batch(model, q_, fid, out)
    H, s = _into(out, (4, 4), lambda o: _core.frame_placement(h.cm, q_, fid, o))
    if s:
        _errors.raise_for(s, model, q, what="frame_placement")
    return H


def frame_placement_batch(model: Model, q: Any, frame: Any, out: Any = None) -> np.ndarray:
    """:func:`frame_placement` over batch axes `(..., 4, 4)`, on the core's threads."""
    h = _view(model)
    fid = model.resolve_frame(frame)
    (q_,) = _apart(out, _f64(q, "q"))
    batch = _batch_shape(model, [(q_, 1)], q, [], None)
    H = _batch_out(out, batch + (4, 4))
    st = _core.frame_placement_batch(h.cm, _rows(q_, batch, (h.nq,)), fid, H.reshape(math.prod(batch), 16))
    _check_batch(st, model, q, [], what="frame_placement")
    return H


# ---------------------------------------------------------------------------
# whole-body quantities and Jacobians (one state or a batch: rows on the core's threads)
# ---------------------------------------------------------------------------


def _state_rows(model: Model, q: Any, v: Any, what: str) -> tuple[CoreHandle, tuple[int, ...], np.ndarray,
                                                                       np.ndarray | None, list[tuple[str, Any]]]:
    """``(handle, batch shape, Q rows, V rows or None, vectors)`` of ``q`` `(..., nq)` and ``v`` `(..., nv)`."""
    h = _view(model)
    q_ = _f64(q, "q")
    v_ = None if v is None else _f64(v, "v")
    vectors = [] if v is None else [("v", v)]
    batch = _batch_shape(model, [(q_, 1)] + ([] if v_ is None else [(v_, 1)]), q, vectors, None)
    Q = _rows(q_, batch, (h.nq,))
    V = _rows(v_, batch, (h.nv,))
    assert Q is not None
    return h, batch, Q, V, vectors


def _mass(model: Model) -> float:
    """The tree's total mass; the reference's error when it has none (the centre of mass is undefined)."""
    mass = float(model.total_mass)
    if not mass > 0.0:
        raise ModelError.no_mass(model.name)
    return mass


def center_of_mass(model: Model, q: Any, v: Any = None) -> np.ndarray | tuple[np.ndarray, np.ndarray]:
    """The centre of mass `(..., 3)` in world coordinates, and with ``v`` its velocity `(..., 3)`::

        c = Σ m_i ⁰c_i / m,    ċ = Σ ⁰R_i (m_i v_i + ω_i × h_i) / m
    """
    h, batch, Q, V, vectors = _state_rows(model, q, v, "center_of_mass")
    mass = _mass(model)
    c = np.empty(batch + (3,))
    cd = None if v is None else np.empty(batch + (3,))
    st = _core.com_batch(h.cm, Q, V, mass, c.reshape(math.prod(batch), 3), None if cd is None else cd.reshape(math.prod(batch), 3))
    _check_batch(st, model, q, vectors, what="center_of_mass")
    return c if cd is None else (c, cd)


def centroidal_momentum(model: Model, q: Any, v: Any) -> np.ndarray:
    """The centroidal momentum ``h_G = [k_G; p] = A_G(q) q̇`` `(..., 6)`."""
    h, batch, Q, V, vectors = _state_rows(model, q, v, "centroidal_momentum")
    mass = _mass(model)
    N = math.prod(batch)
    A = np.empty((N, 6 * h.nv))
    hg = np.empty(batch + (6,))
    st = _core.centroidal_batch(h.cm, Q, V, mass, A, hg.reshape(math.prod(batch), 6))
    _check_batch(st, model, q, vectors, what="centroidal_momentum")
    return hg


# ---------------------------------------------------------------------------
# derivatives (cpp/derivatives.hpp: forward-mode differentiation of the RNEA template)
# ---------------------------------------------------------------------------


def _dynamics_rows(model: Model, q: Any, v: Any, x: Any, f_ext: Any, xname: str, out: Any = None
                   ) -> tuple[CoreHandle, tuple[int, ...], list[Any], list[tuple[str, Any]]]:
    """``(handle, batch shape, [Q, V, X, FX] rows, vectors)`` of a state ``(q, v, x)`` and ``f_ext`` (each apart
    from ``out``: :func:`_apart`)."""
    h = _view(model)
    q_, v_, x_ = _f64(q, "q"), _f64(v, "v"), _f64(x, xname)
    fx = None if f_ext is None else _f64(f_ext, "f_ext")
    q_, v_, x_, fx = _apart(out, q_, v_, x_, fx)
    vectors = [("v", v), (xname, x)]
    parts = [(q_, 1), (v_, 1), (x_, 1)] + ([] if fx is None else [(fx, 2)])
    batch = _batch_shape(model, parts, q, vectors, f_ext)
    rows = [_rows(q_, batch, (h.nq,)), _rows(v_, batch, (h.nv,)), _rows(x_, batch, (h.nv,)),
            _rows(fx, batch, (h.nb, 6))]
    return h, batch, rows, vectors


def _raise_derivative_status(st: tuple[int, int], model: Model, q: Any, vectors: list[tuple[str, Any]], f_ext: Any,
                             rows: list[Any], gravity: bool, what: str) -> None:
    """The reference's error for a failed row; a singular mass matrix words it as ``fd.aba`` does."""
    row, s = st
    if not s:
        return
    if _errors.decode(s)[0] == _errors.SINGULAR:
        _errors.validate(model, q, vectors, f_ext)

        def pick(x: Any) -> Any:
            return None if x is None else x[0 if x.shape[0] == 1 else row]

        fx = pick(rows[3])
        aba(model, pick(rows[0]), np.zeros(model.nv), np.zeros(model.nv),
            None if fx is None else fx.reshape(model.nbodies, 6), gravity)  # raises the reference's error
    _errors.raise_for(s, model, q, vectors, f_ext, _ABA_ARGS if what == "aba_derivatives" else ARG_NAMES, what=what)


ARG_NAMES = _errors.ARG_NAMES
_ABA_ARGS = ("q", "v", "tau", "f_ext", "out")


def _ltl_rows(model: Model, q: Any, extra: Any, name: str, tail: tuple[int, ...]
              ) -> tuple[CoreHandle, tuple[int, ...], np.ndarray, np.ndarray | None]:
    h = _view(model)
    q_ = _f64(q, "q")
    x_ = None if extra is None else _f64(extra, name)
    parts = [(q_, 1)] + ([] if x_ is None else [(x_, len(tail))])
    batch = _batch_shape(model, parts, q, [], None)
    Q = _rows(q_, batch, (h.nq,))
    assert Q is not None
    return h, batch, Q, _rows(x_, batch, tail)


def _raise_ltl(st: tuple[int, int], model: Model, q: Any, what: str) -> None:
    """A factorisation's failure: the reference's words (``fd.aba``'s for a singular mass matrix)."""
    if st[1] and _errors.decode(st[1])[0] == _errors.SINGULAR:
        q_ = _f64(q, "q")
        row = q_.reshape(-1, model.nq)[st[0] if q_.ndim > 1 else 0]
        aba(model, row, np.zeros(model.nv), np.zeros(model.nv), None, False)  # raises the reference's error
    _check_batch(st, model, q, [], what=what)


def mass_matrix_factor(model: Model, q: Any) -> np.ndarray:
    """``L`` `(..., nv, nv)` lower triangular with ``M(q) = Lᵀ L`` and the tree's sparsity (RBDA §6.5)::

        L_kj ≠ 0 only for j = k or j an ancestor dof of k
    """
    h, batch, Q, _ = _ltl_rows(model, q, None, "", ())
    L = np.empty(batch + (h.nv, h.nv))
    _raise_ltl(_core.ltl_batch(h.cm, Q, L.reshape(math.prod(batch), h.nv * h.nv)), model, q, "mass_matrix_factor")
    return L


def mass_solve(model: Model, q: Any, b: Any) -> np.ndarray:
    """``x = M(q)⁻¹ b`` `(..., nv)` for ``b`` `(..., nv)` through the tree-sparse factor (M is never inverted)::

        Lᵀ y = b,   L x = y,   M = Lᵀ L
    """
    h, batch, Q, B = _ltl_rows(model, q, b, "b", (model.nv,))
    x = np.empty(batch + (model.nv,))
    st = _core.mass_solve_batch(h.cm, Q, B, 1, x.reshape(math.prod(batch), model.nv))
    _raise_ltl(st, model, q, "mass_solve")
    return x


def delassus(model: Model, q: Any, J: Any) -> np.ndarray:
    """``J M(q)⁻¹ Jᵀ`` `(..., m, m)` for ``J`` `(..., m, nv)`, without forming M⁻¹::

        J M⁻¹ Jᵀ = (J L⁻¹)(J L⁻¹)ᵀ,   M = Lᵀ L
    """
    J_ = _f64(J, "J")
    if J_.ndim < 2 or J_.shape[-1] != model.nv:
        raise ShapeError(f"J: expected shape (..., m, {model.nv}), got {J_.shape}")
    m = J_.shape[-2]
    h, batch, Q, JR = _ltl_rows(model, q, J_, "J", (m, model.nv))
    D = np.empty(batch + (m, m))
    st = _core.delassus_batch(h.cm, Q, JR, m, D.reshape(math.prod(batch), m * m))
    _raise_ltl(st, model, q, "delassus")
    return D


def constrained_solve(model: Model, q: Any, v: Any, tau: Any, J: Any, c: Any, f_ext: Any = None, *, mu: float = 0.0,
                      max_iter: int = 50, tol: float = 1e-12) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(q̈, λ, residual)`` of ``M q̈ + h = τ + Jᵀ λ`` and ``J q̈ = c`` for ``J`` `(..., m, nv)`, ``c`` `(..., m)`.

    By the Schur complement on M's tree-sparse factor (M is never inverted)::

        q̈_f = M⁻¹ (τ − h),   D = J M⁻¹ Jᵀ,   D λ = c − J q̈_f,   q̈ = q̈_f + M⁻¹ Jᵀ λ

    ``mu > 0``: proximal iterations ``λ ← (D + μ1)⁻¹ (c − J q̈_f + μ λ)`` (Carpentier, Budhiraja & Mansard,
    RSS 2021), which converge to the minimum-norm λ when rows are dependent. ``residual`` `(...)`:
    ``max |J q̈ − c|``.

    Raises:
        ConstraintError: dependent rows with ``mu = 0`` (the message suggests ``mu``), or no convergence
            in ``max_iter`` proximal iterations.
    """
    from ..errors import ConstraintError
    from ..tolerances import DELASSUS_PIVOT_RTOL

    J_ = _f64(J, "J")
    if J_.ndim < 2 or J_.shape[-1] != model.nv:
        raise ShapeError(f"J: expected shape (..., m, {model.nv}), got {J_.shape}")
    m = J_.shape[-2]
    h, batch, _, vectors = _dynamics_rows(model, q, v, tau, f_ext, "tau")
    c_ = _f64(c, "c")
    if c_.shape[-1:] != (m,):
        raise ShapeError(f"c: expected shape (..., {m}) for J with {m} rows, got {c_.shape}")
    try:
        batch = np.broadcast_shapes(batch, J_.shape[:-2], c_.shape[:-1])
    except ValueError:
        raise ShapeError(f"J {J_.shape[:-2]}, c {c_.shape[:-1]} and the state {batch}: batch shapes that do not "
                         "broadcast") from None
    N, nv = math.prod(batch), h.nv
    rows = [_rows(x, batch, tail) for x, tail in ((_f64(q, "q"), (h.nq,)), (_f64(v, "v"), (nv,)),
                                                  (_f64(tau, "tau"), (nv,)))]
    FXr = None if f_ext is None else _rows(_f64(f_ext, "f_ext"), batch, (h.nb, 6))
    qdd, lam, info = np.empty(batch + (nv,)), np.empty(batch + (m,)), np.empty(batch + (2,))
    st = _core.kkt_batch(h.cm, *rows, FXr, _rows(J_, batch, (m, nv)), _rows(c_, batch, (m,)), m, float(mu),
                         int(max_iter), float(tol), DELASSUS_PIVOT_RTOL, qdd.reshape(N, nv), lam.reshape(N, m),
                         info.reshape(N, 2))
    if st[1]:
        _raise_derivative_status(st, model, q, vectors, f_ext, [rows[0], rows[1], rows[2], FXr], True,
                                 "constrained_solve")
    its = info[..., 0]
    if np.any(its == -1):
        raise ConstraintError.dependent(m)
    if np.any(its == -2):
        raise ConstraintError.not_converged(max_iter, tol)
    return qdd, lam, info[..., 1]


def contact_dynamics(model: Model, q: Any, v: Any, tau: Any, specs: np.ndarray, f_ext: Any = None, *,
                     mu: float = 0.0, max_iter: int = 50, tol: float = 1e-12
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(q̈, λ, iterations, residual)`` under point and frame contacts, rows and solve in one core call.

    ``specs`` `(nc, 4)` float64 rows ``[rows (3 | 6), frame index, reference code, K_d]`` (``contacts.hpp``)::

        point: J = linear rows of the frame Jacobian, γ = classical acceleration of the origin at q̈ = 0
        frame: J = the frame Jacobian, γ = its spatial acceleration at q̈ = 0;   c = −γ − K_d J q̇
        M q̈ + h = τ + Jᵀ λ,  J q̈ = c    (Schur complement on M's LᵀL factor)

    ``iterations`` `(...)`: −1 dependent rows (with ``mu = 0``), −2 not converged; the caller raises.
    """
    from ..tolerances import DELASSUS_PIVOT_RTOL

    m = int(specs[:, 0].sum())
    h, batch, rows, vectors = _dynamics_rows(model, q, v, tau, f_ext, "tau")
    N, nv = math.prod(batch), h.nv
    qdd, lam, info = np.empty(batch + (nv,)), np.empty(batch + (m,)), np.empty(batch + (2,))
    st = _core.contact_dynamics_batch(h.cm, *rows, np.ascontiguousarray(specs, dtype=np.float64), float(mu),
                                      int(max_iter), float(tol), DELASSUS_PIVOT_RTOL, qdd.reshape(N, nv),
                                      lam.reshape(N, m), info.reshape(N, 2))
    if st[1]:
        _raise_derivative_status(st, model, q, vectors, f_ext, rows, True, "constrained_dynamics")
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
