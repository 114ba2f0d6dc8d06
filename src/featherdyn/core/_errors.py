"""Statuses of the compiled core → the reference's exceptions, with the reference's messages (private).

The core checks lengths, finiteness and unit quaternions itself and returns a
status (``cpp/checks.hpp``)::

    status = code | arg << 3 | index << 8

On a non-zero status the wrapper calls :func:`raise_for`, which re-checks the
original arguments in the order and words of the public functions' checks
(``featherdyn/_state_checks.py``: ``check_f_ext``, then ``check_state``) — the
error path may be slow, the message must be the same — and raises. A status the re-check does not explain (it should
not happen) still raises, worded from the status itself.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, NoReturn

import numpy as np

from .._state_checks import VECTORS, batch_with_f_ext, check_f_ext, check_state
from ..errors import (
    ConstraintError,
    FeatherdynError,
    ModelError,
    NonFiniteError,
    QuaternionNormError,
    ShapeError,
    SingularMassMatrixError,
)
from ..model import Model

__all__ = ["OK", "LENGTH", "NONFINITE", "QUATERNION", "SINGULAR", "OVERLAP", "NO_MASS", "CONSTRAINT", "ARG_NAMES", "VECTORS",
           "decode", "validate", "raise_for", "singular_error"]

OK, LENGTH, NONFINITE, QUATERNION, SINGULAR, OVERLAP, NO_MASS, CONSTRAINT = range(8)
#: the ``arg`` field of a status (``q1``: a second configuration, ``fd.difference``'s; its ``q0`` is ``q``'s field)
ARG_NAMES = ("q", "v", "a", "f_ext", "out", "frame", "J", "c", "q1", "w", "point")


def decode(status: int) -> tuple[int, int, int]:
    """``(code, arg, index)`` of a status."""
    return status & 7, (status >> 3) & 31, status >> 8


def validate(model: Model, q: Any, vectors: Sequence[tuple[str, Any]] = (), f_ext: Any = None, name: str = "q") -> None:
    """Raise what the public functions raise for these arguments (``f_ext``, then ``q`` or ``name``, vectors, quaternions)."""
    fx = check_f_ext(model, f_ext)
    st = check_state(model, q, name=name, **dict(vectors))
    batch_with_f_ext(st, fx)


def singular_error(model: Model, joint: int, eig_min: float) -> SingularMassMatrixError:
    """The reference ABA's error for ``joint`` whose ``D`` has smallest eigenvalue ``eig_min``."""
    return SingularMassMatrixError.for_joint(model.joint_names[joint], model.body_names[joint], eig_min)


def eig_min(D36: np.ndarray, k: int) -> float:
    """The smallest eigenvalue of the symmetric part of the `(k, k)` block of ``D36`` (row stride 6)."""
    D = D36.reshape(6, 6)[:k, :k]
    return float(np.linalg.eigvalsh((D + D.T) / 2)[0])


def raise_for(status: int, model: Model, q: Any, vectors: Sequence[tuple[str, Any]] = (), f_ext: Any = None,
              arg_names: Sequence[str] = ARG_NAMES, what: str = "featherdyn.core") -> NoReturn:
    """Raise the reference's exception for a failed core call (see the module docstring).

    ``what`` names the computation in the overflow message (as the public functions do); ``arg_names[0]``: q's name.
    """
    validate(model, q, vectors, f_ext, arg_names[0])
    code, arg, index = decode(status)
    name = arg_names[arg] if arg < len(arg_names) else f"argument {arg}"
    if code == LENGTH:
        raise ShapeError(f"{name}: wrong length {index} for model {model.name!r} (nq={model.nq}, nv={model.nv}, "
                         f"nb={model.nbodies})")
    if code == NONFINITE and name == "out":
        raise NonFiniteError.overflowed(what, f"a non-finite value at flat index {index}")
    if code == NONFINITE:
        raise NonFiniteError(f"{name}: expected finite numbers, got a non-finite value at flat index {index}")
    if code == QUATERNION:
        raise QuaternionNormError(f"{name}: the quaternion of joint {model.joint_names[index]!r} is off unit norm")
    if code == SINGULAR:
        raise SingularMassMatrixError.for_joint(model.joint_names[index], model.body_names[index])
    if code == NO_MASS:
        raise ModelError.no_mass(model.name)
    if code == CONSTRAINT:
        raise ConstraintError.singular_frames(index)
    if code == OVERLAP:
        raise ShapeError(f"out: shares memory with {name}; the public functions compute such a call into fresh memory")
    raise FeatherdynError(f"featherdyn.core: unexpected status {status}")
