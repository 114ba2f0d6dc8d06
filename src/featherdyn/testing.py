"""Tolerances and comparisons shared by the test suite and the verification tool.

One place decides how close is close enough, by dtype, so that a float32
computation is never held to float64's standard and a float64 one is never let
off with float32's. A comparison that fails says *which* quantity, *where*
(robot, batch, convention) and at *which* index the error was worst::

    assert_close(tau, tau_pin, "rnea tau", where="robot 'panda'")
    # AssertionError: rnea tau (robot 'panda'): max |actual − expected| = 3.1e-07
    #   at index (4,): actual 1.2500003, expected 1.25; allowed 1e-10 + 1e-10·|expected| (float64)

The test is elementwise, ``|actual − expected| <= atol·scale + rtol·|expected|``
(the rule of :func:`numpy.isclose`, with the absolute part scaled by the typical
magnitude of the operands when the caller gives one). Matching infinities
compare equal; NaN never does.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .tolerances import COMPARISON

__all__ = ["TOLERANCES", "tolerance", "comparison_dtype", "max_error", "assert_close"]

#: ``(rtol, atol)`` by dtype name (defined in :mod:`featherdyn.tolerances`).
TOLERANCES = COMPARISON


def tolerance(dtype: Any = np.float64) -> tuple[float, float]:
    """The ``(rtol, atol)`` pair for comparing results computed in ``dtype``.

    Args:
        dtype: anything :class:`numpy.dtype` accepts. Object arrays (SymPy
            expressions evaluated to numbers) and integers use float64's pair;
            complex types use the pair of their real component.

    Returns:
        ``(rtol, atol)``, e.g. ``(1e-10, 1e-10)`` for float64 and
        ``(1e-4, 1e-4)`` for float32.
    """
    dt = np.dtype(dtype)
    if dt.kind == "c":
        dt = np.empty(0, dtype=dt).real.dtype
    return TOLERANCES.get(dt.name, TOLERANCES["float64"])


def comparison_dtype(*arrays: Any) -> np.dtype:
    """The least precise floating dtype among ``arrays`` (float64 if none is floating).

    A float32 result compared with a float64 reference is judged at float32's
    tolerance: the comparison can be no better than its weaker side.
    """
    worst = np.dtype(np.float64)
    for a in arrays:
        dt = np.asarray(a).dtype
        if dt.kind == "f" and dt.itemsize < worst.itemsize:
            worst = dt
    return worst


def _as_float(x: Any, label: str) -> np.ndarray:
    arr = np.asarray(x)
    if arr.dtype.kind == "O":  # SymPy numbers after substitution
        try:
            return arr.astype(np.float64)
        except (TypeError, ValueError) as exc:
            raise AssertionError(f"{label}: cannot be evaluated to numbers ({exc})") from None
    if arr.dtype.kind not in "biuf":
        raise AssertionError(f"{label}: expected real numbers, got dtype {arr.dtype}")
    return arr.astype(np.float64)


def max_error(actual: Any, expected: Any) -> tuple[float, tuple[int, ...]]:
    """The largest elementwise ``|actual − expected|`` and its index (after broadcasting).

    Matching infinities count as error 0; a NaN on either side counts as
    infinite error. Empty arrays give ``(0.0, ())``.
    """
    a, e = np.broadcast_arrays(_as_float(actual, "actual"), _as_float(expected, "expected"))
    if a.size == 0:
        return 0.0, ()
    with np.errstate(invalid="ignore"):
        err = np.abs(a - e)
    err = np.where((a == e), 0.0, err)  # inf == inf
    err = np.where(np.isnan(err), np.inf, err)
    idx = tuple(int(i) for i in np.unravel_index(int(np.argmax(err)), err.shape))
    return float(err[idx]), idx


def assert_close(
    actual: Any,
    expected: Any,
    quantity: str,
    *,
    dtype: Any = None,
    where: str | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    scale: float = 1.0,
) -> None:
    """Raise :class:`AssertionError` unless ``actual`` matches ``expected`` elementwise.

    Args:
        actual: the computed array (or anything :func:`numpy.asarray` accepts;
            object arrays must hold numbers).
        expected: the reference, of exactly the same shape (no broadcasting: a
            silent broadcast hides a missing batch axis).
        quantity: what is compared, for the message (``"X* f"``, ``"rnea tau"``).
        dtype: the dtype whose tolerance applies; default the least precise
            floating dtype of the two operands (:func:`comparison_dtype`).
        where: optional context for the message (robot, batch shape, convention).
        rtol, atol: override the dtype's pair from :func:`tolerance`.
        scale: typical magnitude of the operands; the absolute tolerance is
            multiplied by it (use it when the expected value is ~0 but is
            computed from terms of size ``scale``).

    The elementwise test::

        |actual − expected| <= atol·scale + rtol·|expected|
    """
    label = quantity + (f" ({where})" if where else "")
    a_shape, e_shape = np.shape(actual), np.shape(expected)
    if a_shape != e_shape:
        raise AssertionError(f"{label}: shape mismatch, actual {a_shape} vs expected {e_shape}")
    dt = np.dtype(dtype) if dtype is not None else comparison_dtype(actual, expected)
    rt, at = tolerance(dt)
    rt = rt if rtol is None else rtol
    at = (at if atol is None else atol) * scale
    a = _as_float(actual, f"{label}: actual")
    e = _as_float(expected, f"{label}: expected")
    if a.size == 0:
        return
    with np.errstate(invalid="ignore"):
        err = np.abs(a - e)
        bound = at + rt * np.abs(e)
        bad = ~((a == e) | (err <= bound))  # a == e covers matching infinities
    if not np.any(bad):
        return
    excess = np.where(bad, np.where(np.isnan(err), np.inf, err), -np.inf)
    idx = tuple(int(i) for i in np.unravel_index(int(np.argmax(excess)), excess.shape))
    n_bad = int(np.count_nonzero(bad))
    raise AssertionError(
        f"{label}: max |actual − expected| = {float(err[idx]):.3g} at index {idx}: "
        f"actual {float(a[idx]):.10g}, expected {float(e[idx]):.10g}; allowed {at:.3g} + {rt:.3g}·|expected| ({dt.name}); "
        f"{n_bad} of {a.size} elements out of tolerance"
    )
