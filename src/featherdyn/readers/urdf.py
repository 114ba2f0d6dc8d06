"""Load a URDF robot description into a :class:`~featherdyn.Model`.

The parser is hostile-input safe: XML goes through ``defusedxml`` with DTDs,
entity declarations and external references forbidden, XInclude elements are
rejected, nesting depth and attribute length are bounded, numbers are parsed in
linear time, and mesh files are never opened. The tree is built without
recursion, so a chain of thousands of links loads. Messages quote at most
:data:`QUOTE_LENGTH` characters of an offending value.

Magnitudes are bounded so that finite input gives finite dynamics. The
algorithms form products such as ``m·|c|²`` (the rotational inertia of a body
about its joint), ``X* I X⁻¹`` along a chain, and ``|p|·|f|`` (the moment of a
force); with

* every length (``<origin xyz>`` of joints and inertials) and every position
  limit at most :data:`MAX_LENGTH` ``= 1e60`` (m or rad) per component, and
* every mass and inertia entry at most :data:`MAX_MASS` ``=``
  :data:`MAX_INERTIA` ``= 1e100`` (kg, kg·m²),

a body's inertia about its joint is below ``3e220`` kg·m² and a chain of
``n`` bodies has composite inertias below ``3n³·1e220``; for ``n ≤ 10⁴``
links and velocities, accelerations and torques up to ``1e10`` the products
RNEA, CRBA and ABA form stay below about ``1e270``, short of the float64
overflow at ``1.8e308``. At the other end ABA divides by articulated
inertias, which it calls singular below
:data:`featherdyn.tolerances.SINGULAR_PIVOT_RTOL` times the largest inertia
entry; a link's ``<inertial>`` must therefore be all zero (massless) or reach
:data:`MIN_INERTIAL` ``= 1e-100`` in its mass or some inertia entry, so that
``q̈`` stays below about ``1e124`` (a subnormal mass gave NaN). Values outside these
limits are refused with a :class:`~featherdyn.URDFError`; real robots are
more than 50 orders of magnitude inside them. Angles (``rpy``) and axis
directions may be any finite number; single tiny inertia entries (round-off
such as ``ixz="2.4e-35"``) are fine.

The tree (RBDA (2008) §4.1; chapter §8.3 and §18):

* bodies in depth-first order, a link's children in document order;
* a fixed base hangs the root link on the world (body ``-1``): its inertia,
  and that of links fixed to it, is dropped as Pinocchio does;
  ``floating_base=True`` makes the root link body 0 on a
  :class:`~featherdyn.FreeFlyerJoint` named ``"root_joint"`` (Pinocchio's name;
  ``"root_joint_1"``, ... if the URDF has a joint or link of that name);
* fixed joints are merged: the child's inertia is moved into the nearest moving
  ancestor's body frame (parallel-axis theorem, ``X* I X⁻¹``) and the link and
  the joint stay as frames;
* the URDF inertia tensor is given in the frame of ``<inertial><origin>``, so in
  the link frame::

      c = xyz,    I_c = R(rpy) I_urdf R(rpy)ᵀ

Frames (:class:`~featherdyn.FrameInfo`), in Pinocchio's order: the root link
(kind ``"link"`` on body ``-1``; or ``"root_joint"`` and a ``"body"`` frame with
a floating base), then per link in body order the joint (``"joint"``: a moving joint's frame is
its child body's frame, so it moves with ``q`` as in Pinocchio; or
``"fixed_joint"`` at the joint in the parent body) and the link (``"body"``
for a moving link, ``"link"`` for a merged one).

Names. The parts featherdyn reads — ``<robot>``'s children, ``<link>`` and
its ``<inertial>`` (``origin``, ``mass``, ``inertia``), ``<joint>`` and its
children — are checked against the URDF specification (ROS wiki
``urdf/XML``, as urdfdom reads it). A name the specification does not define
there is reported in one :class:`~featherdyn.PhysicalityWarning` per file,
each with its line and the nearest valid name (``strict=True`` refuses with a
:class:`~featherdyn.URDFError`), and an error it may have caused names it
(``<jiont>`` leaves two root links). The rule for extensions, which URDF
readers ignore and robot files carry: an element or attribute of another XML
namespace (``xacro:``, ``x:note``) is never reported; the documented or
widespread extension names in :data:`URDF_EXTENSIONS` (``<gazebo>``,
``<transmission>``, ``<ros2_control>``, ``<sensor>``, ``<mujoco>`` under
``<robot>``; PyBullet's ``<contact>`` in a link; vendor attributes found in
example-robot-data's robots) are passed over; the contents of
``<visual>``, ``<collision>``, ``<material>`` and of the extensions are not
looked into (featherdyn does not read them). Anything else is reported.

Differences from Pinocchio's URDF parser, on purpose:

* Pinocchio (through urdfdom) orders a link's children by joint *name*; here
  they keep document order. Joints map by name, so the physics is the same but
  ``q`` may be laid out differently.
* Pinocchio ignores the axis of a ``planar`` joint (its plane is always x-y);
  here the axis is the plane's normal, as the URDF specification says.
* Continuous joints have ``nq = 1`` here (an angle), ``nq = 2`` in Pinocchio.
"""

