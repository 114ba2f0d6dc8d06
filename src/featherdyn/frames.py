"""Optional frame tags and the checks made when tagged values meet.

A spatial value may say which frame its coordinates are expressed in
(``frame``); a motion may further say which body it describes and relative to
which (``body``, ``relative_to``, RigidBodyDynamics.jl's *body* and *base*);
a :class:`~featherdyn.PluckerTransform` may say which frame it maps from
(``source``) and to (``target``). Any hashable value works as a frame name;
strings are usual.

The rule is simple: **untagged values are never checked** (``None`` matches
anything), and combining two tagged values whose frames differ raises
:class:`FrameMismatchError` naming both frames. Results carry the right tags:
adding ``v_A/B`` and ``v_B/C`` gives ``v_A/C``; applying ``X`` (source A,
target B) re-tags the expressed-in frame from A to B.
"""

from __future__ import annotations

import enum
from collections.abc import Hashable

from .errors import FrameMismatchError, ShapeError

__all__ = [
    "FrameMismatchError",
    "Frame",
    "check_same_frame",
    "merge_frames",
    "chain_bodies",
    "ReferenceFrame",
    "LOCAL",
    "WORLD",
    "LOCAL_WORLD_ALIGNED",
    "as_reference_frame",
]

Frame = Hashable | None


def check_same_frame(a: Frame, b: Frame, what: str) -> None:
    """Raise :class:`FrameMismatchError` if both frames are set and differ.

    Args:
        a, b: the frames of the two operands (``None`` = untagged).
        what: the operation, for the message (e.g. ``"motion + motion"``).
    """
    if a is not None and b is not None and a != b:
        raise FrameMismatchError(
            f"{what}: operands are expressed in different frames, {a!r} and {b!r}; "
            f"transform one of them first (X.apply with source={b!r}, target={a!r})"
        )


def merge_frames(a: Frame, b: Frame, what: str) -> Frame:
    """Check ``a`` and ``b`` agree and return the one that is set (or ``None``)."""
    check_same_frame(a, b, what)
    return a if a is not None else b


def chain_bodies(
    body_a: Frame, rel_a: Frame, body_b: Frame, rel_b: Frame, what: str
) -> tuple[Frame, Frame]:
    """Body/relative-to tags of the sum of two relative motions.

    ``v_{A/B} + v_{B/C} = v_{A/C}`` (in either order of the operands); two
    motions of the same pair keep that pair. If any tag is missing the result
    keeps what is certain; two fully tagged motions that neither chain nor
    match raise :class:`FrameMismatchError`.
    """
    if body_a == body_b and rel_a == rel_b:
        return body_a, rel_a
    if rel_a is not None and rel_a == body_b:
        return body_a, rel_b
    if rel_b is not None and rel_b == body_a:
        return body_b, rel_a
    tagged = (body_a, rel_a, body_b, rel_b)
    if all(t is not None for t in tagged):
        raise FrameMismatchError(
            f"{what}: cannot add the velocity of {body_a!r} relative to {rel_a!r} to the velocity of "
            f"{body_b!r} relative to {rel_b!r}: relative motions add as v_A/B + v_B/C = v_A/C"
        )
    return None, None


class ReferenceFrame(enum.Enum):
    """Where frame velocities, accelerations and Jacobians are expressed (Pinocchio's meanings).

    * ``LOCAL``: in the frame itself, reference point its origin.
    * ``WORLD``: in world axes, reference point the world origin (spatial
      velocity in Featherstone's sense).
    * ``LOCAL_WORLD_ALIGNED``: reference point the frame origin, world axes
      (the linear part is the frame origin's velocity in world coordinates).

    :attr:`code` is the integer the compiled engine uses for each (the only
    place those integers are defined).
    """

    LOCAL = "local"
    WORLD = "world"
    LOCAL_WORLD_ALIGNED = "local_world_aligned"

    @property
    def code(self) -> int:
        """``0`` LOCAL, ``1`` WORLD, ``2`` LOCAL_WORLD_ALIGNED (the compiled engine's codes)."""
        return _REFERENCE_CODES[self]


_REFERENCE_CODES = {ReferenceFrame.LOCAL: 0, ReferenceFrame.WORLD: 1, ReferenceFrame.LOCAL_WORLD_ALIGNED: 2}

LOCAL = ReferenceFrame.LOCAL
WORLD = ReferenceFrame.WORLD
LOCAL_WORLD_ALIGNED = ReferenceFrame.LOCAL_WORLD_ALIGNED


def as_reference_frame(reference: object) -> ReferenceFrame:
    """``reference`` as a :class:`ReferenceFrame` (the enum or its name, any case); :class:`ShapeError` otherwise."""
    if isinstance(reference, ReferenceFrame):
        return reference
    if isinstance(reference, str):
        try:
            return ReferenceFrame(reference.lower())
        except ValueError:
            pass
    raise ShapeError(f"reference: expected fd.LOCAL, fd.WORLD or fd.LOCAL_WORLD_ALIGNED, got {reference!r}")
