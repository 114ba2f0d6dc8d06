"""``fd.compile(model)``: the compiled engine bound to one model, with low-overhead calls for control loops.

::

    cm = fd.compile(model)            # loads the kernels (compiled once per machine, cached by Numba)
    tau = cm.rnea(q, v, a)            # (nv,)      inverse dynamics, with gravity
    M = cm.crba(q)                    # (nv, nv)   mass matrix
    ddq = cm.aba(q, v, tau)           # (nv,)      forward dynamics
    oMi = cm.fk(q)                    # (nb, 4, 4) world placements of the bodies
    J = cm.frame_jacobian(q, "tool", fd.LOCAL)   # (6, nv)
    cm.rnea(q, v, a, out=tau)         # writes into tau: no allocation at all
    TAU = cm.rnea_batch(Q, V, A)      # (N, nv), on every core

The model's arrays and a workspace are packed into one array (:attr:`CompiledModel.packed`)
so that a call passes the model as a single argument (each array argument of
a Numba call costs about 0.08 µs). The kernels are generic — nothing is
compiled per model — so a model never seen before is ready at once.

The single-state methods check only what memory safety needs (dtype, length;
Numba checks the rest) — not finiteness nor unit quaternions: validate with
the public functions (``fd.rnea``) while developing. Inputs that are not
float64 C-contiguous writable arrays are converted (a copy). ``cm.kernels``
holds the raw Numba functions with explicit outputs
(``kernels.rnea(cm.packed, q, v, a, tau)``), the cheapest calls there are.

A :class:`CompiledModel` owns a workspace, so one object must not be used by
two threads at once (like Pinocchio's ``Data``): call ``fd.compile(model)``
once per thread. The batched methods are parallel internally and thread-safe.
"""

from __future__ import annotations

import time
from functools import partial
from types import SimpleNamespace
from typing import Any

import numpy as np

from ..errors import ShapeError, SingularMassMatrixError
from ..frames import LOCAL, LOCAL_WORLD_ALIGNED, WORLD, as_reference_frame
from ..model import Model
from . import _dispatch
from ._layout import LOCAL_CODE, LWA_CODE, WORLD_CODE, with_workspace

__all__ = ["CompiledModel", "compile_model"]

_F64 = np.dtype(np.float64)


def _singular_messages(model: Model) -> tuple[str, ...]:
    return _dispatch.singular_messages(model)


def _expected_shapes(model: Model) -> dict[str, tuple[int, ...]]:
    nv, nb = model.nv, model.nbodies
    return {"q": (model.nq,), "v": (nv,), "a": (nv,), "tau": (nv,), "f_ext": (nb, 6),
            "out:rnea": (nv,), "out:nle": (nv,), "out:gravity": (nv,), "out:aba": (nv,), "out:crba": (nv, nv),
            "out:fk": (nb, 4, 4), "out:frame_jacobian": (6, nv)}


def _slow_call(model: Model, where: str, call: Any, inputs: dict[str, Any], out: np.ndarray) -> Any:
    """The path after the kernel refused the arguments: convert the inputs, check every shape, call again.

    Lists, integers, float32 and non-contiguous arrays are converted to fresh
    float64 C-contiguous arrays; a wrong shape raises :class:`ShapeError`
    naming the argument, a bad ``out`` a :class:`TypeError` / :class:`ShapeError`.
    """
    from .._validation import as_array

    shapes = _expected_shapes(model)
    args = []
    for name, x in inputs.items():
        arr = as_array(x, name, check_finite=False)
        if arr.shape != shapes[name]:
            raise ShapeError(f"{where}: {name}: expected shape {shapes[name]}, got {arr.shape}")
        args.append(np.array(arr, dtype=np.float64, order="C"))
    if not isinstance(out, np.ndarray) or out.dtype != _F64 or not out.flags.c_contiguous or not out.flags.writeable:
        raise TypeError(f"{where}: out: expected a writable float64 C-contiguous array")
    if out.shape != shapes[f"out:{where}"]:
        raise ShapeError(f"{where}: out: expected shape {shapes[f'out:{where}']}, got {out.shape}")
    return call(*args, out)


