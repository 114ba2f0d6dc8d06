"""Load an MJCF (MuJoCo XML) model into a :class:`~featherdyn.Model`, with MuJoCo's compiler semantics.

The reading is as hostile-input safe as the URDF loader's (:mod:`featherdyn.readers.mjcf_xml`:
defusedxml, no entities, bounded nesting, include cycles and depth refused,
numbers finite and bounded); every failure is an :class:`~featherdyn.MJCFError`
naming the file, line, element and attribute.

What MuJoCo's compiler does, and featherdyn with it (the ``mujoco`` package
is the oracle in ``tests/integration/test_mjcf_mujoco.py``):

* ``<compiler>``: ``angle`` (degrees by default: ``euler``, ``axisangle``,
  hinge ``range`` and ``ref``), ``eulerseq``, ``autolimits``,
  ``inertiafromgeom`` (``auto``: from the geoms when a body has no
  ``<inertial>``; ``true``: always; ``false``: never),
  ``inertiagrouprange``, ``boundmass``, ``boundinertia``, ``balanceinertia``,
  ``settotalmass``, ``meshdir`` / ``assetdir``; ``<option gravity>`` and
  ``<flag gravity="disable">``.
* default classes (nested ``<default>``, ``class``, ``childclass``),
  ``<include>``, ``<frame>``.
* bodies: ``pos`` and one of ``quat`` (``w x y z``), ``axisangle``,
  ``euler``, ``xyaxes``, ``zaxis``; every child of ``<worldbody>`` starts a
  tree; a body without joints is welded to its parent (its inertia lumped
  into the moving ancestor, as URDF fixed joints; dropped on the world);
* ``<inertial>`` (``diaginertia`` with an orientation, or ``fullinertia``)
  or geom inertia: sphere, capsule, cylinder, box, ellipsoid, ``fromto``,
  ``mass`` or ``density`` (1000), ``shellinertia`` (not ellipsoid), the
  geom's ``group`` within ``inertiagrouprange``; contact settings do not
  matter. Mesh geoms that would contribute inertia are refused ("mesh
  inertia is not supported").
* joints ``hinge``, ``slide``, ``ball``, ``free`` and ``<freejoint/>``, with
  ``pos``, ``axis``, ``ref``, ``armature`` (:attr:`Model.armature`),
  ``range``/``limited``. Several joints on one body become a chain of
  massless featherdyn bodies named ``BODY#0``, ``BODY#1``, ..., the last one
  called ``BODY`` and carrying the inertia (the others are listed in
  :attr:`Model.inserted_bodies`: made by the loader, massless by construction). MuJoCo's rules: a free joint only
  on a top-level body and alone; no rotation after a ball joint in a body; a
  moving body needs mass and inertia.

Coordinates (converters in :mod:`featherdyn.conventions.mujoco`): the tree is
built so that a hinge's or slide's ``q`` *is* MuJoCo's ``qpos`` (the joint's
``ref`` is folded into its placement: MuJoCo turns by ``qpos − ref``), a ball
joint's quaternion is reordered ``(w, x, y, z)`` → ``(x, y, z, w)``, a free
joint's ``qpos``/``qvel`` convert as in the converters. Joints keep
MuJoCo's order, so ``q`` and ``qpos`` have the same layout. A featherdyn
body's frame sits at its last joint's anchor (``pos``); the MJCF body's own
frame is the frame named after it (kind ``"body"``, or ``"link"`` for a
welded body), each joint a ``"joint"`` frame, each ``<site>`` a ``"site"``
frame. Unnamed bodies are ``body<id>`` (MuJoCo's body id), unnamed joints
``BODY/joint<K>`` (K the index among the body's joints), an unnamed
``<freejoint/>`` ``BODY/free``, unnamed sites ``BODY/site<K>``.

Names: an element or attribute MuJoCo's schema does not know is refused as
MuJoCo refuses it, naming the nearest valid one (:mod:`.mjcf_schema`; inside
``<frame>`` and ``<replicate>``, where MuJoCo ignores an unknown attribute, a
:class:`~featherdyn.PhysicalityWarning` names it).

Elements without rigid-tree meaning (``actuator``, ``tendon``, ``equality``,
``contact``, ``sensor``, ``deformable``, ``extension``, ``plugin``) are
ignored with one :class:`~featherdyn.PhysicalityWarning` listing them
(``strict=True`` refuses them); ``visual``, ``statistic``, ``size``,
``custom``, ``keyframe``, cameras and lights are ignored silently. Elements
that would add bodies featherdyn cannot reproduce (``composite``,
``flexcomp``, ``attach``, ``replicate``) are refused.

Source: MuJoCo documentation, XML reference and "Modeling" chapter; checked
against ``mujoco`` 3.x/4.x compiled models.
"""

from __future__ import annotations

import itertools
import math
import os
import warnings
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, cast

import numpy as np

from ..errors import FeatherdynError, MJCFError, ModelError, PhysicalityWarning
from ..joints import FreeFlyerJoint, Joint, PrismaticJoint, RevoluteJoint, SphericalJoint, _with_unit_axis
from ..model import FrameInfo, Model, ModelBuilder
from ..spatial_algebra import PluckerTransform
from .mjcf_inertia import geom_mass_inertia
from .mjcf_mesh import MeshError, clear_mesh_cache, file_mass_properties, mass_properties
from .mjcf_schema import check_names
from .mjcf_xml import (
    I3,
    Z3,
    Doc,
    Mat,
    Vec,
    axis_angle_matrix,
    compose,
    diagonal,
    expand_replicates,
    file_problem,
    given_value,
    mat_mul,
    mat_vec,
    read_defaults,
    read_document,
    read_mjcf_source,
    rotate_diagonal,
    rotate_symmetric,
    rows,
    tag_name,
    vec_add,
    z_to_vector,
)
from .urdf import MAX_INERTIA, MAX_MASS
from .xml import quote, read_source, shorten_quoted

__all__ = ["clear_mesh_cache", "load_mjcf", "load_model", "model_format"]

#: MuJoCo's ``mjMINVAL``: a moving body's mass and principal inertia must exceed it.
MJ_MINVAL = 1e-15
_IGNORED_QUIETLY = frozenset({"visual", "statistic", "size", "custom", "keyframe"})
_NO_TREE_MEANING = ("contact", "equality", "tendon", "actuator", "sensor", "deformable", "extension", "plugin")
_HANDLED_TOP = frozenset({"compiler", "option", "default", "asset", "worldbody"})
_BODY_REFUSED = ("composite", "flexcomp", "attach")
_BODY_QUIET = frozenset({"camera", "light"})
_SIZES_NEEDED = {"sphere": 1, "capsule": 2, "cylinder": 2, "ellipsoid": 3, "box": 3}  # positive sizes of a solid
_Z_AXIS: Vec = (0.0, 0.0, 1.0)
_IDENTITY = PluckerTransform.identity()  # the frames at their body's origin share it (immutable)
_GEOM_TYPES = ("plane", "hfield", "sphere", "capsule", "ellipsoid", "cylinder", "box", "mesh", "sdf")


