"""featherdyn: spatial vector algebra and rigid-body dynamics in Featherstone's notation.

Public names are flat (``fd.SpatialMotion``, ``fd.PluckerTransform``, ...);
see ``docs/architecture.md`` for the layers and the conventions: 6D motion vectors are
``[ω; v]`` (angular first), forces ``[n; f]``, ``PluckerTransform(R, p)`` is
the pose of frame A in frame B and maps A-coordinates to B-coordinates.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from . import algorithms, api, errors, frames, joints, model, results, rotation, spatial_algebra, tolerances
from .api import (
    LOCAL,
    LOCAL_WORLD_ALIGNED,
    WORLD,
    AbaSecondDerivatives,
    CenterOfMass,
    ConstrainedDynamics,
    ConstrainedDynamicsDerivatives,
    ImpulseDynamics,
    ImpulseDynamicsDerivatives,
    Kinematics,
    OperationalSpace,
    ReferenceFrame,
    RneaSecondDerivatives,
    aba,
    aba_derivatives,
    aba_second_derivatives,
    aba_vjp,
    center_of_mass,
    center_of_mass_derivatives,
    centroidal_dynamics_derivatives,
    centroidal_momentum,
    centroidal_momentum_matrix,
    constrained_dynamics,
    constrained_dynamics_derivatives,
    constraint_drift,
    constraint_jacobian,
    coriolis_matrix,
    crba,
    crba_vjp,
    default_backend,
    delassus,
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
    generalized_gravity_derivatives,
    get_num_threads,
    impulse_dynamics,
    impulse_dynamics_derivatives,
    joint_jacobians,
    joint_torque_regressor,
    kinematics_derivatives,
    kinetic_energy,
    kinetic_energy_derivatives,
    mass_matrix_inverse,
    nonlinear_effects,
    operational_space,
    operational_space_inertia,
    potential_energy,
    result_cache_info,
    rnea,
    rnea_derivatives,
    rnea_second_derivatives,
    rnea_vjp,
    set_default_backend,
    set_num_threads,
    set_result_cache_size,
    static_torque_derivatives,
)
from .constraints import FrameContact, LoopConstraint, PointContact
from .errors import (
    BackendError,
    ConstraintError,
    DatasetError,
    DTypeError,
    FeatherdynError,
    FrameMismatchError,
    InertiaError,
    MJCFError,
    ModelError,
    NonFiniteError,
    PhysicalityWarning,
    QuaternionNormError,
    RotationError,
    SDFError,
    ShapeError,
    SpatialTypeError,
    URDFError,
)
from .joints import FreeFlyerJoint, Joint, PlanarJoint, PrismaticJoint, RevoluteJoint, SphericalJoint
from .model import FrameInfo, Mimic, Model, ModelBuilder
from .results import CenterOfMassDerivatives, CentroidalDynamicsDerivatives, KinematicsDerivatives
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
    "load_urdf": "readers.urdf",
    "load_mjcf": "readers.mjcf",
    "load_sdf": "readers.sdf",
    "load_model": "readers.mjcf",
    "load_robot": "robots",
    "list_robots": "robots",
    "neutral": "configuration",
    "random_configuration": "configuration",
    "integrate": "api",
    "difference": "api",
    "integrate_derivatives": "api",
    "difference_derivatives": "api",
    "normalize": "configuration",
    "is_normalized": "configuration",
    "interpolate": "configuration",
    "conventions": None,
    "urdf": None,
    "mjcf": None,
    "robots": None,
    "configuration": None,
    "verify": None,
    "compile": "api",
}

if TYPE_CHECKING:  # the lazy names as a type checker sees them (mypy, IDEs): the objects __getattr__ returns
    from . import configuration as configuration
    from . import conventions as conventions
    from . import mjcf as mjcf
    from . import robots as robots
    from . import urdf as urdf
    from . import verify as verify
    from .api import compile as compile
    from .api import difference as difference
    from .api import difference_derivatives as difference_derivatives
    from .api import integrate as integrate
    from .api import integrate_derivatives as integrate_derivatives
    from .configuration import interpolate as interpolate
    from .configuration import is_normalized as is_normalized
    from .configuration import neutral as neutral
    from .configuration import normalize as normalize
    from .configuration import random_configuration as random_configuration
    from .readers.mjcf import load_mjcf as load_mjcf
    from .readers.mjcf import load_model as load_model
    from .readers.urdf import load_urdf as load_urdf
    from .robots import list_robots as list_robots
    from .robots import load_robot as load_robot


def __getattr__(name: str) -> object:
    import importlib

    if name not in _LAZY:
        raise AttributeError(f"module 'featherdyn' has no attribute {name!r}")
    module_name = _LAZY[name]
    if module_name is None:
        value = importlib.import_module(f".{name}", __name__)
    else:
        value = getattr(importlib.import_module(f".{module_name}", __name__), name)
    globals()[name] = value  # resolved once: later uses are a plain module attribute (no import machinery)
    return value


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
    "DatasetError",
    "DTypeError",
    "FeatherdynError",
    "FrameMismatchError",
    "InertiaError",
    "MJCFError",
    "ModelError",
    "NonFiniteError",
    "PhysicalityWarning",
    "QuaternionNormError",
    "RotationError",
    "SDFError",
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
    "kinetic_energy_derivatives",
    "nonlinear_effects",
    "potential_energy",
    "rnea",
    "rnea_derivatives",
    "rnea_second_derivatives",
    "rnea_vjp",
    "RneaSecondDerivatives",
    "generalized_gravity_derivatives",
    "static_torque_derivatives",
    "PointContact",
    "FrameContact",
    "LoopConstraint",
    "ConstrainedDynamics",
    "ConstrainedDynamicsDerivatives",
    "ImpulseDynamicsDerivatives",
    "constrained_dynamics_derivatives",
    "impulse_dynamics_derivatives",
    "ImpulseDynamics",
    "OperationalSpace",
    "constrained_dynamics",
    "constraint_drift",
    "constraint_jacobian",
    "delassus",
    "impulse_dynamics",
    "operational_space",
    "operational_space_inertia",
    "aba_derivatives",
    "aba_vjp",
    "crba_vjp",
    "aba_second_derivatives",
    "AbaSecondDerivatives",
    "mass_matrix_inverse",
    "frame_velocity_derivatives",
    "frame_acceleration_derivatives",
    "kinematics_derivatives",
    "center_of_mass_derivatives",
    "centroidal_dynamics_derivatives",
    "KinematicsDerivatives",
    "CenterOfMassDerivatives",
    "CentroidalDynamicsDerivatives",
    "joint_torque_regressor",
    "dynamic_parameters",
    "set_default_backend",
    "default_backend",
    "set_num_threads",
    "get_num_threads",
    "set_result_cache_size",
    "result_cache_info",
    "__version__",
    *_LAZY,
]
