"""Input checking shared by every public function: the array rules of every value and every call.

The rules, applied at every public boundary:

* integers and booleans become float64; float16 becomes float32; float32
  stays float32; float64 stays float64; object arrays of real numbers and
  SymPy expressions pass through unchanged (``None``, strings or other
  objects inside raise :class:`DTypeError`); extended precision (float128),
  complex numbers, strings and other dtypes raise :class:`DTypeError`;
* a masked array is read through its mask: any masked entry raises
  :class:`DTypeError` (fill it first), an unmasked one is its data;
* the trailing dimensions must match exactly (a motion is ``(..., 6)``), else
  :class:`ShapeError` naming the argument, the expected and the received shape;
* floating input — and numeric entries of object arrays — must be finite,
  else :class:`NonFiniteError` naming the argument and the first bad index.
"""

from __future__ import annotations

import math
import numbers
from typing import Any

import numpy as np

from ..errors import DTypeError, NonFiniteError, ShapeError
from ..tolerances import ROTATION_ORTHONORMAL


def _shape_text(shape: tuple[int | str, ...]) -> str:
    inner = ", ".join(str(s) for s in shape)
    return f"(..., {inner})" if shape else "(...)"


def as_array(
    x: Any,
    name: str,
    trailing: tuple[int, ...] = (),
    *,
    check_finite: bool = True,
    copy: bool = False,
) -> np.ndarray:
    """Convert ``x`` to an array with trailing shape ``trailing`` (see module doc).

    Args:
        x: anything ``np.asarray`` accepts.
        name: the argument name used in error messages.
        trailing: the required trailing dimensions, e.g. ``(6,)`` or ``(3, 3)``.
        check_finite: reject NaN and infinity in floating input.
        copy: always return a fresh array (so it can be made read-only safely).
    """
    if isinstance(x, np.ma.MaskedArray):
        if np.ma.getmaskarray(x).any():
            raise DTypeError(f"{name}: masked entries have no value; fill them first (x.filled(value))")
        x = np.ma.getdata(x)
    try:
        arr = np.array(x, copy=copy) if copy else np.asarray(x)
    except (ValueError, TypeError) as exc:  # ragged nested lists, ...
        raise ShapeError(f"{name}: cannot be read as an array of shape {_shape_text(trailing)}: {exc}") from None
    kind = arr.dtype.kind
    if kind in "biu":
        arr = arr.astype(np.float64)
    elif kind == "f":
        if arr.dtype.itemsize < 4:
            arr = arr.astype(np.float32)
        elif arr.dtype.itemsize > 8:
            raise DTypeError(
                f"{name}: extended precision ({arr.dtype}) is not supported: expected float64 or float32 "
                "(convert with x.astype(np.float64))"
            )
    elif kind == "O":
        _check_objects(arr, name, check_finite)
        return _check_trailing(arr, name, trailing)
    else:
        raise DTypeError(
            f"{name}: expected real numbers (float64, float32, integers or SymPy objects), got dtype {arr.dtype}"
        )
    _check_trailing(arr, name, trailing)
    if check_finite and arr.dtype.kind == "f" and not np.isfinite(arr).all():
        bad = tuple(int(i) for i in np.argwhere(~np.isfinite(arr))[0])
        raise NonFiniteError(f"{name}: expected finite numbers, got {arr[bad]!r} at index {bad}")
    return arr


def _check_trailing(arr: np.ndarray, name: str, trailing: tuple[int, ...]) -> np.ndarray:
    nt = len(trailing)
    if arr.ndim < nt or (nt and tuple(arr.shape[arr.ndim - nt :]) != tuple(trailing)):
        raise ShapeError(f"{name}: expected shape {_shape_text(trailing)}, got shape {tuple(arr.shape)}")
    return arr


def _check_objects(arr: np.ndarray, name: str, check_finite: bool) -> None:
    """Entries of an object array: real numbers (finite if ``check_finite``) or SymPy expressions."""
    for k, x in enumerate(arr.flat):
        if isinstance(x, (bool, np.bool_)) or not (isinstance(x, numbers.Real) or _is_sympy(x)):
            idx = tuple(int(i) for i in np.unravel_index(k, arr.shape))
            raise DTypeError(f"{name}: expected real numbers or SymPy expressions, got {type(x).__name__} "
                             f"{_short(x)} at index {idx}")
        if check_finite:
            value = numeric_value(x)
            if value is not None and not math.isfinite(value):
                idx = tuple(int(i) for i in np.unravel_index(k, arr.shape))
                raise NonFiniteError(f"{name}: expected finite numbers, got {_short(x)} at index {idx}")


def _is_sympy(x: object) -> bool:
    return hasattr(x, "free_symbols") and hasattr(x, "evalf")


def _short(x: object) -> str:
    text = repr(x)
    return text if len(text) <= 60 else text[:57] + "..."


def numeric_value(x: object) -> float | None:
    """``x`` as a float when it is a number (a SymPy number included), ``None`` when it is symbolic."""
    if _is_sympy(x):
        if getattr(x, "free_symbols", None):
            return None
        try:
            return float(x)  # type: ignore[arg-type]
        except (TypeError, ValueError):  # e.g. zoo, nan or a complex SymPy number
            return math.nan
    try:
        return float(x)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        return math.nan


def as_scalar_batch(x: Any, name: str, *, check_finite: bool = True) -> np.ndarray:
    """A scalar or an array of scalars (batch shape only), e.g. a mass or an angle."""
    return as_array(x, name, (), check_finite=check_finite)


def result_dtype(*arrays: np.ndarray) -> np.dtype:
    """The dtype of a computation on ``arrays``: object wins, then numpy promotion."""
    if any(a.dtype.kind == "O" for a in arrays):
        return np.dtype(object)
    return np.result_type(*arrays)


def readonly(arr: np.ndarray) -> np.ndarray:
    """Mark ``arr`` (which the caller owns) read-only and return it."""
    arr.setflags(write=False)  # (cheaper than ``arr.flags.writeable = False``, which builds a flags object)
    return arr


def check_rotation(rotation: np.ndarray, name: str, tol: float | None = None) -> None:
    """Raise :class:`RotationError` unless every ``(..., 3, 3)`` matrix is in SO(3).

    Checks ``max |RᵀR − 1| <= tol`` and ``det R > 0``. The default tolerance is
    1e-6 for float64 (URDF files print rotations to ~7 digits) and 1e-4 for
    float32. Object (SymPy) arrays are not checked.
    """
    from ..errors import RotationError

    if rotation.dtype.kind == "O":
        return
    if tol is None:
        tol = ROTATION_ORTHONORMAL.of(rotation.dtype)
    rtr = np.swapaxes(rotation, -1, -2) @ rotation
    err = np.abs(rtr - np.eye(3, dtype=rotation.dtype)).max(axis=(-2, -1))
    if np.any(err > tol):
        idx = tuple(int(i) for i in np.argwhere(err > tol)[0]) if err.ndim else ()
        where = f" at batch index {idx}" if idx else ""
        raise RotationError(
            f"{name}: expected a rotation matrix (orthonormal, det +1); "
            f"max |RᵀR − 1| = {float(err[idx]):.3g} > tolerance {tol:g}{where}"
        )
    det = np.linalg.det(rotation)
    if np.any(det <= 0):
        idx = tuple(int(i) for i in np.argwhere(det <= 0)[0]) if np.ndim(det) else ()
        where = f" at batch index {idx}" if idx else ""
        raise RotationError(
            f"{name}: expected a proper rotation (det +1), got det = {float(det[idx]):.3g}{where} "
            "(a reflection: check for a flipped axis)"
        )
