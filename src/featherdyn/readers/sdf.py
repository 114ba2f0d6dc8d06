"""Load an SDFormat (SDF, Gazebo's format) model into a :class:`~featherdyn.Model`.

The reading is as hostile-input safe as the URDF and MJCF loaders' (through
:mod:`featherdyn.readers.xml`: defusedxml, DTDs and entities refused, nesting
and attribute lengths bounded, files read up to a size; numbers finite and
bounded as :mod:`featherdyn.readers.urdf` bounds them); ``<include>`` chains are
bounded by :data:`MAX_INCLUDE_DEPTH` and :data:`MAX_INCLUDES`, and a file that
includes itself is refused. Every failure is an :class:`~featherdyn.SDFError`
naming the file, the line, the element and the attribute.

What is read (SDFormat 1.4–1.11, http://sdformat.org/spec):

* ``<sdf version>`` with one or more ``<model>``, or ``<world>``\\ s holding
  ``<model>``\\ s and ``<include>``\\ s: one model is loaded (``model=`` picks
  it by name; several and no name is an error listing them).
* ``<model>``: ``<link>``, ``<joint>``, ``<frame>``, nested ``<model>`` and
  ``<include>`` (their names scoped as SDFormat does: ``inner::link``),
  ``<static>``, ``<pose>``, ``canonical_link``.
* ``<link>``: ``<pose>``, ``<inertial>`` (``<mass>``, ``<pose>``,
  ``<inertia>`` with ``ixx`` ... ``izz``: about the centre of mass, in the axes
  of the inertial pose, so that in the link frame ``c = p``,
  ``I_c = R I_sdf Rᵀ``). SDFormat's defaults hold: a link without
  ``<inertial>`` has 1 kg and a unit inertia at its origin (a
  :class:`~featherdyn.PhysicalityWarning` names such moving links), a missing
  ``<mass>`` is 1 kg, missing products of inertia are 0. A missing moment
  (``ixx``, ``iyy``, ``izz``) is refused (libsdformat silently takes 1 kg·m²).
* ``<joint type>``: ``revolute``, ``continuous``, ``prismatic``, ``ball``,
  ``fixed``, ``universal`` and ``revolute2`` (two revolute joints in series,
  about ``<axis>`` then ``<axis2>``, named ``J/axis`` and ``J/axis2``, through
  a massless body ``CHILD#0`` listed in :attr:`Model.inserted_bodies`); a
  parent ``world`` hangs the child on the world. ``screw`` and ``gearbox``
  are refused. ``<axis>``/``<axis2>``: ``<xyz>`` (``expressed_in``, 1.7+;
  ``use_parent_model_frame``, 1.5–1.6; in 1.4 always the model frame),
  ``<limit>`` (``lower``/``upper``, ``effort``/``velocity``: a negative value
  or none is unbounded, as SDFormat says), ``<dynamics>`` (``damping``,
  ``friction``: checked, not modelled, as the URDF loader does) and
  ``<mimic>`` (1.11: a :class:`~featherdyn.Mimic` with offset
  ``offset − multiplier · reference``, recorded, not enforced, as the URDF
  loader records ``<mimic>``).
* Poses and frames (SDFormat 1.7+ semantics, which also hold for the defaults
  of 1.4–1.6): ``<pose>`` (6 numbers ``x y z roll pitch yaw``, or 7 with
  ``rotation_format="quat_xyzw"``; ``degrees="true"``) relative to
  ``relative_to`` (``frame`` in 1.5–1.6), by default: a link's and a nested
  model's to the model frame ``__model__``, a joint's to its child link, a
  frame's to the frame it is ``attached_to``. ``<frame attached_to>``, the
  implicit ``__model__`` and ``world`` frames, ``inner::name`` references.
  Relative-to and attached-to cycles are refused.

The tree (RBDA (2008) §4.1): bodies depth-first, a link's child joints in
document order. A moving joint's body frame is the joint frame (the child link
is a ``"body"`` frame at its pose in it); fixed joints are merged as the URDF
loader merges them (the child's inertia lumped into the moving ancestor). The
base: a link hung on ``world`` by a joint is on the world (a fixed joint to the
world drops its inertia, as a URDF root's); a link of a ``<static>`` model
without a parent joint is welded to the world at the model's pose; any other
link without a parent joint floats: body on a :class:`~featherdyn.FreeFlyerJoint`
named ``"root_joint"`` (``"LINK/root_joint"`` when the model has several such
links), as ``load_urdf(floating_base=True)`` does and as Gazebo and Drake
simulate such a link. A link that is the child of two joints (a kinematic
loop) is refused.

Frames (:class:`~featherdyn.FrameInfo`): each joint (``"joint"`` at its
body's origin, or ``"fixed_joint"``), each link (``"body"`` for a moving
link, ``"link"`` for a merged or welded one) and each ``<frame>``
(``"frame"``), placed in the body they are fixed to.

``<include>`` (``<uri>``, ``<name>``, ``<pose>``, ``<static>``): ``model://NAME``
is looked up in the directories of the ``search_path`` argument, then of the
environment variables :data:`SEARCH_PATH_VARIABLES` (``SDF_PATH``,
``GZ_SIM_RESOURCE_PATH``; ``os.pathsep``-separated); ``file://`` URIs and
plain paths are files or model directories (relative ones to the including
file's directory, the current directory for a string). A model directory is
read through its ``model.config`` (the ``<sdf>`` entry of highest version) or
its ``model.sdf``. Network URIs are not fetched; ``merge="true"`` and
``placement_frame`` are refused.

Ignored: every element without rigid-tree meaning (``<visual>``,
``<collision>``, ``<sensor>``, ``<plugin>``, ``<material>``, ``<gravity>``,
``<physics>``, a world's ``<scene>``/``<light>``/..., other namespaces'
elements such as ``drake:``/``gz:``, and names SDFormat does not define), in
one :class:`~featherdyn.PhysicalityWarning` counting them per element
(``strict=True`` refuses them with an :class:`~featherdyn.SDFError`). The
world's ``<gravity>`` is not read: the model has featherdyn's default gravity.
"""

from __future__ import annotations

import math
import os
import re
import warnings
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FeatherdynError, PhysicalityWarning, SDFError
from ..joints import FreeFlyerJoint, Joint, PrismaticJoint, RevoluteJoint, SphericalJoint
from ..model import FrameInfo, Mimic, Model, ModelBuilder
from ..rotation import quat_to_matrix, rpy_to_matrix
from ..spatial_algebra import PluckerTransform, SpatialInertia
from ..tolerances import UNIT_AXIS, URDF_INERTIA_RTOL
from .urdf import _NUMBER, MAX_INERTIA, MAX_LENGTH, MAX_MASS, MIN_INERTIAL
from .xml import MAX_DEPTH, local_name, parse_xml, quote, read_source, reissue_warnings, shorten, shorten_quoted

__all__ = ["MAX_INCLUDES", "MAX_INCLUDE_DEPTH", "SEARCH_PATH_VARIABLES", "load_sdf"]

#: Deepest chain of ``<include>``\ d files (a file including a file ...).
MAX_INCLUDE_DEPTH = 20
#: Most files included in one load.
MAX_INCLUDES = 1000
#: The environment variables searched for ``model://`` URIs, in this order, after the ``search_path`` argument.
SEARCH_PATH_VARIABLES = ("SDF_PATH", "GZ_SIM_RESOURCE_PATH")

_VERSIONS = tuple(f"1.{k}" for k in range(4, 12))
_JOINT_TYPES = ("revolute", "continuous", "prismatic", "ball", "fixed", "universal", "revolute2")
_REFUSED_TYPES = {"screw": "a screw joint couples rotation and translation (no featherdyn joint does)",
                  "gearbox": "a gearbox joint is a constraint between two joints, not a tree joint"}
_INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")
_WORLD = "world"

