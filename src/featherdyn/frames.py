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

from collections.abc import Hashable

from .errors import FrameMismatchError

__all__ = ["FrameMismatchError", "Frame", "check_same_frame", "merge_frames", "chain_bodies"]

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
