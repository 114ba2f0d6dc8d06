"""The public whole-body quantities: energies, centre of mass, centroidal momentum.

Float64 input: the compiled core's kernels (``core/cpp/energy.hpp``,
``centroidal.hpp``); otherwise (or ``backend="reference"``) the forward
kinematics and the reference formulas of ``algorithms/energy.py`` and
``algorithms/centroidal.py``.
"""

from __future__ import annotations

from typing import overload

import numpy as np
from numpy.typing import ArrayLike

from .. import _dask
from .. import core as _compiled
from ..algorithms import centroidal as _centroidal
from ..algorithms import energy as _energy
from ..model import Model
from ..results import CenterOfMass
from ..spatial_algebra import SpatialForce
from ._backend import select_backend
from ._checks import as_dtype, check_state, finite_result, quiet
from .declarations import centroidal_momentum_matrix, kinetic_energy, potential_energy
from .kinematics import kinematics_of

__all__ = ["kinetic_energy", "potential_energy", "center_of_mass", "centroidal_momentum_matrix",
           "centroidal_momentum"]


@overload
def center_of_mass(model: Model, q: ArrayLike, v: None = None, *, backend: str | None = None) -> np.ndarray: ...
@overload
def center_of_mass(model: Model, q: ArrayLike, v: ArrayLike, *, backend: str | None = None) -> CenterOfMass: ...
def center_of_mass(model: Model, q: ArrayLike, v: ArrayLike | None = None, *, backend: str | None = None) -> np.ndarray | CenterOfMass:
    """The centre of mass of the whole tree in world coordinates.

    Returns:
        ``c`` `(..., 3)` without ``v``; with ``v`` a :class:`~featherdyn.CenterOfMass`
        ``(position, velocity)``::

            c = Σ m_i ⁰c_i / m,    ċ = Σ m_i ⁰R_i (v_i + ω_i × c_i) / m

    Raises:
        ModelError: the tree has no mass (the centre of mass is undefined).
    """
    if _dask.lazy(q, v):
        return _dask.call(center_of_mass, model, {"q": q, "v": v}, backend=backend)
    st = check_state(model, q, optional=("v",), v=v)
    if select_backend(backend, st.dtype) == "compiled":
        qd = st.arrays.get("v")
        if qd is None:
            return as_dtype(_compiled.center_of_mass(model, st.q), st.dtype)  # type: ignore[arg-type]
        c, cd = _compiled.center_of_mass(model, st.q, qd)
        return CenterOfMass(as_dtype(c, st.dtype), as_dtype(cd, st.dtype))
    com = quiet(_energy.center_of_mass, model, kinematics_of(model, st, st.arrays.get("v"), None, backend))
    for part in (com if isinstance(com, CenterOfMass) else (com,)):
        finite_result(part, "center_of_mass")
    return com


def centroidal_momentum(model: Model, q: ArrayLike, v: ArrayLike, *, backend: str | None = None) -> SpatialForce:
    """The centroidal momentum ``h_G = [k_G; p]`` `(..., 6)` as a :class:`SpatialForce`.

    ::

        h_G = A_G(q) q̇     (p = m ċ)
    """
    if _dask.lazy(q, v):
        return _dask.call(centroidal_momentum, model, {"q": q, "v": v}, backend=backend)
    st = check_state(model, q, v=v)
    if select_backend(backend, st.dtype) == "compiled":
        return SpatialForce._wrap(as_dtype(_compiled.centroidal_momentum(model, st.q, st.arrays["v"]), st.dtype), None)
    h = quiet(_centroidal.centroidal_momentum, model, kinematics_of(model, st, None, None, backend), st.arrays["v"])
    finite_result(h.vector, "centroidal_momentum")
    return h