def _reference_code(reference: Any) -> int:
    """0, 1, 2 for LOCAL, WORLD, LOCAL_WORLD_ALIGNED (enum members, their names, or the codes themselves)."""
    if isinstance(reference, (int, np.integer)) and not isinstance(reference, bool) and 0 <= reference <= 2:
        return int(reference)
    return as_reference_frame(reference).code


class CompiledModel:
    """A model with its compiled kernels (see the module docstring).

    Attributes:
        model: the :class:`~featherdyn.Model`.
        nq, nv, nb: sizes.
        kernels: the raw Numba functions, outputs last, model first:
            ``fk(MD, q, oM)``, ``rnea(MD, q, v, a, tau)``, ``rnea_fext(MD, q, v, a, f_ext, tau)``,
            ``nle(MD, q, v, h)``, ``gravity(MD, q, g)``, ``crba(MD, q, M)``, ``aba(MD, q, v, tau, qdd)``
            (returns ``-1`` or the index of the joint with a singular articulated inertia),
            ``frame_jacobian(MD, q, frame_index, reference_code, J)`` (codes 0 LOCAL, 1 WORLD,
            2 LOCAL_WORLD_ALIGNED), with ``MD`` = :attr:`packed`. Arguments must be float64
            C-contiguous arrays (``TypeError`` otherwise) of the right lengths (``ValueError``).
        packed: the model's arrays and a workspace packed in one float64 array (do not modify).
        compile_seconds: how long :func:`compile_model` took.
    """

    def __init__(self, model: Model, compile_seconds: float = 0.0) -> None:
        from . import _kernels as _k

        _k.lock_entries()
        self.model = model
        self.nq, self.nv, self.nb = model.nq, model.nv, model.nbodies
        self.compile_seconds = compile_seconds
        MD = self.packed = with_workspace(_dispatch.arrays_of(model).packed, model.nbodies, model.nv)
        k = self.kernels = SimpleNamespace(
            fk=_k.entry_fk, rnea=_k.entry_rnea, rnea_fext=_k.entry_rnea_fext, nle=_k.entry_nle,
            gravity=_k.entry_gravity, crba=_k.entry_crba, aba=_k.entry_aba, frame_jacobian=_k.entry_frame_jacobian,
        )
        nv, nb = self.nv, self.nb
        empty = np.empty
        shape_M, shape_H, shape_J = (nv, nv), (nb, 4, 4), (6, nv)  # built once, not per call
        frames = model._frame_index
        singular = _singular_messages(model)
        k_rnea, k_rnea_fext, k_nle, k_gravity = k.rnea, k.rnea_fext, k.nle, k.gravity
        k_crba, k_aba, k_fk, k_jac = k.crba, k.aba, k.fk, k.frame_jacobian

        # The methods are closures stored on the instance: no bound-method object, few lookups.
        # Numba raises TypeError for arguments that are not float64 C-contiguous arrays and the
        # kernels ValueError for a wrong length: both go to _slow_call (convert, or a clear error).

        def rnea(q: Any, v: Any, a: Any, f_ext: Any = None, out: Any = None) -> np.ndarray:
            """``τ = RNEA(q, v, a)`` `(nv,)` with gravity, optional body-frame ``f_ext`` `(nb, 6)`."""
            if out is None:
                out = empty(nv)
            try:
                if f_ext is None:
                    k_rnea(MD, q, v, a, out)
                else:
                    k_rnea_fext(MD, q, v, a, f_ext, out)
            except (TypeError, ValueError):
                if f_ext is None:
                    _slow_call(model, "rnea", partial(k_rnea, MD), {"q": q, "v": v, "a": a}, out)
                else:
                    _slow_call(model, "rnea", partial(k_rnea_fext, MD), {"q": q, "v": v, "a": a, "f_ext": f_ext},
                               out)
            return out

        def nle(q: Any, v: Any, out: Any = None) -> np.ndarray:
            """``h(q, v) = RNEA(q, v, 0)`` `(nv,)`."""
            if out is None:
                out = empty(nv)
            try:
                k_nle(MD, q, v, out)
            except (TypeError, ValueError):
                _slow_call(model, "nle", partial(k_nle, MD), {"q": q, "v": v}, out)
            return out

        def gravity(q: Any, out: Any = None) -> np.ndarray:
            """``g(q) = RNEA(q, 0, 0)`` `(nv,)`."""
            if out is None:
                out = empty(nv)
            try:
                k_gravity(MD, q, out)
            except (TypeError, ValueError):
                _slow_call(model, "gravity", partial(k_gravity, MD), {"q": q}, out)
            return out

        def crba(q: Any, out: Any = None) -> np.ndarray:
            """The mass matrix ``M(q)`` `(nv, nv)`, full and symmetric."""
            if out is None:
                out = empty(shape_M)
            try:
                k_crba(MD, q, out)
            except (TypeError, ValueError):
                _slow_call(model, "crba", partial(k_crba, MD), {"q": q}, out)
            return out

        def aba(q: Any, v: Any, tau: Any, out: Any = None) -> np.ndarray:
            """``q̈ = ABA(q, v, τ)`` `(nv,)`; ``SingularMassMatrixError`` naming the joint."""
            if out is None:
                out = empty(nv)
            try:
                bad = k_aba(MD, q, v, tau, out)
            except (TypeError, ValueError):
                bad = _slow_call(model, "aba", partial(k_aba, MD), {"q": q, "v": v, "tau": tau}, out)
            if bad >= 0:
                raise SingularMassMatrixError(singular[bad])
            return out

        def fk(q: Any, out: Any = None) -> np.ndarray:
            """World placements of the bodies, homogeneous `(nb, 4, 4)`."""
            if out is None:
                out = empty(shape_H)
            try:
                k_fk(MD, q, out)
            except (TypeError, ValueError):
                _slow_call(model, "fk", partial(k_fk, MD), {"q": q}, out)
            return out

        def frame_jacobian(q: Any, frame: Any, reference: Any = LOCAL, out: Any = None) -> np.ndarray:
            """The Jacobian `(6, nv)` of ``frame`` (name or index) in ``reference`` (``fd.LOCAL``, ...)."""
            if reference is LOCAL:
                ref = LOCAL_CODE
            elif reference is WORLD:
                ref = WORLD_CODE
            elif reference is LOCAL_WORLD_ALIGNED:
                ref = LWA_CODE
            else:
                ref = _reference_code(reference)
            if out is None:
                out = empty(shape_J)
            try:
                k_jac(MD, q, frames[frame] if frame.__class__ is str else frame, ref, out)
            except (TypeError, ValueError, KeyError):
                fid = model.resolve_frame(frame)
                _slow_call(model, "frame_jacobian", lambda q_, J: k_jac(MD, q_, fid, ref, J), {"q": q}, out)
            return out

        self.rnea = rnea
        self.nle = nle
        self.gravity = gravity
        self.crba = crba
        self.aba = aba
        self.fk = fk
        self.frame_jacobian = frame_jacobian

    # batched forms: the public engine path (any batch shape, broadcasting), with the reference's checks skipped

    def rnea_batch(self, q: Any, v: Any, a: Any, f_ext: Any = None, gravity: bool = True,
                   out: Any = None) -> np.ndarray:
        """``τ`` `(..., nv)` for batches of states (leading axes broadcast), on all cores.

        ``out``: a float64 C-contiguous `(..., nv)` array to write into (reusing one avoids
        the page faults of a large fresh array).
        """
        fx = None if f_ext is None else np.asarray(f_ext)
        return _dispatch.rnea(self.model, np.asarray(q), np.asarray(v), np.asarray(a), fx, gravity, _F64,
                              out=out)

    def crba_batch(self, q: Any, out: Any = None) -> np.ndarray:
        """``M`` `(..., nv, nv)` for a batch of configurations, on all cores (``out`` as in :meth:`rnea_batch`)."""
        return _dispatch.crba(self.model, np.asarray(q), _F64, out=out)

    def aba_batch(self, q: Any, v: Any, tau: Any, f_ext: Any = None, gravity: bool = True,
                  out: Any = None) -> np.ndarray:
        """``q̈`` `(..., nv)` for batches of states, on all cores (``out`` as in :meth:`rnea_batch`)."""
        fx = None if f_ext is None else np.asarray(f_ext)
        return _dispatch.aba(self.model, np.asarray(q), np.asarray(v), np.asarray(tau), fx, gravity, _F64,
                             out=out)

    def fk_batch(self, q: Any) -> np.ndarray:
        """World placements `(..., nb, 4, 4)` for a batch of configurations, on all cores."""
        return _dispatch.placements(self.model, np.asarray(q))

    def frame_jacobian_batch(self, q: Any, frame: Any, reference: Any = LOCAL) -> np.ndarray:
        """Jacobians `(..., 6, nv)` of ``frame`` for a batch of configurations, on all cores."""
        return _dispatch.frame_jacobian(self.model, np.asarray(q), self.model.resolve_frame(frame),
                                        _reference_code(reference), _F64)

    def warmup(self) -> None:
        """Call every single-state method once (loads or compiles the kernels), in O(nb) memory.

        The kernels are generic, so the mass matrix — the one output of size
        ``nv²`` — is warmed up on a one-joint model when this model is large.
        """
        from ..configuration import neutral

        q = np.ascontiguousarray(neutral(self.model), dtype=np.float64)
        z = np.zeros(self.nv)
        self.fk(q)
        self.rnea(q, z, z)
        self.rnea(q, z, z, f_ext=np.zeros((self.nb, 6)))
        self.nle(q, z)
        self.gravity(q)
        if self.nv <= _WARMUP_CRBA_MAX_NV:
            self.crba(q)
        else:
            _one_joint_model().crba(np.zeros(1))
        try:
            self.aba(q, z, z)
        except SingularMassMatrixError:
            pass
        self.frame_jacobian(q, 0, LOCAL)

    def __repr__(self) -> str:
        return f"CompiledModel({self.model!r}, compiled in {self.compile_seconds:.2f} s)"


