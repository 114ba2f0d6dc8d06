"""The public derivatives: of inverse and forward dynamics, of frame motion, and the torque regressor.

The derivatives are declared (:mod:`.declarations`: every front end made from each declaration) and
re-exported here with ``dynamic_parameters``. Tangent convention: a derivative with respect to ``q`` is taken along the
tangent of ``fd.integrate`` — ``q ⊕ δ`` with δ in ``v``'s layout (the
free-flyer's ``[ω; v]`` in its own frame, a spherical joint's ω in the child
frame) — the tangent Pinocchio uses, up to its ``[v; ω]`` order. Float64
input runs the compiled core (``core/cpp/derivatives.hpp``,
``frame_derivatives.hpp``, ``regressor.hpp``); other dtypes (and
``backend="reference"``) run the reference in ``algorithms/derivatives.py``.
"""

from __future__ import annotations

import numpy as np

from ..algorithms import derivatives as _ref
from ..model import Model
from .declarations import (
    aba_derivatives,
    aba_vjp,
    crba_vjp,
    frame_acceleration_derivatives,
    frame_velocity_derivatives,
    joint_torque_regressor,
    mass_matrix_inverse,
    rnea_derivatives,
    rnea_vjp,
)

__all__ = ["rnea_derivatives", "aba_derivatives", "rnea_vjp", "aba_vjp", "crba_vjp", "mass_matrix_inverse",
           "frame_velocity_derivatives",
           "frame_acceleration_derivatives", "joint_torque_regressor", "dynamic_parameters"]


def dynamic_parameters(model: Model) -> np.ndarray:
    """The bodies' ten dynamic parameters stacked, `(10 nb,)`, in ``SpatialInertia.to_dynamic_parameters`` order::

        π_i = [m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz]   (I about body i's origin)
    """
    return _ref.dynamic_parameters(model)
