"""Raw-array kernels of the spatial algebra: 3D cross products, ``skew``, broadcasting, messages.

Plain functions on NumPy arrays, dtype-generic (float32, float64 and object
arrays of SymPy expressions), with no knowledge of the spatial value classes;
every other module of :mod:`featherdyn.spatial` builds on them::

    [w]× x = w × x,   (a × b)_i = a_{i+1} b_{i+2} − a_{i+2} b_{i+1}

Sources: RBDA (2008) §2.4–§2.9; chapter appendix A.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .validation import as_array, result_dtype

_NEXT = np.array([1, 2, 0])
_PREV = np.array([2, 0, 1])


def cross3(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a × b`` over the last axis, broadcasting; works for object arrays.

    ::

        (a × b)_i = a_{i+1} b_{i+2} − a_{i+2} b_{i+1}     (indices mod 3)
    """
    # ndarray.take is ~3× cheaper than fancy indexing a[..., _NEXT] on small arrays (the same result)
    return a.take(_NEXT, axis=-1) * b.take(_PREV, axis=-1) - a.take(_PREV, axis=-1) * b.take(_NEXT, axis=-1)


def matvec(m: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``m @ x`` for ``(..., n, k)`` matrices and ``(..., k)`` vectors."""
    return (m @ x[..., None])[..., 0]


def matrix_transpose(m: np.ndarray) -> np.ndarray:
    """``mᵀ`` of each matrix in a batch: `(..., n, k)` → `(..., k, n)` (a view)."""
    return np.swapaxes(m, -1, -2)


def sum_last(x: np.ndarray) -> Any:
    """``Σ_i x[..., i]``: `(..., n)` → `(...)` (a scalar for a single vector)."""
    return x.sum(axis=-1)


def is_weak_scalar(x: object) -> bool:
    """A plain Python number: like NumPy (NEP 50), it takes the dtype of the arrays it meets."""
    return isinstance(x, (int, float)) and not isinstance(x, np.generic)


def adopt_dtype(raw: tuple[object, ...], arrays: list[np.ndarray]) -> list[np.ndarray]:
    """Cast the arrays made from plain Python numbers to the floating dtype of the others.

    ``as_array`` turns ``2.0`` into a float64 array, which would promote a
    float32 computation to float64; NumPy keeps ``float32_array * 2.0`` float32.
    """
    strong = [a for x, a in zip(raw, arrays, strict=True) if not is_weak_scalar(x)]
    if not strong:
        return arrays
    dtype = result_dtype(*strong)
    if dtype.kind != "f":
        return arrays
    return [a.astype(dtype) if is_weak_scalar(x) else a for x, a in zip(raw, arrays, strict=True)]


def skew(w: ArrayLike) -> np.ndarray:
    """The cross-product matrix ``[w]×`` of a 3-vector.

    Args:
        w: `(..., 3)`.

    Returns:
        `(..., 3, 3)`, with ``skew(w) @ x == w × x``::

            [w]× = [[ 0,  -w3,  w2],
                    [ w3,  0,  -w1],
                    [-w2,  w1,  0 ]]
    """
    w = as_array(w, "w", (3,))
    return skew_unchecked(w)


def skew_unchecked(w: np.ndarray) -> np.ndarray:
    """:func:`skew` of an array already checked: `(..., 3)` → `(..., 3, 3)`, ``[w]× x = w × x``; any dtype."""
    z = np.zeros_like(w[..., 0])
    x, y, zz = w[..., 0], w[..., 1], w[..., 2]
    rows = [np.stack([z, -zz, y], axis=-1), np.stack([zz, z, -x], axis=-1), np.stack([-y, x, z], axis=-1)]
    return np.stack(rows, axis=-2)


def unskew(matrix: ArrayLike) -> np.ndarray:
    """The vector ``w`` of a skew-symmetric ``[w]×`` (the "vee" map; inverse of :func:`skew`).

    Args:
        matrix: `(..., 3, 3)`; only its skew-symmetric part is used.

    Returns:
        `(..., 3)`::

            w = ½ (S32 − S23, S13 − S31, S21 − S12)
    """
    s = as_array(matrix, "matrix", (3, 3))
    return unskew_unchecked(s)


def unskew_unchecked(s: np.ndarray) -> np.ndarray:
    """:func:`unskew` of an array already checked: `(..., 3, 3)` → `(..., 3)`, ``w = ½ (S32 − S23, S13 − S31, S21 − S12)``."""
    return np.stack(
        [(s[..., 2, 1] - s[..., 1, 2]) / 2, (s[..., 0, 2] - s[..., 2, 0]) / 2, (s[..., 1, 0] - s[..., 0, 1]) / 2],
        axis=-1,
    )


# the three 3D cross products of each spatial one, gathered so one vectorised call does them all
_CRM_A, _CRM_B = np.array([0, 1, 2, 0, 1, 2, 3, 4, 5]), np.array([0, 1, 2, 3, 4, 5, 0, 1, 2])
_CRF_A, _CRF_B = np.array([0, 1, 2, 3, 4, 5, 0, 1, 2]), np.array([0, 1, 2, 3, 4, 5, 3, 4, 5])


def crm_apply(v: np.ndarray, m: np.ndarray) -> np.ndarray:
    """``[ω × m_ω;  ω × m_v + v × m_ω]`` via the three products (ω×m_ω, ω×m_v, v×m_ω)."""
    c = cross3(v[..., _CRM_A].reshape(v.shape[:-1] + (3, 3)), m[..., _CRM_B].reshape(m.shape[:-1] + (3, 3)))
    return np.concatenate([c[..., 0, :], c[..., 1, :] + c[..., 2, :]], axis=-1)


def crf_apply(v: np.ndarray, f: np.ndarray) -> np.ndarray:
    """``[ω × n + v × f;  ω × f]`` via the three products (ω×n, v×f, ω×f)."""
    c = cross3(v[..., _CRF_A].reshape(v.shape[:-1] + (3, 3)), f[..., _CRF_B].reshape(f.shape[:-1] + (3, 3)))
    return np.concatenate([c[..., 0, :] + c[..., 1, :], c[..., 2, :]], axis=-1)


def broadcast_batch(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``a`` `(..., n)` and ``b`` `(..., k)` broadcast to their common batch shape (read-only views; trailing axes kept)."""
    if a.shape[:-1] == b.shape[:-1]:
        return a, b
    shape = np.broadcast_shapes(a.shape[:-1], b.shape[:-1])
    return np.broadcast_to(a, shape + a.shape[-1:]), np.broadcast_to(b, shape + b.shape[-1:])


def broadcast_rotation_translation(rot: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``E`` `(..., 3, 3)` and ``r`` `(..., 3)` broadcast to their common batch shape, as fresh writable arrays."""
    shape = np.broadcast_shapes(rot.shape[:-2], p.shape[:-1])
    return np.array(np.broadcast_to(rot, shape + (3, 3))), np.array(np.broadcast_to(p, shape + (3,)))


def batch_index(vec: np.ndarray, idx: Any, trailing: int) -> Any:
    """``idx`` as a tuple that indexes only the batch axes of ``vec`` (its last ``trailing`` axes are the value's).

    Raises:
        IndexError: an Ellipsis, or more indices than batch axes.
    """
    if not isinstance(idx, tuple):
        idx = (idx,)
    if any(i is Ellipsis for i in idx):
        raise IndexError("spatial values index their batch axes only; Ellipsis is not supported")
    if len(idx) > vec.ndim - trailing:
        raise IndexError(f"too many indices for batch shape {vec.shape[: vec.ndim - trailing]}")
    return idx


# --------------------------------------------------------------------------
# messages and reprs
# --------------------------------------------------------------------------


def type_name(x: object) -> str:
    """The class name of ``x`` for error messages (``"numpy.ndarray"`` for an array)."""
    return type(x).__name__ if not isinstance(x, np.ndarray) else "numpy.ndarray"


def raw_vector_hint(cls_name: str) -> str:
    """The sentence an error adds when a raw array was given where a ``cls_name`` value is expected."""
    return (
        f"wrap raw 6-vectors explicitly with {cls_name}.from_vector(x) (Featherstone order, angular first) "
        "so that the type (motion or force) and the order are stated"
    )


def format_array(a: np.ndarray) -> str:
    """``a`` printed for a repr or a message: 6 digits, at most 20 entries in full."""
    return np.array2string(np.asarray(a), precision=6, separator=", ", threshold=20)


def format_tags(obj: object) -> str:
    """``", frame=..., body=..."`` for the tags of a spatial value that are set (its repr's tail)."""
    out = []
    for name in ("frame", "body", "relative_to", "source", "target"):
        val = getattr(obj, name, None)
        if val is not None:
            out.append(f", {name}={val!r}")
    return "".join(out)
