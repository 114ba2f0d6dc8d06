"""Input checks of a state against a model (private): what every entry point checks, stated once.

The public functions (:mod:`featherdyn.api`) check their state here before
either implementation sees it, and the compiled core re-checks a state it
refused here to raise the same words: ``q`` `(..., nq)` and each vector `(..., nv)` by trailing length,
finiteness (:mod:`featherdyn.spatial.validation`), unit quaternions of spherical and
free-flyer joints (:data:`featherdyn.tolerances.QUATERNION_NORM`), a common
batch shape, and ``f_ext`` `(..., nb, 6)`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .errors import QuaternionNormError, ShapeError
from .joints import FreeFlyerJoint, SphericalJoint
from .model import Model
from .spatial.validation import as_array, numeric_value, result_dtype
from .tolerances import QUATERNION_NORM

__all__ = ["State", "CONFIGURATIONS", "VECTORS", "check_state", "check_quaternions", "check_f_ext", "check_point",
           "batch_with_f_ext", "batch_with_point"]

#: the state arguments that are configurations `(..., nq)`, whose quaternions are checked (``q``; ``q0`` and ``q1`` of
#: ``fd.difference``); every other state vector is `(..., nv)`
CONFIGURATIONS = ("q", "q0", "q1")
#: the state arguments that are matrices `(..., nv, nv)` (``W``: a cotangent of the mass matrix, ``fd.crba_vjp``'s)
MATRICES = ("W",)
#: the state arguments :func:`check_state` takes among its vectors, after the first configuration (``q`` or ``q0``)
VECTORS = ("v", "a", "tau", "w", "q1", *MATRICES)


@dataclass(frozen=True)
class State:
    """Validated inputs: arrays with a common batch shape and dtype."""

    batch: tuple[int, ...]
    dtype: np.dtype
    q: np.ndarray
    arrays: dict[str, np.ndarray]


def check_state(model: Model, q: Any, check_finite: bool = True, optional: tuple[str, ...] = (), values: bool = True,
                name: str = "q", **vectors: Any) -> State:
    """Validate ``q`` `(..., nq)` (named ``name`` in the messages: ``q0`` for ``fd.difference``) and every named vector
    `(..., nv)` — `(..., nq)` for a configuration (:data:`CONFIGURATIONS`: ``q1``), `(..., nv, nv)` for a matrix
    (:data:`MATRICES`: ``W``).

    A vector named in ``optional`` may be ``None`` (it is then left out of
    :attr:`State.arrays`); ``None`` for ``q`` or any other vector is a
    :class:`ShapeError` naming the argument.

    Raises :class:`ShapeError` naming the argument and the expected trailing
    dimension, :class:`NonFiniteError`, or :class:`QuaternionNormError` naming
    the joint whose quaternion is off unit norm by more than
    :data:`featherdyn.tolerances.QUATERNION_NORM`. ``values=False`` checks the shapes and dtypes only (for the
    compiled core, which checks finiteness and the quaternions of every state itself).
    """
    check_finite = check_finite and values
    if not isinstance(model, Model):
        raise ShapeError(f"model: expected a featherdyn Model, got {type(model).__name__}")
    qq = _vec(q, name, model.nq, "nq", check_finite)
    arrays = {}
    for n, val in vectors.items():
        if val is not None or n not in optional:
            arrays[n] = (_vec(val, n, model.nq, "nq", check_finite) if n in CONFIGURATIONS
                         else _matrix(val, n, model.nv, check_finite) if n in MATRICES
                         else _vec(val, n, model.nv, "nv", check_finite))
    all_arrays = [qq, *arrays.values()]
    shapes = [qq.shape[:-1], *(a.shape[:-2] if n in MATRICES else a.shape[:-1] for n, a in arrays.items())]
    batches = set(shapes)
    try:
        batch = batches.pop() if len(batches) == 1 else np.broadcast_shapes(*shapes)
    except ValueError:
        given = ", ".join(f"{n}: {a.shape}" for n, a in [(name, qq), *arrays.items()])
        raise ShapeError(f"batch shapes do not broadcast ({given})") from None
    dtype = result_dtype(*all_arrays)
    if values:
        check_quaternions(model, qq, name)
        for n, a in arrays.items():
            if n in CONFIGURATIONS:
                check_quaternions(model, a, n)
    return State(batch, dtype, qq, arrays)


def _numeric_part(q: np.ndarray) -> np.ndarray:
    """An object array's entries as floats, NaN where an entry is symbolic (unchecked)."""
    return np.vectorize(lambda x: math.nan if (v := numeric_value(x)) is None else v, otypes=[np.float64])(q)


def _vec(x: Any, name: str, n: int, what: str, check_finite: bool) -> np.ndarray:
    if x is None:
        raise ShapeError(f"{name}: expected an array of shape (..., {what}={n}), got None")
    arr = as_array(x, name, check_finite=False)
    if arr.ndim == 0 or arr.shape[-1] != n:  # the length before the values (a huge zero-stride view: no scan)
        raise ShapeError(f"{name}: expected trailing dimension {what}={n}, got shape {tuple(arr.shape)}")
    return as_array(arr, name) if check_finite else arr


