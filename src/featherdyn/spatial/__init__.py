"""The spatial values: Featherstone's spatial vector algebra, one concept per module.

Motion vectors ``m = [ω; v_O]`` (M⁶) and force vectors ``f = [n_O; f]`` (F⁶)
in Featherstone's order (angular first), Plücker transforms, the spatial
cross products and the spatial rigid-body inertia; the only mixed product is
power, ``motion.dot(force) = ωᵀ n_O + vᵀ f`` (invariant under any ``X``).

The modules, each importing only the ones before it:

* :mod:`.validation` — the array checks every value makes of its input
  (shape, dtype, finiteness, rotation matrices);
* :mod:`.ops` — raw-array kernels: 3D cross products, ``skew``, the three-product
  forms of ``crm``/``crf``, broadcasting and message helpers;
* :mod:`.vectors` — ``SpatialMotion``, ``SpatialForce``, ``crm``, ``crf``, screws;
* :mod:`.inertia` — ``SpatialInertia``;
* :mod:`.transform` — ``PluckerTransform``, ``rotx`` … ``plux``;
* :mod:`.lie` — right Jacobians of the SO(3), SE(3), SE(2) exponential maps.

The chapter's module :mod:`featherdyn.spatial_algebra` re-exports the public
names below. Sources: Featherstone, *Rigid Body Dynamics Algorithms* (2008)
ch. 2; chapter §2–§5, §13 and appendices A, F, H.
"""

from __future__ import annotations

from .inertia import SpatialInertia
from .ops import skew, unskew
from .transform import PluckerTransform, plux, rotx, roty, rotz, xlt
from .vectors import Screw, SpatialForce, SpatialMotion, crf, crm, cross_force, cross_motion, screw_parameters

__all__ = [
    "SpatialMotion",
    "SpatialForce",
    "PluckerTransform",
    "SpatialInertia",
    "Screw",
    "cross_motion",
    "cross_force",
    "crm",
    "crf",
    "skew",
    "unskew",
    "screw_parameters",
    "rotx",
    "roty",
    "rotz",
    "xlt",
    "plux",
]
