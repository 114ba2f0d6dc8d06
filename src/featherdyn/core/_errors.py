"""Statuses of the compiled core → the reference's exceptions, with the reference's messages (private).

The core checks lengths, finiteness and unit quaternions itself and returns a
status (``cpp/checks.hpp``)::

    status = code | arg << 3 | index << 8

On a non-zero status the wrapper calls :func:`raise_for`, which re-checks the
original arguments in the order and words of the public functions' checks
(``api/_checks.py``: ``check_f_ext``, then ``check_state``; the core sits below
the api layer and cannot import them, so :func:`validate` repeats them until
the api calls the core itself) — the error path may be slow, the message must
be the same — and raises. A status the re-check does not explain (it should
not happen) still raises, worded from the status itself.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, NoReturn

import numpy as np

from .._validation import as_array, numeric_value
from ..errors import FeatherdynError, NonFiniteError, QuaternionNormError, ShapeError, SingularMassMatrixError
from ..joints import FreeFlyerJoint, SphericalJoint
from ..model import Model
from ..tolerances import QUATERNION_NORM

__all__ = ["OK", "LENGTH", "NONFINITE", "QUATERNION", "SINGULAR", "ARG_NAMES", "decode", "validate",
           "raise_for", "singular_error"]

OK, LENGTH, NONFINITE, QUATERNION, SINGULAR = range(5)
#: the ``arg`` field of a status
ARG_NAMES = ("q", "v", "a", "f_ext", "out", "frame")


def decode(status: int) -> tuple[int, int, int]:
    """``(code, arg, index)`` of a status."""
    return status & 7, (status >> 3) & 31, status >> 8


def _vec(x: Any, name: str, n: int, what: str) -> np.ndarray:
    if x is None:
        raise ShapeError(f"{name}: expected an array of shape (..., {what}={n}), got None")
    arr = as_array(x, name)
    if arr.ndim == 0 or arr.shape[-1] != n:
        raise ShapeError(f"{name}: expected trailing dimension {what}={n}, got shape {tuple(arr.shape)}")
    return arr


def _f_ext(model: Model, f_ext: Any) -> np.ndarray:
    arr = as_array(f_ext, "f_ext")
    if arr.ndim < 2 or arr.shape[-2:] != (model.nbodies, 6):
        raise ShapeError(
            f"f_ext: expected shape (..., nb={model.nbodies}, 6) of body-frame spatial forces [n; f], "
            f"got shape {tuple(arr.shape)}"
        )
    return arr


def validate(model: Model, q: Any, vectors: Sequence[tuple[str, Any]] = (), f_ext: Any = None) -> None:
    """Raise what the reference raises for these arguments (``f_ext``, then ``q``, the vectors, quaternions)."""
    fx = None if f_ext is None else _f_ext(model, f_ext)
    qq = _vec(q, "q", model.nq, "nq")
    arrays = [("q", qq)] + [(name, _vec(x, name, model.nv, "nv")) for name, x in vectors]
    try:
        batch = np.broadcast_shapes(*(a.shape[:-1] for _, a in arrays))
    except ValueError:
        shapes = ", ".join(f"{n}: {a.shape}" for n, a in arrays)
        raise ShapeError(f"batch shapes do not broadcast ({shapes})") from None
    _check_quaternions(model, qq if qq.dtype.kind != "O" else _numeric_part(qq))
    if fx is not None:
        try:
            np.broadcast_shapes(batch, fx.shape[:-2])
        except ValueError:
            raise ShapeError(
                f"f_ext: batch shape {tuple(fx.shape[:-2])} (shape {tuple(fx.shape)}) does not broadcast with "
                f"the batch shape {tuple(batch)} of the state"
            ) from None


def _numeric_part(q: np.ndarray) -> np.ndarray:
    """An object array's entries as floats, NaN where an entry is symbolic (unchecked)."""
    return np.vectorize(lambda x: math.nan if (v := numeric_value(x)) is None else v, otypes=[np.float64])(q)


def _check_quaternions(model: Model, q: np.ndarray) -> None:
    tol = QUATERNION_NORM.of(q.dtype)
    for i, joint in enumerate(model.joints):
        if isinstance(joint, SphericalJoint):
            quat = q[..., model.idx_q[i] : model.idx_q[i] + 4]
        elif isinstance(joint, FreeFlyerJoint):
            quat = q[..., model.idx_q[i] + 3 : model.idx_q[i] + 7]
        else:
            continue
        with np.errstate(over="ignore", invalid="ignore"):  # a huge entry: inf norm, refused below
            err = np.abs(np.sqrt(np.sum(quat * quat, axis=-1)) - 1)
        err = err[~np.isnan(err)]  # a symbolic quaternion (object arrays) is not checked
        if np.any(err > tol):
            worst = float(np.max(err))
            raise QuaternionNormError(
                f"q: the quaternion of joint {model.joint_names[i]!r} (q[{model.idx_q[i]}:{model.idx_q[i] + joint.nq}]) "
                f"is off unit norm by {worst:.3g} > {tol:g}; featherdyn quaternions are (x, y, z, w) — "
                "normalise with fd.normalize(model, q)"
            )


def singular_error(model: Model, joint: int, eig_min: float) -> SingularMassMatrixError:
    """The reference ABA's error for ``joint`` whose ``D`` has smallest eigenvalue ``eig_min``."""
    return SingularMassMatrixError.for_joint(model.joint_names[joint], model.body_names[joint], eig_min)


def eig_min(D36: np.ndarray, k: int) -> float:
    """The smallest eigenvalue of the symmetric part of the `(k, k)` block of ``D36`` (row stride 6)."""
    D = D36.reshape(6, 6)[:k, :k]
    return float(np.linalg.eigvalsh((D + D.T) / 2)[0])


def raise_for(status: int, model: Model, q: Any, vectors: Sequence[tuple[str, Any]] = (), f_ext: Any = None,
              arg_names: Sequence[str] = ARG_NAMES) -> NoReturn:
    """Raise the reference's exception for a failed core call (see the module docstring)."""
    validate(model, q, vectors, f_ext)
    code, arg, index = decode(status)
    name = arg_names[arg] if arg < len(arg_names) else f"argument {arg}"
    if code == LENGTH:
        raise ShapeError(f"{name}: wrong length {index} for model {model.name!r} (nq={model.nq}, nv={model.nv}, "
                         f"nb={model.nbodies})")
    if code == NONFINITE:
        raise NonFiniteError(f"{name}: expected finite numbers, got a non-finite value at flat index {index}")
    if code == QUATERNION:
        raise QuaternionNormError(f"q: the quaternion of joint {model.joint_names[index]!r} is off unit norm")
    if code == SINGULAR:
        raise SingularMassMatrixError(f"joint {model.joint_names[index]!r}: the mass matrix is singular")
    raise FeatherdynError(f"featherdyn.core: unexpected status {status}")