@dataclass(slots=True)
class _Compiler:
    inertiafromgeom: str = "auto"
    group_range: tuple[int, int] = (0, 5)
    boundmass: float = 0.0
    boundinertia: float = 0.0
    balanceinertia: bool = False
    settotalmass: float = -1.0
    autolimits: bool = True


@dataclass(slots=True)
class _JointSpec:
    elem: Any
    name: str
    kind: str  # hinge, slide, ball, free
    pos: Vec  # in body coordinates
    axis: Vec  # in body coordinates (unit)
    ref: float
    armature: float
    lower: float
    upper: float
    freejoint: bool = False  # written <freejoint/> (its default name: BODY/free)


#: ``(m, c, I_c)``: a mass, its centre and its rotational inertia about the centre (symmetric).
Inertia = tuple[float, Vec, Mat]
_NO_INERTIA: Inertia = (0.0, Z3, (0.0,) * 9)


@dataclass(slots=True)
class _Body:
    elem: Any
    name: str
    parent: int  # MuJoCo body id of the parent (0 = world)
    R: Mat  # pose in the parent body's frame
    p: Vec
    childclass: str
    joints: list[_JointSpec] = field(default_factory=list)
    geoms: list[tuple[Any, str, Mat, Vec]] = field(default_factory=list)  # elem, class, R, p
    sites: list[tuple[str, Mat, Vec]] = field(default_factory=list)
    inertial: Any = None
    inertia: Inertia = _NO_INERTIA  # in the MJCF body frame


def _moved(inertia: Inertia, R: Mat, p: Vec) -> Inertia:
    """The inertia in the frame where the frame it is given in is posed ``(R, p)``::

        m' = m,   c' = R c + p,   I_c' = R I_c Rᵀ      (X* I X⁻¹, RBDA §2.13)
    """
    if R is I3 and p is Z3:
        return inertia
    m, c, ic = inertia
    return m, vec_add(mat_vec(R, c), p), rotate_symmetric(R, ic)


def _combined(a: Inertia, b: Inertia) -> Inertia:
    """Two rigidly joined inertias as one (the parallel-axis theorem for the pair, no cancellation)::

        m = m_a + m_b,   c = (m_a c_a + m_b c_b) / m,   I_c = I_a + I_b + (m_a m_b / m) (|d|² 1 − d dᵀ),  d = c_a − c_b
    """
    ma, ca, ia = a
    mb, cb, ib = b
    m = ma + mb
    if m == 0.0:
        return (0.0, Z3, _sum9(ia, ib))
    wa, wb = ma / m, mb / m
    c = (wa * ca[0] + wb * cb[0], wa * ca[1] + wb * cb[1], wa * ca[2] + wb * cb[2])
    return m, c, _parallel(_sum9(ia, ib), ma * wb, (ca[0] - cb[0], ca[1] - cb[1], ca[2] - cb[2]))


def _sum9(a: Mat, b: Mat) -> Mat:
    """``a + b``."""
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2], a[3] + b[3], a[4] + b[4], a[5] + b[5], a[6] + b[6], a[7] + b[7],
            a[8] + b[8])


def _parallel(ic: Mat, m: float, d: Vec) -> Mat:
    """``I_c + m (|d|² 1 − d dᵀ)``: an inertia about a point ``d`` away from where ``I_c`` is taken."""
    x, y, z = d
    xx, yy, zz = m * x * x, m * y * y, m * z * z
    xy, xz, yz = m * x * y, m * x * z, m * y * z
    return (ic[0] + yy + zz, ic[1] - xy, ic[2] - xz,
            ic[3] - xy, ic[4] + xx + zz, ic[5] - yz,
            ic[6] - xz, ic[7] - yz, ic[8] + xx + yy)


def _axisymmetric(lateral: float, axial: float, z: Vec) -> Mat:
    """``lateral 1 + (axial − lateral) z zᵀ``: the inertia of a body symmetric about the unit axis ``z``."""
    k = axial - lateral
    x, y, w = z
    xy, xz, yz = k * x * y, k * x * w, k * y * w
    return (lateral + k * x * x, xy, xz, xy, lateral + k * y * y, yz, xz, yz, lateral + k * w * w)


def _smallest_above(ic: Mat, floor: float) -> bool:
    """Whether the smallest eigenvalue of the symmetric ``ic`` surely exceeds ``floor``; ``False`` means: compute
    the eigenvalues. Sylvester's criterion on ``A = ic − floor 1``: ``A`` is positive definite iff the pivots of
    its factorisation ``A = L D Lᵀ`` are positive::

        d₁ = a₁₁,   d₂ = a₂₂ − a₁₂² / d₁,   d₃ = a₃₃ − a₁₃² / d₁ − (a₂₃ − a₁₂ a₁₃ / d₁)² / d₂

    Each pivot must clear ``1e-9`` of the largest diagonal entry: where ``A`` is positive definite every term
    subtracted is at most that entry, so round-off (~1e-16 of it) cannot turn a negative pivot positive.
    """
    a, b, c = ic[0] - floor, ic[1], ic[2]
    e, f, i = ic[4] - floor, ic[5], ic[8] - floor
    margin = 1e-9 * max(ic[0], ic[4], ic[8])
    if not a > margin:
        return False
    d2 = e - b * b / a
    if not d2 > margin:
        return False
    g = f - b * c / a
    return i - c * c / a - g * g / d2 > margin


def _add_frame(frames: list[Any], posed: list[int], name: str, body: int, R: Mat, p: Vec, kind: str) -> None:
    """A frame at ``(R, p)`` in body ``body``: at once when at its origin (the shared identity placement), else as
    ``(name, body, (R, p), kind)`` with its index in ``posed`` (placed once all are stacked)."""
    if R is I3 and p is Z3:
        frames.append(FrameInfo(name, body, _IDENTITY, kind))
    else:
        posed.append(len(frames))
        frames.append((name, body, (R, p), kind))


def _unique(name: str, taken: set[str]) -> str:
    out, k = name, 1
    while out in taken:
        k += 1
        out = f"{name}_{k}"
    taken.add(out)
    return out