#: The children featherdyn reads, per element; any other child is an ignored element (module doc).
_READ: dict[str, frozenset[str]] = {
    "sdf": frozenset({"model", "world"}),
    "world": frozenset({"model", "include"}),
    "model": frozenset({"static", "pose", "link", "joint", "frame", "model", "include"}),
    "link": frozenset({"pose", "inertial"}),
    "inertial": frozenset({"mass", "pose", "inertia"}),
    "inertia": frozenset(_INERTIA_KEYS),
    "joint": frozenset({"parent", "child", "pose", "axis", "axis2"}),
    "axis": frozenset({"xyz", "use_parent_model_frame", "limit", "dynamics", "mimic"}),
    "mimic": frozenset({"multiplier", "offset", "reference"}),
    "limit": frozenset({"lower", "upper", "effort", "velocity"}),
    "dynamics": frozenset({"damping", "friction"}),
    "frame": frozenset({"pose"}),
    "include": frozenset({"uri", "name", "pose", "static", "placement_frame"}),
}
#: Children SDFormat defines there without rigid-tree meaning (the others are reported as unknown to SDFormat).
_KNOWN_IGNORED: dict[str, frozenset[str]] = {
    "sdf": frozenset({"actor", "light"}),
    "world": frozenset({"audio", "wind", "include", "gravity", "magnetic_field", "atmosphere", "gui", "physics",
                        "scene", "light", "frame", "actor", "plugin", "road", "spherical_coordinates", "state",
                        "population", "joint"}),
    "model": frozenset({"self_collide", "allow_auto_disable", "plugin", "gripper", "enable_wind"}),
    "link": frozenset({"gravity", "enable_wind", "self_collide", "kinematic", "must_be_base_link", "velocity_decay",
                       "collision", "visual", "sensor", "projector", "audio_sink", "audio_source", "battery",
                       "light", "particle_emitter"}),
    "inertial": frozenset({"density", "auto_inertia_params", "fluid_added_mass"}),
    "joint": frozenset({"gearbox_ratio", "gearbox_reference_body", "thread_pitch", "screw_thread_pitch", "physics",
                        "sensor"}),
    "axis": frozenset({"initial_position"}),
    "limit": frozenset({"stiffness", "dissipation"}),
    "dynamics": frozenset({"spring_reference", "spring_stiffness"}),
    "include": frozenset({"plugin", "namespace"}),
}

Pose = tuple[np.ndarray, np.ndarray]  # (R (3, 3), p (3,)): a frame's pose, mapping its coordinates to the other's
_IDENTITY: Pose = (np.eye(3), np.zeros(3))
for _a in _IDENTITY:
    _a.setflags(write=False)  # shared by every pose that is the identity


def _compose(a: Pose, b: Pose) -> Pose:
    """``a ∘ b``: the pose of frame C in A from B in A (``a``) and C in B (``b``)."""
    return a[0] @ b[0], a[0] @ b[1] + a[1]


def _inverse(a: Pose) -> Pose:
    return a[0].T, -(a[0].T @ a[1])


def _plucker(a: Pose) -> PluckerTransform:
    return PluckerTransform(a[0], a[1])


# ---------------------------------------------------------------------------
# the records of the documents
# ---------------------------------------------------------------------------


@dataclass(slots=True)
class _File:
    """One parsed document: its label for messages, its path, its elements' lines, its version."""

    label: str
    path: str | None
    lines: dict[Any, int]
    ns: str
    version: tuple[int, int]

    @property
    def directory(self) -> Path:
        return Path(self.path).parent if self.path else Path.cwd()


@dataclass(slots=True)
class _Node:
    """A frame of the pose graph: a link, a joint, a ``<frame>`` or a model's implicit frame."""

    key: str  # "kind:scoped name"
    name: str  # scoped name ("inner::link")
    kind: str  # "link", "joint", "frame", "model"
    scope: _Scope  # the scope its references resolve in (a model's: its parent's, for its pose)
    file: _File
    elem: Any
    pose: Pose = _IDENTITY
    relative_to: str = ""  # as written ("" = the kind's default)
    pose_elem: Any = None
    attached_to: str = ""  # a <frame>'s, as written


@dataclass(slots=True)
class _Scope:
    """A model: its implicit frame, its names, whether it is static."""

    prefix: str  # "" for the loaded model, "inner::" for a nested one
    file: _File
    elem: Any
    name: str
    static: bool
    model_key: str  # its implicit frame's node
    canonical: str = ""  # canonical_link as written
    links: dict[str, str] = field(default_factory=dict)  # local name -> node key
    joints: dict[str, str] = field(default_factory=dict)
    frames: dict[str, str] = field(default_factory=dict)
    models: dict[str, _Scope] = field(default_factory=dict)
    first_link: str = ""
    first_model: _Scope | None = None

    @property
    def version(self) -> tuple[int, int]:
        return self.file.version


@dataclass(slots=True)
class _JointRec:
    node: _Node
    type: str
    parent: str  # the parent reference as written
    child: str
    # (direction as written, lower, upper, velocity, effort, the frame it is written in: "" the joint's, else a
    # reference resolved in the joint's scope, "__model__" for 1.4-1.6's model frame; the <xyz> element)
    axes: list[tuple[np.ndarray, float, float, float, float, str, Any]]
    parent_link: str = ""  # link node keys, or "world"
    child_link: str = ""
    # per axis: (leader joint as written, leader axis "axis"/"axis2", multiplier, offset, reference, <mimic>) or None
    mimics: list[tuple[str, str, float, float, float, Any] | None] = field(default_factory=list)


# ---------------------------------------------------------------------------
# the reader
# ---------------------------------------------------------------------------


