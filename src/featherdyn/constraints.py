"""Constraints: point and frame contacts, loop closures (values), and their plans on a model.

The mathematics is in ``algorithms/constraints.py`` (reference) and ``core/cpp/contacts.hpp``
(compiled); the public functions (``fd.constrained_dynamics`` & co.) in ``api/constraints.py``.

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
import operator
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .errors import ConstraintError, FeatherdynError, ModelError, ShapeError
from .frames import LOCAL, ReferenceFrame, as_reference_frame
from .model import Model

__all__ = ["PointContact", "FrameContact", "LoopConstraint", "Constraint", "as_constraints", "check_bodies",
           "ContactPlan", "contact_plan", "resolve_frames", "frames_plan", "solver_settings", "ConstraintPlans", "plans_of", "cached_contact_plan",
           "cached_frames_plan"]


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


def as_constraints(constraints: Sequence[Constraint] | Constraint) -> list[Constraint]:
    """The ``constraints`` argument of the public functions as a non-empty list, or a :class:`ModelError`."""
    items = [constraints] if isinstance(constraints, (PointContact, FrameContact, LoopConstraint)) else \
        list(constraints)
    for c in items:
        if not isinstance(c, (PointContact, FrameContact, LoopConstraint)):
            raise ModelError(f"constraints: expected fd.PointContact, fd.FrameContact or fd.LoopConstraint, got "
                             f"{type(c).__name__}")
    if not items:
        raise ModelError("constraints: expected at least one constraint")
    return items


def check_bodies(model: Model, items: Sequence[Constraint]) -> None:
    """Refuse constraints without rows to act on: a contact on a frame fixed to the world, a loop within one body."""
    def body(frame: str | int) -> int:
        return model.frames[model.resolve_frame(frame)].body

    for c in items:
        if isinstance(c, (PointContact, FrameContact)) and body(c.frame) == -1:
            raise ConstraintError(f"{type(c).__name__}({c.frame!r}): the frame is fixed to the world, so the contact "
                                  "has nothing to hold (its rows are zero); constrain a frame of a moving body")
        if isinstance(c, LoopConstraint) and body(c.frame_a) == body(c.frame_b):
            where = "the world" if body(c.frame_a) == -1 else f"body {model.body_names[body(c.frame_a)]!r}"
            raise ConstraintError(f"LoopConstraint({c.frame_a!r}, {c.frame_b!r}): both frames are fixed to {where}, "
                                  "so the loop has nothing to close (its rows are zero)")


@dataclass(frozen=True, eq=False)
class ContactPlan:
    """Point and frame contacts (or frames) resolved against a model: what the compiled core receives.

    Attributes:
        specs: `(nc, 4)` float64, read-only, a row per contact ``[rows (3 | 6), frame index, reference code, K_d]``
            (``core/cpp/contacts.hpp``).
        slices: each contact's rows in λ.
        size: m, the number of rows.
    """

    specs: np.ndarray
    slices: tuple[slice, ...]
    size: int


def _plan(rows: list[tuple[int, int, ReferenceFrame, float]]) -> ContactPlan:
    specs = np.array([[k, fid, ref.code, kd] for k, fid, ref, kd in rows], dtype=np.float64).reshape(len(rows), 4)
    specs.setflags(write=False)
    ends = np.cumsum([k for k, _, _, _ in rows]).tolist()
    return ContactPlan(specs, tuple(slice(e - k, e) for e, (k, _, _, _) in zip(ends, rows, strict=True)),
                       ends[-1] if ends else 0)


def contact_plan(model: Model, constraints: Sequence[Constraint]) -> ContactPlan | None:
    """The plan of ``constraints`` when every one is a point or frame contact (checked: :func:`as_constraints`,
    :func:`check_bodies`), else ``None`` (a loop: the rows are built in Python)."""
    items = as_constraints(constraints)
    if any(isinstance(c, LoopConstraint) for c in items):
        return None
    check_bodies(model, items)
    return _plan([(c.size, model.resolve_frame(c.frame), c.reference, c.baumgarte[1])  # type: ignore[union-attr]
                  for c in items])


def resolve_frames(model: Model, frames: Sequence[str | int] | str | int, reference: ReferenceFrame | str
                   ) -> tuple[list[int], ReferenceFrame]:
    """The indices of ``frames`` (a name or index, or a sequence of them: at least one) and the reference frame."""
    names = [frames] if isinstance(frames, (str, int)) else list(frames)
    if not names:
        raise ShapeError("frames: expected at least one frame")
    ref = as_reference_frame(reference)
    return [model.resolve_frame(f) for f in names], ref


def frames_plan(model: Model, frames: Sequence[str | int] | str | int, reference: ReferenceFrame | str
                ) -> ContactPlan:
    """The plan of frames held like frame contacts (6 rows each, no damping): the operational space's task rows."""
    fids, ref = resolve_frames(model, frames, reference)
    return _plan([(6, fid, ref, 0.0) for fid in fids])