class _Loader:
    def __init__(self, doc: Doc, path: str | None) -> None:
        self.doc = doc
        self.path = path
        self.comp = _Compiler()
        self.gravity: Vec = (0.0, 0.0, -9.81)
        self.gravity_disabled = False
        self.meshdir: str | None = None
        self.assetdir: str | None = None
        self.meshes: dict[str, Any] = {}
        self.mesh_cache: dict[str, tuple[float, Vec, Mat]] = {}
        self.joint_cache: dict[tuple[str, Vec], Joint] = {}  # joints are immutable: one per kind and axis
        self.bodies: list[_Body] = []
        self.ignored: list[str] = []
        self.site_names: set[str] = set()
        self.model_name: str | None = None

    # -- top level ------------------------------------------------------------

    def read_top(self) -> None:
        doc = self.doc
        self.model_name = doc.root.get("model")
        for elem in doc.root:
            kind = tag_name(elem.tag)
            if not kind:
                continue
            if kind == "compiler":
                self.read_compiler(elem)
            elif kind == "option":
                self.read_option(elem)
            elif kind in _NO_TREE_MEANING:
                if kind not in self.ignored:
                    self.ignored.append(kind)
                if doc.strict:
                    raise doc.error(elem, f"<{kind}> has no rigid-tree meaning and is refused with strict=True")
            elif kind == "body":  # outside <worldbody>: MuJoCo's schema takes it and its compiler ignores it
                what = "body (outside <worldbody>)"
                if what not in self.ignored:
                    self.ignored.append(what)
                if doc.strict:
                    raise doc.error(elem, "<body> outside <worldbody> is ignored by MuJoCo; refused with strict=True")
            elif kind not in _HANDLED_TOP and kind not in _IGNORED_QUIETLY:
                raise doc.error(elem, f"unknown MJCF element <{kind}> in <mujoco>")
        read_defaults(doc)
        for tendons in (e for e in doc.root if tag_name(e.tag) == "tendon"):
            self.check_tendons(tendons)
        for asset in (e for e in doc.root if tag_name(e.tag) == "asset"):
            for m in asset:
                if tag_name(m.tag) == "mesh":
                    name = m.get("name") or Path(m.get("file", "")).stem
                    if name:
                        self.meshes[name] = m
                    file = m.get("file")
                    problem = None if file is None else file_problem(self.asset_path(file))  # MuJoCo reads each
                    if problem is not None:
                        raise doc.error(m, f"file={quote(file)}: cannot read the mesh file "
                                        f"{quote(str(self.asset_path(file)))}: {problem}")

    def check_tendons(self, tendons: Any) -> None:
        """Refuse a tendon with armature: MuJoCo adds ``armature · Jᵀ J`` (J the tendon's Jacobian, `(1, nv)`) to
        the mass matrix (measured: a fixed tendon of coefficients c adds ``armature · c cᵀ``), which couples
        joints in different branches and has no place in the tree algorithms; the rest of a tendon (stiffness,
        damping, limits) is a force and is ignored with the other elements without rigid-tree meaning."""
        doc = self.doc
        for t in tendons:
            if tag_name(t.tag) in ("fixed", "spatial"):
                attrs = doc.attrs(t, "tendon", doc.element_class(t, "main"))
                if doc.number(t, attrs, "armature", 0.0, MAX_MASS) != 0:
                    raise doc.error(t, f"armature={quote(attrs['armature'])}: a tendon's armature adds "
                                    "armature·JᵀJ to the mass matrix (MuJoCo), coupling the tendon's joints, which "
                                    "featherdyn's tree algorithms do not model (set it to 0 or remove the tendon)")

    def read_compiler(self, elem: Any) -> None:
        doc, a, c = self.doc, elem.attrib, self.comp
        if "angle" in a:
            doc.degree = doc.choice(elem, a, "angle", ("degree", "radian"), "degree") == "degree"
        if "eulerseq" in a:
            seq = a["eulerseq"]
            if len(seq) != 3 or any(ch not in "xyzXYZ" for ch in seq):
                raise doc.error(elem, f"eulerseq={quote(seq)}: expected three letters of xyzXYZ")
            doc.eulerseq = seq
        if "coordinate" in a and a["coordinate"] != "local":
            raise doc.error(elem, f"coordinate={quote(a['coordinate'])}: only local coordinates exist (MuJoCo "
                            "removed 'global')")
        if "alignfree" in a and doc.boolean(elem, a, "alignfree", False):
            raise doc.error(elem, "alignfree='true' (moving free bodies' frames to their inertial frames) is not "
                            "supported")
        if "inertiafromgeom" in a:
            c.inertiafromgeom = doc.choice(elem, a, "inertiafromgeom", ("true", "false", "auto"), "auto")
        if "inertiagrouprange" in a:
            g = doc.floats(elem, a, "inertiagrouprange", (2,))
            if g is None or any(x != int(x) for x in g):
                raise doc.error(elem, f"inertiagrouprange={quote(a['inertiagrouprange'])}: expected two integers")
            c.group_range = (int(g[0]), int(g[1]))
        for key in ("boundmass", "boundinertia", "settotalmass"):
            if key in a:
                setattr(c, key, doc.number(elem, a, key, 0.0, MAX_MASS))
        if "balanceinertia" in a:
            c.balanceinertia = doc.boolean(elem, a, "balanceinertia", False)
        if "autolimits" in a:
            c.autolimits = doc.boolean(elem, a, "autolimits", True)
        self.meshdir = a.get("meshdir", self.meshdir)
        self.assetdir = a.get("assetdir", self.assetdir)

    def read_option(self, elem: Any) -> None:
        g = self.doc.floats(elem, elem.attrib, "gravity", (3,))
        if g is not None:
            self.gravity = (g[0], g[1], g[2])
        for flag in elem:
            if tag_name(flag.tag) == "flag" and flag.get("gravity") == "disable":
                self.gravity_disabled = True

    # -- the body tree --------------------------------------------------------

    def read_bodies(self) -> None:
        doc = self.doc
        world = _Body(None, "world", -1, I3, Z3, "main")
        self.bodies.append(world)
        worldbodies = [e for e in doc.root if tag_name(e.tag) == "worldbody"]
        # pending bodies in MuJoCo's order (depth first, document order): (elem, parent id, R, p, childclass)
        pending: list[tuple[Any, int, Mat, Vec, str]] = []
        for wb in worldbodies:
            pending += self.read_content(0, wb, "main")
        pending.reverse()
        while pending:
            elem, parent, R, p, childclass = pending.pop()
            if "childclass" in elem.attrib:
                childclass = doc.element_class(elem, childclass, "childclass")
            Rb, pb = doc.pose(elem, elem.attrib)
            if R is not I3 or p is not Z3:  # in a <frame>
                Rb, pb = compose(R, p, Rb, pb)
            body = _Body(elem, elem.get("name") or "", parent, Rb, pb, childclass)
            self.bodies.append(body)
            children = self.read_content(len(self.bodies) - 1, elem, childclass)
            pending += reversed(children)

    def read_content(self, b: int, elem: Any, childclass: str) -> list[tuple[Any, int, Mat, Vec, str]]:
        """Joints, geoms, sites, inertial of body ``b`` from ``elem`` and its frames; returns its child bodies."""
        doc = self.doc
        body = self.bodies[b] if b < len(self.bodies) else None
        children: list[tuple[Any, int, Mat, Vec, str]] = []
        is_world = b == 0
        geoms = self.bodies[b].geoms
        # the children in document order, a <frame>'s read in its place: for the element and each open frame, (its
        # children not yet read, the frame's rotation and position in body coordinates, childclass)
        open_frames: list[tuple[Iterator[Any], Mat, Vec, str]] = [(iter(elem), I3, Z3, childclass)]
        while open_frames:
            left, R, p, cc = open_frames[-1]
            for child in left:
                kind = child.tag
                if not isinstance(kind, str):  # a comment or a processing instruction
                    continue
                if kind == "geom":
                    geoms.append((child, cc if "class" not in child.attrib else doc.element_class(child, cc), R, p))
                elif kind == "body":
                    children.append((child, b, R, p, cc))
                elif kind == "frame":
                    cls = doc.element_class(child, cc)
                    attrs = doc.attrs(child, "frame", cls)
                    Rf, pf = doc.pose(child, attrs)
                    sub_cc = doc.element_class(child, cc, "childclass")
                    open_frames.append((iter(child), *compose(R, p, Rf, pf), sub_cc))
                    break  # its children next, then this element's again
                elif kind == "site":
                    cls = doc.element_class(child, cc)
                    attrs = doc.attrs(child, "site", cls)
                    Rs, ps = self.geom_pose(child, attrs)
                    self.bodies[b].sites.append((child.get("name") or "", *compose(R, p, Rs, ps)))
                elif kind in ("joint", "freejoint"):
                    if is_world or body is None:
                        raise doc.error(child, "a joint of the world body: joints belong in a <body>")
                    body.joints.append(self.read_joint(child, kind, cc, R, p, len(body.joints)))
                elif kind == "inertial":
                    if is_world or body is None:
                        raise doc.error(child, "<inertial> of the world body")
                    if body.inertial is not None:
                        raise doc.error(child, "a second <inertial> in one body")
                    body.inertial = (child, R, p)
                elif kind in _BODY_REFUSED:
                    raise doc.error(child, f"<{kind}> is not supported by featherdyn's MJCF loader (it adds bodies or "
                                    "joints featherdyn cannot reproduce); expand it into plain bodies first")
                elif kind == "plugin":
                    if doc.strict:
                        raise doc.error(child, "<plugin> has no rigid-tree meaning and is refused with strict=True")
                    if "plugin" not in self.ignored:
                        self.ignored.append("plugin")
                elif kind not in _BODY_QUIET:
                    raise doc.error(child, f"unknown MJCF element <{kind}> in a body")
            else:
                open_frames.pop()
        return children

    def geom_pose(self, elem: Any, attrs: dict[str, str]) -> tuple[Mat, Vec]:
        """Pose of a geom or site in its body frame; from ``fromto`` when given: z along ``from − to`` (measured)."""
        line = self.fromto(elem, attrs)
        if line is None:
            return self.doc.pose(elem, attrs)
        return z_to_vector(line[0]), line[1]

    def fromto(self, elem: Any, attrs: dict[str, str]) -> tuple[Vec, Vec, float] | None:
        """``(z, middle, length)`` of a ``fromto`` segment: the unit vector along ``from − to`` (the geom's z axis,
        measured), the midpoint (its centre) and the distance; ``None`` without ``fromto``."""
        ft = self.doc.floats(elem, attrs, "fromto", (6,)) if "fromto" in attrs else None
        if ft is None:
            return None
        if "pos" in attrs and any(self.doc.floats(elem, attrs, "pos", (3,)) or ()):  # measured: "0 0 0" is allowed
            raise self.doc.error(elem, f"pos={quote(attrs['pos'])} and fromto both given (MuJoCo refuses a "
                                 "non-zero pos with fromto)")
        d = (ft[0] - ft[3], ft[1] - ft[4], ft[2] - ft[5])
        n = math.hypot(*d)
        if n < 1e-10:
            raise self.doc.error(elem, f"fromto={quote(attrs['fromto'])}: the two points coincide")
        return (d[0] / n, d[1] / n, d[2] / n), ((ft[0] + ft[3]) / 2, (ft[1] + ft[4]) / 2, (ft[2] + ft[5]) / 2), n

    def read_joint(self, elem: Any, kind: str, cc: str, R: Mat, p: Vec, index: int) -> _JointSpec:
        doc = self.doc
        if kind == "freejoint":
            attrs = dict(elem.attrib)  # a <freejoint> takes no default class (measured: MuJoCo ignores them)
            jtype = "free"
        else:
            attrs = doc.attrs(elem, "joint", cc if "class" not in elem.attrib else doc.element_class(elem, cc))
            jtype = attrs.get("type", "hinge")
            if jtype not in ("hinge", "slide", "ball", "free"):
                doc.choice(elem, attrs, "type", ("hinge", "slide", "ball", "free"), "hinge")  # the message
        given = doc.floats(elem, attrs, "pos", (3,))
        pos: Vec = Z3 if given is None else given  # type: ignore[assignment]  # three floats
        given = doc.floats(elem, attrs, "axis", (3,))
        axis: Vec = _Z_AXIS if given is None else given  # type: ignore[assignment]
        if given is not None and jtype in ("hinge", "slide"):
            axis = doc._direction(elem, attrs, "axis", axis)
        ref = doc.number(elem, attrs, "ref", 0.0)
        armature = doc.floats(elem, attrs, "armature", (1,), (0.0,), MAX_MASS)[0]  # type: ignore[index]
        if armature < 0:
            raise doc.error(elem, f"armature={quote(attrs['armature'])}: expected a value >= 0")
        lower, upper = -math.inf, math.inf
        limited = attrs.get("limited", "auto")
        if limited not in ("true", "false", "auto"):
            doc.choice(elem, attrs, "limited", ("true", "false", "auto"), "auto")  # the message
        has_range = given_value(attrs, "range")
        if limited == "auto":
            if has_range and not self.comp.autolimits:
                raise doc.error(elem, "range given but not limited, with autolimits='false' (MuJoCo refuses this: "
                                "set limited='true' or 'false')")
            limited = "true" if has_range else "false"
        if limited == "true" and jtype in ("hinge", "slide"):
            rng = doc.floats(elem, attrs, "range", (2,), (0.0, 0.0)) or (0.0, 0.0)
            lower, upper = rng
            if not lower < upper:
                raise doc.error(elem, f"range={quote(attrs.get('range', '0 0'))}: a limited joint needs "
                                "range[0] < range[1] (MuJoCo)")
            if jtype == "hinge" and doc.degree:
                lower, upper = math.radians(lower), math.radians(upper)
        if jtype == "hinge":
            if ref and doc.degree:
                ref = math.radians(ref)
        elif jtype in ("ball", "free"):
            ref = 0.0
        name = elem.get("name") or ""
        if R is not I3:
            pos, axis = mat_vec(R, pos), mat_vec(R, axis)
        return _JointSpec(elem, name, jtype, vec_add(pos, p) if jtype != "free" else pos, axis, ref, armature, lower,
                          upper, kind == "freejoint")

    # -- inertia --------------------------------------------------------------

    def body_inertia(self, b: int) -> None:
        """Mass, centre of mass and rotational inertia about it, in the MJCF body frame (MuJoCo's rules)."""
        body = self.bodies[b]
        doc, comp = self.doc, self.comp
        use_geoms = comp.inertiafromgeom == "true" or (comp.inertiafromgeom == "auto" and body.inertial is None)
        moving = bool(body.joints) or self.moving[b]
        parts: list[Inertia] = []
        if use_geoms:
            for elem, cls, R, p in body.geoms:
                got = self.geom_inertia(elem, cls, R, p, moving)
                if got is not None:
                    parts.append(got)
            if not parts and body.inertial is not None:  # measured: inertiafromgeom='true' keeps it then
                use_geoms = False
        principal: list[float] | None = None  # the principal moments when known (bounding or balancing resets them)
        if use_geoms and len(parts) == 1:
            body.inertia = parts[0]
        elif use_geoms:
            total = 0.0
            first = [0.0, 0.0, 0.0]
            for m, c, _ in parts:
                total += m
                first[0] += m * c[0]
                first[1] += m * c[1]
                first[2] += m * c[2]
            com: Vec = (first[0] / total, first[1] / total, first[2] / total) if total > 0 else Z3
            second: Mat = (0.0,) * 9
            for m, c, ic in parts:
                second = _parallel(_sum9(second, ic), m, (c[0] - com[0], c[1] - com[1], c[2] - com[2]))
            body.inertia = (total, com, second)
        elif body.inertial is not None:
            elem, R, p = body.inertial
            attrs = elem.attrib
            pos = doc.floats(elem, attrs, "pos", (3,))
            if pos is None:
                raise doc.error(elem, "<inertial> needs 'pos'")
            mass = doc.floats(elem, attrs, "mass", (1,), None, MAX_MASS)
            if mass is None:
                raise doc.error(elem, "<inertial> needs 'mass'")
            if mass[0] < 0:
                raise doc.error(elem, f"mass={quote(attrs['mass'])}: expected a mass >= 0")
            diag = doc.floats(elem, attrs, "diaginertia", (3,), None, MAX_MASS)
            full = doc.floats(elem, attrs, "fullinertia", (6,), None, MAX_MASS)
            if (diag is None) == (full is None):
                raise doc.error(elem, "<inertial> needs exactly one of 'diaginertia' and 'fullinertia'")
            if full is not None:
                given = [k for k in ("quat", "axisangle", "euler", "xyaxes", "zaxis") if k in attrs]
                if given:
                    raise doc.error(elem, f"fullinertia and an orientation ({given[0]}): MuJoCo accepts one")
                xx, yy, zz, xy, xz, yz = full
                tensor: Mat = (xx, xy, xz, xy, yy, yz, xz, yz, zz)
                Ri = I3
                ev = principal = np.linalg.eigvalsh(np.array(rows(tensor))).tolist()
            else:
                assert diag is not None
                tensor = diagonal((diag[0], diag[1], diag[2]))
                Ri = doc.rotation(elem, attrs)
                ev = principal = sorted(diag)
            scale = max(abs(ev[0]), abs(ev[2]), MJ_MINVAL)
            if ev[0] < -1e-12 * scale:
                raise doc.error(elem, f"the inertia is not positive semi-definite (principal moments "
                                f"{', '.join(f'{e:.6g}' for e in ev)})")
            body.inertia = (mass[0], vec_add(mat_vec(R, (pos[0], pos[1], pos[2])), p),
                            rotate_symmetric(mat_mul(R, Ri), tensor))
        if (comp.boundmass > 0 or comp.boundinertia > 0 or comp.balanceinertia) and self.bound_and_balance(body):
            principal = None
        mass_, _, inertia = body.inertia
        largest = max(map(abs, inertia))
        if not (math.isfinite(mass_) and math.isfinite(largest)) or mass_ > MAX_MASS or largest > MAX_INERTIA:
            raise doc.error(body.elem, f"body {body.name or b!r}: mass {mass_:g} and inertia entries up to "
                            f"{largest:g}: expected at most {MAX_MASS:g} (MAX_MASS, MAX_INERTIA of featherdyn.readers.urdf: "
                            "larger values overflow the dynamics)")
        if body.inertial is not None and not use_geoms:  # MuJoCo checks after bounding and balancing
            ev = principal if principal is not None else np.linalg.eigvalsh(np.array(rows(inertia))).tolist()
            if ev[0] + ev[1] < ev[2] * (1 - 1e-10) - MJ_MINVAL:
                raise doc.error(body.inertial[0], "principal moments violate the triangle inequality A + B >= C "
                                f"({', '.join(f'{e:.6g}' for e in ev)}); MuJoCo refuses this unless "
                                "<compiler balanceinertia='true'>")

    def bound_and_balance(self, body: _Body) -> bool:
        """``boundmass``, ``boundinertia``, ``balanceinertia`` on the body's inertia; whether its tensor was
        recomposed."""
        comp = self.comp
        m, c, ic = body.inertia
        if comp.boundmass > 0 and m < comp.boundmass:
            m = comp.boundmass
        recomposed = comp.boundinertia > 0 or comp.balanceinertia
        if recomposed:
            ev, V = np.linalg.eigh(np.array(rows(ic)))
            ev = np.maximum(ev, comp.boundinertia) if comp.boundinertia > 0 else ev
            if comp.balanceinertia and ev[0] + ev[1] < ev[2]:
                ev = np.full(3, ev.mean())
            out = V @ np.diag(ev) @ V.T
            ic = tuple(((out + out.T) / 2).ravel().tolist())
        body.inertia = (m, c, ic)
        return recomposed

    def geom_inertia(self, elem: Any, cls: str, R: Mat, p: Vec, moving: bool) -> Inertia | None:
        """``(m, c, I_c)`` of a geom in body coordinates, or ``None`` when it adds nothing."""
        doc = self.doc
        attrs = doc.attrs(elem, "geom", cls)
        gtype = attrs.get("type", "sphere")
        if gtype not in _SIZES_NEEDED:  # not a solid primitive: one of the others, or a message
            gtype = doc.choice(elem, attrs, "type", _GEOM_TYPES, "sphere")
        lo, hi = self.comp.group_range
        if not lo <= (doc.number(elem, attrs, "group", 0.0) if "group" in attrs else 0) <= hi:  # absent: 0
            return None
        if gtype in ("plane", "hfield"):
            if moving:
                raise doc.error(elem, f"type={gtype!r}: a {gtype} is only allowed in static bodies (MuJoCo)")
            return None
        mass: float | None = None
        if given_value(attrs, "mass"):
            mass = doc.number(elem, attrs, "mass", 0.0, MAX_MASS)
            if mass < 0:
                raise doc.error(elem, f"mass={quote(attrs['mass'])}: expected a mass >= 0")
            if mass == 0:
                return None
        density = doc.floats(elem, attrs, "density", (1,), (1000.0,), MAX_MASS)[0]  # type: ignore[index]
        if density < 0:
            raise doc.error(elem, f"density={quote(attrs['density'])}: expected a density >= 0")
        if gtype == "sdf":
            raise doc.error(elem, "type='sdf': SDF geom inertia is not supported by featherdyn's MJCF loader; give "
                            "the body an <inertial>, or set this geom's mass='0' or a group outside "
                            "inertiagrouprange")
        shell = "shellinertia" in attrs and doc.boolean(elem, attrs, "shellinertia", False)
        if gtype == "mesh":
            if "shellinertia" in attrs:
                raise doc.error(elem, "shellinertia on a mesh geom: for mesh geoms, inertia is specified in the mesh "
                                "asset (<mesh inertia='shell'>), as MuJoCo requires")
            measure, c_mesh, J = self.mesh_properties(elem, attrs)
            m = mass if mass is not None else density * measure
            Rg, pg = compose(R, p, *doc.pose(elem, attrs))
            k = m / measure
            return m, vec_add(mat_vec(Rg, c_mesh), pg), rotate_symmetric(Rg, tuple(x * k for x in J))  # type: ignore[arg-type]
        given = doc.floats(elem, attrs, "size", (1, 2, 3)) or (0.0,)
        size = given + (0.0, 0.0)[: 3 - len(given)]  # three sizes, the missing ones 0
        turn: Mat | None  # the geom's rotation in the frame (R, p); from fromto, made below only if needed
        if given_value(attrs, "fromto"):
            zg, pg, length = self.fromto(elem, attrs)  # type: ignore[misc]
            turn = None  # a sphere's, capsule's or cylinder's inertia needs the z axis only
            # measured: a capsule/cylinder keeps its radius; a box/ellipsoid is (size[0], size[0], half)
            if gtype in ("capsule", "cylinder"):
                size = (size[0], length / 2, 0.0)
            elif gtype in ("box", "ellipsoid"):
                size = (size[0], size[0], length / 2)
        else:
            turn, pg = doc.pose(elem, attrs)
            zg = (turn[2], turn[5], turn[8])  # its z axis
        needed = _SIZES_NEEDED[gtype]
        if not (size[0] > 0 and (needed < 2 or size[1] > 0) and (needed < 3 or size[2] > 0)):
            k = next(k for k in range(needed) if not size[k] > 0)
            raise doc.error(elem, f"size={quote(attrs.get('size', ''))}: size {k} of a {gtype} must be positive "
                            f"(got {size[k]:g})")
        try:
            got = geom_mass_inertia(gtype, size, density, mass, shell)
        except ValueError as exc:  # a volume that underflows to 0
            raise doc.error(elem, f"size={quote(attrs.get('size', ''))}, mass={quote(attrs['mass'])}: {exc}") from None
        if got is None:
            raise doc.error(elem, f"shellinertia='true' of a {gtype} is not supported")
        m, principal = got
        c = vec_add(pg if R is I3 else mat_vec(R, pg), p)
        if gtype == "sphere":
            return m, c, diagonal(principal)
        if gtype in ("capsule", "cylinder"):  # I = I_xx 1 + (I_zz − I_xx) z zᵀ, z the axis in body coordinates
            return m, c, _axisymmetric(principal[0], principal[2], zg if R is I3 else mat_vec(R, zg))
        return m, c, rotate_diagonal(mat_mul(R, z_to_vector(zg) if turn is None else turn), principal)

    def mesh_properties(self, geom: Any, attrs: dict[str, str]) -> tuple[float, Vec, Mat]:
        """``(V, c, I_c/ρ)`` of the geom's mesh asset in the geom frame (cached per asset)."""
        doc = self.doc
        name = attrs.get("mesh")
        if name is None or name not in self.meshes:
            raise doc.error(geom, f"mesh={quote(name or '')}: no <mesh> asset of that name")
        elem = self.meshes[name]
        if name in self.mesh_cache:
            return self.mesh_cache[name]
        cls = doc.element_class(elem, "main")
        mattrs = doc.attrs(elem, "mesh", cls)
        mode = doc.choice(elem, mattrs, "inertia", ("legacy", "exact", "convex", "shell"), "legacy")
        for key in ("refpos", "refquat"):
            if key in mattrs:
                raise doc.error(elem, f"{key}: mesh reference frames are not supported")
        scale = cast(Vec, doc.floats(elem, mattrs, "scale", (3,), (1.0, 1.0, 1.0)))
        try:
            if "file" in mattrs:
                got = file_mass_properties(self.asset_path(mattrs["file"]), scale, mode)
            else:
                got = _inline_mass_properties(doc.float_list(elem, mattrs, "vertex", 3),
                                              doc.float_list(elem, mattrs, "face", 3), scale, mode)
        except MeshError as exc:
            raise doc.error(elem, str(exc)) from None
        self.mesh_cache[name] = got
        return got

    def asset_path(self, file: str) -> Path:
        return _asset_file(self.doc.model_dir, file, self.meshdir, self.assetdir)

    # -- the featherdyn model -------------------------------------------------

    def build(self) -> tuple[Model, list[str]]:
        """The featherdyn model and the model builder's warnings (messages, not yet issued)."""
        doc, bodies, comp = self.doc, self.bodies, self.comp
        nb = len(bodies)
        # a body moves if it or an ancestor has a joint (its inertia then matters: plane/mesh checks)
        moving = self.moving = [False] * nb
        for b in range(1, nb):
            moving[b] = bool(bodies[b].joints) or moving[bodies[b].parent]
            # a static body's inertia matters only to settotalmass (its meshes are not even read otherwise)
            if (moving[b] or comp.settotalmass > 0):
                self.body_inertia(b)
        if comp.settotalmass > 0:
            total = sum(bodies[b].inertia[0] for b in range(1, nb))
            if total > 0:
                k = comp.settotalmass / total
                for b in range(1, nb):
                    m, c, ic = bodies[b].inertia
                    bodies[b].inertia = (m * k, c, tuple(x * k for x in ic))  # type: ignore[assignment]
        # names (MuJoCo's where given)
        body_names: set[str] = {body.name for body in bodies[1:] if body.name}
        if len(body_names) < nb - 1:
            for b in range(1, nb):
                if not bodies[b].name:
                    bodies[b].name = _unique(f"body{b}", body_names)
        joint_names: set[str] = {j.name for body in bodies for j in body.joints if j.name}
        for body in bodies[1:]:
            for k, j in enumerate(body.joints):
                if not j.name:
                    j.name = _unique(f"{body.name}/free" if j.freejoint and j.kind == "free"
                                     else f"{body.name}/joint{k}", joint_names)

        for body in bodies:  # named sites first, so that generated names avoid them
            for site_name, _, _ in body.sites:
                if site_name in self.site_names:
                    raise MJCFError(f"{doc.label}: site name {site_name!r} is used twice (MuJoCo: repeated name)")
                if site_name:
                    self.site_names.add(site_name)
        fd_body = [-1] * nb
        # each MJCF body frame in its featherdyn body, (R, p)
        pose_fd_mj: list[tuple[Mat, Vec]] = [(I3, Z3)] * nb
        taken = set(body_names)
        # the featherdyn bodies, column by column (the builder's order), and their inertias with the welded MJCF bodies
        # folded in; handed to the builder once complete
        names: list[str] = []
        ups: list[int] = []
        joints: list[Joint] = []
        jnames: list[str] = []
        rotations: list[Mat] = []  # the placements
        translations: list[Vec] = []
        lower: list[tuple[float, ...]] = []
        upper: list[tuple[float, ...]] = []
        armature: list[tuple[float, ...]] = []
        unbounded: list[tuple[float, ...]] = []  # velocity and effort limits
        inertias: list[Inertia] = []
        # the frames, each a FrameInfo, or (name, body, (R, p), kind) until the placements are stacked (posed: where)
        frames: list[Any] = []
        posed: list[int] = []
        owner: dict[int, _Body] = {}  # the moving MJCF body of each featherdyn body that carries one
        inserted: list[str] = []  # the massless carriers of all but the last joint of a body (Model.inserted_bodies)
        for b in range(1, nb):
            body = bodies[b]
            parent = body.parent
            R, p = compose(*pose_fd_mj[parent], body.R, body.p)
            js = body.joints
            if not js:
                up = fd_body[b] = fd_body[parent]
                pose_fd_mj[b] = (R, p)
                if up >= 0:
                    inertias[up] = _combined(inertias[up], _moved(body.inertia, R, p))
                _add_frame(frames, posed, body.name, up, R, p, "link")
                if body.sites:
                    self.add_sites(frames, posed, body, up, R, p)
                continue
            if len(js) > 1 or js[0].kind == "free":
                self.check_joints(body, b)
            up = fd_body[parent]
            last = len(js) - 1
            for k, j in enumerate(js):
                joint: Joint
                kind = j.kind
                # placement = X ∘ (anchor at pos) ∘ (turn by -ref); the frame after the joint goes back by -pos
                if kind == "hinge":
                    rotations.append(mat_mul(R, axis_angle_matrix(j.axis, -j.ref)))
                    translations.append(vec_add(mat_vec(R, j.pos), p))
                    joint = self.joint("hinge", j.axis)
                elif kind == "slide":
                    a = j.axis
                    rotations.append(R)
                    translations.append(vec_add(mat_vec(R, (-j.ref * a[0], -j.ref * a[1], -j.ref * a[2])), p))
                    joint = self.joint("slide", a)
                elif kind == "free":
                    rotations.append(I3)
                    translations.append(Z3)
                    joint = self.joint("free", Z3)
                else:
                    rotations.append(R)
                    translations.append(vec_add(mat_vec(R, j.pos), p))
                    joint = self.joint("ball", Z3)
                names.append(body.name if k == last else _unique(f"{body.name}#{k}", taken))
                if k != last:
                    inserted.append(names[-1])
                ups.append(up)
                joints.append(joint)
                jnames.append(j.name)
                if kind in ("hinge", "slide"):  # one coordinate, its limits
                    lower.append((j.lower,))
                    upper.append((j.upper,))
                    armature.append((j.armature,))
                    unbounded.append((math.inf,))
                else:
                    lower.append((-math.inf,) * joint.nq)
                    upper.append((math.inf,) * joint.nq)
                    armature.append((j.armature,) * joint.nv)
                    unbounded.append((math.inf,) * joint.nv)
                up = len(names) - 1
                frames.append(FrameInfo(j.name, up, _IDENTITY, "joint"))  # at its body's origin
                if kind in ("slide", "free") or j.pos is Z3:
                    R, p = I3, Z3
                else:
                    R, p = I3, (-j.pos[0], -j.pos[1], -j.pos[2])
                inertias.append(_moved(body.inertia, R, p) if k == last else _NO_INERTIA)
            fd_body[b] = up
            pose_fd_mj[b] = (R, p)
            owner[up] = body
            _add_frame(frames, posed, body.name, up, R, p, "body")
            if body.sites:
                self.add_sites(frames, posed, body, up, R, p)
        if bodies[0].sites:
            self.add_sites(frames, posed, bodies[0], -1, I3, Z3)
        # MuJoCo's rule on moving bodies is on the body with its welded descendants (its weld group)
        for i, body in owner.items():
            mass, _, ic = inertias[i]
            if mass < MJ_MINVAL or not _smallest_above(ic, MJ_MINVAL):
                principal = np.linalg.eigvalsh(np.array(rows(ic)))
                if mass < MJ_MINVAL or float(principal.min()) < MJ_MINVAL:
                    raise doc.error(body.elem, f"body {body.name!r}: mass {mass:g} and principal inertia "
                                    f"{principal.tolist()} with its welded descendants: MuJoCo requires the mass and "
                                    f"inertia of a moving body to exceed mjMINVAL = {MJ_MINVAL:g}")
        builder = ModelBuilder(self.model_name or "MuJoCo Model", Z3 if self.gravity_disabled else self.gravity)
        builder.source = self.path
        builder._extend(names, ups, joints, jnames, rotations, translations, [m for m, _, _ in inertias],
                        [c for _, c, _ in inertias], [ic for _, _, ic in inertias], lower, upper, unbounded, unbounded,
                        armature, tuple(inserted))
        if posed:  # their placements: one stacked read-only array, each frame's a view of its row
            chain = itertools.chain.from_iterable
            n = len(posed)
            stacked = np.fromiter(itertools.chain(chain(frames[i][2][0] for i in posed),
                                                  chain(frames[i][2][1] for i in posed)), np.float64, 12 * n)
            stacked.setflags(write=False)
            Rs, ps = stacked[:9 * n].reshape(n, 3, 3), stacked[9 * n:].reshape(n, 3)
            wrap = PluckerTransform._wrap_read_only  # (views of the read-only buffer)
            for i, R_k, p_k in zip(posed, Rs, ps, strict=True):
                fname, body_index, _, fkind = frames[i]
                frames[i] = FrameInfo(fname, body_index, wrap(R_k, p_k), fkind)
        builder._append_frames(frames)
        return builder._build(doc.strict, True)

    def joint(self, kind: str, axis: Vec) -> Joint:
        """The joint model of a kind and axis (shared: joint models are immutable)."""
        key = (kind, axis)
        joint = self.joint_cache.get(key)
        if joint is None:
            if kind == "free":
                joint = FreeFlyerJoint()
            elif kind == "ball":
                joint = SphericalJoint()
            elif kind == "slide":
                joint = _with_unit_axis(PrismaticJoint, axis)  # the axis: normalised by read_joint, then rotated
            else:
                joint = _with_unit_axis(RevoluteJoint, axis)
            self.joint_cache[key] = joint
        return joint

    def check_joints(self, body: _Body, b: int) -> None:
        doc = self.doc
        kinds = [j.kind for j in body.joints]
        if "free" in kinds:
            j = body.joints[kinds.index("free")]
            if body.parent != 0:
                raise doc.error(j.elem, "a free joint can only be used on a top-level body (a child of <worldbody>)")
            if len(kinds) > 1:
                raise doc.error(j.elem, f"body {body.name!r}: a free joint must be the body's only joint (MuJoCo: "
                                "more than 6 dofs in a body)")
        for k, kind in enumerate(kinds):
            if kind == "ball" and any(x in ("hinge", "ball") for x in kinds[k + 1:]):
                raise doc.error(body.joints[k].elem, f"body {body.name!r}: a ball joint followed by a rotation in the "
                                "same body (MuJoCo refuses this)")

    def add_sites(self, frames: list[Any], posed: list[int], body: _Body, fd: int, R: Mat, p: Vec) -> None:
        """The body's sites as frames of featherdyn body ``fd``, where the MJCF body frame is posed ``(R, p)``."""
        for k, (name, Rs, ps) in enumerate(body.sites):
            full = name or _unique(f"{body.name}/site{k}", self.site_names)
            _add_frame(frames, posed, full, fd, *compose(R, p, Rs, ps), "site")


