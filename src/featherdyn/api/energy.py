"""The public whole-body quantities: energies, centre of mass, centroidal momentum.

Float64 input: the compiled core's kernels (``core/cpp/energy.hpp``,
``centroidal.hpp``); otherwise (or ``backend="reference"``) the forward
kinematics and the reference formulas of ``algorithms/energy.py`` and
``algorithms/centroidal.py``.
"""

from __future__ import annotations

from .declarations import (
    center_of_mass,
    centroidal_momentum,
    centroidal_momentum_matrix,
    kinetic_energy,
    kinetic_energy_derivatives,
    potential_energy,
)

__all__ = ["kinetic_energy", "kinetic_energy_derivatives", "potential_energy", "center_of_mass", "centroidal_momentum_matrix",
           "centroidal_momentum"]
