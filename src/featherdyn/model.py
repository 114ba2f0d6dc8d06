"""The kinematic tree: an immutable :class:`Model`, and :class:`ModelBuilder` to make one.

Bodies are numbered ``0 … nb−1`` with ``parent[i] < i`` and ``−1`` the fixed
world (depth-first order of the URDF tree). Body ``i`` hangs from its parent
through joint ``i``: the joint frame sits at ``joint_placements[i]`` (the
pose of the joint frame in the parent body's frame, Pinocchio's
``jointPlacements``) and the body's frame is the joint's successor frame, so
the pose of body ``i`` in its parent is::

    ᵖM_i(q) = joint_placements[i] @ joints[i].pose(q_i)

and Featherstone's ``X_up[i] = ⁱX_λ(i)`` is its inverse action. Body inertias
are expressed in the body frame. Every URDF link (including links merged
through fixed joints) and every joint is a named :class:`FrameInfo`.

Source: RBDA (2008) §4.1–4.2; chapter §8.3 and §18.
"""

from __future__ import annotations

import difflib
import itertools
import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field, fields
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .errors import InertiaError, ModelError, PhysicalityWarning, ShapeError
from .joints import FreeFlyerJoint, Joint
from .spatial import PluckerTransform, SpatialInertia
from .spatial.validation import as_array

__all__ = ["Model", "ModelBuilder", "FrameInfo", "Mimic", "DEFAULT_GRAVITY"]

DEFAULT_GRAVITY = (0.0, 0.0, -9.81)
# per-model caches of the compiled engines: set on first use, never pickled
_CACHES = ("_fast", "_core", "_plans")


@dataclass(frozen=True, slots=True)
class FrameInfo:
    """A named frame fixed to a body.

    Attributes:
        name: the frame's name (URDF link or joint name).
        body: index of the body it is fixed to (``-1`` = the world).
        placement: its pose in that body's frame.
        kind: ``"body"`` (a moving link's own frame), ``"link"`` (a link merged
            through a fixed joint, or the fixed root link), ``"joint"`` (a moving
            joint's frame: the joint's successor frame, i.e. fixed to the child
            body at identity, moving with ``q`` as Pinocchio's JOINT frames) or
            ``"fixed_joint"``.
    """

    name: str
    body: int
    placement: PluckerTransform
    kind: str


@dataclass(frozen=True, slots=True)
class Mimic:
    """A URDF ``<mimic>`` record (parsed, not enforced — as Pinocchio's default)::

        q_joint = multiplier · q_mimicked + offset
    """

    joint: str
    mimicked: str
    multiplier: float = 1.0
    offset: float = 0.0


#: The identity placement, shared by frames that sit at their body's origin (immutable: read-only arrays).
_IDENTITY = PluckerTransform.identity()


def _ro(a: Any, dtype: Any = np.float64) -> np.ndarray:
    out = np.array(a, dtype=dtype)
    out.setflags(write=False)
    return out