from __future__ import annotations

import difflib
import math
import os
import re
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FeatherdynError, PhysicalityWarning, URDFError
from ..joints import FreeFlyerJoint, Joint, PlanarJoint, PrismaticJoint, RevoluteJoint
from ..model import Mimic, Model, ModelBuilder
from ..rotation import rpy_to_matrix
from ..spatial_algebra import PluckerTransform, SpatialInertia
from ..tolerances import UNIT_AXIS, URDF_INERTIA_RTOL
from .xml import (
    local_name,
    parse_xml,
    quote,
    read_source,
    reissue_warnings,
    shorten,
    shorten_quoted,
)

__all__ = ["load_urdf"]

#: Largest length accepted, in metres per component: origins, centres of mass, prismatic limits (module doc).
MAX_LENGTH = 1e60
#: Largest mass accepted, in kg (module doc).
MAX_MASS = 1e100
#: Largest magnitude of an inertia tensor entry accepted, in kg·m² (module doc).
MAX_INERTIA = 1e100
#: Smallest scale of a non-zero ``<inertial>`` accepted: its mass or some inertia entry must reach it (module doc).
MIN_INERTIAL = 1e-100

# a digit run matches one way only (the fraction needs its dot), so a failed match backtracks in linear time
_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
_INERTIA_KEYS = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")



# ---------------------------------------------------------------------------
# names: the URDF specification's, and the known extensions
# ---------------------------------------------------------------------------

#: The elements and attributes of the URDF specification where featherdyn reads them (ROS wiki ``urdf/XML``,
#: urdfdom): ``{element: (attributes, {child: its entry key})}``; ``visual``, ``collision`` and ``material`` are
#: known but not looked into (featherdyn does not read them).
_SPEC: dict[str, tuple[frozenset[str], dict[str, str]]] = {
    "robot": (frozenset({"name", "version"}),
              {"link": "link", "joint": "joint", "material": ""}),
    "link": (frozenset({"name"}), {"inertial": "inertial", "visual": "", "collision": ""}),
    "inertial": (frozenset(), {"origin": "origin", "mass": "mass", "inertia": "inertia"}),
    "origin": (frozenset({"xyz", "rpy"}), {}),
    "mass": (frozenset({"value"}), {}),
    "inertia": (frozenset(_INERTIA_KEYS), {}),
    "joint": (frozenset({"name", "type"}),
              {"origin": "origin", "parent": "parent", "child": "child", "axis": "axis", "calibration": "calibration",
               "dynamics": "dynamics", "limit": "limit", "safety_controller": "safety_controller",
               "mimic": "mimic"}),
    "parent": (frozenset({"link"}), {}),
    "child": (frozenset({"link"}), {}),
    "axis": (frozenset({"xyz"}), {}),
    "calibration": (frozenset({"rising", "falling", "reference_position"}), {}),
    "dynamics": (frozenset({"damping", "friction"}), {}),
    "limit": (frozenset({"lower", "upper", "effort", "velocity"}), {}),
    "safety_controller": (frozenset({"soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"}), {}),
    "mimic": (frozenset({"joint", "multiplier", "offset"}), {}),
}

#: Names outside the specification that robot files use as extensions, passed over silently (where each comes from):
#: ``{element: (attributes, children)}``; an extension element's content is not looked into.
URDF_EXTENSIONS: dict[str, tuple[frozenset[str], frozenset[str]]] = {
    # transmission: ROS transmissions; gazebo: Gazebo; sensor: the URDF sensor specification; ros2_control;
    # mujoco: MuJoCo's URDF extension (<mujoco><compiler .../></mujoco>)
    "robot": (frozenset(), frozenset({"transmission", "gazebo", "sensor", "ros2_control", "mujoco"})),
    # contact: PyBullet's URDF extension; gravity, kinematic, self_collide, surface: Gazebo's link properties as
    # PAL's TIAGo files write them; collision_checking: urdfdom's former collision extension; self_filter:
    # robot_self_filter (PR2); type: PR2's sensor links (type="laser", "camera")
    "link": (frozenset({"type"}), frozenset({"contact", "gravity", "kinematic", "self_collide", "surface",
                                             "collision_checking", "self_filter"})),
    "joint": (frozenset({"dont_collapse"}), frozenset()),  # Isaac Sim's URDF importer: keep a fixed joint
    "limit": (frozenset({"command_effort", "current", "gear_velocity"}), frozenset()),  # ANYbotics' ANYmal files
    "dynamics": (frozenset({"D", "K", "mu_coulomb", "mu_viscous"}), frozenset()),  # Franka's panda files
}

_NO_EXTENSION: tuple[frozenset[str], frozenset[str]] = (frozenset(), frozenset())
_QUOTED = "'{}'"


def _nearest(name: str, valid: set[str] | frozenset[str], shape: str) -> str:
    close = difflib.get_close_matches(name, sorted(valid), n=1, cutoff=0.6)
    return f"did you mean {shape.format(close[0])}?" if close else \
        "expected one of " + ", ".join(shape.format(v) for v in sorted(valid))