class _Reader:
    """Reads the documents, resolves the frames and builds the model."""

    def __init__(self, strict: bool, search_path: Sequence[str | os.PathLike[str]] | None) -> None:
        self.strict = strict
        self.search: list[Path] = [Path(p) for p in (search_path or ())]
        for var in SEARCH_PATH_VARIABLES:
            self.search += [Path(p) for p in os.environ.get(var, "").split(os.pathsep) if p]
        self.ignored: dict[str, int] = {}  # "<parent>/<child>" -> count
        self.unknown: dict[str, int] = {}
        self.nodes: dict[str, _Node] = {}
        self.links: list[str] = []  # link node keys in document order
        self.joints: list[_JointRec] = []
        self.includes = 0
        self.top: _Scope | None = None
        self.model_pose: Pose = _IDENTITY  # the loaded model's pose in the world
        self.default_inertia: list[str] = []
        self.inertial: dict[str, tuple[float, Pose, np.ndarray] | None] = {}
        self.joint_child_key: dict[str, str] = {}
        self.scope_of: dict[str, _Scope] = {}
        self.caught: list[warnings.WarningMessage] = []
        self.complaints: list[str] = []
        self.label = ""

    # -- messages ----------------------------------------------------------

    @staticmethod
    def where(f: _File, elem: Any, what: str = "") -> str:
        line = f.lines.get(elem)
        return ": ".join([f.label] + ([f"line {line}"] if line else []) + ([what] if what else []))

    def error(self, f: _File, elem: Any, msg: str, what: str = "") -> SDFError:
        if not what and elem is not None:
            what = _describe(elem, f.ns)
        return SDFError(f"{self.where(f, elem, what)}: {msg}")

    def warn(self, msg: str) -> None:
        """A physicality complaint: an error with ``strict=True``, else kept for :func:`load_sdf` to issue."""
        if self.strict:
            raise SDFError(msg + " (strict=True)")
        self.complaints.append(msg)

    # -- documents ---------------------------------------------------------

    def parse(self, path_or_xml: Any) -> tuple[_File, Any]:
        text, label, path = read_source(path_or_xml, SDFError, "SDF", "load_sdf")
        root, lines = parse_xml(text, label, SDFError, "SDF", line_depth=MAX_DEPTH)
        tag = root.tag if isinstance(root.tag, str) else ""
        ns = tag[: tag.index("}") + 1] if tag.startswith("{") else ""
        if local_name(tag, ns) != "sdf":
            hint = {"robot": " (a URDF: use featherdyn.load_urdf or load_model)",
                    "mujoco": " (an MJCF model: use featherdyn.load_mjcf or load_model)"}.get(local_name(tag, ns), "")
            raise SDFError(f"{label}: line {lines.get(root, 1)}: expected the root element <sdf>, "
                           f"got <{shorten(tag)}>{hint}")
        version = root.get("version")
        if version is None:
            raise SDFError(f"{label}: line {lines.get(root, 1)}: <sdf>: missing the attribute 'version' "
                           f"(one of {', '.join(_VERSIONS)})")
        if version.strip() not in _VERSIONS:
            raise SDFError(f"{label}: line {lines.get(root, 1)}: <sdf> version={quote(version)}: expected an "
                           f"SDFormat version featherdyn reads, one of {', '.join(_VERSIONS)}")
        major, minor = version.strip().split(".")
        return _File(label, path, lines, ns, (int(major), int(minor))), root

    def children(self, f: _File, elem: Any, kind: str) -> list[tuple[str, Any]]:
        """The children of ``elem`` (an SDF ``kind`` element) featherdyn reads, in document order; the others are
        counted as ignored (module doc)."""
        read = _READ.get(kind, frozenset())
        out = []
        for c in elem:
            if not isinstance(c.tag, str):
                continue  # a comment or processing instruction
            name = local_name(c.tag, f.ns)
            if name in read:
                out.append((name, c))
            elif name.startswith("{") or name in _KNOWN_IGNORED.get(kind, ()):
                what = f"<{kind}>/<{shorten(name)}>"
                self.ignored[what] = self.ignored.get(what, 0) + 1
            else:
                what = f"<{kind}>/<{shorten(name)}>"
                self.unknown[what] = self.unknown.get(what, 0) + 1
        return out

    def child(self, f: _File, elem: Any, name: str) -> Any:
        for c in elem:
            if isinstance(c.tag, str) and local_name(c.tag, f.ns) == name:
                return c
        return None

    # -- values ------------------------------------------------------------

    def numbers(self, f: _File, elem: Any, count: tuple[int, ...], what: str, bound: tuple[float, str] | None = None,
                allow_inf: bool = False) -> list[float]:
        """The element's text as ``count`` finite decimals (``inf`` too with ``allow_inf``), each at most
        ``bound = (largest, its name)`` in magnitude."""
        text = elem.text or ""
        parts = text.split()
        tag = shorten(local_name(elem.tag, f.ns))
        shown = f"<{tag}>{quote(text.strip())}</{tag}>" if len(text) < 200 else f"<{tag}> text {quote(text)}"
        if len(parts) not in count:
            expected = " or ".join(str(c) for c in count)
            raise self.error(f, elem, f"{shown}: expected {expected} number{'s' if max(count) > 1 else ''}, "
                             f"got {len(parts)}", what)
        out = []
        for s in parts:
            if allow_inf and s.lower() in ("inf", "+inf", "-inf", "infinity", "+infinity", "-infinity"):
                out.append(-math.inf if s.startswith("-") else math.inf)
                continue
            if not _NUMBER.fullmatch(s):
                raise self.error(f, elem, f"{shown}: {quote(s)} is not a decimal number", what)
            x = float(s)
            if not math.isfinite(x):
                raise self.error(f, elem, f"{shown}: {quote(s)} is out of range (not finite)", what)
            if bound is not None and abs(x) > bound[0]:
                raise self.error(f, elem, f"{shown}: expected a magnitude of at most {bound[0]:g} ({bound[1]}: "
                                 f"larger values overflow the dynamics), got {x:g}", what)
            out.append(x)
        return out

    def number(self, f: _File, parent: Any, name: str, default: float | None, what: str,
               bound: tuple[float, str] | None = None, allow_inf: bool = False) -> float:
        """The number in ``parent``'s child ``<name>``, ``default`` if absent (``None``: required)."""
        c = self.child(f, parent, name)
        if c is None:
            if default is None:
                raise self.error(f, parent, f"<{local_name(parent.tag, f.ns)}> needs a <{name}> element", what)
            return default
        return self.numbers(f, c, (1,), what, bound, allow_inf)[0]

    def boolean(self, f: _File, parent: Any, name: str, default: bool, what: str) -> bool:
        c = self.child(f, parent, name)
        if c is None:
            return default
        text = (c.text or "").strip()
        if text.lower() in ("true", "1"):
            return True
        if text.lower() in ("false", "0"):
            return False
        raise self.error(f, c, f"<{name}>{quote(text)}</{name}>: expected true, false, 1 or 0", what)

    def text(self, f: _File, parent: Any, name: str, what: str, required: bool = True) -> str:
        c = self.child(f, parent, name)
        value = (c.text or "").strip() if c is not None else ""
        if not value and required:
            raise self.error(f, c if c is not None else parent,
                             f"needs a non-empty <{name}> element" if c is None else f"<{name}> is empty", what)
        return value

    def pose(self, f: _File, parent: Any, what: str) -> tuple[Pose, str, Any]:
        """``(pose, relative_to as written, the <pose> element)`` of ``parent``'s ``<pose>`` (identity if absent)."""
        elem = self.child(f, parent, "pose")
        if elem is None:
            return _IDENTITY, "", None
        rel = elem.get("relative_to", "") if f.version >= (1, 7) else elem.get("frame", "")
        fmt = elem.get("rotation_format", "euler_rpy")
        if fmt not in ("euler_rpy", "quat_xyzw"):
            raise self.error(f, elem, f"<pose> rotation_format={quote(fmt)}: expected 'euler_rpy' or 'quat_xyzw'", what)
        degrees = elem.get("degrees", "false").strip().lower()
        if degrees not in ("true", "false", "1", "0"):
            raise self.error(f, elem, f"<pose> degrees={quote(degrees)}: expected true, false, 1 or 0", what)
        if not (elem.text or "").strip():
            return _IDENTITY, rel.strip(), elem  # SDFormat's default: "0 0 0 0 0 0"
        if fmt == "euler_rpy":
            values = self.numbers(f, elem, (6,), what)
            rpy = np.array(values[3:])
            if degrees in ("true", "1"):
                rpy = np.radians(rpy)
            R = np.asarray(rpy_to_matrix(rpy), dtype=np.float64)
        else:
            values = self.numbers(f, elem, (7,), what)
            quat = np.array(values[3:])
            norm = float(np.linalg.norm(quat))
            if not norm > 1e-12:
                raise self.error(f, elem, f"<pose> quaternion {values[3:]}: expected a non-zero quaternion "
                                 "(x y z w)", what)
            R = np.asarray(quat_to_matrix(quat / norm), dtype=np.float64)
        p = np.array(values[:3])
        if np.abs(p).max() > MAX_LENGTH:
            raise self.error(f, elem, f"<pose> position {values[:3]}: expected each at most {MAX_LENGTH:g} "
                             "(MAX_LENGTH: larger values overflow the dynamics)", what)
        return (R, p), rel.strip(), elem

    # -- models ------------------------------------------------------------

    def candidates(self, f: _File, root: Any) -> list[tuple[str, _File, Any, Any]]:
        """Every model the document offers: ``(name, its file, its <model>, the <include> that brought it or None)``."""
        out: list[tuple[str, _File, Any, Any]] = []
        for kind, elem in self.children(f, root, "sdf"):
            if kind == "model":
                out.append((self.model_name(f, elem), f, elem, None))
                continue
            for wkind, inner in self.children(f, elem, "world"):
                if wkind == "model":
                    out.append((self.model_name(f, inner), f, inner, None))
                else:
                    g, model_el = self.included(f, inner, [])
                    name = self.text(f, inner, "name", "<include>", required=False) or self.model_name(g, model_el)
                    out.append((name, g, model_el, inner))
        return out

    def model_name(self, f: _File, elem: Any) -> str:
        name = elem.get("name")
        if name is None or not name.strip():
            raise self.error(f, elem, "missing or empty 'name' attribute", "<model>")
        if "::" in name:
            raise self.error(f, elem, f"name={quote(name)}: '::' separates scopes and is not allowed in a name",
                             "<model>")
        return name

    def read_model(self, f: _File, elem: Any, prefix: str, name: str, parent: _Scope | None,
                   include: tuple[_File, Any] | None, chain: list[str]) -> _Scope:
        """Read a ``<model>`` (and what it nests) into the node table; returns its scope. ``include``: the file and
        ``<include>`` element that brought it (its ``<pose>`` and ``<static>`` replace the model's own)."""
        what = f"<model name={quote(name)}>"
        static = self.boolean(f, elem, "static", False, what)
        pose, rel, pose_el = self.pose(f, elem, what)
        pose_file = f
        if include is not None:
            inc_file, inc = include
            static = self.boolean(inc_file, inc, "static", static, what)
            rel = ""  # a relative_to of the included file names nothing in the includer's scope
            if self.child(inc_file, inc, "pose") is not None:
                pose, rel, pose_el = self.pose(inc_file, inc, what)
                pose_file = inc_file
        if elem.get("placement_frame"):
            raise self.error(f, elem, "placement_frame is not supported by featherdyn (give the model's pose "
                             "directly)", what)
        scope = _Scope(prefix, f, elem, name, static or (parent is not None and parent.static),
                       model_key=f"model:{prefix[:-2] if prefix else '__model__'}",
                       canonical=(elem.get("canonical_link") or "").strip() if f.version >= (1, 7) else "")
        if parent is None:  # the loaded model: its pose is in the world
            if rel not in ("", _WORLD):
                raise self.error(pose_file, pose_el, f"<pose> relative_to={quote(rel)}: the loaded model's pose can "
                                 "only be relative to the world", what)
            self.model_pose = pose
        else:  # a nested model: its frame is a node of the parent's scope
            node = _Node(scope.model_key, prefix[:-2], "model", parent, pose_file, elem, pose, rel, pose_el)
            self.add_node(node, parent, name, "models")
            parent.models[name] = scope
            if parent.first_model is None:
                parent.first_model = scope
        for kind, c in self.children(f, elem, "model"):
            if kind == "link":
                self.read_link(scope, c)
            elif kind == "joint":
                self.read_joint(scope, c)
            elif kind == "frame":
                self.read_frame(scope, c)
            elif kind == "model":
                if f.version < (1, 5):
                    raise self.error(f, c, "nested models need SDFormat 1.5 or later", what)
                inner = self.model_name(f, c)
                self.read_model(f, c, f"{prefix}{inner}::", inner, scope, None, chain)
            elif kind == "include":
                g, model_el = self.included(f, c, chain)
                inner = self.text(f, c, "name", "<include>", required=False) or self.model_name(g, model_el)
                if "::" in inner:
                    raise self.error(f, c, f"<name>{quote(inner)}</name>: '::' is not allowed in a name", "<include>")
                self.read_model(g, model_el, f"{prefix}{inner}::", inner, scope, (f, c),
                                [*chain, f.path or f.label])
        return scope

    def add_node(self, node: _Node, scope: _Scope, local: str, table: str) -> None:
        names = (scope.links, scope.joints, scope.frames, scope.models)
        # SDFormat 1.7+: names are unique among a model's links, joints, frames and nested models
        clash = [t for t in names if local in t]
        if clash and (scope.version >= (1, 7) or local in getattr(scope, table)):
            kind = node.kind if node.kind != "model" else "nested model"
            raise self.error(node.file, node.elem, f"the name {quote(local)} is used twice in <model "
                             f"name={quote(scope.name)}> (a {kind} and an earlier element: names of links, joints, "
                             "frames and nested models must be unique in their model)")
        if table != "models":
            getattr(scope, table)[local] = node.key
        self.nodes[node.key] = node

    def read_link(self, scope: _Scope, elem: Any) -> None:
        f = scope.file
        name = self.local_name_of(f, elem, "link")
        what = f"<link name={quote(name)}>"
        node = _Node(f"link:{scope.prefix}{name}", scope.prefix + name, "link", scope, f, elem)
        node.pose, node.relative_to, node.pose_elem = self.pose(f, elem, what)
        self.add_node(node, scope, name, "links")
        self.links.append(node.key)
        if not scope.first_link:
            scope.first_link = node.key
        self.inertial[node.key] = self.read_inertial(f, elem, what)

    def read_inertial(self, f: _File, link: Any, what: str) -> tuple[float, Pose, np.ndarray] | None:
        """``(mass, pose of the inertia's frame in the link, tensor about the centre of mass)``, ``None`` for SDFormat's
        default (no ``<inertial>``)."""
        self.children(f, link, "link")
        elem = self.child(f, link, "inertial")
        if elem is None:
            return None
        if (elem.get("auto") or "").strip().lower() in ("true", "1"):
            raise self.error(f, elem, "<inertial auto=\"true\">: inertia computed from the collision geometry is "
                             "not supported by featherdyn; give <mass> and <inertia>", what)
        self.children(f, elem, "inertial")
        mass = self.number(f, elem, "mass", 1.0, what, (MAX_MASS, "MAX_MASS"))
        if mass < 0:
            raise self.error(f, self.child(f, elem, "mass"), f"<mass>: expected a mass >= 0, got {mass:g}", what)
        pose, rel, pose_el = self.pose(f, elem, what)
        if rel:
            raise self.error(f, pose_el, f"<inertial><pose relative_to={quote(rel)}>: an inertial pose is relative "
                             "to its link (SDFormat); relative_to is not supported there", what)
        inertia = self.child(f, elem, "inertia")
        if inertia is None:
            tensor = np.eye(3)  # SDFormat's default
        else:
            self.children(f, inertia, "inertia")
            for k in ("ixx", "iyy", "izz"):
                if self.child(f, inertia, k) is None:
                    raise self.error(f, inertia, f"<inertia> needs <{k}> (the moments ixx, iyy, izz are required; "
                                     "libsdformat would silently take 1 kg·m²)", what)
            ixx, ixy, ixz, iyy, iyz, izz = (self.number(f, inertia, k, 0.0, what, (MAX_INERTIA, "MAX_INERTIA"))
                                            for k in _INERTIA_KEYS)
            tensor = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        largest = float(np.abs(tensor).max())
        if 0 < max(mass, largest) < MIN_INERTIAL:
            raise self.error(f, elem, f"<inertial>: expected 0 (a massless link) or a mass or inertia entry of at "
                             f"least {MIN_INERTIAL:g} (MIN_INERTIAL: forward dynamics divides by it), got mass "
                             f"{mass:g} and inertia entries of at most {largest:g}", what)
        self.check_inertia(f, elem, what, mass, tensor)
        return mass, pose, tensor

    def check_inertia(self, f: _File, elem: Any, what: str, mass: float, tensor: np.ndarray) -> None:
        ev = np.linalg.eigvalsh(tensor)
        scale = float(np.abs(ev).max())
        if scale == 0:
            return
        tol = URDF_INERTIA_RTOL * scale
        moments = ", ".join(f"{e:.6g}" for e in ev)
        if mass == 0:
            self.warn(f"{self.where(f, elem, what)}: zero mass but non-zero rotational inertia (principal moments "
                      f"{moments})")
        elif ev[0] < -tol:
            self.warn(f"{self.where(f, elem, what)}: inertia is not positive semi-definite (principal moments "
                      f"{moments})")
        elif ev[0] + ev[1] < ev[2] - tol:
            self.warn(f"{self.where(f, elem, what)}: principal moments violate the triangle inequality "
                      f"I1 + I2 >= I3 ({moments})")

    def local_name_of(self, f: _File, elem: Any, kind: str) -> str:
        name = elem.get("name")
        if name is None or not name.strip():
            raise self.error(f, elem, "missing or empty 'name' attribute", f"<{kind}>")
        if "::" in name:
            raise self.error(f, elem, f"name={quote(name)}: '::' separates scopes and is not allowed in a name",
                             f"<{kind}>")
        if f.version >= (1, 7) and (name == _WORLD or (name.startswith("__") and name.endswith("__"))):
            raise self.error(f, elem, f"name={quote(name)}: the name is reserved by SDFormat", f"<{kind}>")
        return name

    def read_frame(self, scope: _Scope, elem: Any) -> None:
        f = scope.file
        name = self.local_name_of(f, elem, "frame")
        what = f"<frame name={quote(name)}>"
        self.children(f, elem, "frame")
        node = _Node(f"frame:{scope.prefix}{name}", scope.prefix + name, "frame", scope, f, elem,
                     attached_to=(elem.get("attached_to") or "").strip())
        node.pose, node.relative_to, node.pose_elem = self.pose(f, elem, what)
        self.add_node(node, scope, name, "frames")

    def read_joint(self, scope: _Scope, elem: Any) -> None:
        f = scope.file
        name = self.local_name_of(f, elem, "joint")
        what = f"<joint name={quote(name)}>"
        self.children(f, elem, "joint")
        jtype = elem.get("type")
        if jtype is None:
            raise self.error(f, elem, "missing the attribute 'type' (one of " + ", ".join(_JOINT_TYPES) + ")", what)
        if jtype in _REFUSED_TYPES:
            raise self.error(f, elem, f"type={quote(jtype)} is not supported: {_REFUSED_TYPES[jtype]}", what)
        if jtype not in _JOINT_TYPES:
            raise self.error(f, elem, f"type={quote(jtype)}: unknown joint type; expected one of "
                             + ", ".join(_JOINT_TYPES), what)
        parent = self.text(f, elem, "parent", what)
        child = self.text(f, elem, "child", what)
        node = _Node(f"joint:{scope.prefix}{name}", scope.prefix + name, "joint", scope, f, elem)
        node.pose, node.relative_to, node.pose_elem = self.pose(f, elem, what)
        self.add_node(node, scope, name, "joints")
        names = {"revolute": ("axis",), "continuous": ("axis",), "prismatic": ("axis",),
                 "universal": ("axis", "axis2"), "revolute2": ("axis", "axis2")}.get(jtype, ())
        axes = [self.read_axis(scope, elem, tag, jtype, what) for tag in names]
        mimics = [self.read_mimic(f, self.child(f, elem, tag), what) for tag in names]
        self.joints.append(_JointRec(node, jtype, parent, child, axes, mimics=mimics))

    def read_mimic(self, f: _File, axis: Any, what: str) -> tuple[str, str, float, float, float, Any] | None:
        """An axis's ``<mimic joint axis>`` (SDFormat 1.11): ``follower = multiplier (leader − reference) + offset``."""
        elem = None if axis is None else self.child(f, axis, "mimic")
        if elem is None:
            return None
        self.children(f, elem, "mimic")
        leader = (elem.get("joint") or "").strip()
        if not leader:
            raise self.error(f, elem, "<mimic> needs a non-empty 'joint' attribute", what)
        leader_axis = (elem.get("axis") or "axis").strip()
        if leader_axis not in ("axis", "axis2"):
            raise self.error(f, elem, f"<mimic> axis={quote(leader_axis)}: expected 'axis' or 'axis2'", what)
        return (leader, leader_axis, self.number(f, elem, "multiplier", 1.0, what),
                self.number(f, elem, "offset", 0.0, what), self.number(f, elem, "reference", 0.0, what), elem)

    def read_axis(self, scope: _Scope, joint: Any, tag: str, jtype: str,
                  what: str) -> tuple[np.ndarray, float, float, float, float, str, Any]:
        """The axis as written, its limits and the frame it is written in (:class:`_JointRec`); the direction is
        turned into the joint frame once the poses are known (:meth:`axis_in_joint`)."""
        f = scope.file
        elem = self.child(f, joint, tag)
        if elem is None:
            if f.version < (1, 7):
                raise self.error(f, joint, f"a {jtype} joint needs an <{tag}> element (SDFormat {f.version[0]}."
                                 f"{f.version[1]})", what)
            return np.array([0.0, 0.0, 1.0]), -math.inf, math.inf, math.inf, math.inf, "", None
        self.children(f, elem, "axis")
        xyz_el = self.child(f, elem, "xyz")
        xyz = np.array([0.0, 0.0, 1.0]) if xyz_el is None else np.array(self.numbers(f, xyz_el, (3,), what))
        largest = float(np.abs(xyz).max())
        scaled = xyz / largest if largest > 0 else xyz
        length = largest * float(np.linalg.norm(scaled))
        if length < 1e-12:
            raise self.error(f, xyz_el, f"<{tag}><xyz> {xyz.tolist()}: expected a direction, got a zero-length axis",
                             what)
        if abs(length - 1.0) > UNIT_AXIS:
            self.warn(f"{self.where(f, xyz_el, what)}: <{tag}><xyz> {xyz.tolist()} has length {length:.6g}; "
                      "normalised")
        limit = self.child(f, elem, "limit")
        lower, upper, velocity, effort = -math.inf, math.inf, math.inf, math.inf
        if limit is not None:
            self.children(f, limit, "limit")
            bound = (MAX_LENGTH, "MAX_LENGTH")
            lower = self.number(f, limit, "lower", -math.inf, what, bound, allow_inf=True)
            upper = self.number(f, limit, "upper", math.inf, what, bound, allow_inf=True)
            velocity = self.number(f, limit, "velocity", math.inf, what, allow_inf=True)
            effort = self.number(f, limit, "effort", math.inf, what, allow_inf=True)
            velocity = math.inf if velocity < 0 else velocity  # negative: not enforced (SDFormat)
            effort = math.inf if effort < 0 else effort
        dynamics = self.child(f, elem, "dynamics")
        if dynamics is not None:  # checked, not modelled (the model has no joint damping or friction)
            self.children(f, dynamics, "dynamics")
            for k in ("damping", "friction"):
                self.number(f, dynamics, k, 0.0, what)
        if f.version < (1, 5):
            frame = "__model__"  # SDFormat 1.4: the axis is in the model frame
        elif f.version < (1, 7):
            frame = "__model__" if self.boolean(f, elem, "use_parent_model_frame", False, what) else ""
        else:
            frame = (xyz_el.get("expressed_in") or "").strip() if xyz_el is not None else ""
        return scaled / float(np.linalg.norm(scaled)), lower, upper, velocity, effort, frame, xyz_el

    # -- includes ----------------------------------------------------------

    def included(self, f: _File, inc: Any, chain: list[str]) -> tuple[_File, Any]:
        """The file an ``<include>`` names, parsed, and its one ``<model>``."""
        what = "<include>"
        self.children(f, inc, "include")
        if (inc.get("merge") or "").strip().lower() in ("true", "1"):
            raise self.error(f, inc, "merge=\"true\" is not supported by featherdyn (include the model nested)", what)
        if self.child(f, inc, "placement_frame") is not None:
            raise self.error(f, inc, "<placement_frame> is not supported by featherdyn (give the <pose> directly)", what)
        uri = self.text(f, inc, "uri", what)
        path = self.resolve_uri(f, inc, uri, what)
        key = str(path.resolve())
        here = [*chain, f.path or f.label]
        if key in (str(Path(c).resolve()) for c in here if c and not c.startswith("<")):
            raise self.error(f, inc, f"<uri>{quote(uri)}</uri>: include cycle ({' -> '.join(here)} -> {path})", what)
        if len(here) > MAX_INCLUDE_DEPTH:
            raise self.error(f, inc, f"includes nested deeper than {MAX_INCLUDE_DEPTH} files (MAX_INCLUDE_DEPTH)", what)
        self.includes += 1
        if self.includes > MAX_INCLUDES:
            raise self.error(f, inc, f"more than {MAX_INCLUDES} included files (MAX_INCLUDES)", what)
        g, root = self.parse(str(path))
        models = [c for kind, c in self.children(g, root, "sdf") if kind == "model"]
        if len(models) != 1:
            raise SDFError(f"{g.label}: an included file must hold exactly one <model> (as a direct child of <sdf>), "
                           f"found {len(models)} (included by {self.where(f, inc, what)})")
        return g, models[0]

    def resolve_uri(self, f: _File, inc: Any, uri: str, what: str) -> Path:
        """The file of an include URI (a model directory's main file)."""
        scheme = uri.split("://", 1)[0].lower() if "://" in uri else ""
        if scheme == "model":
            rest = uri.split("://", 1)[1]
            name, _, sub = rest.partition("/")
            tried = []
            for d in self.search:
                candidate = d / name / sub if sub else d / name
                tried.append(str(d))
                if candidate.exists():
                    return self.model_file(f, inc, candidate, uri, what)
            where = ", ".join(tried) if tried else "no directories (search_path is empty and " + \
                " and ".join(SEARCH_PATH_VARIABLES) + " are unset)"
            raise self.error(f, inc, f"<uri>{quote(uri)}</uri>: no model {quote(name)} found in {where}", what)
        if scheme == "file":
            path = Path(uri.split("://", 1)[1])
        elif scheme:
            raise self.error(f, inc, f"<uri>{quote(uri)}</uri>: the scheme {quote(scheme)} is not supported "
                             "(expected model://, file:// or a path; network URIs are not fetched)", what)
        else:
            path = Path(uri)
        if not path.is_absolute():
            path = f.directory / path
        if not path.exists():
            raise self.error(f, inc, f"<uri>{quote(uri)}</uri>: no such file or directory: {path}", what)
        return self.model_file(f, inc, path, uri, what)

    def model_file(self, f: _File, inc: Any, path: Path, uri: str, what: str) -> Path:
        """``path``, or for a model directory the SDF file its ``model.config`` names (else its ``model.sdf``)."""
        if not path.is_dir():
            return path
        config = path / "model.config"
        if config.is_file():
            text, label, _ = read_source(str(config), SDFError, "model.config", "load_sdf")
            root, _ = parse_xml(text, label, SDFError, "model.config")
            best: tuple[tuple[int, ...], str] | None = None
            for e in root.iter():
                if isinstance(e.tag, str) and e.tag.rsplit("}", 1)[-1] == "sdf" and (e.text or "").strip():
                    v = tuple(int(x) for x in re.findall(r"\d+", e.get("version", "0")))
                    if best is None or v > best[0]:
                        best = (v, (e.text or "").strip())
            if best is None:
                raise self.error(f, inc, f"<uri>{quote(uri)}</uri>: {label} names no <sdf> file", what)
            return path / best[1]
        if (path / "model.sdf").is_file():
            return path / "model.sdf"
        raise self.error(f, inc, f"<uri>{quote(uri)}</uri>: the directory {path} has neither model.config nor "
                         "model.sdf", what)

    # -- frames ------------------------------------------------------------

    def resolve(self, scope: _Scope, ref: str, f: _File, elem: Any, what: str, attr: str,
                world: bool = False) -> str:
        """The node key a reference names in ``scope``: ``__model__``, a local name, ``inner::name``, or
        ``world`` where ``world`` allows it."""
        if ref == _WORLD and world:
            return _WORLD
        s, rest = scope, ref
        while "::" in rest:
            head, rest = rest.split("::", 1)
            if head not in s.models:
                raise self.error(f, elem, f"{attr} {quote(ref)}: no nested model {quote(head)} in <model "
                                 f"name={quote(s.name)}>", what)
            s = s.models[head]
        if rest == "__model__":
            return s.model_key
        for table in (s.links, s.frames, s.joints):
            if rest in table:
                return table[rest]
        if rest in s.models:
            return s.models[rest].model_key
        known = sorted([*s.links, *s.frames, *s.joints, *s.models])
        shown = ", ".join(quote(k) for k in known[:10]) + (", ..." if len(known) > 10 else "")
        hint = " ('world' is only a joint's parent here)" if ref == _WORLD else ""
        raise self.error(f, elem, f"{attr} {quote(ref)}: no link, joint, frame or model of that name in <model "
                         f"name={quote(s.name)}> (its names: {shown or 'none'}){hint}", what)

    def node_what(self, node: _Node) -> str:
        return f"<{node.kind} name={quote(node.name)}>"

    def relative_key(self, node: _Node) -> str:
        """The node ``node``'s pose is relative to."""
        what = self.node_what(node)
        if node.relative_to:
            return self.resolve(node.scope, node.relative_to, node.file, node.pose_elem, what, "relative_to")
        if node.kind == "joint":
            return self.joint_child_key[node.key]
        if node.kind == "frame" and node.attached_to:
            return self.resolve(node.scope, node.attached_to, node.file, node.elem, what, "attached_to")
        return node.scope.model_key

    def poses(self) -> dict[str, Pose]:
        """Every node's pose in the loaded model's frame (SDFormat's pose graph, resolved along ``relative_to``)."""
        assert self.top is not None
        X: dict[str, Pose] = {self.top.model_key: _IDENTITY, _WORLD: _inverse(self.model_pose)}
        for start in self.nodes:
            chain: list[str] = []
            key = start
            while key not in X:
                if key in chain:
                    loop = chain[chain.index(key):] + [key]
                    node = self.nodes[key]
                    raise self.error(node.file, node.pose_elem or node.elem, "the poses' relative_to form a cycle: "
                                     + " -> ".join(quote(self.nodes[k].name) for k in loop), self.node_what(node))
                chain.append(key)
                key = self.relative_key(self.nodes[key])
            for k in reversed(chain):
                rel = self.relative_key(self.nodes[k])
                X[k] = _compose(X[rel], self.nodes[k].pose)
        return X

    def attached_link(self, key: str) -> str:
        """The link node (or ``world``) a node is fixed to: SDFormat's attached-to graph."""
        seen: list[str] = []
        while True:
            if key == _WORLD or key.startswith("link:"):
                return key
            if key in seen:
                looped = self.nodes[key]
                raise self.error(looped.file, looped.elem, "attached_to forms a cycle: "
                                 + " -> ".join(quote(self.nodes[k].name) for k in [*seen, key]),
                                 self.node_what(looped))
            seen.append(key)
            if key.startswith("joint:"):
                key = self.joint_child_key[key]
            elif key.startswith("frame:"):
                node = self.nodes[key]
                key = (self.resolve(node.scope, node.attached_to, node.file, node.elem, self.node_what(node),
                                    "attached_to") if node.attached_to else node.scope.model_key)
            else:  # a model's frame: its canonical link
                scope = self.scope_of[key]
                if scope.static:
                    return _WORLD
                if scope.canonical:
                    key = self.resolve(scope, scope.canonical, scope.file, scope.elem, f"<model name={quote(scope.name)}>",
                                       "canonical_link")
                elif scope.first_link:
                    key = scope.first_link
                elif scope.first_model is not None:
                    key = scope.first_model.model_key
                else:
                    raise self.error(scope.file, scope.elem, "the model has no link (a model frame needs a canonical "
                                     "link)", f"<model name={quote(scope.name)}>")

    # -- the whole -----------------------------------------------------------

    def load(self, path_or_xml: Any, model: str | None) -> tuple[Model, str]:
        f, root = self.parse(path_or_xml)
        self.label = f.label
        found = self.candidates(f, root)
        if not found:
            raise SDFError(f"{f.label}: the document holds no <model> (directly or in a <world>)")
        names = [n for n, *_ in found]
        if model is None:
            if len(found) > 1:
                raise SDFError(f"{f.label}: the document holds {len(found)} models ({', '.join(map(quote, names))}); "
                               "pick one with model=NAME")
            pick = found[0]
        else:
            matches = [c for c in found if c[0] == model]
            if not matches:
                raise SDFError(f"{f.label}: model={quote(model)}: no such model; the document holds "
                               + ", ".join(map(quote, names)))
            if len(matches) > 1:
                raise SDFError(f"{f.label}: model={quote(model)}: {len(matches)} models have that name")
            pick = matches[0]
        name, g, elem, include = pick
        self.top = self.read_model(g, elem, "", name, None, None if include is None else (f, include),
                                   [] if include is None else [f.path or f.label])
        self.scope_of = {s.model_key: s for s in _scopes(self.top)}
        # joints' ends (a frame or a nested model names the link it is attached to)
        for j in self.joints:
            what = self.node_what(j.node)
            if j.child == _WORLD:
                raise self.error(j.node.file, j.node.elem, "<child>world</child>: the world cannot be a child", what)
            self.joint_child_key[j.node.key] = self.resolve(j.node.scope, j.child, j.node.file, j.node.elem, what,
                                                            "<child>")
        for j in self.joints:
            what = self.node_what(j.node)
            j.parent_link = self.attached_link(self.resolve(j.node.scope, j.parent, j.node.file, j.node.elem, what,
                                                            "<parent>", world=True))
            j.child_link = self.attached_link(self.joint_child_key[j.node.key])
            if j.child_link == _WORLD:
                raise self.error(j.node.file, j.node.elem, f"<child>{quote(j.child)}</child> is fixed to the world "
                                 "(a static model): it cannot be a joint's child", what)
        X = self.poses()
        return self.build(f, name, X), f.label

    def build(self, f: _File, name: str, X: dict[str, Pose]) -> Model:
        """The model of the resolved tree."""
        parent_joint: dict[str, _JointRec] = {}
        children: dict[str, list[_JointRec]] = {k: [] for k in [*self.links, _WORLD]}
        for j in self.joints:
            what = self.node_what(j.node)
            if j.type != "fixed" and j.node.scope.static:
                raise self.error(j.node.file, j.node.elem, f"type={quote(j.type)} in a static model: only fixed joints "
                                 "are permitted there (as Drake says; Gazebo does not move them)", what)
            if j.parent_link == j.child_link:
                raise self.error(j.node.file, j.node.elem, f"parent and child are the same link "
                                 f"{quote(self.nodes[j.child_link].name)} (a loop)", what)
            if j.child_link in parent_joint:
                other = parent_joint[j.child_link].node
                raise self.error(j.node.file, j.node.elem, f"link {quote(self.nodes[j.child_link].name)} has two "
                                 f"parents (joints {quote(other.name)} and {quote(j.node.name)}): a kinematic loop, "
                                 "which a featherdyn model (a tree) cannot hold", what)
            parent_joint[j.child_link] = j
            children[j.parent_link].append(j)
        roots = [k for k in self.links if k not in parent_joint]
        free = [k for k in roots if self.attached_link(self.nodes[k].scope.model_key) != _WORLD]
        b = ModelBuilder(name)
        b.source = f.path
        taken = {self.nodes[k].name for k in [*self.links, *(j.node.key for j in self.joints)]}
        body_of: dict[str, int] = {}  # link key -> body index (-1: the world)
        in_body: dict[str, Pose] = {}  # link key -> the link's pose in its body's frame
        X_world_model = self.model_pose
        order: list[str] = []
        frames: list[tuple[str, int, Pose, str]] = []  # (name, body, placement, kind), made FrameInfo at once

        def visit(start: list[_JointRec]) -> None:
            stack = list(reversed(start))
            while stack:
                j = stack.pop()
                self.add_joint(b, j, X, body_of, in_body, frames)
                order.append(j.child_link)
                stack.extend(reversed(children[j.child_link]))

        for key in self.links:
            link = self.nodes[key]
            if key in parent_joint:
                continue
            if key in free:
                joint = "root_joint" if len(free) == 1 else f"{link.name}/root_joint"
                while joint in taken:
                    joint += "_"
                body_of[key] = b.add_body(link.name, -1, FreeFlyerJoint(), inertia=self.link_inertia(key, _IDENTITY),
                                          joint_name=joint)
                in_body[key] = _IDENTITY
                frames.append((joint, body_of[key], _IDENTITY, "joint"))
                frames.append((link.name, body_of[key], _IDENTITY, "body"))
            else:  # welded to the world at its pose: its inertia is dropped
                body_of[key] = -1
                in_body[key] = _compose(X_world_model, X[key])
                frames.append((link.name, -1, in_body[key], "link"))
            visit(children[key])
        # joints hanging on the world, in document order
        in_body[_WORLD] = _IDENTITY
        body_of[_WORLD] = -1
        visit(children[_WORLD])
        missing = [k for k in self.links if k not in body_of]
        if missing:  # a cycle of joints with no root
            first = self.nodes[missing[0]]
            raise self.error(first.file, first.elem, "the joints form a cycle through this link (every link of the "
                             "cycle has a parent joint): a kinematic loop, which a featherdyn model cannot hold",
                             self.node_what(first))
        # <frame>s, fixed to their links' bodies
        for key, node in self.nodes.items():
            if node.kind != "frame":
                continue
            on = self.attached_link(key)
            frames.append((node.name, body_of[on], _compose(in_body[on], _compose(_inverse(X[on]), X[key])), "frame"))
        for m in self.mimic_records():
            b.add_mimic(m)
        if self.default_inertia:
            shown = ", ".join(quote(n) for n in self.default_inertia[:10])
            more = f" and {len(self.default_inertia) - 10} more" if len(self.default_inertia) > 10 else ""
            self.warn(f"{f.label}: moving links without <inertial> take SDFormat's default, 1 kg with a unit "
                      f"inertia (1 kg·m²) at the link origin: {shown}{more}")
        if frames:  # the placements as one batch of transforms (one check of the rotations)
            X_frames = PluckerTransform(np.stack([pose[0] for _, _, pose, _ in frames]),
                                        np.stack([pose[1] for _, _, pose, _ in frames]))
            b._append_frames([FrameInfo(name, body, X_frames[k], kind)
                              for k, (name, body, _, kind) in enumerate(frames)])
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", PhysicalityWarning)
            model = b.build(strict=self.strict)
        self.caught = list(caught)
        return model

    def mimic_records(self) -> list[Mimic]:
        """Each ``<mimic>`` as a :class:`~featherdyn.Mimic` between featherdyn joints (recorded, not enforced, as
        the URDF loader records them): ``q_follower = multiplier · q_leader + (offset − multiplier · reference)``."""
        out = []
        by_key = {j.node.key: j for j in self.joints}
        for j in self.joints:
            for k, mimic in enumerate(j.mimics):
                if mimic is None:
                    continue
                leader, leader_axis, multiplier, offset, reference, elem = mimic
                what = self.node_what(j.node)
                key = self.resolve(j.node.scope, leader, j.node.file, elem, what, "<mimic> joint")
                other = by_key.get(key)
                if other is None or other.type not in ("revolute", "continuous", "prismatic", "universal",
                                                       "revolute2"):
                    raise self.error(j.node.file, elem, f"<mimic> joint={quote(leader)}: expected a moving joint "
                                     "with an axis", what)
                if leader_axis == "axis2" and len(other.axes) < 2:
                    raise self.error(j.node.file, elem, f"<mimic> axis='axis2': joint {quote(leader)} has one axis",
                                     what)
                if other is j and (leader_axis == "axis") == (k == 0):
                    raise self.error(j.node.file, elem, "<mimic>: the axis mimics itself", what)
                out.append(Mimic(self.axis_joint_name(j, k), self.axis_joint_name(other, int(leader_axis == "axis2")),
                                 multiplier, offset - multiplier * reference))
        return out

    @staticmethod
    def axis_joint_name(j: _JointRec, k: int) -> str:
        """The featherdyn joint of a joint's ``k``-th axis (``J``, or ``J/axis``, ``J/axis2`` for two axes)."""
        return j.node.name if len(j.axes) == 1 else f"{j.node.name}/{('axis', 'axis2')[k]}"

    def link_inertia(self, key: str, X_body_link: Pose) -> SpatialInertia:
        """The link's inertia in its body's frame; SDFormat's default (1 kg, unit inertia) without ``<inertial>``."""
        data = self.inertial[key]
        if data is None:
            self.default_inertia.append(self.nodes[key].name)
            data = (1.0, _IDENTITY, np.eye(3))
        mass, (R, p), tensor = data
        inertia = SpatialInertia(mass, p, R @ tensor @ R.T)
        return _plucker(X_body_link).apply(inertia) if X_body_link is not _IDENTITY else inertia

    def add_joint(self, b: ModelBuilder, j: _JointRec, X: dict[str, Pose], body_of: dict[str, int],
                  in_body: dict[str, Pose], frames: list[tuple[str, int, Pose, str]]) -> None:
        """Add the joint ``j`` and its child link (the parent is added)."""
        P, C, J = j.parent_link, j.child_link, j.node.key
        body = body_of[P]
        # the joint frame in the parent's body: X_body_P ∘ X_P_J (poses at the model's initial configuration)
        X_body_J = _compose(in_body[P], _compose(_inverse(X[P]), X[J]))
        X_J_C = _compose(_inverse(X[J]), X[C])
        child = self.nodes[C].name
        if j.type == "fixed":
            frames.append((j.node.name, body, X_body_J, "fixed_joint"))
            in_body[C] = _compose(X_body_J, X_J_C)
            body_of[C] = body
            frames.append((child, body, in_body[C], "link"))
            if body >= 0:
                b.add_inertia(body, self.link_inertia(C, in_body[C]))
            return
        axes = [self.axis_in_joint(j, k, X) for k in range(len(j.axes))]
        inertia = self.link_inertia(C, X_J_C)
        if j.type == "ball":
            body_of[C] = b.add_body(child, body, SphericalJoint(), placement=_plucker(X_body_J), inertia=inertia,
                                    joint_name=j.node.name)
            frames.append((j.node.name, body_of[C], _IDENTITY, "joint"))
        elif len(axes) == 2:  # universal, revolute2: two revolute joints through a massless carrier
            (a1, lo1, hi1, v1, e1), (a2, lo2, hi2, v2, e2) = axes
            names = (f"{j.node.name}/axis", f"{j.node.name}/axis2")
            carrier = f"{child}#0"
            b._extend([carrier], [body], [RevoluteJoint(a1)], [names[0]], [X_body_J[0].ravel()], [X_body_J[1]],
                      [0.0], [np.zeros(3)], [np.zeros(9)], [np.array([lo1])], [np.array([hi1])], [np.array([v1])],
                      [np.array([e1])], [np.zeros(1)], (carrier,))
            mid = b.nbodies - 1
            frames.append((names[0], mid, _IDENTITY, "joint"))
            body_of[C] = b.add_body(child, mid, RevoluteJoint(a2), inertia=inertia, joint_name=names[1],
                                    lower=lo2, upper=hi2, velocity_limit=v2, effort_limit=e2)
            frames.append((names[1], body_of[C], _IDENTITY, "joint"))
        else:
            a, lo, hi, vel, eff = axes[0]
            bounded = j.type != "continuous"
            joint: Joint = PrismaticJoint(a) if j.type == "prismatic" else RevoluteJoint(a)
            body_of[C] = b.add_body(child, body, joint, placement=_plucker(X_body_J), inertia=inertia,
                                    joint_name=j.node.name, lower=lo if bounded else None,
                                    upper=hi if bounded else None, velocity_limit=vel, effort_limit=eff)
            frames.append((j.node.name, body_of[C], _IDENTITY, "joint"))
        in_body[C] = X_J_C
        frames.append((child, body_of[C], X_J_C, "body"))

    def axis_in_joint(self, j: _JointRec, k: int, X: dict[str, Pose]) -> tuple[np.ndarray, float, float, float, float]:
        """The joint's ``k``-th axis in the joint frame (``a_J = R_Jᵀ R_E a_E`` for an axis written in frame E) and its
        limits."""
        axis, lo, hi, vel, eff, frame, xyz_el = j.axes[k]
        if frame:
            key = self.resolve(j.node.scope, frame, j.node.file, xyz_el, self.node_what(j.node), "expressed_in")
            axis = X[j.node.key][0].T @ (X[key][0] @ axis)
        return axis, lo, hi, vel, eff