#: above this many velocities, warm-up does not build this model's (nv, nv) mass matrix
_WARMUP_CRBA_MAX_NV = 256


def _one_joint_model() -> CompiledModel:
    """A compiled one-revolute-joint model: warms up the generic kernels at no memory cost."""
    from ..joints import RevoluteJoint
    from ..model import ModelBuilder
    from ..spatial_algebra import SpatialInertia

    b = ModelBuilder("warmup")
    b.add_body("link", parent=-1, joint=RevoluteJoint(np.array([0.0, 0.0, 1.0])),
               inertia=SpatialInertia(1.0, [0.1, 0.0, 0.0], np.eye(3) * 0.01))
    return CompiledModel(b.build())


def compile_model(model: Model, *, warmup: bool = True) -> CompiledModel:
    """The compiled engine bound to ``model`` (see :class:`CompiledModel`).

    The kernels are generic (compiled once per machine, then loaded from
    Numba's disk cache), so nothing is compiled per model; ``warmup`` runs each
    method once at the neutral configuration so that loading (or the first
    compilation) happens here rather than in the first call of a control loop.
    """
    if not isinstance(model, Model):
        from ..errors import ModelError

        raise ModelError(f"compile: expected a featherdyn Model, got {type(model).__name__}")
    t0 = time.perf_counter()
    cm = CompiledModel(model)
    if warmup:
        cm.warmup()
    cm.compile_seconds = time.perf_counter() - t0
    return cm