@dataclass(frozen=True, slots=True, eq=False)
class Model:
    """An immutable rigid-body tree. Build one with :class:`ModelBuilder` or :func:`featherdyn.load_urdf`.

    Attributes:
        name: the robot's name.
        parents: `(nb,)` parent body of each body (``-1`` = world), ``parents[i] < i``.
        joints: the joint of each body.
        joint_names, body_names: names, unique within each list.
        joint_placements: pose of each joint frame in its parent body, batched `(nb,)`.
        inertias: spatial inertia of each body in its own frame, batched `(nb,)`.
        gravity: `(3,)` gravity in world coordinates.
        frames: every named frame.
        idx_q, nqs, idx_v, nvs: where each body's joint sits in ``q`` and ``v``.
        lower, upper: `(nq,)` position limits (``±inf`` where unbounded).
        velocity_limit, effort_limit: `(nv,)` (``inf`` where not given).
        mimics: URDF mimic records.
        source: the file the model came from (``None`` if built in code).
        armature: `(nv,)` reflected rotor inertia per degree of freedom (MJCF ``armature``, Pinocchio's
            ``model.armature``), added to the mass matrix's diagonal: ``M(q) + diag(armature)``; zero when not
            given (URDF has none). Read-only float64.
        inserted_bodies: the names of the bodies a loader made that the file does not have: the massless
            bodies carrying all but the last of several joints on one MJCF body (``BODY#0``, ``BODY#1``, ...).
            Their zero inertia is by construction, so physicality checks (``featherdyn info``, ``verify``'s
            diagnostics) pass over them; ``()`` for a model built in code or from a URDF.
    """

    name: str
    parents: tuple[int, ...]
    joints: tuple[Joint, ...]
    joint_names: tuple[str, ...]
    body_names: tuple[str, ...]
    joint_placements: PluckerTransform
    inertias: SpatialInertia
    gravity: np.ndarray
    frames: tuple[FrameInfo, ...]
    idx_q: tuple[int, ...]
    nqs: tuple[int, ...]
    idx_v: tuple[int, ...]
    nvs: tuple[int, ...]
    lower: np.ndarray
    upper: np.ndarray
    velocity_limit: np.ndarray
    effort_limit: np.ndarray
    mimics: tuple[Mimic, ...] = ()
    source: str | None = None
    armature: np.ndarray = None  # type: ignore[assignment]  # None -> zeros (nv,) in __post_init__
    inserted_bodies: tuple[str, ...] = ()
    _frame_index: dict[str, int] = field(default_factory=dict, repr=False)
    # the compiled engine's one-state fast path, set on first use (engine/_fast.py); unset until then
    _fast: Any = field(init=False, repr=False, compare=False)
    # the compiled core's flat model arrays, set on first use (core/_model_view.py); unset until then
    _core: Any = field(init=False, repr=False, compare=False)
    # the plans of constraint sets (featherdyn/constraints.py: plans_of), set on first use; unset until then
    _plans: Any = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        # derived from frames (first of a name wins), so dataclasses.replace(model, frames=...) stays consistent
        names = [f.name for f in self.frames]
        # the first frame of a name wins: inserted last, from the end backwards
        index = dict(zip(reversed(names), range(len(names) - 1, -1, -1), strict=True))
        object.__setattr__(self, "_frame_index", index)
        nv = sum(self.nvs)
        if self.armature is None:
            object.__setattr__(self, "armature", _ro(np.zeros(nv)))
        else:
            arm = np.asarray(self.armature)
            if arm.dtype.kind == "O":  # symbolic models (featherdyn.symbolic) keep their expressions
                arm = arm.copy()
                arm.flags.writeable = False
            else:
                arm = _ro(arm)
            if arm.shape != (nv,):
                raise ModelError(f"armature: expected shape (nv,) = ({nv},), got {arm.shape}")
            if arm.dtype.kind == "f":
                values = arm.tolist()  # a few numbers: Python's comparisons cost less than numpy's reductions
                if not all(0 <= v < math.inf for v in values):  # (a NaN fails)
                    raise ModelError(f"armature: expected finite values >= 0, got {values}")
            object.__setattr__(self, "armature", arm)

    # pickling and copying leave out the caches of the compiled engines (rebuilt on first use). By __reduce__, not
    # __getstate__: Python 3.10 and 3.11.0-3.11.3 replace a slots dataclass's own __getstate__ and __setstate__
    # with ones that read every field, the unset caches too (CPython gh-104035, fixed in 3.11.4).
    def __reduce__(self) -> tuple[Any, tuple[tuple[Any, ...]]]:
        return _model_from_state, (tuple(getattr(self, name) for name in _PICKLED),)

    @property
    def nbodies(self) -> int:
        """Number of moving bodies ``nb``."""
        return len(self.parents)

    @property
    def nq(self) -> int:
        """Length of the configuration vector ``q``."""
        return sum(self.nqs)

    @property
    def nv(self) -> int:
        """Length of the velocity vector ``v`` (and of ``a``, ``τ``)."""
        return sum(self.nvs)

    @property
    def total_mass(self) -> Any:
        """Sum of the body masses (the fixed root link of a fixed-base robot is not a body).

        A float, or a SymPy expression for a model with symbolic masses.
        """
        total = np.sum(self.inertias.mass)
        return total if self.inertias.mass.dtype.kind == "O" else float(total)

    @property
    def floating_base(self) -> bool:
        """Whether body 0 hangs from the world by a free-flyer joint."""
        return bool(self.nbodies and self.parents[0] == -1 and isinstance(self.joints[0], FreeFlyerJoint))

    @property
    def tree_transforms(self) -> PluckerTransform:
        """Alias of :attr:`joint_placements` (Featherstone's ``Xtree``, as poses)."""
        return self.joint_placements

    def resolve_frame(self, frame: str | int) -> int:
        """A frame index from a name (:meth:`frame_id`) or an index; :class:`ModelError` when unknown.

        Raises:
            ModelError: an unknown name or an index outside ``0 … len(frames) − 1``.
            ShapeError: ``frame`` is neither a string nor an integer.
        """
        if isinstance(frame, str):
            return self.frame_id(frame)
        if isinstance(frame, (int, np.integer)) and not isinstance(frame, bool):
            if not 0 <= int(frame) < len(self.frames):
                if not self.frames:
                    raise ModelError(f"frame: index {frame}, but model {self.name!r} has no frames")
                raise ModelError(f"frame: index {frame} out of range 0..{len(self.frames) - 1}")
            return int(frame)
        raise ShapeError(f"frame: expected a frame name or index, got {type(frame).__name__}")

    def frame_id(self, name: str, kind: str | None = None) -> int:
        """Index of the frame called ``name`` in :attr:`frames`; :class:`ModelError` if unknown.

        URDF links and joints may share a name (a link ``LF_KFE`` and its joint
        ``LF_KFE``): the first frame of that name is returned, or the one of the
        given ``kind`` (``"body"``, ``"link"``, ``"joint"``, ``"fixed_joint"``).
        """
        if kind is not None:
            for k, f in enumerate(self.frames):
                if f.name == name and f.kind == kind:
                    return k
            raise ModelError(f"no frame {name!r} of kind {kind!r} in model {self.name!r}")
        try:
            return self._frame_index[name]
        except (KeyError, TypeError):
            raise ModelError(
                f"frame {name!r} not found in model {self.name!r}{_similar(name, [f.name for f in self.frames])}"
            ) from None

    def body_id(self, name: str) -> int:
        """Index of the body called ``name``; :class:`ModelError` if unknown."""
        try:
            return self.body_names.index(name)
        except ValueError:
            raise ModelError(f"body {name!r} not found in model {self.name!r}{_similar(name, self.body_names)}") from None

    def joint_id(self, name: str) -> int:
        """Index of the body whose joint is called ``name``; :class:`ModelError` if unknown."""
        try:
            return self.joint_names.index(name)
        except ValueError:
            raise ModelError(f"joint {name!r} not found in model {self.name!r}{_similar(name, self.joint_names)}") from None

    def _check_body(self, i: Any, allow_world: bool) -> int:
        lo = -1 if allow_world else 0
        if isinstance(i, bool) or not isinstance(i, (int, np.integer)) or not (lo <= i < self.nbodies):
            world = "-1 (world) or " if allow_world else ""
            raise ModelError(f"expected a body index {world}0..{self.nbodies - 1}, got {i!r}")
        return int(i)

    def children(self, i: int) -> list[int]:
        """The bodies whose parent is ``i`` (``-1`` for the world)."""
        i = self._check_body(i, allow_world=True)
        return [j for j, p in enumerate(self.parents) if p == i]

    def subtree(self, i: int) -> list[int]:
        """Body ``i`` and all its descendants (in body order)."""
        i = self._check_body(i, allow_world=False)
        inside = {i}
        for j in range(i + 1, self.nbodies):
            if self.parents[j] in inside:
                inside.add(j)
        return sorted(inside)

    def __repr__(self) -> str:
        base = "floating" if self.floating_base else "fixed"
        return (f"Model({self.name!r}: {self.nbodies} bodies, nq={self.nq}, nv={self.nv}, {base} base, "
                f"mass={_fmt_mass(self.total_mass)} kg)")


