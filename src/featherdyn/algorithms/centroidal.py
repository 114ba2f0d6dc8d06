"""Centroidal momentum and the centroidal momentum matrix (Orin & Goswami 2008).

The momentum of the whole tree about its centre of mass ``c``, in world axes,
as a force vector ``h_G = [k_G; p]`` (angular first)::

    h_O = Σ_i ⁰X_i^* I_i v_i = A_O q̇,    A_O[:, k] = ⁰I^C_k ⁰X_k S_k
    h_G = [k_O − c × p;  p] = A_G q̇

(``⁰I^C_k``: the world-frame composite inertia of the subtree of ``k``.)
Pinocchio's ``computeCentroidalMomentum`` / ``ccrba`` give the same with
linear first.
"""

from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..model import Model
from ..results import Kinematics
from ..spatial import SpatialForce, SpatialMotion
from ..spatial.ops import cross3
from ._common import TreeData, expand_inertia
from .energy import center_of_mass
from .jacobians import world_columns
from .kinematics import body_at, forward_kinematics

__all__ = ["centroidal_momentum_matrix", "centroidal_momentum_matrix_at", "centroidal_momentum"]


def _shift_to_com(h: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Move force vectors `(..., 6)` from the world origin to the point ``c`` (world axes)."""
    return np.concatenate([h[..., :3] - cross3(c, h[..., 3:]), h[..., 3:]], axis=-1)


def centroidal_momentum_matrix(model: Model, kin: Kinematics) -> np.ndarray:
    """``A_G(q)`` `(..., 6, nv)` with ``h_G = A_G q̇`` (rows ``[k_G; p]``, world axes, about the CoM).

    ``kin`` holds the placements at ``q`` (velocities are not used).
    """
    batch = kin.placements.shape[:-1]
    td = TreeData(model, kin.placements.dtype)
    IC = [body_at(kin.placements, i).apply(td.I[i]) for i in range(model.nbodies)]
    for i in range(model.nbodies - 1, -1, -1):
        if model.parents[i] != -1:
            IC[model.parents[i]] = IC[model.parents[i]] + IC[i]
    cols = world_columns(model, td, kin.placements, batch)  # (..., nv, 6)
    A = np.zeros_like(cols) if cols.dtype.kind != "O" else cols.copy()
    for k in range(model.nbodies):
        sk = slice(model.idx_v[k], model.idx_v[k] + model.nvs[k])
        A[..., sk, :] = (expand_inertia(IC[k]) @ SpatialMotion._wrap(cols[..., sk, :], None)).vector
    c = center_of_mass(model, Kinematics(model, kin.placements, None, None, kin.parent_placements))
    assert isinstance(c, np.ndarray)
    return np.swapaxes(_shift_to_com(A, c[..., None, :]), -1, -2)


def centroidal_momentum_matrix_at(model: Model, q: np.ndarray) -> np.ndarray:
    """:func:`centroidal_momentum_matrix` at ``q`` `(..., 6, nv)` (public: :func:`featherdyn.centroidal_momentum_matrix`).

    Raises:
        ModelError: the tree has no mass (the centre of mass is undefined).
    """
    if not model.total_mass > 0:
        raise ModelError.no_mass(model.name)
    return centroidal_momentum_matrix(model, forward_kinematics(model, q))


def centroidal_momentum(model: Model, kin: Kinematics, qd: np.ndarray) -> SpatialForce:
    """The centroidal momentum ``h_G = [k_G; p]`` `(..., 6)` as a :class:`SpatialForce`.

    ::

        h_G = A_G(q) q̇     (p = m ċ)
    """
    A = centroidal_momentum_matrix(model, kin)
    return SpatialForce._wrap((A @ qd[..., None])[..., 0], None)


def centroidal_momentum_at(model: Model, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """``h_G = A_G(q) q̇`` `(..., 6)` of the state, the declaration's reference (:func:`centroidal_momentum`)."""
    return centroidal_momentum(model, forward_kinematics(model, q), qd).vector
