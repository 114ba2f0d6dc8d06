"""The public dynamics functions: RNEA, its special cases, CRBA, ABA and the Coriolis matrix.

Each function checks its input (:mod:`._checks`), picks a backend
(:mod:`._backend`) and calls the reference recursion in
:mod:`featherdyn.algorithms` or the compiled core (:mod:`featherdyn.core`); one
float64 state is finished in the core (``_backend.public_call``: the
public names are objects that hand every other call to the ``_general_*``
function). The equations are in the
docstrings; the recursions are in ``algorithms/rnea.py``, ``crba.py``,
``aba.py`` and ``coriolis.py``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .. import _dask
from .. import core as _compiled
from ..algorithms import aba as _aba
from ..algorithms import coriolis as _coriolis
from ..algorithms import crba as _crba
from ..algorithms import rnea as _rnea
from ..core._model_view import CoreHandle
from ..model import Model
from ._backend import public_call, select_backend
from ._checks import State, as_dtype, batch_with_f_ext, check_f_ext, check_state, finite_result, quiet
from .kinematics import kinematics_of

__all__ = ["rnea", "nonlinear_effects", "generalized_gravity", "crba", "aba", "coriolis_matrix"]

def _inverse_dynamics(model: Model, st: State, v: np.ndarray, a: np.ndarray, fx: np.ndarray | None, gravity: bool,
                      backend: str | None) -> np.ndarray:
    """RNEA on a checked state, by the backend ``backend`` resolves to."""
    dtype = batch_with_f_ext(st, fx)[1]
    if select_backend(backend, dtype) == "compiled":
        return finite_result(as_dtype(_compiled.rnea(model, st.q, v, a, fx, gravity), dtype), "rnea")
    return finite_result(quiet(_rnea.rnea, model, st.q, v, a, fx, gravity), "rnea")


def _general_rnea(model: Model, q: ArrayLike, v: ArrayLike, a: ArrayLike, f_ext: ArrayLike | None = None, *, gravity: bool = True,
         backend: str | None = None) -> np.ndarray:
    """Joint forces ``τ`` `(..., nv)` that produce accelerations ``a`` in state ``(q, v)`` (RNEA).

    Args:
        model: the tree (gravity from ``model.gravity``).
        q: `(..., nq)`; v, a: `(..., nv)`.
        f_ext: optional `(..., nb, 6)` external spatial forces ``[n; f]`` on each
            body, in body coordinates (Pinocchio's ``fext`` in LOCAL frames).
        gravity: set ``False`` to leave gravity out.
        backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

    ::

        τ = M(q) q̈ + C(q, q̇) q̇ + g(q) − Σ_i J_iᵀ f_i^ext
    """
    if _dask.lazy(q, v, a, f_ext):
        return _dask.call(rnea, model, {"q": q, "v": v, "a": a, "f_ext": f_ext}, gravity=gravity, backend=backend)
    fx = check_f_ext(model, f_ext)
    st = check_state(model, q, v=v, a=a)
    return _inverse_dynamics(model, st, st.arrays["v"], st.arrays["a"], fx, gravity, backend)


#: one float64 state finished in the compiled core (``_backend.public_call``)
rnea = public_call("rnea", _general_rnea, (CoreHandle,))


def _general_nonlinear_effects(model: Model, q: ArrayLike, v: ArrayLike, *, backend: str | None = None) -> np.ndarray:
    """Coriolis, centrifugal and gravity forces `(..., nv)`::

        h(q, q̇) = C(q, q̇) q̇ + g(q) = RNEA(q, q̇, 0)
    """
    if _dask.lazy(q, v):
        return _dask.call(nonlinear_effects, model, {"q": q, "v": v}, backend=backend)
    st = check_state(model, q, v=v)
    qd = st.arrays["v"]
    return _inverse_dynamics(model, st, qd, np.zeros(qd.shape, dtype=qd.dtype), None, True, backend)


#: one float64 state finished in the compiled core (``_backend.public_call``)
nonlinear_effects = public_call("nonlinear_effects", _general_nonlinear_effects, (CoreHandle,))


def _general_generalized_gravity(model: Model, q: ArrayLike, *, backend: str | None = None) -> np.ndarray:
    """Gravity forces `(..., nv)`::

        g(q) = RNEA(q, 0, 0)
    """
    if _dask.lazy(q):
        return _dask.call(generalized_gravity, model, {"q": q}, backend=backend)
    st = check_state(model, q)
    zero = np.zeros(st.q.shape[:-1] + (model.nv,), dtype=st.dtype)
    return _inverse_dynamics(model, st, zero, zero, None, True, backend)


#: one float64 state finished in the compiled core (``_backend.public_call``)
generalized_gravity = public_call("generalized_gravity", _general_generalized_gravity, (CoreHandle,))


def _general_crba(model: Model, q: ArrayLike, *, backend: str | None = None) -> np.ndarray:
    """The joint-space mass matrix ``M(q)`` `(..., nv, nv)`, full and symmetric (CRBA).

    ::

        T = ½ q̇ᵀ M(q) q̇,    M_ij = S_iᵀ ⁱX_j^* I^C_j S_j   (j in the subtree of i)
    """
    if _dask.lazy(q):
        return _dask.call(crba, model, {"q": q}, backend=backend)
    st = check_state(model, q)
    if select_backend(backend, st.dtype) == "compiled":
        return finite_result(as_dtype(_compiled.crba(model, st.q), st.dtype), "crba")
    return finite_result(quiet(_crba.crba, model, st.q), "crba")


#: one float64 state finished in the compiled core (``_backend.public_call``)
crba = public_call("crba", _general_crba, (CoreHandle,))


def _general_aba(model: Model, q: ArrayLike, v: ArrayLike, tau: ArrayLike, f_ext: ArrayLike | None = None, *, gravity: bool = True,
        backend: str | None = None) -> np.ndarray:
    """Joint accelerations ``q̈`` `(..., nv)` produced by joint forces ``τ`` in state ``(q, v)`` (ABA).

    Args:
        model: the tree.
        q: `(..., nq)`; v, tau: `(..., nv)`.
        f_ext: optional `(..., nb, 6)` body-frame external forces ``[n; f]``.
        gravity: set ``False`` to leave gravity out.
        backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

    ::

        q̈ = M(q)⁻¹ (τ − C(q, q̇) q̇ − g(q) + Σ_i J_iᵀ f_i^ext)

    Raises:
        SingularMassMatrixError: naming the joint, when ``M(q)`` is singular.
    """
    if _dask.lazy(q, v, tau, f_ext):
        return _dask.call(aba, model, {"q": q, "v": v, "tau": tau, "f_ext": f_ext}, gravity=gravity, backend=backend)
    fx = check_f_ext(model, f_ext)
    st = check_state(model, q, v=v, tau=tau)
    dtype = batch_with_f_ext(st, fx)[1]
    if select_backend(backend, dtype) == "compiled":
        qdd = _compiled.aba(model, st.q, st.arrays["v"], st.arrays["tau"], fx, gravity)
        return finite_result(as_dtype(qdd, dtype), "aba")
    return finite_result(quiet(_aba.aba, model, st.q, st.arrays["v"], st.arrays["tau"], fx, gravity), "aba")


#: one float64 state finished in the compiled core (``_backend.public_call``)
aba = public_call("aba", _general_aba, (CoreHandle,))


def coriolis_matrix(model: Model, q: ArrayLike, v: ArrayLike, *, backend: str | None = None) -> np.ndarray:
    """``C(q, q̇)`` `(..., nv, nv)`: ``C q̇ = RNEA(q, q̇, 0) − g(q)`` and ``Ṁ − 2C`` is skew-symmetric.

    The Christoffel-consistent factorisation (Pinocchio's ``computeCoriolisMatrix``);
    see ``algorithms/coriolis.py``.
    """
    if _dask.lazy(q, v):
        return _dask.call(coriolis_matrix, model, {"q": q, "v": v}, backend=backend)
    st = check_state(model, q, v=v)
    return finite_result(quiet(_coriolis.coriolis_matrix, model, kinematics_of(model, st, st.arrays["v"], None, backend)),
                         "coriolis_matrix")
