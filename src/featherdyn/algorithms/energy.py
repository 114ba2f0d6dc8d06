"""Energies and the centre of mass.

::

    T = Σ_i ½ v_iᵀ I_i v_i          U = −Σ_i m_i gᵀ ⁰c_i          c = Σ_i m_i ⁰c_i / Σ_i m_i

(``⁰c_i`` is body ``i``'s centre of mass in world coordinates.)
"""

from __future__ import annotations

import numpy as np

from ..errors import ModelError
from ..model import Model
from ..results import CenterOfMass, Kinematics
from ..spatial.ops import cross3
from ._common import TreeData, zeros
from .crba import crba
from .derivatives import rnea_partials
from .kinematics import body_at, forward_kinematics, motion_at

__all__ = ["kinetic_energy", "kinetic_energy_at", "kinetic_energy_derivatives_at", "potential_energy",
           "potential_energy_at", "center_of_mass"]


def kinetic_energy(model: Model, kin: Kinematics, qd: np.ndarray | None = None) -> np.ndarray:
    """Kinetic energy `(...)` from the body velocities of ``kin`` and the joint velocities ``qd`` `(..., nv)`::

        T = Σ_i ½ v_iᵀ I_i v_i + ½ Σ_k armature_k q̇_k² = ½ q̇ᵀ M(q) q̇

    The rotors' term (the armature, M's diagonal addition) needs ``qd``; as
    Pinocchio's ``computeKineticEnergy`` and MuJoCo's energy.
    """
    assert kin.velocities is not None
    td = TreeData(model, kin.placements.dtype)
    T = zeros(kin.placements.shape[:-1], (), td.dtype)
    for i in range(model.nbodies):
        T = T + td.I[i].kinetic_energy(motion_at(kin.velocities, i))
    arm = model.armature
    if qd is not None and arm is not None and np.any(arm != 0):
        for k in np.flatnonzero(arm):  # (a loop: SymPy object arrays too)
            T = T + 0.5 * arm[k] * qd[..., k] * qd[..., k]
    return T


def _world_coms(model: Model, kin: Kinematics, td: TreeData) -> list[np.ndarray]:
    out = []
    for i in range(model.nbodies):
        oM = body_at(kin.placements, i)
        out.append((oM.rotation @ td.I[i].com[..., None])[..., 0] + oM.translation)
    return out


def potential_energy(model: Model, kin: Kinematics) -> np.ndarray:
    """Gravitational potential energy `(...)` (zero at the world origin)::

        U = −Σ_i m_i gᵀ ⁰c_i
    """
    td = TreeData(model, kin.placements.dtype)
    g = model.gravity.astype(td.dtype)
    U = np.zeros(kin.placements.shape[:-1], dtype=td.dtype)
    for i, c in enumerate(_world_coms(model, kin, td)):
        U = U - td.I[i].mass * (c * g).sum(axis=-1)
    return U


def center_of_mass(model: Model, kin: Kinematics) -> np.ndarray | CenterOfMass:
    """The centre of mass of the whole tree in world coordinates, from the placements of ``kin``.

    Returns:
        ``c`` `(..., 3)` when ``kin`` has no velocities; else a :class:`CenterOfMass`
        ``(position, velocity)``::

            c = Σ m_i ⁰c_i / m,    ċ = Σ m_i ⁰R_i (v_i + ω_i × c_i) / m

    Raises:
        ModelError: the tree has no mass (the centre of mass is undefined).
    """
    td = TreeData(model, kin.placements.dtype)
    batch = kin.placements.shape[:-1]
    m = model.total_mass
    if not m > 0:
        raise ModelError.no_mass(model.name)
    pos = np.zeros(batch + (3,), dtype=td.dtype)
    for i, c in enumerate(_world_coms(model, kin, td)):
        pos = pos + td.I[i].mass * c
    pos = pos / m
    if kin.velocities is None:
        return pos
    vel = np.zeros(batch + (3,), dtype=td.dtype)
    for i in range(model.nbodies):
        vi = motion_at(kin.velocities, i)
        v_com_body = vi.linear + cross3(vi.angular, td.I[i].com)
        vel = vel + td.I[i].mass * (body_at(kin.placements, i).rotation @ v_com_body[..., None])[..., 0]
    return CenterOfMass(pos, vel / m)


def kinetic_energy_at(model: Model, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """:func:`kinetic_energy` at the state ``(q, q̇)`` `(...)` (public: :func:`featherdyn.kinetic_energy`)."""
    return kinetic_energy(model, forward_kinematics(model, q, qd), qd)


def kinetic_energy_derivatives_at(model: Model, q: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(∂T/∂q, ∂T/∂q̇)`` `(..., nv)` each (public: :func:`featherdyn.kinetic_energy_derivatives`), from RNEA's
    derivatives at rest: ``M(q) q̇ = RNEA(q, 0, q̇)`` without gravity, so::

        ∂T/∂q = ½ q̇ᵀ ∂(M q̇)/∂q = ½ q̇ᵀ (∂τ/∂q)(q, 0, q̇),     ∂T/∂q̇ = M q̇

    (the compiled kernel's O(nb) recursion is a different derivation of the same numbers; ∂/∂q along
    ``fd.integrate``'s tangent)."""
    dq = rnea_partials(model, q, qd * 0, qd, None, False)[0]
    return 0.5 * np.einsum("...i,...ik->...k", qd, dq), np.einsum("...ij,...j->...i", crba(model, q), qd)


def potential_energy_at(model: Model, q: np.ndarray) -> np.ndarray:
    """:func:`potential_energy` at ``q`` `(...)` (public: :func:`featherdyn.potential_energy`)."""
    return potential_energy(model, forward_kinematics(model, q))


def center_of_mass_at(model: Model, q: np.ndarray, qd: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray | None]:
    """``(c, ċ)`` `(..., 3)` of the state (``ċ`` ``None`` without ``qd``): :func:`center_of_mass` of its
    kinematics, the declaration's reference."""
    com = center_of_mass(model, forward_kinematics(model, q, qd))
    return (com.position, com.velocity) if isinstance(com, CenterOfMass) else (com, None)
