"""Reading an MJCF document (private to :mod:`featherdyn.mjcf`): includes, default classes, numbers, orientations.

The XML goes through the URDF loader's safe reader (:mod:`featherdyn._urdf_xml`:
defusedxml, no DTDs or entities, bounded nesting and attribute length).
``<include file=...>`` elements are replaced by the children of the included
file's ``<mujoco>`` root, each file read the same safe way, relative to the
main file's directory; cycles, missing files, more than
:data:`MAX_INCLUDE_DEPTH` nested or :data:`MAX_INCLUDES` included files are
refused. Every element remembers its file and line for messages.

Default classes follow MuJoCo: the top-level ``<default>`` is class
``"main"``; a nested ``<default class="X">`` inherits its parent's
attributes per element kind; an element uses its ``class``, else the
``childclass`` of the nearest enclosing body or frame, else ``"main"``.

Orientations (MuJoCo's "frame orientations"): ``quat`` ``(w, x, y, z)``,
``axisangle``, ``euler`` (``eulerseq``: lower case intrinsic, upper case
extrinsic), ``xyaxes``, ``zaxis``; angles in degrees unless
``<compiler angle="radian">``; at most one per element.
"""

from __future__ import annotations

import math
import os
import re
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from ._urdf_xml import MAX_DEPTH, _parse_xml, _quote, _read_source, _shorten
from .errors import MJCFError, PhysicalityWarning
from .urdf import MAX_LENGTH

#: Deepest nesting of ``<include>`` files accepted.
MAX_INCLUDE_DEPTH = 20
#: Most files a model may include in all.
MAX_INCLUDES = 1000
# the magnitude bounds are the URDF loader's (featherdyn.urdf module doc: finite input, finite dynamics)

# a digit run matches one way only (the fraction needs its dot), so a failed match backtracks in linear time
_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_ORIENTATIONS = ("quat", "axisangle", "euler", "xyaxes", "zaxis")
# element kinds that default classes configure (the rest are accepted and ignored)
_DEFAULT_KINDS = frozenset({"joint", "geom", "site", "mesh", "inertial", "frame"})


