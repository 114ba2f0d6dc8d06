"""Spatial vector algebra: the chapter's ``spatial_algebra.py``.

Motion vectors ``m = [ω; v_O]`` (M⁶) and force vectors ``f = [n_O; f]`` (F⁶)
in Featherstone's order (angular first), Plücker transforms, the spatial
cross products and the spatial rigid-body inertia. Everything broadcasts over
leading batch axes and keeps the dtype it is given (float64, float32, or
object arrays of SymPy expressions).

The classes exist for type safety: a motion and a force never add, a force is
never moved with the motion transform, and the only mixed product is power::

    motion.dot(force) = ωᵀ n_O + vᵀ f         (invariant under any X)

Sources: Featherstone, *Rigid Body Dynamics Algorithms* (2008) ch. 2;
chapter §2–§5, §13 and appendices A, F, H.
The code lives in the package :mod:`featherdyn.spatial`, one concept per
module (``ops``, ``vectors``, ``inertia``, ``transform``); this module keeps
the chapter's address for its public names, ``featherdyn.spatial_algebra.NAME``.
"""

from __future__ import annotations

from .spatial import (
    PluckerTransform,
    Screw,
    SpatialForce,
    SpatialInertia,
    SpatialMotion,
    crf,
    crm,
    cross_force,
    cross_motion,
    plux,
    rotx,
    roty,
    rotz,
    screw_parameters,
    skew,
    unskew,
    xlt,
)

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
