"""Random kinematic trees and states for the dynamics tests, deterministic from a seed.

Shared by ``tests/reference``, ``tests/properties`` and ``tests/unit`` (the
test directory is on ``sys.path`` because ``tests/conftest.py`` lives there).
Nothing here calls the algorithms under test: trees are built with
:class:`featherdyn.ModelBuilder`, configurations with each joint's own
``random`` and ``integrate``.

Every tree has, besides its bodies,

* a frame ``"<body>_tool"`` fixed to every body at a random, non-identity
  placement (so frame offsets are exercised), and
* a frame ``"world_marker"`` fixed to the world.

Inertias are physical (positive mass, positive principal moments that satisfy
the triangle inequality, rotated principal axes, centre of mass off the
origin) and of unit order, so absolute and relative errors mean the same thing.
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

import featherdyn as fd
from featherdyn.model import Model

__all__ = [
    "KINDS",
    "TREES",
    "TreeSpec",
    "State",
    "random_axis",
    "random_rotation",
    "random_placement",
    "random_inertia",
    "random_tree",
    "tree",
    "random_q",
    "random_state",
    "integrate",
    "tool_frames",
]

#: joint kinds the random trees draw from (planar always has normal +z: Pinocchio's planar joint)
KINDS = ("revolute", "prismatic", "spherical", "planar")


def random_axis(rng: np.random.Generator) -> np.ndarray:
    """A uniformly random unit 3-vector."""
    a = rng.normal(size=3)
    return a / np.linalg.norm(a)


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A uniformly random rotation matrix (from a normalised Gaussian quaternion, written out)."""
    x, y, z, w = rng.normal(size=4) / 1.0
    n = np.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def random_placement(rng: np.random.Generator, scale: float = 0.6) -> fd.PluckerTransform:
    """A random pose: uniform rotation, translation with components of size ``scale``."""
    return fd.PluckerTransform(random_rotation(rng), rng.uniform(-scale, scale, 3))


def random_inertia(rng: np.random.Generator) -> fd.SpatialInertia:
    """A physically valid random inertia (mass 0.5…3 kg, CoM within 0.3 m of the origin)."""
    mass = rng.uniform(0.5, 3.0)
    com = rng.uniform(-0.3, 0.3, 3)
    a, b = rng.uniform(0.02, 0.3, 2)
    c = abs(a - b) + rng.uniform(0.1, 0.9) * (a + b - abs(a - b))  # |a − b| < c < a + b
    Q = random_rotation(rng)
    Ic = Q @ np.diag([a, b, c]) @ Q.T
    return fd.SpatialInertia(mass, com, (Ic + Ic.T) / 2)


def _joint(kind: str, rng: np.random.Generator) -> fd.Joint:
    if kind == "revolute":
        return fd.RevoluteJoint(random_axis(rng))
    if kind == "prismatic":
        return fd.PrismaticJoint(random_axis(rng))
    if kind == "spherical":
        return fd.SphericalJoint()
    if kind == "planar":
        return fd.PlanarJoint([0.0, 0.0, 1.0])
    if kind == "free_flyer":
        return fd.FreeFlyerJoint()
    raise ValueError(f"unknown joint kind {kind!r}")


def _dfs_parent(parents: list[int], rng: np.random.Generator) -> int:
    """A random parent for the next body that keeps the numbering depth-first.

    Depth-first (pre-order) numbering, which Pinocchio assumes (a subtree's
    velocities are contiguous), holds when the new body hangs from the last
    body or from one of its ancestors.
    """
    path = []
    j = len(parents) - 1
    while j != -1:
        path.append(j)
        j = parents[j]
    return int(path[rng.integers(0, len(path))])


def random_tree(
    seed: int,
    nbodies: int = 6,
    *,
    root: str = "revolute",
    kinds: Sequence[str] = KINDS,
    branching: bool = True,
    gravity: Sequence[float] = (0.0, 0.0, -9.81),
) -> Model:
    """A random tree of ``nbodies`` bodies, deterministic from ``seed``.

    Args:
        seed: the seed of every random choice.
        nbodies: number of moving bodies.
        root: the kind of the root joint (``"free_flyer"`` for a floating base).
        kinds: the kinds the other joints are drawn from.
        branching: ``False`` for a chain (parent of body i is i − 1); ``True``
            draws each parent among body i − 1 and its ancestors (depth-first
            numbering, as ``load_urdf`` gives and Pinocchio needs).
        gravity: world gravity.
    """
    rng = np.random.default_rng(seed)
    b = fd.ModelBuilder(f"tree{seed}", gravity=gravity)
    parents: list[int] = []
    for i in range(nbodies):
        kind = root if i == 0 else str(rng.choice(list(kinds)))
        parent = -1 if i == 0 else (_dfs_parent(parents, rng) if branching else i - 1)
        parents.append(parent)
        placement = None if i == 0 and kind == "free_flyer" else random_placement(rng)
        b.add_body(f"b{i}", parent, _joint(kind, rng), placement=placement, inertia=random_inertia(rng))
    for i in range(nbodies):
        b.add_frame(f"b{i}_tool", i, random_placement(rng, 0.4))
    b.add_frame("world_marker", -1, random_placement(rng, 0.5))
    return b.build()