class Doc:
    """The parsed document: where each element came from, the compiler settings, the default classes."""

    def __init__(self, root: Any, where: dict[Any, tuple[str, int]], label: str, model_dir: Path,
                 strict: bool) -> None:
        self.root = root
        self.where_of = where
        self.label = label
        self.model_dir = model_dir
        self.strict = strict
        self.degree = True
        self.eulerseq = "xyz"
        self.own_defaults: dict[str, dict[str, dict[str, str]]] = {}
        self.default_parent: dict[str, str | None] = {}
        self._resolved: dict[tuple[str, str], dict[str, str]] = {}

    # -- messages -------------------------------------------------------------

    def where(self, elem: Any) -> str:
        label, line = self.where_of.get(elem, (self.label, 0))
        tag = _shorten(str(elem.tag)) if isinstance(elem.tag, str) else "?"
        name = elem.get("name")
        named = f" name={_quote(name)}" if name is not None else ""
        return f"{label}: " + (f"line {line}: " if line else "") + f"<{tag}{named}>"

    def error(self, elem: Any, msg: str) -> MJCFError:
        return MJCFError(f"{self.where(elem)}: {msg}")

    def warn(self, elem: Any, msg: str) -> None:
        text = f"{self.where(elem)}: {msg}"
        if self.strict:
            raise MJCFError(text + " (strict=True)")
        warnings.warn(text, PhysicalityWarning, stacklevel=4)

    # -- attributes -----------------------------------------------------------

    def class_defaults(self, cls: str, kind: str) -> dict[str, str]:
        """The attributes class ``cls`` gives elements of ``kind``: its ancestors' from ``"main"`` down, overlaid."""
        key = (cls, kind)
        if key not in self._resolved:
            chain: list[str] = []
            c: str | None = cls
            while c is not None:
                chain.append(c)
                c = self.default_parent[c]
            merged: dict[str, str] = {}
            for c in reversed(chain):
                _overlay(merged, self.own_defaults[c].get(kind, {}))
            self._resolved[key] = merged
        return self._resolved[key]

    def attrs(self, elem: Any, kind: str, cls: str) -> dict[str, str]:
        """The element's attributes over those of its default class (an orientation given replaces the default's)."""
        merged = dict(self.class_defaults(cls, kind))
        _overlay(merged, dict(elem.attrib))
        return merged

    def element_class(self, elem: Any, childclass: str, attr: str = "class") -> str:
        """The default class of ``elem``: its ``attr`` (``class``, or ``childclass`` for what it passes on)."""
        cls = elem.get(attr)
        if cls is None:
            return childclass
        if cls not in self.own_defaults:
            raise self.error(elem, f"{attr}={_quote(cls)}: unknown default class (defined: "
                             f"{', '.join(repr(c) for c in list(self.own_defaults)[:20])})")
        return cls

    def floats(self, elem: Any, attrs: dict[str, str], name: str, counts: tuple[int, ...],
               default: list[float] | None = None, bound: float = MAX_LENGTH) -> list[float] | None:
        """The attribute as finite decimals, ``len`` one of ``counts``; ``default`` when absent."""
        text = attrs.get(name)
        if text is None:
            return default
        parts = text.split()
        if len(parts) not in counts:
            want = " or ".join(str(c) for c in counts)
            raise self.error(elem, f"{name}={_quote(text)}: expected {want} number{'s' if max(counts) > 1 else ''}, "
                             f"got {len(parts)}")
        out = []
        for s in parts:
            if not _NUMBER.fullmatch(s):
                raise self.error(elem, f"{name}={_quote(text)}: {_quote(s)} is not a decimal number")
            x = float(s)
            if not math.isfinite(x) or abs(x) > bound:
                raise self.error(elem, f"{name}={_quote(text)}: expected a magnitude of at most {bound:g} "
                                 f"(larger values overflow the dynamics), got {_quote(s)}")
            out.append(x)
        return out

    def require(self, elem: Any, attrs: dict[str, str], name: str, counts: tuple[int, ...],
                bound: float = MAX_LENGTH) -> list[float]:
        """:meth:`floats` of an attribute that must be present."""
        got = self.floats(elem, attrs, name, counts, None, bound)
        if got is None:
            raise self.error(elem, f"needs the attribute {name!r}")
        return got

    def float_list(self, elem: Any, attrs: dict[str, str], name: str, multiple_of: int) -> list[float]:
        """The attribute as finite decimals, a multiple of ``multiple_of`` of them (``[]`` when absent)."""
        text = attrs.get(name)
        if text is None:
            return []
        n = len(text.split())
        if n % multiple_of:
            raise self.error(elem, f"{name}={_quote(text)}: expected a multiple of {multiple_of} numbers, got {n}")
        return self.floats(elem, attrs, name, (n,)) or []

    def number(self, elem: Any, attrs: dict[str, str], name: str, default: float,
               bound: float = MAX_LENGTH) -> float:
        got = self.floats(elem, attrs, name, (1,), None, bound)
        return default if got is None else got[0]

    def choice(self, elem: Any, attrs: dict[str, str], name: str, options: tuple[str, ...], default: str) -> str:
        text = attrs.get(name, default)
        if text not in options:
            raise self.error(elem, f"{name}={_quote(text)}: expected one of {', '.join(options)}")
        return text

    def boolean(self, elem: Any, attrs: dict[str, str], name: str, default: bool) -> bool:
        return self.choice(elem, attrs, name, ("true", "false"), "true" if default else "false") == "true"

    def angle(self, x: float) -> float:
        return math.radians(x) if self.degree else x

    # -- poses ----------------------------------------------------------------

    def rotation(self, elem: Any, attrs: dict[str, str]) -> np.ndarray:
        """The element's orientation as a rotation matrix (identity when none is given)."""
        given = [k for k in _ORIENTATIONS if k in attrs]
        if len(given) > 1:
            raise self.error(elem, f"several orientations given ({', '.join(given)}); MuJoCo accepts one")
        if not given:
            return np.eye(3)
        kind = given[0]
        if kind == "quat":
            q = self.require(elem, attrs, "quat", (4,))
            n = math.sqrt(sum(c * c for c in q))
            if n < 1e-10:
                raise self.error(elem, f"quat={_quote(attrs['quat'])}: a zero quaternion is not a rotation")
            return quat_wxyz_matrix(np.array(q) / n)
        if kind == "axisangle":
            aa = self.require(elem, attrs, "axisangle", (4,))
            axis = self._direction(elem, attrs, "axisangle", np.array(aa[:3]))
            return axis_angle_matrix(axis, self.angle(aa[3]))
        if kind == "euler":
            e = self.require(elem, attrs, "euler", (3,))
            R = np.eye(3)
            for letter, a in zip(self.eulerseq, e, strict=True):
                axis = np.eye(3)["xyz".index(letter.lower())]
                Rk = axis_angle_matrix(axis, self.angle(a))
                R = R @ Rk if letter.islower() else Rk @ R
            return R
        if kind == "xyaxes":
            v = self.require(elem, attrs, "xyaxes", (6,))
            x = self._direction(elem, attrs, "xyaxes", np.array(v[:3]))
            y = np.array(v[3:]) - x * float(np.dot(x, v[3:]))
            y = self._direction(elem, attrs, "xyaxes", y, "the y axis is parallel to the x axis")
            return np.column_stack([x, y, np.cross(x, y)])
        z = self.require(elem, attrs, "zaxis", (3,))
        return z_to_vector(self._direction(elem, attrs, "zaxis", np.array(z)))

    def _direction(self, elem: Any, attrs: dict[str, str], name: str, v: np.ndarray,
                   why: str = "a zero vector") -> np.ndarray:
        largest = float(np.max(np.abs(v)))
        n = largest * float(np.linalg.norm(v / largest)) if largest > 0 else 0.0
        if n < 1e-10:
            raise self.error(elem, f"{name}={_quote(attrs[name])}: {why} is not a direction")
        return np.asarray(v / n, dtype=np.float64)

    def pose(self, elem: Any, attrs: dict[str, str]) -> tuple[np.ndarray, np.ndarray]:
        """``(R, p)``: the element's ``pos`` and orientation in its parent's frame."""
        p = self.floats(elem, attrs, "pos", (3,), [0.0, 0.0, 0.0]) or [0.0, 0.0, 0.0]
        return self.rotation(elem, attrs), np.array(p)