def _unknown_names(root: Any, ns: str, lines: dict[Any, int]) -> list[str]:
    """Each element and attribute name in the parts featherdyn reads that is neither the URDF specification's nor a
    known extension (module doc, "Names"), with its line and the nearest valid name, in document order."""
    out: list[str] = []
    # (element, its entry in _SPEC or None for an unknown name, its parent's kind, the parent's line), popped in
    # document order
    stack: list[tuple[Any, str | None, str, int | None]] = [(root, "robot", "", None)]
    while stack:
        elem, kind, parent, parent_line = stack.pop()
        line = lines.get(elem, parent_line)
        at = f"line {line}: " if line else ""
        if kind is None:
            name = local_name(elem.tag, ns)
            out.append(f"{at}element <{shorten(name)}> in <{parent}> ({_nearest(name, set(_SPEC[parent][1]), '<{}>')})")
            continue
        attrs, children = _SPEC[kind]
        ext_attrs, ext_children = URDF_EXTENSIONS.get(kind, _NO_EXTENSION)
        for attr in elem.attrib:
            if attr not in attrs and attr not in ext_attrs and not attr.startswith("{"):  # {ns}: namespaced
                out.append(f"{at}<{kind}> attribute {quote(attr)} ({_nearest(attr, attrs, _QUOTED)})")
        inner: list[tuple[Any, str | None, str, int | None]] = []
        for child in elem:
            name = local_name(child.tag, ns)
            if not name or name.startswith("{"):  # a comment, or another namespace's element
                continue
            entry = children.get(name)
            if entry is None and name not in ext_children:
                inner.append((child, None, kind, line))
            elif entry:  # (visual, collision, material and the extensions are not looked into)
                inner.append((child, entry, kind, line))
        stack.extend(reversed(inner))
    return out


# ---------------------------------------------------------------------------
# the document's records
# ---------------------------------------------------------------------------


@dataclass(slots=True)
class _Link:
    name: str
    line: int
    inertial: _Inertial | None


@dataclass(slots=True)
class _Inertial:
    mass: float
    xyz: list[float]  # <origin>: the centre of mass and the axes the tensor is given in
    rpy: list[float]
    tensor: list[list[float]]
    elem: Any  # the <inertia> element, for messages


@dataclass(slots=True)
class _Joint:
    name: str
    type: str
    line: int
    parent: str
    child: str
    xyz: list[float]  # origin: pose of the joint frame in the parent link frame
    rpy: list[float]
    axis: np.ndarray
    lower: float
    upper: float
    velocity: float
    effort: float
    mimic: tuple[str, float, float, int] | None  # (joint, multiplier, offset, line)
    limit_missing: tuple[str, ...]  # required <limit> attributes that are absent ("effort", "velocity")