def _scopes(scope: _Scope) -> Iterable[_Scope]:
    yield scope
    for inner in scope.models.values():
        yield from _scopes(inner)


def _describe(elem: Any, ns: str) -> str:
    tag = local_name(elem.tag, ns) if isinstance(elem.tag, str) else ""
    name = elem.get("name")
    return f"<{shorten(tag)} name={quote(name)}>" if name is not None else f"<{shorten(tag)}>"


def load_sdf(path_or_xml: str | os.PathLike[str] | bytes, model: str | None = None, strict: bool = False, *,
             search_path: Sequence[str | os.PathLike[str]] | None = None) -> Model:
    """Load a model of an SDFormat (SDF) document (module doc: what is read and what is ignored).

    Args:
        path_or_xml: a file path, an XML string (starting with ``<``) or bytes.
        model: the name of the model to load when the document holds several
            (in a ``<world>``, directly or by ``<include>``); ``None`` loads the
            only one.
        strict: refuse ignored elements (visuals, collisions, plugins, ...:
            module doc) and turn physicality warnings into errors.
        search_path: directories searched for ``model://NAME`` includes before
            those of ``SDF_PATH`` and ``GZ_SIM_RESOURCE_PATH``.

    Returns:
        The :class:`~featherdyn.Model`, named after the model, with ``source``
        the path (``None`` for a string). Links without a parent joint float
        on a free-flyer ``"root_joint"`` unless the model is ``<static>``; a
        joint whose parent is ``world`` fixes its child to the world.

    Raises:
        SDFError: naming the file, line, element and attribute: malformed or
            hostile XML; a root other than ``<sdf>`` or a version outside
            1.4–1.11; no model, or several without ``model=``, or an unknown
            ``model=`` (the message lists the names); a missing or duplicate
            name; an unknown or unsupported joint type; a joint end naming
            nothing; a link with two parents or a cycle (kinematic loops); a
            ``relative_to``/``attached_to`` naming nothing or forming a cycle;
            a number that is not a finite decimal, a wrong count of them, or
            beyond the loaders' bounds (:data:`featherdyn.urdf.MAX_LENGTH`,
            ``MAX_MASS``, ``MAX_INERTIA``); a negative mass; an ``<inertia>``
            without ``ixx``, ``iyy`` or ``izz``; a zero axis; an include that
            cannot be found, a cycle of includes, more than
            :data:`MAX_INCLUDE_DEPTH` nested or :data:`MAX_INCLUDES` included
            files. Every failure is an ``SDFError`` (a
            :class:`~featherdyn.ModelError`, a ``ValueError``).

    Warns:
        PhysicalityWarning: once, counting the ignored elements; moving links
            without ``<inertial>`` (SDFormat's 1 kg unit inertia); inertias
            that are indefinite or break the triangle inequality; non-unit
            axes (normalised); the model builder's checks (massless moving
            subtrees, lower > upper limits).
    """
    reader = _Reader(strict, search_path)
    try:
        built, label = reader.load(path_or_xml, model)
    except SDFError:
        raise
    except FeatherdynError as exc:  # a check of the spatial types or the model builder: name the source
        raise SDFError(f"{reader.label}: {shorten_quoted(str(exc))}") from None
    ignored = sorted(reader.ignored.items()) + [(f"{k} (unknown to SDFormat)", n) for k, n in sorted(reader.unknown.items())]
    if ignored:
        shown = ", ".join(f"{k} ×{n}" if n > 1 else k for k, n in ignored)
        msg = f"{label}: ignored SDF elements without rigid-tree meaning: {shown}"
        if strict:
            raise SDFError(msg + " (strict=True refuses them)")
        warnings.warn(msg, PhysicalityWarning, stacklevel=2)
    for msg in reader.complaints:
        warnings.warn(msg, PhysicalityWarning, stacklevel=2)
    reissue_warnings(reader.caught, label)
    return built
