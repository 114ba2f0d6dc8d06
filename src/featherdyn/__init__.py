"""featherdyn: spatial vector algebra and rigid-body dynamics in Featherstone's notation.

Public names are flat (``fd.SpatialMotion``, ``fd.PluckerTransform``, ...);
see ``docs/architecture.md`` for the layers and the conventions: 6D motion vectors are
``[ω; v]`` (angular first), forces ``[n; f]``, ``PluckerTransform(R, p)`` is
the pose of frame A in frame B and maps A-coordinates to B-coordinates.
"""

from __future__ import annotations

from . import algorithms, api, errors, frames, joints, model, results, rotation, spatial_algebra, tolerances
from .api import (
    LOCAL,
    LOCAL_WORLD_ALIGNED,
    WORLD,
    CenterOfMass,
    Kinematics,
    ReferenceFrame,
    aba,
    aba_derivatives,
    center_of_mass,
    centroidal_momentum,
    centroidal_momentum_matrix,
    coriolis_matrix,
    crba,
    default_backend,
    dynamic_parameters,
    forward_kinematics,
    frame_acceleration,
    frame_acceleration_derivatives,
    frame_classical_acceleration,
    frame_jacobian,
    frame_jacobian_time_variation,
    frame_placement,
    frame_velocity,
    frame_velocity_derivatives,
    generalized_gravity,
    get_num_threads,
    joint_jacobians,
    joint_torque_regressor,
    kinetic_energy,
    mass_matrix_inverse,
    nonlinear_effects,
    potential_energy,
    rnea,
    rnea_derivatives,
    set_default_backend,
    set_num_threads,
)
from .errors import (
    BackendError,
    ConstraintError,
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
from .joints import FreeFlyerJoint, Joint, PlanarJoint, PrismaticJoint, RevoluteJoint, SphericalJoint
from .model import FrameInfo, Mimic, Model, ModelBuilder
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

# names whose modules are imported on first use (keeps `import featherdyn` light)
_LAZY = {
    "load_urdf": "urdf",
    "load_robot": "robots",
    "list_robots": "robots",
    "neutral": "configuration",
    "random_configuration": "configuration",
    "integrate": "configuration",
    "difference": "configuration",
    "integrate_derivatives": "configuration",
    "difference_derivatives": "configuration",
    "normalize": "configuration",
    "is_normalized": "configuration",
    "interpolate": "configuration",
    "conventions": None,
    "urdf": None,
    "robots": None,
    "configuration": None,
    "verify": None,
    "compile": "api",
}


def __getattr__(name: str) -> object:
    import importlib

    if name not in _LAZY:
        raise AttributeError(f"module 'featherdyn' has no attribute {name!r}")
    module_name = _LAZY[name]
    if module_name is None:
        return importlib.import_module(f".{name}", __name__)
    return getattr(importlib.import_module(f".{module_name}", __name__), name)


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))

__all__ = [
    "algorithms",
    "api",
    "results",
    "tolerances",
    "errors",
    "frames",
    "joints",
    "model",
    "rotation",
    "spatial_algebra",
    "BackendError",
    "ConstraintError",
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
    "FreeFlyerJoint",
    "Joint",
    "PlanarJoint",
    "PrismaticJoint",
    "RevoluteJoint",
    "SphericalJoint",
    "FrameInfo",
    "Mimic",
    "Model",
    "ModelBuilder",
    "LOCAL",
    "LOCAL_WORLD_ALIGNED",
    "WORLD",
    "CenterOfMass",
    "Kinematics",
    "ReferenceFrame",
    "aba",
    "center_of_mass",
    "centroidal_momentum",
    "centroidal_momentum_matrix",
    "coriolis_matrix",
    "crba",
    "forward_kinematics",
    "frame_acceleration",
    "frame_classical_acceleration",
    "frame_jacobian",
    "frame_jacobian_time_variation",
    "frame_placement",
    "frame_velocity",
    "generalized_gravity",
    "joint_jacobians",
    "kinetic_energy",
    "nonlinear_effects",
    "potential_energy",
    "rnea",
    "rnea_derivatives",
    "aba_derivatives",
    "mass_matrix_inverse",
    "frame_velocity_derivatives",
    "frame_acceleration_derivatives",
    "joint_torque_regressor",
    "dynamic_parameters",
    "set_default_backend",
    "default_backend",
    "set_num_threads",
    "get_num_threads",
    "__version__",
    *_LAZY,
]
