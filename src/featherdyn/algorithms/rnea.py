"""Inverse dynamics by the Recursive Newton–Euler Algorithm, and its special cases.

RNEA (chapter §8.1, appendix F.5; RBDA table 5.1), gravity entered as a base
acceleration ``a₀ = −g``::

    v_i = X_up[i] v_λ(i) + S_i q̇_i
    a_i = X_up[i] a_λ(i) + S_i q̈_i + v_i × S_i q̇_i
    f_i = I_i a_i + v_i ×* I_i v_i − f_i^ext
    τ_i = S_iᵀ f_i,        f_λ(i) += X_up[i]ᵀ f_i      (i = nb−1 … 0)
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validation import as_array, result_dtype
from ..engine import _fast
from ..errors import ShapeError
from ..model import Model
from ..spatial_algebra import SpatialForce, SpatialMotion, cross_force, cross_motion
from ._common import TreeData, check_state, select_backend, zeros

__all__ = ["rnea", "nonlinear_effects", "generalized_gravity"]


def _f_ext(model: Model, f_ext: Any) -> np.ndarray | None:
    if f_ext is None:
        return None
    arr = as_array(f_ext, "f_ext")
    if arr.ndim < 2 or arr.shape[-2:] != (model.nbodies, 6):
        raise ShapeError(
            f"f_ext: expected shape (..., nb={model.nbodies}, 6) of body-frame spatial forces [n; f], "
            f"got shape {tuple(arr.shape)}"
        )
    return arr


def _batch_with_f_ext(batch: tuple[int, ...], fx: np.ndarray | None) -> tuple[int, ...]:
    """The batch shape of the state broadcast with that of ``f_ext`` `(..., nb, 6)`."""
    if fx is None:
        return batch
    try:
        return np.broadcast_shapes(batch, fx.shape[:-2])
    except ValueError:
        raise ShapeError(
            f"f_ext: batch shape {tuple(fx.shape[:-2])} (shape {tuple(fx.shape)}) does not broadcast with "
            f"the batch shape {tuple(batch)} of the state"
        ) from None


def rnea(model: Model, q: Any, v: Any, a: Any, f_ext: Any = None, *, gravity: bool = True,
         backend: str | None = None) -> np.ndarray:
    """Joint forces ``τ`` `(..., nv)` that produce accelerations ``a`` in state ``(q, v)``.

    Args:
        model: the tree (gravity from ``model.gravity``).
        q: `(..., nq)`; v, a: `(..., nv)`.
        f_ext: optional `(..., nb, 6)` external spatial forces ``[n; f]`` on each
            body, in body coordinates (Pinocchio's ``fext`` in LOCAL frames).
        gravity: set ``False`` to leave gravity out.

    ::

        τ = M(q) q̈ + C(q, q̇) q̇ + g(q) − Σ_i J_iᵀ f_i^ext
    """
    fast = _fast.path(model, backend)
    # one float64 state: the checked kernel validates and computes (see engine/_fast.py)
    if fast is not None and f_ext is None:
        tau = _fast._EMPTY(fast.nv)
        try:
            if fast.rnea(fast.MD, q, v, a, gravity, tau) == 0:
                return tau
        except (TypeError, ValueError):  # Numba refuses the argument types
            pass
    fx = _f_ext(model, f_ext)
    st = check_state(model, q, v=v, a=a)
    dtype = st.dtype if fx is None else result_dtype(np.empty(0, st.dtype), fx)
    batch = _batch_with_f_ext(st.batch, fx)
    if select_backend(backend, dtype) == "compiled":
        from ..engine import _dispatch

        return _dispatch.rnea(model, st.q, st.arrays["v"], st.arrays["a"], fx, gravity, dtype)
    td = TreeData(model, dtype)
    qd, qdd = st.arrays["v"], st.arrays["a"]
    a0 = td.a0 if gravity else SpatialMotion._wrap(np.zeros(6, dtype=td.dtype), None)

    X_up: list = []
    vel: list[SpatialMotion] = []
    acc: list[SpatialMotion] = []
    f: list[SpatialForce] = []
    for i in range(td.nb):
        lam = td.parents[i]
        X_up.append(td.pose_in_parent(st.q, i).inverse())
        vJ = td.vJ(qd, i)
        v_i = vJ if lam == -1 else X_up[i].apply(vel[lam]) + vJ
        a_i = X_up[i].apply(a0 if lam == -1 else acc[lam]) + td.vJ(qdd, i) + cross_motion(v_i, vJ)
        f_i = td.I[i] @ a_i + cross_force(v_i, td.I[i] @ v_i)
        if fx is not None:
            f_i = f_i - SpatialForce._wrap(fx[..., i, :], None)
        vel.append(v_i)
        acc.append(a_i)
        f.append(f_i)

    tau = zeros(batch, (model.nv,), td.dtype)
    for i in range(td.nb - 1, -1, -1):
        lam = td.parents[i]
        tau[..., model.idx_v[i] : model.idx_v[i] + model.nvs[i]] = f[i].vector @ td.S[i]
        if lam != -1:
            f[lam] = f[lam] + X_up[i].apply_inverse(f[i])
    return tau


def nonlinear_effects(model: Model, q: Any, v: Any, *, backend: str | None = None) -> np.ndarray:
    """Coriolis, centrifugal and gravity forces `(..., nv)`::

        h(q, q̇) = C(q, q̇) q̇ + g(q) = RNEA(q, q̇, 0)
    """
    fast = _fast.path(model, backend)
    if fast is not None:
        h = _fast._EMPTY(fast.nv)
        try:
            if fast.nle(fast.MD, q, v, h) == 0:
                return h
        except (TypeError, ValueError):  # Numba refuses the argument types
            pass
    st = check_state(model, q, v=v)
    zero = np.zeros(st.arrays["v"].shape, dtype=st.arrays["v"].dtype)
    return rnea(model, st.q, st.arrays["v"], zero, backend=backend)


def generalized_gravity(model: Model, q: Any, *, backend: str | None = None) -> np.ndarray:
    """Gravity forces `(..., nv)`::

        g(q) = RNEA(q, 0, 0)
    """
    fast = _fast.path(model, backend)
    if fast is not None:
        g = _fast._EMPTY(fast.nv)
        try:
            if fast.gravity(fast.MD, q, g) == 0:
                return g
        except (TypeError, ValueError):  # Numba refuses the argument types
            pass
    st = check_state(model, q)
    zero = np.zeros(st.q.shape[:-1] + (model.nv,), dtype=st.dtype)
    return rnea(model, st.q, zero, zero, backend=backend)
