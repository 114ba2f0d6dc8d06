"""The reference algorithms: batched NumPy, dtype-generic, written like the book (one algorithm per file)."""

from __future__ import annotations

from ._common import LOCAL, LOCAL_WORLD_ALIGNED, WORLD, ReferenceFrame
from .aba import aba
from .centroidal import centroidal_momentum, centroidal_momentum_matrix
from .coriolis import coriolis_matrix
from .crba import crba
from .energy import CenterOfMass, center_of_mass, kinetic_energy, potential_energy
from .jacobians import frame_jacobian, frame_jacobian_time_variation, joint_jacobians
from .kinematics import (
    Kinematics,
    forward_kinematics,
    frame_acceleration,
    frame_classical_acceleration,
    frame_placement,
    frame_velocity,
)
from .rnea import generalized_gravity, nonlinear_effects, rnea

__all__ = [
    "LOCAL",
    "LOCAL_WORLD_ALIGNED",
    "WORLD",
    "ReferenceFrame",
    "aba",
    "centroidal_momentum",
    "centroidal_momentum_matrix",
    "coriolis_matrix",
    "crba",
    "CenterOfMass",
    "center_of_mass",
    "kinetic_energy",
    "potential_energy",
    "frame_jacobian",
    "frame_jacobian_time_variation",
    "joint_jacobians",
    "Kinematics",
    "forward_kinematics",
    "frame_acceleration",
    "frame_classical_acceleration",
    "frame_placement",
    "frame_velocity",
    "generalized_gravity",
    "nonlinear_effects",
    "rnea",
]
