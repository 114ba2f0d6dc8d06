"""The public kinematics functions: forward kinematics, frame quantities and Jacobians.

``forward_kinematics``, ``frame_placement``, the frame velocities and accelerations and the
Jacobians are declared (``api/declarations.py``); :func:`kinematics_of` gives the functions
built on the forward kinematics (the constraints' rows) the declared kinematics by the chosen
backend.
"""

from __future__ import annotations

from typing import cast

import numpy as np

from ..algorithms import kinematics as _kin
from ..core import declared as _declared
from ..model import Model
from ..results import Kinematics
from ._backend import select_backend
from ._checks import State, as_dtype, finite_result, quiet
from .declarations import (
    DECLARATIONS,
    forward_kinematics,
    frame_jacobian,
    frame_jacobian_time_variation,
    frame_placement,
    joint_jacobians,
)
from .declared import Record

__all__ = [
    "kinematics_of",
    "forward_kinematics",
    "frame_placement",
    "joint_jacobians",
    "frame_jacobian",
    "frame_jacobian_time_variation",
]


def kinematics_of(model: Model, st: State, v: np.ndarray | None, a: np.ndarray | None,
                  backend: str | None) -> Kinematics:
    """Forward kinematics of a checked state (``v``, ``a`` from it or ``None``) by the backend ``backend`` picks:
    the declared ``forward_kinematics`` (its core's batch, or its reference)."""
    if select_backend(backend, st.dtype) == "compiled":
        decl = DECLARATIONS["forward_kinematics"]
        outs = _declared.run(decl.name, model, st.batch, [st.q, v, a])
        assert isinstance(decl.result, Record)
        return cast(Kinematics, decl.result.make(model, {n: None if x is None else as_dtype(x, st.dtype)
                                                         for n, x in zip(decl.outputs, outs, strict=True)}))
    kin = quiet(_kin.forward_kinematics, model, st.q, v, a)
    finite_result(kin.placements.translation, "forward kinematics: placements")
    for what, m in (("velocities", kin.velocities), ("accelerations", kin.accelerations)):
        if m is not None:
            finite_result(m.vector, f"forward kinematics: {what}")
    return kin
