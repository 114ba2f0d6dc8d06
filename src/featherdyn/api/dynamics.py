"""The public dynamics functions: RNEA, its special cases, CRBA, ABA and the Coriolis matrix.

RNEA, ``nonlinear_effects``, ``generalized_gravity``, CRBA and ABA are declared
(:mod:`.declarations`: every front end made from the declaration) and re-exported
here; the Coriolis matrix is written out below. The recursions are in
``algorithms/rnea.py``, ``crba.py``, ``aba.py`` and ``coriolis.py``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .. import _dask
from ..algorithms import coriolis as _coriolis
from ..model import Model
from ._checks import check_state, finite_result, quiet
from .declarations import aba, crba, generalized_gravity, nonlinear_effects, rnea
from .kinematics import kinematics_of

__all__ = ["rnea", "nonlinear_effects", "generalized_gravity", "crba", "aba", "coriolis_matrix"]


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