def _asset_file(model_dir: Path, file: str, meshdir: str | None, assetdir: str | None) -> Path:
    """An asset's file: an absolute path as is, else under ``meshdir`` (else ``assetdir``) in the model's folder."""
    p = Path(file)
    return p if p.is_absolute() else model_dir / (meshdir or assetdir or "") / p


def _inline_mass_properties(vertex: tuple[float, ...], face: tuple[float, ...], scale: Vec,
                            mode: str) -> tuple[float, Vec, Mat]:
    """:func:`mass_properties` of a mesh given in the document (``vertex``, ``face``: the numbers, by threes)."""
    V = np.array(vertex, dtype=np.float64).reshape(-1, 3)
    if any(f != int(f) for f in face):
        raise MeshError("face indices must be integers")
    if face and (min(face) < 0 or max(face) >= len(V)):  # (before the int64 array: an index may exceed its range)
        raise MeshError(f"a face index is outside 0..{len(V) - 1}")
    F = np.array(face, dtype=np.int64).reshape(-1, 3)
    return mass_properties(V, F, scale, mode)


def load_mjcf(path_or_xml: str | os.PathLike[str] | bytes, *, strict: bool = False) -> Model:
    """Load an MJCF (MuJoCo XML) model with MuJoCo's compiler semantics (module doc: what is supported).

    Args:
        path_or_xml: a file path, an XML string (starting with ``<``) or bytes.
            ``<include>`` files are found relative to the main file's
            directory (the current directory for a string).
        strict: refuse elements without rigid-tree meaning (``actuator``,
            ``tendon``, ...) and turn physicality warnings into errors.

    Returns:
        The :class:`~featherdyn.Model`; ``q`` has MuJoCo's ``qpos`` layout (convert
        with :func:`featherdyn.conventions.q_from_mujoco` & co.), ``armature``
        MuJoCo's ``dof_armature``.

    Mesh files: the mass properties of each are kept for later loads in the
    same process, as MuJoCo keeps the meshes it has read, while the file is
    unchanged (device, inode, size, modification and change times; files
    written in the last second are read every time); :func:`clear_mesh_cache`
    forgets them.

    Raises:
        MJCFError: bad XML, hostile input (entities, include cycles, depth),
            a number that is not finite or too large, an element or
            attribute MuJoCo's schema does not know (the message names the
            nearest valid one), an unknown class or attribute value, a missing include, a model MuJoCo's
            compiler refuses (massless moving body, misplaced free joint, ...)
            or one featherdyn does not support (mesh inertia, ``replicate``).
            Every failure is an ``MJCFError`` (a :class:`~featherdyn.ModelError`,
            a ``ValueError``) naming the file, line, element and attribute.

    Warns:
        PhysicalityWarning: once, listing the ignored elements without
            rigid-tree meaning; once, listing the unknown attributes inside
            ``<frame>`` and ``<replicate>`` (MuJoCo ignores them there).
    """
    source = read_mjcf_source(path_or_xml)
    path = None if isinstance(path_or_xml, (bytes, bytearray, memoryview)) or (
        isinstance(path_or_xml, str) and path_or_xml.lstrip("\ufeff \t\r\n").startswith("<")) else str(path_or_xml)
    model, label, ignored, complaints = _load(path_or_xml, source, path, strict)
    if ignored:
        warnings.warn(f"{label}: ignored MJCF elements without rigid-tree meaning: {', '.join(ignored)}",
                      PhysicalityWarning, stacklevel=2)
    for msg in complaints:  # the model builder's warnings, named by the file
        warnings.warn(f"{label}: {shorten_quoted(msg)}", PhysicalityWarning, stacklevel=2)
    return model