@dataclass(frozen=True)
class TreeSpec:
    """A named recipe for :func:`random_tree`."""

    name: str
    seed: int
    nbodies: int
    root: str
    branching: bool
    kinds: tuple[str, ...] = KINDS


#: the trees the reference and property tests run on: fixed and floating base, chains and branches, every joint type
TREES: tuple[TreeSpec, ...] = (
    TreeSpec("revolute_chain", 11, 6, "revolute", False, ("revolute",)),
    TreeSpec("fixed_chain_mixed", 12, 6, "prismatic", False),
    TreeSpec("fixed_branch_mixed", 13, 8, "spherical", True),
    TreeSpec("planar_root_branch", 14, 5, "planar", True, ("revolute", "prismatic")),
    TreeSpec("free_chain", 15, 6, "free_flyer", False),
    TreeSpec("free_branch", 16, 9, "free_flyer", True),
)

_SPECS = {s.name: s for s in TREES}


@functools.cache
def tree(name: str) -> Model:
    """The tree of :data:`TREES` called ``name`` (cached; models are immutable)."""
    s = _SPECS[name]
    return random_tree(s.seed, s.nbodies, root=s.root, kinds=s.kinds, branching=s.branching)


def tool_frames(model: Model) -> list[str]:
    """The names of the frames the trees carry besides the body frames (tools and the world marker)."""
    return [f.name for f in model.frames if f.name.endswith("_tool") or f.name == "world_marker"]


def random_q(model: Model, rng: np.random.Generator, size: tuple[int, ...] = ()) -> np.ndarray:
    """Random configurations `(*size, nq)` from each joint's ``random`` (unit quaternions)."""
    parts = []
    for i, joint in enumerate(model.joints):
        n = model.nqs[i]
        parts.append(joint.random(rng, np.full(n, -np.inf), np.full(n, np.inf), size=size or None))
    q = np.concatenate(parts, axis=-1) if parts else np.zeros(tuple(size) + (0,))
    return q.reshape(tuple(size) + (model.nq,))


def integrate(model: Model, q: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``q ⊕ v`` joint by joint with ``joint.integrate`` (the configuration reached moving with ``v`` for unit time)."""
    q = np.asarray(q, dtype=np.float64)
    v = np.asarray(v, dtype=np.float64)
    parts = []
    for i, joint in enumerate(model.joints):
        qi = q[..., model.idx_q[i] : model.idx_q[i] + model.nqs[i]]
        vi = v[..., model.idx_v[i] : model.idx_v[i] + model.nvs[i]]
        parts.append(joint.integrate(qi, vi))
    return np.concatenate(parts, axis=-1)


@dataclass(frozen=True)
class State:
    """A random state: configuration, velocity, acceleration, joint forces and external forces `(nb, 6)`."""

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    tau: np.ndarray
    f_ext: np.ndarray
    w: np.ndarray  # a cotangent of an (nv,) result (fd.rnea_vjp's)
    W: np.ndarray | None = None  # a cotangent of an (nv, nv) result (fd.crba_vjp's)


def random_state(model: Model, seed: int, size: tuple[int, ...] = ()) -> State:
    """A random :class:`State` (batch shape ``size``), deterministic from ``seed``."""
    rng = np.random.default_rng(seed)
    size = tuple(size)
    return State(
        q=random_q(model, rng, size),
        v=rng.normal(size=size + (model.nv,)),
        a=rng.normal(size=size + (model.nv,)),
        tau=rng.normal(size=size + (model.nv,)) * 5,
        f_ext=rng.normal(size=size + (model.nbodies, 6)),
        w=rng.normal(size=size + (model.nv,)),
        W=rng.normal(size=size + (model.nv, model.nv)),
    )


@functools.cache
def library_robot(name: str, floating: bool) -> Model | None:
    """A robot of the library (example-robot-data), fixed or floating, or ``None`` if it does not load."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            return fd.load_robot(name, floating_base=floating)
        except fd.FeatherdynError:
            return None


def library_robot_names() -> list[str]:
    """The names of the library's robots (empty without example-robot-data)."""
    try:
        return list(fd.list_robots())
    except fd.FeatherdynError:  # pragma: no cover - example-robot-data missing
        return []


def pinocchio_pair(name: str, floating: bool):  # type: ignore[no-untyped-def]
    """``(model, pin_model, pin_data, JointMap)`` of a library robot read by featherdyn and by Pinocchio."""
    import warnings

    import pinocchio as pin

    from featherdyn.robots import robot_path
    from featherdyn.verify.bridge import JointMap

    model = library_robot(name, floating)
    assert model is not None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        path = str(robot_path(name))
        pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(path)
    return model, pm, pm.createData(), JointMap(model, pm)