class _Doc:
    """Parsing context: the file label, strictness and helpers for messages."""

    def __init__(self, label: str, lines: dict[Any, int], ns: str, strict: bool) -> None:
        self.label = label
        self.lines = lines
        self.ns = ns
        self.strict = strict

    def where(self, elem: Any, what: str = "", line: int | None = None) -> str:
        line = self.lines.get(elem) if line is None else line
        parts = [self.label] + ([f"line {line}"] if line else []) + ([what] if what else [])
        return ": ".join(parts)

    def error(self, elem: Any, what: str, msg: str, line: int | None = None) -> URDFError:
        return URDFError(f"{self.where(elem, what, line)}: {msg}")

    def warn(self, elem: Any, what: str, msg: str, line: int | None = None) -> None:
        text = f"{self.where(elem, what, line)}: {msg}"
        if self.strict:
            raise URDFError(text + " (strict=True)")
        warnings.warn(text, PhysicalityWarning, stacklevel=4)

    def children(self, elem: Any, name: str) -> list[Any]:
        return [c for c in elem if local_name(c.tag, self.ns) == name]

    def child(self, elem: Any, name: str) -> Any:
        for c in elem:
            if local_name(c.tag, self.ns) == name:
                return c
        return None

    def floats(
        self,
        elem: Any,
        attr: str,
        count: int,
        what: str,
        default: list[float] | None = None,
        bound: tuple[float, str] | None = None,
    ) -> list[float]:
        """The attribute as ``count`` finite decimals; ``default`` if absent (``None``: required).

        ``bound = (largest, name)`` refuses a magnitude above ``largest`` (the
        module constant ``name``). Parsing is linear in the attribute's length.
        """
        tag = shorten(local_name(elem.tag, self.ns))
        text = elem.get(attr)
        if text is None:
            if default is None:
                raise self.error(elem, what, f"<{tag}> needs the attribute {attr!r}")
            return default
        quoted = f"<{tag}> {attr}={quote(text)}"
        parts = text.split()
        if len(parts) != count:
            raise self.error(elem, what, f"{quoted}: expected {count} number{'s' if count > 1 else ''}, got {len(parts)}")
        out = []
        for s in parts:
            if not _NUMBER.fullmatch(s):
                raise self.error(elem, what, f"{quoted}: {quote(s)} is not a decimal number")
            x = float(s)
            if not math.isfinite(x):
                raise self.error(elem, what, f"{quoted}: {quote(s)} is out of range (not finite)")
            if bound is not None and abs(x) > bound[0]:
                raise self.error(
                    elem, what, f"{quoted}: expected a magnitude of at most {bound[0]:g} ({bound[1]}: larger values "
                    f"overflow the dynamics), got {x:g}"
                )
            out.append(x)
        return out

    def number(
        self, elem: Any, attr: str, what: str, default: float | None = None, bound: tuple[float, str] | None = None
    ) -> float:
        return self.floats(elem, attr, 1, what, None if default is None else [default], bound)[0]

    def name(self, elem: Any, kind: str) -> str:
        name = elem.get("name")
        if name is None or not name.strip():
            raise self.error(elem, f"<{kind}>", "missing or empty 'name' attribute")
        return name

    def origin(self, elem: Any, what: str) -> tuple[list[float], list[float]]:
        """``(xyz, rpy)`` of the element's ``<origin>`` (zeros if absent); ``|xyz|`` at most :data:`MAX_LENGTH`."""
        o = self.child(elem, "origin")
        if o is None:
            return [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
        xyz = self.floats(o, "xyz", 3, what, [0.0, 0.0, 0.0], (MAX_LENGTH, "MAX_LENGTH"))
        return xyz, self.floats(o, "rpy", 3, what, [0.0, 0.0, 0.0])


def _parse_link(doc: _Doc, elem: Any) -> _Link:
    name = doc.name(elem, "link")
    what = f"<link name={quote(name)}>"
    inertial = doc.child(elem, "inertial")
    out = None
    if inertial is not None:
        mass_el = doc.child(inertial, "mass")
        if mass_el is None:
            raise doc.error(inertial, what, "<inertial> needs a <mass value=...> element")
        inertia_el = doc.child(inertial, "inertia")
        if inertia_el is None:
            raise doc.error(inertial, what, "<inertial> needs an <inertia ixx=... izz=...> element")
        mass = doc.number(mass_el, "value", what, bound=(MAX_MASS, "MAX_MASS"))
        if mass < 0:
            raise doc.error(mass_el, what, f"<mass> value={quote(mass_el.get('value'))}: expected a mass >= 0, got a "
                            f"negative mass {mass:g}")
        ixx, ixy, ixz, iyy, iyz, izz = (
            doc.number(inertia_el, k, what, bound=(MAX_INERTIA, "MAX_INERTIA")) for k in _INERTIA_KEYS
        )
        xyz, rpy = doc.origin(inertial, what)
        largest_entry = max(abs(ixx), abs(ixy), abs(ixz), abs(iyy), abs(iyz), abs(izz))
        if 0 < max(mass, largest_entry) < MIN_INERTIAL:
            raise doc.error(
                inertial, what, f"<inertial>: expected 0 (a massless link) or a mass or inertia entry of at least "
                f"{MIN_INERTIAL:g} (MIN_INERTIAL: forward dynamics divides by it), got mass {mass:g} and inertia "
                f"entries of at most {largest_entry:g}"
            )
        out = _Inertial(mass, xyz, rpy, [[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]], inertia_el)
    return _Link(name, doc.lines.get(elem, 0), out)


def _link_inertias(doc: _Doc, links: list[_Link]) -> dict[str, SpatialInertia]:
    """Check each ``<inertial>`` and express it in its link's frame, all links at once::

        c = xyz,    I_c = R(rpy) I_urdf R(rpy)ᵀ
    """
    having = [link for link in links if link.inertial is not None]
    if not having:
        return {}
    ins = [link.inertial for link in having if link.inertial is not None]
    mass = np.array([i.mass for i in ins])
    tensor = np.array([i.tensor for i in ins])
    # eigenvalues are rotation invariant: check the tensor as written
    ev = np.linalg.eigvalsh(tensor)
    scale = np.abs(ev).max(axis=-1)
    tol = URDF_INERTIA_RTOL * scale
    bad_psd = (ev[:, 0] < -tol) & (scale > 0)
    bad_tri = (ev[:, 0] + ev[:, 1] < ev[:, 2] - tol) & (scale > 0)
    for k in np.flatnonzero((scale > 0) & ((mass == 0) | bad_psd | bad_tri)):
        what = f"<link name={quote(having[k].name)}>"
        moments = ", ".join(f"{e:.6g}" for e in ev[k])
        if mass[k] == 0:
            doc.warn(ins[k].elem, what, f"zero mass but non-zero rotational inertia (principal moments {moments})")
        elif bad_psd[k]:
            doc.warn(ins[k].elem, what, f"inertia is not positive semi-definite (principal moments {moments})")
        else:
            doc.warn(ins[k].elem, what, f"principal moments violate the triangle inequality I1 + I2 >= I3 ({moments})")
    R = np.asarray(rpy_to_matrix(np.array([i.rpy for i in ins])), dtype=np.float64)
    inertias = SpatialInertia(mass, np.array([i.xyz for i in ins]), R @ tensor @ np.swapaxes(R, -1, -2))
    return {link.name: inertias[k] for k, link in enumerate(having)}


def _parse_joint(doc: _Doc, elem: Any) -> _Joint:
    name = doc.name(elem, "joint")
    what = f"<joint name={quote(name)}>"
    jtype = elem.get("type")
    if jtype is None:
        raise doc.error(elem, what, "missing 'type' attribute (one of " + ", ".join(_JOINT_TYPES) + ")")
    if jtype not in _JOINT_TYPES:
        raise doc.error(elem, what, f"unknown joint type {quote(jtype)}; expected one of " + ", ".join(_JOINT_TYPES))
    ends = []
    for end in ("parent", "child"):
        e = doc.child(elem, end)
        if e is None:
            raise doc.error(elem, what, f"missing <{end} link=...> element")
        link = e.get("link")
        if link is None or not link.strip():
            raise doc.error(e, what, f"<{end}> needs a non-empty 'link' attribute")
        ends.append(link)
    xyz, rpy = doc.origin(elem, what)

    axis = np.array([1.0, 0.0, 0.0])  # URDF default
    if jtype in ("revolute", "continuous", "prismatic", "planar"):
        axis_el = doc.child(elem, "axis")
        if axis_el is not None:
            axis = np.array(doc.floats(axis_el, "xyz", 3, what, [1.0, 0.0, 0.0]))
            # the length as largest component × length of the scaled axis: |axis|² overflows from 1.3e154 on
            largest = float(np.abs(axis).max())
            scaled = axis / largest if largest > 0 else axis
            n_scaled = float(np.linalg.norm(scaled))
            length = largest * n_scaled  # may be inf (only in the message below)
            if length < 1e-12:
                raise doc.error(
                    axis_el, what, f"<axis> xyz={axis.tolist()}: expected a direction, got a zero-length joint axis"
                    + (f" (length {length:.3g})" if length > 0 else "")
                )
            if abs(length - 1.0) > UNIT_AXIS:
                shown = f"{length:.6g}" if math.isfinite(length) else f"{n_scaled:.6g} × {largest:.6g}"
                doc.warn(axis_el, what, f"axis {axis.tolist()} has length {shown}; normalised")
            axis = scaled / n_scaled

    lower, upper, velocity, effort = -math.inf, math.inf, math.inf, math.inf
    limit = doc.child(elem, "limit")
    limit_missing: tuple[str, ...] = ()
    if jtype in ("revolute", "prismatic") and limit is None:
        raise doc.error(elem, what, f"a {jtype} joint needs a <limit lower=... upper=... effort=... velocity=...> element")
    if limit is not None and jtype in ("revolute", "prismatic", "continuous"):
        if jtype != "continuous":
            # URDF defaults; lower > upper: ModelBuilder warns. Bounded so that upper − lower stays finite
            # (random configurations draw from it)
            bound = (MAX_LENGTH, "MAX_LENGTH")
            lower = doc.number(limit, "lower", what, 0.0, bound)
            upper = doc.number(limit, "upper", what, 0.0, bound)
        velocity = doc.number(limit, "velocity", what, math.inf)
        effort = doc.number(limit, "effort", what, math.inf)
        limit_missing = tuple(a for a in ("effort", "velocity") if limit.get(a) is None)

    mimic = None
    mimic_el = doc.child(elem, "mimic")
    if mimic_el is not None:
        target = mimic_el.get("joint")
        if target is None or not target.strip():
            raise doc.error(mimic_el, what, "<mimic> needs a non-empty 'joint' attribute")
        if target == name:
            raise doc.error(mimic_el, what, "the joint mimics itself")
        mimic = (
            target,
            doc.number(mimic_el, "multiplier", what, 1.0),
            doc.number(mimic_el, "offset", what, 0.0),
            doc.lines.get(mimic_el, 0),
        )
    return _Joint(
        name, jtype, doc.lines.get(elem, 0), ends[0], ends[1], xyz, rpy, axis, lower, upper, velocity, effort, mimic,
        limit_missing,
    )


# ---------------------------------------------------------------------------
# the tree
# ---------------------------------------------------------------------------


def _link_order(doc: _Doc, links: dict[str, _Link], joints: list[_Joint]) -> tuple[str, list[tuple[str, _Joint]]]:
    """The root link and the other links in depth-first order (children in document order), with their parent joint."""
    parent_joint: dict[str, _Joint] = {}
    children: dict[str, list[_Joint]] = {name: [] for name in links}
    for j in joints:
        for end, link in (("parent", j.parent), ("child", j.child)):
            if link not in links:
                raise URDFError(
                    f"{doc.label}: line {j.line}: <joint name={quote(j.name)}>: unknown {end} link {quote(link)}"
                )
        if j.parent == j.child:
            raise URDFError(
                f"{doc.label}: line {j.line}: <joint name={quote(j.name)}>: parent and child are the same link "
                f"{quote(j.child)} (a cycle)"
            )
        if j.child in parent_joint:
            other = parent_joint[j.child]
            raise URDFError(
                f"{doc.label}: line {j.line}: <joint name={quote(j.name)}>: link {quote(j.child)} has two parents "
                f"(joints {quote(other.name)} and {quote(j.name)}); a URDF must be a tree"
            )
        parent_joint[j.child] = j
        children[j.parent].append(j)

    roots = [name for name in links if name not in parent_joint]
    if not roots:
        raise URDFError(f"{doc.label}: the joints form a cycle: every link has a parent joint, so there is no root link")
    if len(roots) > 1:
        shown = ", ".join(quote(r) for r in roots[:10]) + (", ..." if len(roots) > 10 else "")
        raise URDFError(
            f"{doc.label}: more than one root link ({len(roots)}: {shown}): the links are not all connected; "
            "every link but the root must be the child of exactly one joint"
        )
    root = roots[0]
    order: list[tuple[str, _Joint]] = []
    stack = [j for j in reversed(children[root])]
    while stack:
        j = stack.pop()
        order.append((j.child, j))
        stack.extend(reversed(children[j.child]))
    if len(order) != len(links) - 1:
        reached = {root} | {name for name, _ in order}
        # every unreached link has a parent; following parents from one must loop
        link = next(name for name in links if name not in reached)
        seen: dict[str, int] = {}
        while link not in seen:
            seen[link] = len(seen)
            link = parent_joint[link].parent
        loop = list(seen)[seen[link]:]
        raise URDFError(
            f"{doc.label}: the joints form a cycle through links "
            + _arrows([*reversed(loop), loop[-1]])
            + f" (joint {quote(parent_joint[loop[0]].name)}); a URDF must be a tree"
        )
    return root, order


def _arrows(names: list[str], most: int = 8) -> str:
    """``'a' -> 'b' -> 'a'``, shortened in the middle for long loops."""
    shown = [quote(x) for x in names]
    if len(shown) > most:
        shown = [*shown[: most // 2], f"... ({len(names) - most} more)", *shown[-(most // 2):]]
    return " -> ".join(shown)


def _check_mimics(doc: _Doc, joints: dict[str, _Joint]) -> list[Mimic]:
    out = []
    follows: dict[str, str] = {}
    for j in joints.values():
        if j.mimic is None:
            continue
        target, mult, offset, line = j.mimic
        what = f"<joint name={quote(j.name)}>"
        if target not in joints:
            doc.warn(None, what, f"<mimic> of unknown joint {quote(target)}; ignored", line)
            continue
        if j.type == "fixed":  # a reduced model froze the mimicking joint: nothing to record
            continue
        if joints[target].type == "fixed":
            doc.warn(None, what, f"<mimic> of the fixed joint {quote(target)}; ignored", line)
            continue
        follows[j.name] = target
        out.append(Mimic(j.name, target, mult, offset))
    # each joint follows at most one other: walk each chain once, a chain that meets itself is a cycle
    done: set[str] = set()
    for start in follows:
        path: dict[str, int] = {}
        nxt: str | None = start
        while nxt is not None and nxt not in done and nxt not in path:
            path[nxt] = len(path)
            nxt = follows.get(nxt)
        if nxt is not None and nxt in path:
            loop = list(path)[path[nxt]:]
            raise URDFError(
                f"{doc.label}: line {joints[loop[0]].line}: <joint name={quote(loop[0])}>: mimic cycle "
                + _arrows([*loop, loop[0]])
            )
        done.update(path)
    return out


def _make_joint(j: _Joint) -> Joint:
    if j.type in ("revolute", "continuous"):  # continuous: a revolute joint without position limits
        return RevoluteJoint(j.axis)
    if j.type == "prismatic":
        return PrismaticJoint(j.axis)
    if j.type == "planar":
        return PlanarJoint(j.axis)
    return FreeFlyerJoint()  # floating


def _check_limits_given(doc: _Doc, joints: list[_Joint]) -> None:
    """One warning (an error with ``strict=True``) listing the joints whose ``<limit>`` lacks effort or velocity."""
    lacking = [j for j in joints if j.limit_missing]
    if not lacking:
        return
    most = 10
    shown = ", ".join(f"{quote(j.name)} (line {j.line}: no {' or '.join(j.limit_missing)})" for j in lacking[:most])
    more = f" and {len(lacking) - most} more" if len(lacking) > most else ""
    doc.warn(
        None, "",
        f"<limit> needs both 'effort' and 'velocity' (the URDF specification requires them); {len(lacking)} "
        f"joint{'s' if len(lacking) > 1 else ''} without: {shown}{more}; the missing limits are recorded as "
        "unbounded (inf)",
    )


def _free_flyer_name(joints: dict[str, _Joint], links: dict[str, _Link]) -> str:
    """``"root_joint"`` (Pinocchio's name), or ``"root_joint_1"``, ``"root_joint_2"``, ... if the URDF uses it."""
    name, k = "root_joint", 0
    while name in joints or name in links:
        k += 1
        name = f"root_joint_{k}"
    return name


def _build(
    doc: _Doc,
    root_el: Any,
    path: str | None,
    root: str,
    order: list[tuple[str, _Joint]],
    inertia_of: dict[str, SpatialInertia],
    mimics: list[Mimic],
    floating_base: bool,
    joints: dict[str, _Joint],
    links: dict[str, _Link],
) -> tuple[Model, list[warnings.WarningMessage]]:
    """The model of the checked tree, and the warnings of the model builder's own checks (to re-emit)."""

    # joint frames in the frame of the parent link's body, all joints at once
    R_joint = np.asarray(rpy_to_matrix(np.array([j.rpy for _, j in order]).reshape(-1, 3)), dtype=np.float64)
    p_joint = np.array([j.xyz for _, j in order]).reshape(-1, 3)
    pose_in_body: dict[str, tuple[np.ndarray, np.ndarray] | None] = {root: None}  # None: the body's own frame
    for k, (child, j) in enumerate(order):
        pose = pose_in_body[j.parent]
        if pose is not None:  # the parent link was merged into its body: compose
            R0, p0 = pose
            R_joint[k], p_joint[k] = R0 @ R_joint[k], R0 @ p_joint[k] + p0
        pose_in_body[child] = (R_joint[k], p_joint[k]) if j.type == "fixed" else None
    X_joint = PluckerTransform(R_joint, p_joint)

    name = root_el.get("name") or (Path(path).stem if path else "robot")
    b = ModelBuilder(name)
    b.source = path
    body_of: dict[str, int] = {}  # the body each link belongs to (-1: the world)
    identity = PluckerTransform.identity()
    if floating_base:
        flyer = _free_flyer_name(joints, links)
        b.add_body(root, -1, FreeFlyerJoint(), inertia=inertia_of.get(root), joint_name=flyer)
        b.add_frame(flyer, 0, identity, "joint")
        b.add_frame(root, 0, identity, "body")
        body_of[root] = 0
    else:
        b.add_frame(root, -1, identity, "link")  # its inertia (and its fixed children's) is dropped
        body_of[root] = -1

    joint_models: dict[tuple[str, tuple[float, ...]], Joint] = {}  # joints are immutable values: share them
    for k, (child, j) in enumerate(order):
        body = body_of[j.parent]
        X = X_joint[k]
        inertia = inertia_of.get(child)
        if j.type == "fixed":
            b.add_frame(j.name, body, X, "fixed_joint")
            b.add_frame(child, body, X, "link")
            body_of[child] = body
            if body >= 0 and inertia is not None:
                b.add_inertia(body, X.apply(inertia))  # X* I X⁻¹: parallel-axis theorem
            continue
        key = (j.type, tuple(j.axis.tolist()))
        if key not in joint_models:
            joint_models[key] = _make_joint(j)
        bounded = j.type != "continuous"
        body_of[child] = b.add_body(
            child,
            body,
            joint_models[key],
            placement=X,
            inertia=inertia,
            joint_name=j.name,
            lower=j.lower if bounded else None,
            upper=j.upper if bounded else None,
            velocity_limit=j.velocity,
            effort_limit=j.effort,
        )
        b.add_frame(j.name, body_of[child], identity, "joint")  # moves with the joint, as in Pinocchio
        b.add_frame(child, body_of[child], identity, "body")
    for m in mimics:
        b.add_mimic(m)

    # the builder checks the whole model (massless subtrees, lower > upper limits): the caller names the file
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", PhysicalityWarning)
        model = b.build(strict=doc.strict)
    return model, list(caught)


def load_urdf(path_or_xml: str | os.PathLike[str] | bytes, floating_base: bool = False, strict: bool = False) -> Model:
    """Load a URDF robot description.

    Args:
        path_or_xml: a file path (``str`` or :class:`os.PathLike`), an XML
            string (a ``str`` whose first character after whitespace and BOM
            is ``<``) or the file's bytes (UTF-8, UTF-8 or UTF-16/32 with BOM,
            or the encoding its XML declaration names).
        floating_base: if ``True`` the root link is body 0 on a free-flyer
            joint named ``"root_joint"`` (Pinocchio's name; ``"root_joint_1"``,
            ``"root_joint_2"``, ... if the URDF has a joint or link of that
            name); otherwise it is fixed to the world and its inertia dropped
            (Pinocchio's behaviour).
        strict: turn every :class:`~featherdyn.PhysicalityWarning` (below)
            into a :class:`~featherdyn.URDFError`.

    Returns:
        The :class:`~featherdyn.Model`, named after ``<robot name=...>`` (the
        file stem, or ``"robot"``, if the attribute is missing), with
        ``source`` the path (``None`` for a string).

    Raises:
        URDFError: naming the file (``<string>`` / ``<bytes>``), the line, the
            element and the link or joint, and the attribute: malformed XML;
            DTDs, entities, external references or XInclude (never expanded or
            read); nesting deeper than :data:`MAX_DEPTH`; an attribute longer
            than :data:`MAX_ATTRIBUTE_LENGTH` characters; undecodable bytes; a
            root element other than ``<robot>``; no links; a missing, empty or
            duplicate link or joint name; an unknown joint type; a joint without
            ``<parent>``/``<child>``, or naming an unknown link; a link with two
            parents, a cycle, more than one root; a revolute or prismatic joint
            without ``<limit>``; a number that is not a finite decimal or a
            wrong count of them; a length, position limit, mass or inertia entry
            beyond :data:`MAX_LENGTH`, :data:`MAX_MASS` or :data:`MAX_INERTIA`,
            or an ``<inertial>`` below :data:`MIN_INERTIAL` but not zero
            (module doc); a negative mass; ``<inertial>`` without ``<mass>`` or
            ``<inertia>``; a zero-length axis; a joint mimicking itself or a
            mimic cycle. Every failure of the loader is a ``URDFError`` (a
            :class:`~featherdyn.ModelError`, a ``ValueError``).

    Warns:
        PhysicalityWarning: a link inertia that is indefinite or violates the
            triangle inequality beyond the relative tolerance
            :data:`featherdyn.tolerances.URDF_INERTIA_RTOL`; zero mass with non-zero inertia; a non-unit
            axis (normalised); lower > upper limits; a ``<limit>`` without the
            ``effort`` or ``velocity`` the URDF specification requires (one
            warning per file, listing the joints); a mimic of an unknown or
            fixed joint (ignored); a moving joint whose subtree has no mass (a
            singular mass matrix). Real robot files have all of these.
            Once per file: the element and attribute names the URDF
            specification does not define where featherdyn reads them, and
            that are no known extension (module doc, "Names"), each with its
            line and the nearest valid name.

    Whitespace before the ``<?xml ...?>`` declaration is accepted (as
    Pinocchio, MuJoCo and PyBullet do), in files, strings and bytes.

    Elements other than ``<link>`` and ``<joint>`` (``<transmission>``,
    ``<gazebo>``, ``<material>``, ...) are ignored (an unknown name is
    reported, see Warns); ``<mimic>`` is recorded
    (:class:`~featherdyn.Mimic`), not enforced; velocity and effort limits are
    recorded (``inf`` where absent); position limits of continuous, planar and
    floating joints are unbounded.
    """
    text, label, path = read_source(path_or_xml)
    root_el, lines = parse_xml(text, label)
    tag = root_el.tag if isinstance(root_el.tag, str) else ""
    ns = tag[: tag.index("}") + 1] if tag.startswith("{") else ""
    if local_name(tag, ns) != "robot":
        hint = " (an SDFormat document: use featherdyn.load_sdf or load_model)" if local_name(tag, ns) == "sdf" else ""
        raise URDFError(
            f"{label}: line {lines.get(root_el, 1)}: expected the root element <robot>, got <{shorten(tag)}>{hint}"
        )
    doc = _Doc(label, lines, ns, strict)
    unknown = _unknown_names(root_el, ns, lines)
    if unknown:
        most = 10
        more = f" and {len(unknown) - most} more" if len(unknown) > most else ""
        names = f"{'; '.join(unknown[:most])}{more}"
        if strict:
            raise URDFError(f"{label}: unknown URDF names: {names} (strict=True)")
        warnings.warn(f"{label}: unknown URDF names, ignored (strict=True refuses them): {names}", PhysicalityWarning,
                      stacklevel=2)
    try:  # an error the unknown names may explain names them
        links: dict[str, _Link] = {}
        joints: dict[str, _Joint] = {}
        for elem in root_el:
            kind = local_name(elem.tag, ns)
            if kind == "link":
                link = _parse_link(doc, elem)
                if link.name in links:
                    raise doc.error(
                        elem, f"<link name={quote(link.name)}>",
                        f"duplicate link name (first defined on line {links[link.name].line})",
                    )
                links[link.name] = link
            elif kind == "joint":
                joint = _parse_joint(doc, elem)
                if joint.name in joints:
                    raise doc.error(
                        elem, f"<joint name={quote(joint.name)}>",
                        f"duplicate joint name (first defined on line {joints[joint.name].line})",
                    )
                joints[joint.name] = joint
        if not links:
            xacro = any(isinstance(e.tag, str) and "xacro" in e.tag for e in root_el)
            hint = " (an unexpanded xacro file? run xacro first)" if xacro else ""
            raise URDFError(f"{label}: <robot> has no <link> elements{hint}")

        _check_limits_given(doc, list(joints.values()))
        root, order = _link_order(doc, links, list(joints.values()))
        mimics = _check_mimics(doc, joints)
        try:
            inertia_of = _link_inertias(doc, list(links.values()))
            model, caught = _build(doc, root_el, path, root, order, inertia_of, mimics, floating_base, joints, links)
        except URDFError:
            raise
        except FeatherdynError as exc:  # a check of the spatial types or the model builder: name the file
            raise URDFError(f"{label}: {shorten_quoted(str(exc))}") from None
    except URDFError as exc:
        if not unknown:
            raise
        raise URDFError(f"{exc}; the file has unknown names, which may be why: {names}") from None
    reissue_warnings(caught, label)
    return model