#: the fields a pickled Model carries: all but the caches, in declaration order
_PICKLED = tuple(f.name for f in fields(Model) if f.name not in _CACHES)


def _model_from_state(state: tuple[Any, ...]) -> Model:
    """A :class:`Model` from ``Model.__reduce__``'s state (the values of ``_PICKLED``)."""
    model = object.__new__(Model)
    for name, value in zip(_PICKLED, state, strict=True):
        object.__setattr__(model, name, value)
    return model


def _similar(name: Any, candidates: Sequence[str]) -> str:
    """A hint listing the candidates closest to ``name`` (spelling, then substring), or ``""``."""
    if not isinstance(name, str):
        return f"; names are strings, got {type(name).__name__}"
    close = difflib.get_close_matches(name, candidates, n=5, cutoff=0.6)
    close += [c for c in candidates if name.lower() in c.lower() and c not in close]
    return f"; similar: {close[:5]}" if close else ""


def _check_name(name: Any, what: str) -> str:
    if not isinstance(name, str) or not name:
        raise ModelError(f"{what}: expected a non-empty string, got {name!r}")
    return name


def _fmt_mass(m: Any) -> str:
    return f"{m:.4g}" if isinstance(m, float) else str(m)


class ModelBuilder:
    """Make a :class:`Model` in code: add bodies in order (parents first), then :meth:`build`.

    Example (the chapter's appendix-D 2R arm)::

        b = ModelBuilder("2R")
        l1 = b.add_body("link1", -1, RevoluteJoint([0, 0, 1]), inertia=I1, joint_name="joint1")
        b.add_body("link2", l1, RevoluteJoint([0, 0, 1]),
                   placement=PluckerTransform(np.eye(3), [1.0, 0, 0]), inertia=I2)
        model = b.build()
    """

    def __init__(self, name: str = "model", gravity: Sequence[float] = DEFAULT_GRAVITY) -> None:
        self.name = name
        if (type(gravity) is tuple and len(gravity) == 3 and type(gravity[0]) is type(gravity[1]) is type(gravity[2])
                is float and math.isfinite(gravity[0] + gravity[1] + gravity[2])):  # three finite floats: no conversion
            self.gravity = np.array(gravity)
        else:
            g = as_array(gravity, "gravity", (3,))
            if g.shape != (3,):
                raise ModelError(f"gravity: expected shape (3,), got {g.shape}")
            self.gravity = g.astype(np.float64)
        self._parents: list[int] = []
        self._joints: list[Joint] = []
        self._joint_names: list[str] = []
        self._body_names: list[str] = []
        self._body_set: set[str] = set()  # for O(1) duplicate checks on long chains
        self._joint_set: set[str] = set()
        # each body's placement (R, p) and inertia (m, c, I_c), matrices flattened row by row, stacked by build()
        self._rotations: list[Any] = []
        self._translations: list[Any] = []
        self._masses: list[float] = []
        self._coms: list[Any] = []
        self._inertias_com: list[Any] = []
        self._lower: list[np.ndarray] = []
        self._upper: list[np.ndarray] = []
        self._vel: list[np.ndarray] = []
        self._eff: list[np.ndarray] = []
        self._armature: list[np.ndarray] = []
        self._frames: list[FrameInfo] = []
        self._mimics: list[Mimic] = []
        self._limit_problems: list[str] = []
        self.source: str | None = None
        self._inserted: tuple[str, ...] = ()  # Model.inserted_bodies (a loader's, set by _extend)
        # whether every body came through _extend, whose inertias are exactly symmetric (a loader's): then build()
        # checks only that they are finite
        self._symmetric = True

    @property
    def nbodies(self) -> int:
        return len(self._parents)

    def add_body(
        self,
        name: str,
        parent: int,
        joint: Joint,
        *,
        placement: PluckerTransform | None = None,
        inertia: SpatialInertia | None = None,
        joint_name: str | None = None,
        lower: ArrayLike | None = None,
        upper: ArrayLike | None = None,
        velocity_limit: ArrayLike | None = None,
        effort_limit: ArrayLike | None = None,
        armature: ArrayLike | None = None,
    ) -> int:
        """Add a body hanging from ``parent`` (``-1`` = world) through ``joint``; returns its index.

        Args:
            name: body name (unique).
            parent: index of an already added body, or ``-1``.
            joint: its joint model.
            placement: pose of the joint frame in the parent body frame (default identity).
            inertia: spatial inertia in the body frame (default zero).
            joint_name: defaults to ``name + "_joint"``.
            lower, upper: `(nq,)` position limits (default unbounded).
            velocity_limit, effort_limit: `(nv,)` (default unbounded).
            armature: `(nv,)` or a number: reflected rotor inertia of the joint's degrees of freedom (default 0).
        """
        _check_name(name, "body name")
        joint_name = f"{name}_joint" if joint_name is None else _check_name(joint_name, f"body {name!r}: joint_name")
        if name in self._body_set:
            raise ModelError(f"body name {name!r} is used twice")
        if joint_name in self._joint_set:
            raise ModelError(f"joint name {joint_name!r} is used twice (body {name!r})")
        if not isinstance(joint, Joint):
            raise ModelError(f"body {name!r}: joint must be a featherdyn Joint, got {type(joint).__name__}")
        if (
            isinstance(parent, bool)
            or not isinstance(parent, (int, np.integer))
            or not (-1 <= parent < self.nbodies)
        ):
            raise ModelError(
                f"body {name!r}: parent must be -1 (world) or an existing body index 0..{self.nbodies - 1} "
                f"(bodies are added parents first), got {parent!r}"
            )
        placement = PluckerTransform.identity() if placement is None else placement
        if not isinstance(placement, PluckerTransform) or placement.shape != ():
            raise ModelError(f"body {name!r}: placement must be a single PluckerTransform")
        inertia = SpatialInertia.zero() if inertia is None else inertia
        if not isinstance(inertia, SpatialInertia) or inertia.shape != ():
            raise ModelError(f"body {name!r}: inertia must be a single SpatialInertia")
        if inertia.dtype.kind != "f" or not (np.all(np.isfinite(inertia.inertia_com)) and np.isfinite(inertia.mass)):
            raise ModelError(f"body {name!r}: inertia must hold finite floating-point numbers")
        if float(inertia.mass) < 0:
            raise InertiaError(f"body {name!r}: negative mass {float(inertia.mass):g}")
        lo = self._limit(lower, joint.nq, -math.inf, f"body {name!r}: lower", "nq")
        hi = self._limit(upper, joint.nq, math.inf, f"body {name!r}: upper", "nq")
        vel = self._limit(velocity_limit, joint.nv, math.inf, f"body {name!r}: velocity_limit", "nv")
        eff = self._limit(effort_limit, joint.nv, math.inf, f"body {name!r}: effort_limit", "nv")
        try:
            arm = np.broadcast_to(np.asarray(0.0 if armature is None else armature, dtype=np.float64),
                                  (joint.nv,)).copy()
        except (TypeError, ValueError):
            raise ModelError(f"body {name!r}: armature: expected a number or {joint.nv} numbers, "
                             f"got {armature!r}") from None
        if not (np.all(np.isfinite(arm)) and np.all(arm >= 0)):
            raise ModelError(f"body {name!r}: armature: expected finite values >= 0, got {arm.tolist()}")
        if np.any(lo > hi):
            self._limit_problems.append(
                f"joint {joint_name!r} (body {name!r}): lower limit {lo.tolist()} above upper limit {hi.tolist()}"
            )
        return self._append(name, int(parent), joint, joint_name, placement.rotation.ravel(), placement.translation,
                            float(inertia.mass), inertia.com, inertia.inertia_com.ravel(), lo, hi, vel, eff, arm)

    def _append(self, name: str, parent: int, joint: Joint, joint_name: str, rotation: Any, translation: Any,
                mass: float, com: Any, inertia_com: Any, lower: Any, upper: Any, velocity_limit: Any,
                effort_limit: Any, armature: Any) -> int:
        """Record a body whose values are already checked: :meth:`add_body`'s, and a loader's that has checked its
        own (names unique, numbers finite, ``rotation`` and ``inertia_com`` as 9 numbers row by row, 3-vectors as 3,
        limits and armature of the joint's sizes, ``inertia_com`` symmetric); returns its index."""
        self._symmetric = False  # symmetric to round-off: build() checks and averages
        self._parents.append(parent)
        self._joints.append(joint)
        self._joint_names.append(joint_name)
        self._body_names.append(name)
        self._joint_set.add(joint_name)
        self._body_set.add(name)
        self._rotations.append(rotation)
        self._translations.append(translation)
        self._masses.append(mass)
        self._coms.append(com)
        self._inertias_com.append(inertia_com)
        self._lower.append(lower)
        self._upper.append(upper)
        self._vel.append(velocity_limit)
        self._eff.append(effort_limit)
        self._armature.append(armature)
        return len(self._parents) - 1

    def _extend(self, names: list[str], parents: list[int], joints: list[Joint], joint_names: list[str],
                rotations: list[Any], translations: list[Any], masses: list[float], coms: list[Any],
                inertias_com: list[Any], lower: list[Any], upper: list[Any], velocity_limit: list[Any],
                effort_limit: list[Any], armature: list[Any], inserted: tuple[str, ...] = ()) -> None:
        """:meth:`_append` of several bodies at once: each argument lists one entry per body, in body order; each
        ``inertia_com`` exactly symmetric (a loader's own, mirrored), the others as :meth:`_append` requires;
        ``inserted`` names the bodies the loader made (:attr:`Model.inserted_bodies`)."""
        self._inserted += inserted
        self._parents += parents
        self._joints += joints
        self._joint_names += joint_names
        self._body_names += names
        self._joint_set.update(joint_names)
        self._body_set.update(names)
        self._rotations += rotations
        self._translations += translations
        self._masses += masses
        self._coms += coms
        self._inertias_com += inertias_com
        self._lower += lower
        self._upper += upper
        self._vel += velocity_limit
        self._eff += effort_limit
        self._armature += armature

    @staticmethod
    def _limit(val: Any, n: int, default: float, name: str, size_name: str) -> np.ndarray:
        if val is None:
            return np.full(n, default)
        arr = as_array(val, name, check_finite=False)
        if arr.dtype.kind != "f" or arr.ndim > 1 or arr.shape not in ((), (1,), (n,)):
            raise ModelError(
                f"{name}: expected a number or {n} numbers ({size_name}={n} for this joint), got {val!r}"
            )
        out = np.broadcast_to(arr, (n,)).astype(np.float64)
        if np.any(np.isnan(out)):
            raise ModelError(f"{name}: limits must not be NaN")
        return out

    def add_inertia(self, body: int, inertia: SpatialInertia) -> None:
        """Lump ``inertia`` (expressed in ``body``'s frame) into that body (fixed-joint merging)."""
        if isinstance(body, bool) or not isinstance(body, (int, np.integer)) or not (0 <= body < self.nbodies):
            raise ModelError(f"add_inertia: no body {body!r} (expected 0..{self.nbodies - 1})")
        if not isinstance(inertia, SpatialInertia) or inertia.shape != ():
            raise ModelError("add_inertia: inertia must be a single SpatialInertia")
        self._symmetric = False
        total = SpatialInertia(self._masses[body], self._coms[body],
                               np.reshape(self._inertias_com[body], (3, 3))) + inertia
        self._masses[body] = float(total.mass)
        self._coms[body], self._inertias_com[body] = total.com, total.inertia_com.ravel()

    def add_frame(self, name: str, body: int, placement: PluckerTransform | None = None, kind: str = "link") -> None:
        """Add a named frame fixed to ``body`` (``-1`` = world) at ``placement``."""
        _check_name(name, "frame name")
        if isinstance(body, bool) or not isinstance(body, (int, np.integer)) or not (-1 <= body < self.nbodies):
            raise ModelError(f"frame {name!r}: no body {body!r} (expected -1 or 0..{self.nbodies - 1})")
        placement = PluckerTransform.identity() if placement is None else placement
        if not isinstance(placement, PluckerTransform) or placement.shape != ():
            raise ModelError(f"frame {name!r}: placement must be a single PluckerTransform")
        self._frames.append(FrameInfo(name, int(body), placement, kind))

    def _append_frames(self, frames: list[FrameInfo]) -> None:
        """Record frames a loader has checked itself (names strings, bodies added or ``-1``, single placements)."""
        self._frames += frames

    def add_mimic(self, mimic: Mimic) -> None:
        """Record a URDF mimic relation (not enforced)."""
        self._mimics.append(mimic)

    def build(self, *, strict: bool = False, check_inertias: bool = True) -> Model:
        """Validate and freeze the model.

        Checks: names unique; a body whose subtree has no mass (the mass matrix
        would be singular) and a lower limit above the upper one warn with
        :class:`PhysicalityWarning`, or raise :class:`ModelError` with
        ``strict=True``.
        """
        model, complaints = self._build(strict, check_inertias)
        for msg in complaints:
            warnings.warn(msg, PhysicalityWarning, stacklevel=3)  # attributed as before: the caller's caller
        return model

    def _build(self, strict: bool, check_inertias: bool) -> tuple[Model, list[str]]:
        """:meth:`build`, its warnings returned as messages (a loader names its file in them); with ``strict``
        the first is raised."""
        for what, listed, distinct in (("body", self._body_names, self._body_set),
                                       ("joint", self._joint_names, self._joint_set)):
            if len(distinct) != len(listed):  # a name used twice: find the first
                seen: set[str] = set()
                for n in listed:
                    if n in seen:
                        raise ModelError(f"{what} name {n!r} is used twice")
                    seen.add(n)
        nb = self.nbodies
        idx_q, idx_v, nqs, nvs, q0, v0 = [], [], [], [], 0, 0
        for j in self._joints:
            nq, nv = j.nq, j.nv
            idx_q.append(q0)
            idx_v.append(v0)
            nqs.append(nq)
            nvs.append(nv)
            q0 += nq
            v0 += nv
        # every number of the bodies in one read-only array (one conversion): placements, inertias, limits and
        # armature are its parts
        chain = itertools.chain.from_iterable
        sizes = (9 * nb, 3 * nb, nb, 3 * nb, 9 * nb, q0, q0, v0, v0, v0, 3)
        flat = np.fromiter(itertools.chain(
            chain(self._rotations), chain(self._translations), self._masses, chain(self._coms),
            chain(self._inertias_com), chain(self._lower), chain(self._upper), chain(self._vel), chain(self._eff),
            chain(self._armature), self.gravity), np.float64, sum(sizes))
        flat.setflags(write=False)
        parts, at = [], 0
        for size in sizes:
            parts.append(flat[at:at + size])
            at += size
        (rotations, translations, masses, coms, ics, lower, upper, velocity_limit, effort_limit, armature,
         gravity) = parts
        if nb:
            placements = PluckerTransform._wrap(rotations.reshape(nb, 3, 3), translations.reshape(nb, 3), None, None)
            coms, ics = coms.reshape(nb, 3), ics.reshape(nb, 3, 3)
            if self._symmetric and math.isfinite(sum(self._masses) + sum(map(sum, self._coms))
                                                 + sum(map(sum, self._inertias_com))):
                # only a loader's numbers (_extend: exactly symmetric), all finite: what SpatialInertia checks
                inertias = SpatialInertia._wrap(masses, coms, ics, None)
            else:
                inertias = SpatialInertia(masses, coms, ics)
        else:
            placements = PluckerTransform.identity((0,))
            inertias = SpatialInertia.zero((0,))
        frames = list(self._frames)
        names = {f.name for f in frames}
        identity = _IDENTITY
        for i, bname in enumerate(self._body_names):  # every body is a frame, unless one of the same name exists
            if bname not in names:
                frames.append(FrameInfo(bname, i, identity, "body"))
                names.add(bname)
        model = Model(
            name=self.name,
            parents=tuple(self._parents),
            joints=tuple(self._joints),
            joint_names=tuple(self._joint_names),
            body_names=tuple(self._body_names),
            joint_placements=placements,
            inertias=inertias,
            gravity=gravity,
            frames=tuple(frames),
            idx_q=tuple(idx_q),
            nqs=tuple(nqs),
            idx_v=tuple(idx_v),
            nvs=tuple(nvs),
            lower=lower,
            upper=upper,
            velocity_limit=velocity_limit,
            effort_limit=effort_limit,
            mimics=tuple(self._mimics),
            source=self.source,
            armature=armature,  # (copied by Model)
            inserted_bodies=self._inserted,
        )
        complaints = list(self._limit_problems)
        if check_inertias:
            if self._symmetric:  # the inertias are the builder's numbers, unchanged: tested without numpy
                has_mass = [m > 0 or any(ic) for m, ic in zip(self._masses, self._inertias_com, strict=True)]
                complaints += _massless(model, has_mass)
            else:
                complaints += massless_subtrees(model)
        if strict and complaints:
            raise ModelError(complaints[0] + " (strict=True)")
        return model, complaints