def quat_wxyz_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrix of a unit quaternion ``(w, x, y, z)``."""
    w, x, y, z = (float(c) for c in q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def axis_angle_matrix(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues: ``R = 1 + sin θ [a]× + (1 − cos θ) [a]×²`` for a unit ``axis``."""
    K = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * (K @ K)


def z_to_vector(v: np.ndarray) -> np.ndarray:
    """The smallest rotation taking ``(0, 0, 1)`` to the unit vector ``v`` (π about x when opposite), as MuJoCo."""
    z = np.array([0.0, 0.0, 1.0])
    axis = np.cross(z, v)
    s = float(np.linalg.norm(axis))
    if s < 1e-14:
        return np.eye(3) if v[2] > 0 else np.diag([1.0, -1.0, -1.0])
    return axis_angle_matrix(axis / s, math.atan2(s, float(v[2])))


# ---------------------------------------------------------------------------
# reading, includes
# ---------------------------------------------------------------------------


def _local(tag: Any) -> str:
    return tag if isinstance(tag, str) else ""


def _read(path_or_xml: Any) -> tuple[Any, dict[Any, tuple[str, int]], str, str | None]:
    text, label, path = _read_source(path_or_xml, MJCFError, "MJCF", "load_mjcf")
    root, lines = _parse_xml(text, label, MJCFError, "MJCF", line_depth=MAX_DEPTH)
    return root, {e: (label, n) for e, n in lines.items()}, label, path


