"""The compiled engine behind the public algorithms (private): batching, layout, calls into the kernels.

The public functions (``fd.rnea`` & co.) validate their input with the
reference's checks and then, for the compiled backend, call these with the
validated arrays. Inputs are made float64, C-contiguous and writable (a copy
only where they are not already), batch axes are flattened to one axis of
length ``N`` — or 1 for an input that is broadcast — and the result is
reshaped back and cast to the requested dtype (float32 stays float32 when the
compiled backend is forced).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import BackendError, SingularMassMatrixError
from ..frames import ReferenceFrame
from ..model import Model
from ..results import Kinematics
from ..spatial_algebra import PluckerTransform, SpatialMotion
from . import _kernels as _k
from . import _lanes as _ln
from . import _layout as _lay
from ._layout import ModelArrays, model_arrays, workspace_size

__all__ = ["arrays_of", "rnea", "crba", "aba", "forward_kinematics", "placements", "frame_jacobian"]

_F64 = np.dtype(np.float64)
_CACHE: dict[int, tuple[Model, ModelArrays]] = {}
_CACHE_SIZE = 64

def arrays_of(model: Model) -> ModelArrays:
    """The flat arrays of ``model``, computed once per model object (a small LRU keyed by identity)."""
    hit = _CACHE.get(id(model))
    if hit is not None and hit[0] is model:
        return hit[1]
    md = model_arrays(model)
    if len(_CACHE) >= _CACHE_SIZE:
        _CACHE.pop(next(iter(_CACHE)))
    _CACHE[id(model)] = (model, md)
    return md


def as_f64(x: np.ndarray, name: str) -> np.ndarray:
    """``x`` as a C-contiguous, writable float64 array (no copy when it already is one)."""
    if x.dtype != _F64:
        try:
            x = x.astype(np.float64)
        except (TypeError, ValueError) as exc:
            raise BackendError(
                f"backend='compiled': {name} cannot be converted to float64 ({exc}); "
                "symbolic input needs backend='reference'"
            ) from None
    if not (x.flags.c_contiguous and x.flags.writeable):
        x = np.array(x, dtype=np.float64, order="C")
    return x


def _rows(x: np.ndarray, name: str, batch: tuple[int, ...], tail: int) -> np.ndarray:
    """``x`` `(*b, *t)` as `(N or 1, *t)` for the batch shape ``batch`` (``len(t) = tail``)."""
    tshape = x.shape[x.ndim - tail :]
    bx = x.shape[: x.ndim - tail]
    if bx == batch:
        return as_f64(x, name).reshape((math.prod(batch), *tshape))
    if math.prod(bx) == 1:
        return as_f64(x, name).reshape((1, *tshape))
    return as_f64(np.broadcast_to(x, batch + tshape), name).reshape((math.prod(batch), *tshape))


def _out(x: np.ndarray, dtype: np.dtype) -> np.ndarray:
    return x if dtype == _F64 or dtype.kind == "O" else x.astype(dtype)


def _batch_of(*shapes: tuple[int, ...]) -> tuple[int, ...]:
    return np.broadcast_shapes(*shapes)


def _ws(width: int, nb: int) -> np.ndarray:
    return np.empty(workspace_size(width, nb))


def _threads() -> int:
    """Numba's thread count (``NUMBA_NUM_THREADS``, or set with ``numba.set_num_threads``)."""
    import numba

    return int(numba.get_num_threads())


def _batch_out(out: np.ndarray | None, shape: tuple[int, ...]) -> np.ndarray:
    """A fresh ``shape`` array, or ``out`` (float64, C-contiguous, writable, that shape) to write into.

    Writing into a preallocated ``out`` also avoids the first-touch page faults
    of a large fresh array, which the threads would otherwise take in parallel.
    """
    if out is None:
        return np.empty(shape)
    if not (isinstance(out, np.ndarray) and out.dtype == _F64 and out.flags.c_contiguous and out.flags.writeable):
        raise TypeError("out: expected a writable float64 C-contiguous array")
    if out.shape != shape:
        from ..errors import ShapeError

        raise ShapeError(f"out: expected shape {shape}, got {out.shape}")
    return out