def massless_subtrees(model: Model) -> list[str]:
    """Messages for each moving joint whose whole subtree has no mass and no rotational inertia.

    Such a joint makes the joint-space mass matrix singular (ABA would divide by zero).
    """
    nb = model.nbodies
    mass, ic = model.inertias.mass, model.inertias.inertia_com
    if mass.dtype.kind == "O":  # symbolic: element by element
        has_mass = [bool(mass[i] > 0 or np.any(ic[i] != 0)) for i in range(nb)]
    else:  # as Python floats: cheaper than numpy's comparisons for the few bodies of a model
        has_mass = [m > 0 or any(row) for m, row in zip(mass.tolist(), ic.reshape(nb, 9).tolist(), strict=True)]
    return _massless(model, has_mass)


def _massless(model: Model, has_mass: list[Any]) -> list[str]:
    """:func:`massless_subtrees` given whether each body has a mass or a rotational inertia."""
    nb = model.nbodies
    sub = list(has_mass)
    for i in range(nb - 1, -1, -1):
        p = model.parents[i]
        if p >= 0:
            sub[p] = sub[p] or sub[i]
    out = []
    for i in range(nb):
        if not sub[i]:
            out.append(
                f"joint {model.joint_names[i]!r} (body {model.body_names[i]!r}): its subtree has no mass; "
                "the mass matrix will be singular"
            )
    return out
