"""Checks of the public functions (private): the state checks, and results that must stay finite.

The state checks themselves (:func:`check_state`, :func:`check_f_ext`) live in
the model layer (``featherdyn/_state_checks.py``) so that the compiled core can
raise the same words; this module adds what only the public layer does.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np

from .._state_checks import VECTORS, State, batch_with_f_ext, batch_with_point, check_f_ext, check_point, check_state
from ..errors import NonFiniteError

__all__ = ["State", "VECTORS", "check_state", "check_f_ext", "check_point", "batch_with_f_ext", "batch_with_point",
           "as_dtype", "finite_result", "quiet"]


_F64 = np.dtype(np.float64)


def as_dtype(x: np.ndarray, dtype: np.dtype) -> np.ndarray:
    """The compiled core's float64 result in the input's dtype (float32 stays float32 when the core is forced)."""
    return x if dtype == _F64 else x.astype(dtype)


def finite_result(result: np.ndarray, what: str) -> np.ndarray:
    """``result``, or :class:`NonFiniteError` when checked, finite input gave a non-finite result.

    Finite input overflows only when the state or the model holds magnitudes
    whose products exceed float64's range (about 1.8e308): say so rather than
    return inf or NaN. Object (SymPy) results are not checked.
    """
    if result.dtype.kind == "f" and not np.isfinite(result).all():
        bad = tuple(int(i) for i in np.argwhere(~np.isfinite(result))[0])
        raise NonFiniteError.overflowed(what, f"{result[bad]!r} at index {bad}")
    return result


_R = TypeVar("_R")


def quiet(function: Callable[..., _R], *args: Any) -> _R:
    """``function(*args)`` (a reference computation) without NumPy's overflow warnings.

    Finite input that overflows is reported by :func:`finite_result` as a
    featherdyn error instead of a ``RuntimeWarning`` followed by inf or NaN.
    """
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        return function(*args)