def rnea(model: Model, q: np.ndarray, v: np.ndarray, a: np.ndarray, fext: np.ndarray | None, gravity: bool,
         dtype: np.dtype, out: np.ndarray | None = None) -> np.ndarray:
    """``τ`` `(..., nv)`; ``fext`` `(..., nb, 6)` or ``None``; ``out``: an array to write into."""
    md = arrays_of(model)
    shapes = [q.shape[:-1], v.shape[:-1], a.shape[:-1]] + ([fext.shape[:-2]] if fext is not None else [])
    batch = _batch_of(*shapes)
    if batch == ():
        tau = _batch_out(out, (md.nv,))
        fx = md.no_fext if fext is None else as_f64(fext, "f_ext")
        _k.rnea_core(md.BI, md.BF, md.G, as_f64(q, "q"), as_f64(v, "v"), as_f64(a, "a"), fx, bool(gravity), tau,
                    _ws(_lay.WS_RNEA, md.nb))
        return _out(tau, dtype)
    FX = np.zeros((1, 0, 6)) if fext is None else _rows(fext, "f_ext", batch, 2)
    result = _batch_out(out, batch + (md.nv,))
    TAU = result.reshape((math.prod(batch), md.nv))
    _ln.rnea_lanes(md.BI, md.BF, md.G, _rows(q, "q", batch, 1), _rows(v, "v", batch, 1), _rows(a, "a", batch, 1),
                   FX, bool(gravity), TAU, _threads())
    return _out(result, dtype)


def crba(model: Model, q: np.ndarray, dtype: np.dtype, out: np.ndarray | None = None) -> np.ndarray:
    """``M(q)`` `(..., nv, nv)`; ``out``: an array to write into."""
    md = arrays_of(model)
    batch = q.shape[:-1]
    if batch == ():
        M = _batch_out(out, (md.nv, md.nv))
        _k.crba_core(md.BI, md.BF, as_f64(q, "q"), M, _ws(_lay.WS_CRBA, md.nb))
        return _out(M, dtype)
    result = _batch_out(out, batch + (md.nv, md.nv))
    M = result.reshape((math.prod(batch), md.nv, md.nv))
    _ln.crba_lanes(md.BI, md.BF, _rows(q, "q", batch, 1), M, _threads())
    return _out(result, dtype)


def singular_messages(model: Model) -> tuple[str, ...]:
    """The :class:`~featherdyn.errors.SingularMassMatrixError` message for each joint."""
    return tuple(str(SingularMassMatrixError.for_joint(model.joint_names[i], model.body_names[i]))
                 for i in range(model.nbodies))


def _singular(model: Model, joint: int, state: tuple[int, ...] | None) -> SingularMassMatrixError:
    return SingularMassMatrixError.for_joint(model.joint_names[joint], model.body_names[joint], batch_index=state)


def aba(model: Model, q: np.ndarray, v: np.ndarray, tau: np.ndarray, fext: np.ndarray | None, gravity: bool,
        dtype: np.dtype, out: np.ndarray | None = None) -> np.ndarray:
    """``q̈`` `(..., nv)`; raises :class:`SingularMassMatrixError` naming the joint; ``out`` to write into."""
    md = arrays_of(model)
    shapes = [q.shape[:-1], v.shape[:-1], tau.shape[:-1]] + ([fext.shape[:-2]] if fext is not None else [])
    batch = _batch_of(*shapes)
    if batch == ():
        qdd = _batch_out(out, (md.nv,))
        fx = md.no_fext if fext is None else as_f64(fext, "f_ext")
        bad = _k.aba_core(md.BI, md.BF, md.G, as_f64(q, "q"), as_f64(v, "v"), as_f64(tau, "tau"), fx, bool(gravity),
                         qdd, _ws(_lay.WS_ABA, md.nb))
        if bad >= 0:
            raise _singular(model, int(bad), None)
        return _out(qdd, dtype)
    FX = np.zeros((1, 0, 6)) if fext is None else _rows(fext, "f_ext", batch, 2)
    result = _batch_out(out, batch + (md.nv,))
    QDD = result.reshape((math.prod(batch), md.nv))
    bad = _ln.aba_lanes(md.BI, md.BF, md.G, _rows(q, "q", batch, 1), _rows(v, "v", batch, 1),
                        _rows(tau, "tau", batch, 1), FX, bool(gravity), QDD, _threads())
    if bad >= 0:
        state, joint = divmod(int(bad), max(md.nb, 1))
        raise _singular(model, joint, tuple(int(i) for i in np.unravel_index(state, batch)))
    return _out(result, dtype)


