"""featherdyn: spatial vector algebra and rigid-body dynamics in Featherstone's notation.

Public names are flat (``fd.SpatialMotion``, ``fd.PluckerTransform``, ...);
see ``shared/DESIGN.md`` for the conventions: 6D motion vectors are
``[ω; v]`` (angular first), forces ``[n; f]``, ``PluckerTransform(R, p)`` is
the pose of frame A in frame B and maps A-coordinates to B-coordinates.
"""

from __future__ import annotations

from . import errors, frames, rotation, spatial_algebra
from .errors import (
    DTypeError,
    FeatherdynError,
    FrameMismatchError,
    InertiaError,
    ModelError,
    NonFiniteError,
    PhysicalityWarning,
    QuaternionNormError,
    RotationError,
    ShapeError,
    SpatialTypeError,
    URDFError,
)
from .spatial_algebra import (
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

__version__ = "0.1.0"

__all__ = [
    "errors",
    "frames",
    "rotation",
    "spatial_algebra",
    "DTypeError",
    "FeatherdynError",
    "FrameMismatchError",
    "InertiaError",
    "ModelError",
    "NonFiniteError",
    "PhysicalityWarning",
    "QuaternionNormError",
    "RotationError",
    "ShapeError",
    "SpatialTypeError",
    "URDFError",
    "PluckerTransform",
    "Screw",
    "SpatialForce",
    "SpatialInertia",
    "SpatialMotion",
    "crf",
    "crm",
    "cross_force",
    "cross_motion",
    "plux",
    "rotx",
    "roty",
    "rotz",
    "screw_parameters",
    "skew",
    "unskew",
    "xlt",
    "__version__",
]