def read_document(path_or_xml: Any, strict: bool) -> Doc:
    """Parse the main file, check its root is ``<mujoco>``, expand every ``<include>``.

    Each pass replaces every ``<include>`` present by its file's content, so
    the passes are bounded by the include depth; each element remembers the
    chain of files that brought it (for cycles).
    """
    root, where, label, path = _read(path_or_xml)
    if _local(root.tag) != "mujoco":
        tag = _shorten(_local(root.tag) or "?")
        hint = " (a URDF: use featherdyn.load_urdf or load_model)" if tag == "robot" else ""
        raise MJCFError(f"{label}: expected the root element <mujoco>, got <{tag}>{hint}")
    model_dir = Path(path).parent if path is not None else Path(os.getcwd())
    doc = Doc(root, where, label, model_dir, strict)
    chain_of: dict[Any, tuple[str, ...]] = {root: (str(Path(path).resolve()) if path else label,)}
    included = 0
    seen: set[str] = set()
    while True:
        parent_of = {c: p for p in root.iter() for c in p}
        includes = [e for e in root.iter() if _local(e.tag) == "include"]
        if not includes:
            return doc
        for inc in includes:
            up = inc
            while up not in chain_of:
                up = parent_of[up]
            chain = chain_of[up]
            file = inc.get("file")
            if file is None or not file.strip():
                raise doc.error(inc, "<include> needs a 'file' attribute")
            target = (doc.model_dir / file).resolve()
            if str(target) in chain:
                raise doc.error(inc, f"file={_quote(file)}: include cycle ("
                                + " -> ".join(_quote(c) for c in (*chain, str(target))) + ")")
            if str(target) in seen:
                raise doc.error(inc, f"file={_quote(file)}: already included (MuJoCo includes a file once)")
            seen.add(str(target))
            if len(chain) > MAX_INCLUDE_DEPTH:
                raise doc.error(inc, f"includes nested deeper than {MAX_INCLUDE_DEPTH} files (MAX_INCLUDE_DEPTH)")
            included += 1
            if included > MAX_INCLUDES:
                raise doc.error(inc, f"more than {MAX_INCLUDES} included files (MAX_INCLUDES)")
            if not target.is_file():
                raise doc.error(inc, f"file={_quote(file)}: the included file {_quote(str(target))} does not exist")
            sub, sub_where, _, _ = _read(target)
            if _local(sub.tag) not in ("mujoco", "mujocoinclude"):  # <mujocoinclude>: MuJoCo's older root, still read
                raise doc.error(inc, f"file={_quote(file)}: an included file's root must be <mujoco>, got "
                                f"<{_shorten(_local(sub.tag) or '?')}>")
            doc.where_of.update(sub_where)
            parent = parent_of[inc]
            k = list(parent).index(inc)
            parent.remove(inc)
            for j, elem in enumerate(list(sub)):
                parent.insert(k + j, elem)
                chain_of[elem] = (*chain, str(target))


# ---------------------------------------------------------------------------
# default classes
# ---------------------------------------------------------------------------


def read_defaults(doc: Doc) -> None:
    """Record each default class's own attributes per element kind, and its parent class."""
    doc.own_defaults["main"] = {}
    doc.default_parent["main"] = None
    stack: list[tuple[Any, str]] = []
    for top in (e for e in doc.root if _local(e.tag) == "default"):
        name = top.get("class", "main")
        if name != "main":
            raise doc.error(top, f"class={_quote(name)}: the top-level <default> is class 'main'")
        stack.append((top, "main"))
    while stack:
        elem, cls = stack.pop()
        table = doc.own_defaults[cls]
        for child in elem:
            kind = _local(child.tag)
            if kind == "default":
                name = child.get("class")
                if name is None or not name:
                    raise doc.error(child, "a nested <default> needs a 'class' attribute")
                if name in doc.own_defaults:
                    raise doc.error(child, f"class={_quote(name)}: default class defined twice")
                doc.own_defaults[name] = {}
                doc.default_parent[name] = cls
                stack.append((child, name))
            elif kind in _DEFAULT_KINDS:
                own = dict(child.attrib)
                if "class" in own or "name" in own:
                    raise doc.error(child, "an element of a <default> takes no 'name' or 'class'")
                _overlay(table.setdefault(kind, {}), own)


