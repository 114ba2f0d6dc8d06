"""Constraint descriptions: point and frame contacts, loop closures (values; the algorithms are in ``api/constraints.py``).

Definitions (the public functions' docstrings repeat them)::

    M q̈ + h = τ + Jᵀ λ,        J q̈ + γ = −K_p e − K_d J v

* :class:`PointContact`: the frame's origin does not move — 3 rows, the linear
  rows of the frame Jacobian in ``reference``; γ the classical acceleration of
  the origin at q̈ = 0; λ a force (3,) on the robot at the origin, in ``reference``.
* :class:`FrameContact`: the frame does not move — 6 rows, the frame Jacobian;
  γ the frame's spatial acceleration at q̈ = 0; λ a wrench ``[n; f]`` (6,).
* :class:`LoopConstraint`: frames a and b move together along the chosen axes
  of ``[ω; v]`` — the chosen rows of ``J_a − ᵃX_b J_b`` (the velocity of a
  relative to b, in a's coordinates, then in ``reference``); λ the force from
  body b on body a; ``e`` the chosen rows of ``log(ᵃM_b)``.

``baumgarte = (K_p, K_d)`` (non-negative) stabilises drift; contacts have no
position error (``e = 0``), so their ``K_p`` has no effect.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .errors import ModelError
from .frames import LOCAL, ReferenceFrame, as_reference_frame

__all__ = ["PointContact", "FrameContact", "LoopConstraint", "Constraint"]


def _gains(baumgarte: object, what: str) -> tuple[float, float]:
    try:
        kp, kd = (float(x) for x in baumgarte)  # type: ignore[attr-defined]
    except (TypeError, ValueError):
        raise ModelError(f"{what}: baumgarte: expected two numbers (K_p, K_d), got {baumgarte!r}") from None
    if not (math.isfinite(kp) and math.isfinite(kd) and kp >= 0 and kd >= 0):
        raise ModelError(f"{what}: baumgarte: expected finite non-negative gains (K_p, K_d), got {baumgarte!r}")
    return kp, kd


def _frame(frame: object, what: str) -> str | int:
    if isinstance(frame, bool) or not isinstance(frame, (str, int)):
        raise ModelError(f"{what}: frame: expected a frame name or index, got {type(frame).__name__} {frame!r}")
    return frame


@dataclass(frozen=True)
class PointContact:
    """The origin of ``frame`` does not move (3 rows; λ a force ``(3,)`` in ``reference``)."""

    frame: str | int
    reference: ReferenceFrame = LOCAL
    baumgarte: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "frame", _frame(self.frame, "PointContact"))
        object.__setattr__(self, "reference", as_reference_frame(self.reference))
        object.__setattr__(self, "baumgarte", _gains(self.baumgarte, "PointContact"))

    @property
    def size(self) -> int:
        """The number of constraint rows, 3."""
        return 3


@dataclass(frozen=True)
class FrameContact:
    """``frame`` does not move (6 rows; λ a wrench ``[n; f]`` in ``reference``)."""

    frame: str | int
    reference: ReferenceFrame = LOCAL
    baumgarte: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "frame", _frame(self.frame, "FrameContact"))
        object.__setattr__(self, "reference", as_reference_frame(self.reference))
        object.__setattr__(self, "baumgarte", _gains(self.baumgarte, "FrameContact"))

    @property
    def size(self) -> int:
        """The number of constraint rows, 6."""
        return 6


@dataclass(frozen=True)
class LoopConstraint:
    """Frames ``frame_a`` and ``frame_b`` move together along the chosen ``axes`` of ``[ω; v]`` (1–6 rows).

    The rows are those of the relative spatial velocity ``v_a − ᵃX_b v_b`` (in a's frame, then
    ``reference``): the motion of b carried to a's origin. With all six axes in ``LOCAL`` this is
    Pinocchio's two-joint ``RigidConstraintModel(CONTACT_6D, …, LOCAL)`` (tested). Pinocchio's 3D
    loops, and its ``LOCAL_WORLD_ALIGNED`` loops, compare the velocities of the two frame *origins*
    instead: the same rows once the loop is closed (the origins coincide), different rows and drift
    while it is open.
    """

    frame_a: str | int
    frame_b: str | int
    axes: tuple[bool, ...] = (True,) * 6
    reference: ReferenceFrame = LOCAL
    baumgarte: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "frame_a", _frame(self.frame_a, "LoopConstraint"))
        object.__setattr__(self, "frame_b", _frame(self.frame_b, "LoopConstraint"))
        axes = tuple(self.axes)
        if len(axes) != 6 or not all(isinstance(x, bool) for x in axes) or not any(axes):
            raise ModelError(f"LoopConstraint: axes: expected six booleans over [ω; v], at least one True, "
                             f"got {self.axes!r}")
        object.__setattr__(self, "axes", axes)
        object.__setattr__(self, "reference", as_reference_frame(self.reference))
        object.__setattr__(self, "baumgarte", _gains(self.baumgarte, "LoopConstraint"))

    @property
    def size(self) -> int:
        """The number of constraint rows (chosen axes)."""
        return sum(self.axes)


Constraint = PointContact | FrameContact | LoopConstraint
