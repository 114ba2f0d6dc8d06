"""Every tolerance featherdyn decides with, stated once, by dtype.

A value here is a *fact* of the library (when is a quaternion unit, when is a
joint's articulated inertia singular, how close two results must be), so each
is defined in this module and nowhere else; the test
``tests/unit/test_facts_once.py`` fails on a second definition. Modules read
them through the names below, e.g. ``QUATERNION_NORM.of(q.dtype)``.

A :class:`DtypeTolerance` holds one number for float64 (also used for object
arrays of SymPy numbers and for integers) and one for float32, whose ~7 digits
cannot meet float64's standard. See ``docs/architecture.md`` ("Facts once").
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

__all__ = [
    "DtypeTolerance",
    "QUATERNION_NORM",
    "ROTATION_ORTHONORMAL",
    "SPATIAL_STRUCTURE",
    "INERTIA_STRUCTURE",
    "INERTIA_PHYSICAL",
    "SMALL_ANGLE",
    "UNIT_AXIS",
    "URDF_INERTIA_RTOL",
    "SINGULAR_PIVOT_RTOL",
    "DELASSUS_PIVOT_RTOL",
    "COMPARISON",
    "VERIFY_ALGEBRA",
    "VERIFY_DYNAMICS",
    "VERIFY_SECOND_ORDER",
    "VERIFY_ABA_DIFFERENCE_ROUNDING",
    "CHECK_VALUES",
    "default_tol",
]


class DtypeTolerance(NamedTuple):
    """A tolerance that depends on the floating type of the data it judges."""

    float64: float
    float32: float

    def of(self, dtype: Any) -> float:
        """The tolerance for data of ``dtype`` (float32 → :attr:`float32`, anything else → :attr:`float64`)."""
        return self.float32 if np.dtype(dtype) == np.float32 else self.float64


def default_tol(dtype: Any, float64: float, float32: float) -> float:
    """Pick between two tolerances by dtype (object arrays and integers use the float64 one)."""
    return DtypeTolerance(float64, float32).of(dtype)


#: ``| ‖quat‖ − 1 |`` above this: the quaternion (of ``q``, a rotation, a converter's input) is refused.
#: URDF files and user input carry ~7 digits; float32 round-off of a normalised quaternion is ~1e-7.
QUATERNION_NORM = DtypeTolerance(1e-6, 1e-4)

#: ``max |RᵀR − 1|`` above this: a matrix is not a rotation (URDF files print rotations to ~7 digits).
ROTATION_ORTHONORMAL = DtypeTolerance(1e-6, 1e-4)

#: structural checks of 6×6 matrices read back as transforms (``X = [[R, 0], [p×R, R]]``).
SPATIAL_STRUCTURE = DtypeTolerance(1e-9, 1e-5)

#: structural checks of 6×6 matrices read back as spatial inertias (symmetry, the ``m 1`` block).
INERTIA_STRUCTURE = DtypeTolerance(1e-9, 1e-5)

#: physical-validity checks of a spatial inertia (positive mass, principal moments, triangle
#: inequality), relative to the largest principal moment.
INERTIA_PHYSICAL = DtypeTolerance(1e-12, 1e-6)

#: below this angle (radians) the exponential / logarithm maps use Taylor series instead of closed forms.
SMALL_ANGLE = DtypeTolerance(1e-2, 1e-1)

#: a joint axis or unit vector whose length is off 1 by more than this is normalised with a warning.
UNIT_AXIS = 1e-6

#: relative tolerance of the URDF inertia checks (files print about 6 significant digits).
URDF_INERTIA_RTOL = 1e-6

#: ABA's singularity rule: joint ``i`` is singular when the smallest eigenvalue of its articulated
#: inertia ``D_i = S_iᵀ IA_i S_i`` is ``<=`` this times the largest entry of any body's spatial inertia.
#: The message is :meth:`featherdyn.errors.SingularMassMatrixError.for_joint`.
SINGULAR_PIVOT_RTOL = 1e-14

#: a Delassus matrix J M⁻¹ Jᵀ whose Cholesky pivot falls below this × its largest diagonal entry has
#: dependent constraint rows (constrained dynamics with mu = 0 refuse it and suggest mu > 0)
DELASSUS_PIVOT_RTOL = 1e-12

#: ``(rtol, atol)`` by dtype name for comparing two computations of the same quantity
#: (:func:`featherdyn.testing.assert_close`, the verification tool). float64 results agree with
#: Pinocchio to ~1e-13 on unit-scale data; 1e-10 leaves room for long chains. float32 carries
#: ~7 digits; 1e-4 leaves room for a few dozen operations on unit-scale values.
COMPARISON: dict[str, tuple[float, float]] = {
    "float64": (1e-10, 1e-10),
    "float32": (1e-4, 1e-4),
    "float16": (1e-2, 1e-2),
}

#: ``featherdyn verify``: relative tolerance of the spatial-algebra comparisons with Pinocchio.
VERIFY_ALGEBRA = 1e-12

#: ``featherdyn verify``: default relative tolerance of the robot comparisons with Pinocchio.
VERIFY_DYNAMICS = 1e-9

#: ``featherdyn verify``: relative tolerance of the second-order derivatives against central differences of the
#: first order (``verify/derivatives.py``; measured on the robot library: ≤ 2e-9 for RNEA's).
VERIFY_SECOND_ORDER = 1e-5

#: ``featherdyn verify``: the rounding of the central differences of ``fd.aba_derivatives`` per unit of cond(M)
#: (2.2e-16 / ε at ε = 1e-4, with a factor 50): ABA's second-order rows are held to
#: ``max(VERIFY_SECOND_ORDER, cond(M) × this)``.
VERIFY_ABA_DIFFERENCE_ROUNDING = 1e-10

#: ``featherdyn check``: default relative tolerance ``|a − b| / max(|b|, 1)`` for the user's values
#: (float32-saved values of long arms carry ~1e-6 of round-off).
CHECK_VALUES = 1e-6