def _matrix(x: Any, name: str, n: int, check_finite: bool) -> np.ndarray:
    if x is None:
        raise ShapeError(f"{name}: expected an array of shape (..., nv={n}, nv={n}), got None")
    arr = as_array(x, name, check_finite=False)
    if arr.ndim < 2 or arr.shape[-2:] != (n, n):
        raise ShapeError(f"{name}: expected trailing dimensions (nv, nv) = ({n}, {n}), got shape {tuple(arr.shape)}")
    return as_array(arr, name) if check_finite else arr


def check_quaternions(model: Model, q: np.ndarray, name: str = "q") -> None:
    """Raise :class:`QuaternionNormError` naming the argument, the joint, the norm and the first batch index unless each
    quaternion of the configuration ``q`` `(..., nq)` (spherical, free-flyer) is unit within
    :data:`featherdyn.tolerances.QUATERNION_NORM`. A symbolic entry (object arrays) is not checked."""
    numeric = q if q.dtype.kind != "O" else _numeric_part(q)
    tol = QUATERNION_NORM.of(q.dtype)
    for i, joint in enumerate(model.joints):
        if isinstance(joint, (SphericalJoint, FreeFlyerJoint)):
            start = model.idx_q[i] + (3 if isinstance(joint, FreeFlyerJoint) else 0)
        else:
            continue
        quat = numeric[..., start : start + 4]
        with np.errstate(over="ignore", invalid="ignore"):  # a huge entry: inf norm, refused below
            norm = np.sqrt(np.sum(quat * quat, axis=-1))
        bad = np.abs(norm - 1) > tol  # (NaN, a symbolic quaternion: not refused)
        if np.any(bad):
            idx = tuple(int(k) for k in np.argwhere(bad)[0]) if bad.ndim else ()
            where = f" at batch index {idx}" if idx else ""
            raise QuaternionNormError(
                f"{name}: joint {model.joint_names[i]!r} ({joint.kind}, {name}[{start}:{start + 4}]): "
                f"expected a unit quaternion (x, y, z, w), got norm {float(norm[idx]):.9g}{where} "
                f"(tolerance {tol:g}); normalise q with featherdyn.normalize(model, q)"
            )


def check_f_ext(model: Model, f_ext: Any, values: bool = True) -> np.ndarray | None:
    """``f_ext`` as an array `(..., nb, 6)` of body-frame spatial forces ``[n; f]`` (``None`` stays ``None``);
    ``values=False``: its shape only (the compiled core checks its values)."""
    if f_ext is None:
        return None
    arr = as_array(f_ext, "f_ext", check_finite=False)
    if arr.ndim < 2 or arr.shape[-2:] != (model.nbodies, 6):
        raise ShapeError(
            f"f_ext: expected shape (..., nb={model.nbodies}, 6) of body-frame spatial forces [n; f], "
            f"got shape {tuple(arr.shape)}"
        )
    return as_array(arr, "f_ext") if values else arr


def check_point(point: Any, values: bool = True) -> np.ndarray | None:
    """``point`` as an array `(..., 3)` of a point's coordinates in a frame (``fd.kinematics_derivatives``'; ``None``
    stays ``None``); ``values=False``: its shape and dtype only (the compiled core checks its values)."""
    return None if point is None else as_array(point, "point", (3,), check_finite=values)


def batch_with_point(batch: tuple[int, ...], dtype: np.dtype, point: np.ndarray | None
                     ) -> tuple[tuple[int, ...], np.dtype]:
    """The batch shape and dtype of a state's (``batch``, ``dtype``) together with ``point`` `(..., 3)`."""
    if point is None:
        return batch, dtype
    try:
        joint = np.broadcast_shapes(batch, point.shape[:-1])
    except ValueError:
        raise ShapeError(f"point: batch shape {tuple(point.shape[:-1])} (shape {tuple(point.shape)}) does not "
                         f"broadcast with the batch shape {tuple(batch)} of the state") from None
    return joint, result_dtype(np.empty(0, dtype), point)


def batch_with_f_ext(st: State, fx: np.ndarray | None) -> tuple[tuple[int, ...], np.dtype]:
    """The batch shape and dtype of the state together with ``f_ext`` `(..., nb, 6)`."""
    if fx is None:
        return st.batch, st.dtype
    try:
        batch = np.broadcast_shapes(st.batch, fx.shape[:-2])
    except ValueError:
        raise ShapeError(
            f"f_ext: batch shape {tuple(fx.shape[:-2])} (shape {tuple(fx.shape)}) does not broadcast with "
            f"the batch shape {tuple(st.batch)} of the state"
        ) from None
    return batch, result_dtype(np.empty(0, st.dtype), fx)

