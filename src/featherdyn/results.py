"""Result values of the algorithms: plain frozen records of arrays and spatial values.

Both implementations (the reference in :mod:`featherdyn.algorithms` and the
compiled engine) return these, and the public functions hand them to the
caller unchanged, so they live below both, next to the model they describe.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from .model import Model
from .spatial import PluckerTransform, SpatialMotion

__all__ = ["Kinematics", "CenterOfMass"]


@dataclass(frozen=True)
class Kinematics:
    """The result of :func:`featherdyn.forward_kinematics` (body axis last among the batch axes).

    Attributes:
        placements: world placements ``⁰M_i`` of the bodies, batch shape `(..., nb)`.
        velocities: body velocities ``v_i`` in body coordinates `(..., nb, 6)` (``None`` if no ``v``).
        accelerations: spatial accelerations ``a_i`` in body coordinates `(..., nb, 6)`,
            without gravity (``None`` if no ``a``).
        parent_placements: ``ᵖM_i``, the pose of each body in its parent, `(..., nb)`.
    """

    model: Model
    placements: PluckerTransform
    velocities: SpatialMotion | None
    accelerations: SpatialMotion | None
    parent_placements: PluckerTransform


class CenterOfMass(NamedTuple):
    """Position `(..., 3)` and velocity `(..., 3)` of the centre of mass, in world coordinates."""

    position: np.ndarray
    velocity: np.ndarray