def _fk_arrays(model: Model, q: np.ndarray, v: np.ndarray | None, a: np.ndarray | None,
               parents: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(⁰M, ᵖM, v, a)``: `(..., nb, 4, 4)` twice (``ᵖM`` with no bodies unless ``parents``), `(..., nb, 6)`
    twice (no bodies where ``v`` / ``a`` is ``None``)."""
    md = arrays_of(model)
    nb = md.nb
    shapes = [q.shape[:-1]] + [x.shape[:-1] for x in (v, a) if x is not None]
    batch = _batch_of(*shapes)
    N = math.prod(batch)
    nbp = nb if parents else 0
    nbv = nb if v is not None else 0
    nba = nb if a is not None else 0
    if batch == ():
        oM, pM = np.empty((nb, 4, 4)), np.empty((nbp, 4, 4))
        vel, acc = np.empty((nbv, 6)), np.empty((nba, 6))
        empty = np.empty(0)
        _k.fk_core(md.BI, md.BF, as_f64(q, "q"), empty if v is None else as_f64(v, "v"),
                   empty if a is None else as_f64(a, "a"), oM, pM, vel, acc, _ws(_lay.WS_FK, nb))
        return oM, pM, vel, acc
    oM, pM = np.empty((N, nb, 4, 4)), np.empty((N, nbp, 4, 4))
    vel, acc = np.empty((N, nbv, 6)), np.empty((N, nba, 6))
    none = np.empty((1, 0))
    _k.fk_batch(md.BI, md.BF, _rows(q, "q", batch, 1), none if v is None else _rows(v, "v", batch, 1),
                none if a is None else _rows(a, "a", batch, 1), oM, pM, vel, acc, workspace_size(_lay.WS_FK, nb),
                _threads())
    return (oM.reshape(batch + (nb, 4, 4)), pM.reshape(batch + (nbp, 4, 4)), vel.reshape(batch + (nbv, 6)),
            acc.reshape(batch + (nba, 6)))


def placements(model: Model, q: np.ndarray) -> np.ndarray:
    """World placements of the bodies, homogeneous `(..., nb, 4, 4)`."""
    return _fk_arrays(model, q, None, None, False)[0]


def forward_kinematics(model: Model, q: np.ndarray, v: np.ndarray | None, a: np.ndarray | None,
                       dtype: np.dtype) -> Any:
    """The :class:`~featherdyn.results.Kinematics` of ``(q, v, a)`` (``a`` needs ``v``)."""
    oM, pM, vel, acc = _fk_arrays(model, q, v, a, True)

    def transforms(H: np.ndarray) -> PluckerTransform:
        return PluckerTransform._wrap(_out(H[..., :3, :3], dtype), _out(H[..., :3, 3], dtype), None, None)

    return Kinematics(
        model=model,
        placements=transforms(oM),
        velocities=SpatialMotion._wrap(_out(vel, dtype), None) if v is not None else None,
        accelerations=SpatialMotion._wrap(_out(acc, dtype), None) if a is not None else None,
        parent_placements=transforms(pM),
    )


def frame_jacobian(model: Model, q: np.ndarray, frame: int, reference: ReferenceFrame | int, dtype: np.dtype) -> np.ndarray:
    """The Jacobian `(..., 6, nv)` of frame index ``frame`` in ``reference`` (a ReferenceFrame or a code 0–2)."""
    md = arrays_of(model)
    ref = reference if isinstance(reference, int) else reference.code
    body = int(md.FB[frame])
    batch = q.shape[:-1]
    if batch == ():
        J = np.empty((6, md.nv))
        _k.frame_jacobian_core(md.BI, md.BF, as_f64(q, "q"), body, md.FR, 12 * frame, ref, J, np.empty(_lay.WS_TAIL))
        return _out(J, dtype)
    J = np.empty((math.prod(batch), 6, md.nv))
    _k.frame_jacobian_batch(md.BI, md.BF, _rows(q, "q", batch, 1), body, md.FR, 12 * frame, ref, J, _lay.WS_TAIL,
                           _threads())
    return _out(J.reshape(batch + (6, md.nv)), dtype)