def solver_settings(mu: object, max_iter: object, tol: object) -> tuple[float, int, float]:
    """The constraint solve's settings checked: ``mu`` a finite number ≥ 0 (the proximal regularisation),
    ``max_iter`` an integer ≥ 1, ``tol`` a finite number > 0; else a :class:`ConstraintError` naming them."""
    try:
        m, t = float(mu), float(tol)  # type: ignore[arg-type]
        k = operator.index(max_iter)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ConstraintError(f"mu, max_iter, tol: expected numbers (max_iter an integer), got {mu!r}, {max_iter!r}, "
                              f"{tol!r}") from None
    if not 0.0 <= m < math.inf:
        raise ConstraintError(f"mu: expected a finite number >= 0 (the proximal regularisation), got {mu!r}")
    if k < 1:
        raise ConstraintError(f"max_iter: expected an integer >= 1, got {max_iter!r}")
    if not 0.0 < t < math.inf:
        raise ConstraintError(f"tol: expected a finite number > 0, got {tol!r}")
    return m, k, t


def _same_items(a: list[Any], b: list[Any]) -> bool:
    """``a == b`` for two lists (item by item, identity first), ``False`` when an item's ``==`` is not a truth
    value (an array where a constraint or a frame belongs: the caller's general path words that)."""
    try:
        return a == b
    except (TypeError, ValueError):
        return False


#: a plan and the caller's compiled copy of it (the core's checked specs; ``None`` when the core cannot take it)
Compiled = tuple[ContactPlan, Any]
#: the caller's compiler of a plan
Compile = Callable[[Model, ContactPlan], Any]


class ConstraintPlans:
    """One model's plans, kept on the model (``model._plans``, made on first use by :func:`plans_of`): freed with it.

    Plans are keyed by a hashable description (a tuple of constraints; frames and a reference), at most
    :attr:`MAX` of them (then the cache is emptied: a program cycling through more sets rebuilds them). The last
    argument of each kind is kept with its plan, one tuple replaced whole (thread-safe reads), and compared first:
    a control loop passing the same list each step pays a few pointer compares, not the constraints' hashes.
    """

    MAX = 64
    __slots__ = ("by_key", "last_contacts", "last_frames")

    def __init__(self) -> None:
        self.by_key: dict[Any, Compiled | None] = {}
        self.last_contacts: tuple[Any, Compiled | None] = (None, None)
        self.last_frames: tuple[Any, Any, Compiled | None] = (None, None, None)

    def get(self, key: Any, build: Callable[[], ContactPlan | None], model: Model, compile: Compile
            ) -> Compiled | None:
        """``(plan, compile(model, plan))`` of ``key``, the plan built by ``build()`` on first use (``None`` when it
        builds none); ``TypeError`` for an unhashable key."""
        try:
            return self.by_key[key]
        except KeyError:
            pass
        plan = build()
        found = None if plan is None else (plan, compile(model, plan))
        if len(self.by_key) >= self.MAX:
            self.by_key = {}
        self.by_key[key] = found
        return found


def plans_of(model: Model) -> ConstraintPlans:
    """``model._plans``, made on first use (the model's other caches, ``_core`` and ``_fast``, work the same way)."""
    try:
        plans: ConstraintPlans = model._plans
        return plans
    except AttributeError:
        plans = ConstraintPlans()
        object.__setattr__(model, "_plans", plans)
        return plans


def cached_contact_plan(model: Model, constraints: Any, compile: Compile) -> Compiled | None:
    """``(plan, compile(model, plan))`` of :func:`contact_plan`, cached on the model; ``None`` when a constraint is
    a loop or an item is unhashable (not a constraint: the caller's general path words the error)."""
    try:
        plans: ConstraintPlans = model._plans
    except AttributeError:
        plans = plans_of(model)
    last, found = plans.last_contacts
    if constraints is last or (type(constraints) is list and type(last) is list and _same_items(constraints, last)):
        return found
    return _look_up_contacts(plans, model, constraints, compile)


def _look_up_contacts(plans: ConstraintPlans, model: Model, constraints: Any, compile: Compile) -> Compiled | None:
    # (apart from cached_contact_plan: its closure would cost every call two cells)
    try:
        key = constraints if type(constraints) is tuple else (constraints,) if isinstance(
            constraints, (PointContact, FrameContact, LoopConstraint)) else tuple(constraints)
        found = plans.get(key, lambda: contact_plan(model, key), model, compile)
    except TypeError:
        return None
    if type(constraints) in (list, tuple):
        plans.last_contacts = (constraints.copy() if type(constraints) is list else constraints, found)
    return found


def cached_frames_plan(model: Model, frames: Any, reference: Any, compile: Compile) -> Compiled | None:
    """``(plan, compile(model, plan))`` of :func:`frames_plan`, cached on the model; ``None`` when the caller's
    general path must word an error (no frames, an unknown frame or reference, unhashable input: not cached)."""
    try:
        plans: ConstraintPlans = model._plans
    except AttributeError:
        plans = plans_of(model)
    last, last_reference, found = plans.last_frames
    if reference is last_reference and (frames is last or (
            type(frames) is list and type(last) is list and _same_items(frames, last))):
        return found
    return _look_up_frames(plans, model, frames, reference, compile)


def _look_up_frames(plans: ConstraintPlans, model: Model, frames: Any, reference: Any, compile: Compile
                    ) -> Compiled | None:
    try:
        key = ((frames,) if isinstance(frames, (str, int)) else tuple(frames), as_reference_frame(reference))
        found = plans.get(key, lambda: frames_plan(model, *key), model, compile)
    except (TypeError, ValueError, FeatherdynError):
        return None
    if type(frames) in (list, tuple, str, int):
        plans.last_frames = (frames.copy() if type(frames) is list else frames, reference, found)
    return found