def _overlay(base: dict[str, str], top: dict[str, str]) -> None:
    """``base.update(top)``, where an orientation (or ``fromto``) in ``top`` removes ``base``'s."""
    if any(k in top for k in (*_ORIENTATIONS, "fromto")):
        for k in (*_ORIENTATIONS, "fromto"):
            base.pop(k, None)
    base.update(top)


# ---------------------------------------------------------------------------
# <replicate>
# ---------------------------------------------------------------------------

#: Most elements ``<replicate>`` may create in all.
MAX_REPLICATED = 1_000_000


def expand_replicates(doc: Doc) -> None:
    """Replace each ``<replicate>`` by ``count`` copies of its children, innermost first (MuJoCo's rules).

    Copy ``k`` sits in a ``<frame>`` at ``T^k``, ``T = (offset, euler)``
    (angles in the compiler's unit); every named element inside gets
    ``sep`` and ``k`` appended, ``k`` zero-padded to the digits of
    ``count`` (measured: ``count=11`` gives ``b00 … b10``; a nested
    replicate's suffix comes first). Unnamed elements stay unnamed.
    """
    import copy

    created = 0
    while True:
        parent_of = {c: p for p in doc.root.iter() for c in p}
        innermost = [e for e in doc.root.iter() if _local(e.tag) == "replicate"
                     and not any(_local(d.tag) == "replicate" for d in e.iter() if d is not e)]
        if not innermost:
            return
        for rep in innermost:
            attrs = dict(rep.attrib)
            count_text = attrs.get("count", "")
            if not count_text.strip().isdigit() or int(count_text) < 1:
                raise doc.error(rep, f"count={_quote(count_text)}: expected a positive integer")
            count = int(count_text)
            for child in rep:
                if _local(child.tag) in ("joint", "freejoint", "inertial"):
                    raise doc.error(child, "a joint or inertial cannot be a direct child of <replicate> (MuJoCo)")
            size = sum(1 for _ in rep.iter()) - 1
            created += count * size
            if created > MAX_REPLICATED:
                raise doc.error(rep, f"<replicate> would create more than {MAX_REPLICATED} elements (MAX_REPLICATED)")
            offset = np.array(doc.floats(rep, attrs, "offset", (3,), [0.0, 0.0, 0.0]) or [0.0, 0.0, 0.0])
            step = doc.rotation(rep, {k: v for k, v in attrs.items() if k == "euler"})
            sep = attrs.get("sep", "")
            digits = len(str(count))
            parent = parent_of[rep]
            at = list(parent).index(rep)
            parent.remove(rep)
            R, p = np.eye(3), np.zeros(3)
            for k in range(count):
                frame = type(rep)("frame", {
                    "pos": " ".join(repr(float(x)) for x in p),
                    "xyaxes": " ".join(repr(float(x)) for x in (*R[:, 0], *R[:, 1])),
                })
                doc.where_of[frame] = doc.where_of.get(rep, (doc.label, 0))
                suffix = f"{sep}{k:0{digits}d}"
                for child in rep:
                    clone = copy.deepcopy(child)
                    for orig, new in zip(child.iter(), clone.iter(), strict=True):
                        doc.where_of[new] = doc.where_of.get(orig, doc.where_of.get(rep, (doc.label, 0)))
                        if new.get("name") is not None:
                            new.set("name", new.get("name") + suffix)
                    frame.append(clone)
                parent.insert(at + k, frame)
                R, p = R @ step, R @ offset + p
