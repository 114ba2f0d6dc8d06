"""The public entry points: input checks, backend choice, the compiled core's one-state path, result types.

``fd.rnea`` & co. are defined here and re-exported flat by :mod:`featherdyn`.
Each checks its input (:mod:`._checks`), chooses between the reference
algorithms (:mod:`featherdyn.algorithms`, written like the book) and the
compiled core (:mod:`featherdyn.core`, C++) (:mod:`._backend`), and calls one
of them. Layers (``docs/architecture.md``): values → model →
{algorithms, core} → api → tools (verify, cli, benchmarks).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..frames import LOCAL, LOCAL_WORLD_ALIGNED, WORLD, ReferenceFrame
from ..model import Model
from ..results import AbaSecondDerivatives, CenterOfMass, Kinematics, RneaSecondDerivatives
from . import declarations as _declarations
from ._backend import (
    default_backend,
    get_num_threads,
    result_cache_info,
    set_default_backend,
    set_num_threads,
    set_result_cache_size,
)
from .constraint_derivatives import (
    ConstrainedDynamicsDerivatives,
    ImpulseDynamicsDerivatives,
    constrained_dynamics_derivatives,
    impulse_dynamics_derivatives,
)
from .constraints import (
    ConstrainedDynamics,
    ImpulseDynamics,
    OperationalSpace,
    constrained_dynamics,
    constraint_drift,
    constraint_jacobian,
    delassus,
    impulse_dynamics,
    operational_space,
    operational_space_inertia,
)
from .declarations import *  # noqa: F403  (the declared algorithms: api/declarations.py's __all__)
from .declared import compiled_method
from .derivatives import (
    aba_derivatives,
    aba_vjp,
    crba_vjp,
    dynamic_parameters,
    frame_acceleration_derivatives,
    frame_velocity_derivatives,
    joint_torque_regressor,
    mass_matrix_inverse,
    rnea_derivatives,
    rnea_vjp,
)
from .dynamics import coriolis_matrix
from .energy import (
    center_of_mass,
    centroidal_momentum,
    centroidal_momentum_matrix,
    kinetic_energy,
    kinetic_energy_derivatives,
    potential_energy,
)
from .kinematics import (
    forward_kinematics,
    frame_jacobian,
    frame_jacobian_time_variation,
    frame_placement,
    joint_jacobians,
)

if TYPE_CHECKING:
    from ..core.compiled import CompiledModel

__all__ = [
    "LOCAL",
    "LOCAL_WORLD_ALIGNED",
    "WORLD",
    "ReferenceFrame",
    "CenterOfMass",
    "Kinematics",
    "RneaSecondDerivatives",
    "AbaSecondDerivatives",
    "ConstrainedDynamics",
    "ImpulseDynamics",
    "ConstrainedDynamicsDerivatives",
    "ImpulseDynamicsDerivatives",
    "constrained_dynamics_derivatives",
    "impulse_dynamics_derivatives",
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
    "dynamic_parameters",
    "frame_acceleration_derivatives",
    "frame_velocity_derivatives",
    "joint_torque_regressor",
    "mass_matrix_inverse",
    "rnea_derivatives",
    "rnea_vjp",
    "center_of_mass",
    "centroidal_momentum",
    "centroidal_momentum_matrix",
    "compile",
    "coriolis_matrix",
    "default_backend",
    "forward_kinematics",
    "frame_jacobian",
    "frame_jacobian_time_variation",
    "frame_placement",
    "joint_jacobians",
    "kinetic_energy",
    "kinetic_energy_derivatives",
    "potential_energy",
    "set_default_backend",
    "set_num_threads",
    "get_num_threads",
    "set_result_cache_size",
    "result_cache_info",
    *_declarations.__all__,
]


#: fd.compile's methods that had a separate ``*_batch`` form (the same method now)
_BATCH_ALIASES = ("rnea", "crba", "aba", "frame_jacobian", "rnea_derivatives", "aba_derivatives", "placements")


def compile(model: Model, *, warmup: bool = True) -> CompiledModel:
    """The compiled core bound to ``model`` for control loops (``cm.rnea(q, v, a, out=tau)``, ``*_batch``).

    See :func:`featherdyn.core.compiled.compile_model`; the bound methods check
    their input as ``fd.rnea`` & co. do.
    """
    from ..core.compiled import compile_model

    cm = compile_model(model, warmup=warmup)
    for decl in _declarations.DECLARATIONS.values():  # the declared algorithms' methods (api/declared.py)
        method = compiled_method(decl, model)
        setattr(cm, decl.method or decl.name, method)
        if decl.name in _BATCH_ALIASES:  # the batch forms' former names: the method takes any batch shape
            setattr(cm, f"{decl.method or decl.name}_batch", method)
    return cm