def _load(path_or_xml: Any, source: tuple[str, str, str | None], path: str | None,
          strict: bool) -> tuple[Model, str, list[str], list[str]]:
    """The Python reader: ``(model, label, ignored elements, the model builder's warnings)``."""
    doc = read_document(path_or_xml, strict, source)
    check_names(doc)
    loader = _Loader(doc, path)
    try:
        loader.read_top()
        expand_replicates(doc)
        loader.read_bodies()
        model, complaints = loader.build()
    except MJCFError:
        raise
    except FeatherdynError as exc:  # a check of the spatial types or the model builder: name the file
        raise MJCFError(f"{doc.label}: {shorten_quoted(str(exc))}") from None
    return model, doc.label, loader.ignored, complaints


def model_format(path_or_xml: str | os.PathLike[str] | bytes) -> str:
    """``"urdf"``, ``"mjcf"`` or ``"sdf"``: the format of a model file or text, by its root element (``<robot>`` /
    ``<mujoco>`` / ``<sdf>``); a file named ``*.sdf`` or ``*.world`` is SDF without being read.

    Raises:
        MJCFError: unreadable, not XML, or another root element; a ``URDFError`` instead for a file named
            ``*.urdf`` (a malformed URDF is a URDF error to its reader).
    """
    from ..errors import URDFError
    from .xml import parse_xml

    name = os.fspath(path_or_xml).lower() if isinstance(path_or_xml, (str, os.PathLike)) else ""
    if name.endswith((".sdf", ".world")) and not name.lstrip("\ufeff \t\r\n").startswith("<"):
        return "sdf"
    error: type[ModelError] = URDFError if name.endswith(".urdf") else MJCFError
    text, label, _ = read_source(path_or_xml, error, "model", "load_model")
    root, _ = parse_xml(text, label, error, "model", line_depth=1)
    tag = tag_name(root.tag).split("}", 1)[-1]
    if tag == "robot":
        return "urdf"
    if tag == "mujoco":
        return "mjcf"
    if tag == "sdf":
        return "sdf"
    raise error(f"{label}: expected the root element <robot> (URDF), <mujoco> (MJCF) or <sdf> (SDFormat), "
                f"got <{tag[:100]}>")


def load_model(path_or_xml: str | os.PathLike[str] | bytes, *, strict: bool = False) -> Model:
    """Load a URDF, an MJCF or an SDFormat model, told apart by the root element (``<robot>``, ``<mujoco>`` or
    ``<sdf>``; a file named ``*.sdf`` or ``*.world`` is SDFormat).

    A URDF loads with a fixed base (:func:`featherdyn.load_urdf` takes
    ``floating_base=True``); an MJCF as :func:`load_mjcf`; an SDF document as
    :func:`featherdyn.load_sdf` (its only model; ``load_sdf(..., model=NAME)``
    picks one of several).

    Raises:
        MJCFError: none of the root elements; the loaders' errors otherwise.
    """
    from .urdf import load_urdf

    fmt = model_format(path_or_xml)
    if fmt == "urdf":
        return load_urdf(path_or_xml, strict=strict)
    if fmt == "sdf":
        from .sdf import load_sdf

        return load_sdf(path_or_xml, strict=strict)
    return load_mjcf(path_or_xml, strict=strict)
