"""Reading an MJCF document (used by :mod:`featherdyn.readers.mjcf`): includes, default classes, numbers, orientations.

The XML goes through the URDF loader's safe reader (:mod:`featherdyn.readers.xml`:
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

import errno
import math
import os
import re
import stat
import warnings
from pathlib import Path
from typing import Any

from ..errors import MJCFError, PhysicalityWarning
from .urdf import MAX_LENGTH
from .xml import ElementIndex, ElementLines, parse_elements, quote, read_source, shorten

#: Deepest nesting of ``<include>`` files accepted.
MAX_INCLUDE_DEPTH = 20
#: Most files a model may include in all.
MAX_INCLUDES = 1000
# the magnitude bounds are the URDF loader's (featherdyn.readers.urdf module doc: finite input, finite dynamics)

# a digit run matches one way only (the fraction needs its dot), so a failed match backtracks in linear time
_NUMBER = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_SHORT_CEILING = 1e59  # the magnitude no decimal without an exponent in fewer than 60 characters reaches
_ORIENTATIONS = ("quat", "axisangle", "euler", "xyaxes", "zaxis")
_REPLACING = frozenset((*_ORIENTATIONS, "fromto"))  # given on an element, they replace all of its class's
# element kinds that default classes configure (the rest are accepted and ignored)
_DEFAULT_KINDS = frozenset({"joint", "geom", "site", "mesh", "inertial", "frame", "tendon"})


class Doc:
    """The parsed document: where each element came from, the compiler settings, the default classes."""

    def __init__(self, root: Any, where: tuple[ElementIndex, ElementLines], label: str, path: str | None,
                 strict: bool) -> None:
        self.root = root
        # where each element came from: each parsed file's document-order index of its elements and their lines,
        # and the file and index of the elements made or moved later (replicates)
        self.sources = [where]
        self.where_of: dict[Any, tuple[ElementLines | None, int]] = {}
        self.label = label
        self.path = path
        self.strict = strict
        self.may_replicate = True  # False: surely no <replicate> (read_document)
        self.degree = True
        self.eulerseq = "xyz"
        self.own_defaults: dict[str, dict[str, dict[str, str]]] = {}
        self.default_parent: dict[str, str | None] = {}
        self._resolved: dict[tuple[str, str], dict[str, str]] = {}
        # attrs' defaults of a class and kind: all, and without orientations and fromto (for an element giving one)
        self._resolved_pair: dict[tuple[str, str], tuple[dict[str, str], dict[str, str]]] = {}
        self._parsed: dict[str, tuple[tuple[float, ...], float]] = {}

    @property
    def model_dir(self) -> Path:
        """The main file's directory (the current directory for a string): where includes and assets are found."""
        return Path(self.path).parent if self.path is not None else Path(os.getcwd())

    # -- messages -------------------------------------------------------------

    def locate(self, elem: Any) -> tuple[ElementLines | None, int]:
        """The lines of the file an element came from and its document-order index there (``(None, -1)``: unknown)."""
        got = self.where_of.get(elem)
        if got is not None:
            return got
        for index, lines in self.sources:
            k = index.get(elem)
            if k is not None:
                return lines, k
        return None, -1

    def where(self, elem: Any) -> str:
        source, index = self.locate(elem)
        label, line = (self.label, 0) if source is None else (source.label, source.line(index))
        tag = shorten(str(elem.tag)) if isinstance(elem.tag, str) else "?"
        name = elem.get("name")
        named = f" name={quote(name)}" if name is not None else ""
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
        pair = self._resolved_pair.get((cls, kind))
        if pair is None:
            defaults = self.class_defaults(cls, kind)
            pair = self._resolved_pair[cls, kind] = defaults, {k: v for k, v in defaults.items() if k not in _REPLACING}
        defaults, unposed = pair
        own = elem.attrib
        if not defaults:
            return own  # read only by the loader
        merged = defaults.copy() if _REPLACING.isdisjoint(own) else unposed.copy()  # (as _overlay)
        merged.update(own)
        if "" in own.values():  # measured: an empty number is not read, the class's value stays (an empty
            for k, v in own.items():  # orientation still replaces the class's, and is then the identity)
                if v == "" and k in defaults and k not in _REPLACING:
                    merged[k] = defaults[k]
        return merged

    def element_class(self, elem: Any, childclass: str, attr: str = "class") -> str:
        """The default class of ``elem``: its ``attr`` (``class``, or ``childclass`` for what it passes on)."""
        cls = elem.get(attr)
        if cls is None:
            return childclass
        if cls not in self.own_defaults:
            raise self.error(elem, f"{attr}={quote(cls)}: unknown default class (defined: "
                             f"{', '.join(repr(c) for c in list(self.own_defaults)[:20])})")
        return cls

    def floats(self, elem: Any, attrs: dict[str, str], name: str, counts: tuple[int, ...],
               default: tuple[float, ...] | None = None, bound: float = MAX_LENGTH) -> tuple[float, ...] | None:
        """The attribute as finite decimals, ``len`` one of ``counts``; ``default`` when absent.

        A text is parsed once per document (the same few texts recur: ``"0 0 0"``, a class's ``size``):
        :attr:`_parsed` keeps its numbers and a ceiling of their magnitudes (:func:`_parse_decimals`).
        """
        text = attrs.get(name)
        if text is None:
            return default
        got = self._parsed.get(text)
        if got is None:
            got = self._parsed[text] = _parse_decimals(text)
        values, ceiling = got
        if 0 <= ceiling <= bound and len(values) in counts:  # the usual case: decimals, small enough, as many
            return values
        if not values:  # measured: MuJoCo reads an empty (or blank) number as not given
            return default
        if len(values) not in counts:
            want = " or ".join(str(c) for c in counts)
            raise self.error(elem, f"{name}={quote(text)}: expected {want} number{'s' if max(counts) > 1 else ''}, "
                             f"got {len(values)}")
        if ceiling < 0:  # a part is not a decimal: name it
            bad = next(s for s in text.split() if not _NUMBER.fullmatch(s))
            raise self.error(elem, f"{name}={quote(text)}: {quote(bad)} is not a decimal number")
        if ceiling > bound and max(map(abs, values)) > bound:  # also +inf: a decimal too long for a double
            bad = next(s for s in text.split() if abs(float(s)) > bound)
            raise self.error(elem, f"{name}={quote(text)}: expected a magnitude of at most {bound:g} "
                             f"(larger values overflow the dynamics), got {quote(bad)}")
        return values

    def require(self, elem: Any, attrs: dict[str, str], name: str, counts: tuple[int, ...],
                bound: float = MAX_LENGTH) -> tuple[float, ...]:
        """:meth:`floats` of an attribute that must be present."""
        got = self.floats(elem, attrs, name, counts, None, bound)
        if got is None:
            raise self.error(elem, f"needs the attribute {name!r}")
        return got

    def float_list(self, elem: Any, attrs: dict[str, str], name: str, multiple_of: int) -> tuple[float, ...]:
        """The attribute as finite decimals, a multiple of ``multiple_of`` of them (``()`` when absent)."""
        text = attrs.get(name)
        if text is None:
            return ()
        n = len(text.split())
        if n % multiple_of:
            raise self.error(elem, f"{name}={quote(text)}: expected a multiple of {multiple_of} numbers, got {n}")
        return self.floats(elem, attrs, name, (n,)) or ()

    def number(self, elem: Any, attrs: dict[str, str], name: str, default: float,
               bound: float = MAX_LENGTH) -> float:
        got = self.floats(elem, attrs, name, (1,), None, bound)
        return default if got is None else got[0]

    def choice(self, elem: Any, attrs: dict[str, str], name: str, options: tuple[str, ...], default: str) -> str:
        text = attrs.get(name, default)
        if text not in options:
            raise self.error(elem, f"{name}={quote(text)}: expected one of {', '.join(options)}")
        return text

    def boolean(self, elem: Any, attrs: dict[str, str], name: str, default: bool) -> bool:
        return self.choice(elem, attrs, name, ("true", "false"), "true" if default else "false") == "true"

    def angle(self, x: float) -> float:
        return math.radians(x) if self.degree else x

    # -- poses ----------------------------------------------------------------

    def rotation(self, elem: Any, attrs: dict[str, str]) -> Mat:
        """The element's orientation as a rotation matrix (:data:`I3` itself when none is given)."""
        if _REPLACING.isdisjoint(attrs):
            return I3
        given = [k for k in _ORIENTATIONS if k in attrs]
        if not given:
            return I3
        if len(given) > 1:
            raise self.error(elem, f"several orientations given ({', '.join(given)}); MuJoCo accepts one")
        kind = given[0]
        if not given_value(attrs, kind):  # measured: given but empty, it is the identity
            return I3
        if kind == "quat":
            w, x, y, z = self.require(elem, attrs, "quat", (4,))
            n = math.hypot(w, x, y, z)
            if n < 1e-10:
                raise self.error(elem, f"quat={quote(attrs['quat'])}: a zero quaternion is not a rotation")
            return quat_wxyz_matrix((w / n, x / n, y / n, z / n))
        if kind == "axisangle":
            aa = self.require(elem, attrs, "axisangle", (4,))
            axis = self._direction(elem, attrs, "axisangle", (aa[0], aa[1], aa[2]))
            return axis_angle_matrix(axis, self.angle(aa[3]))
        if kind == "euler":
            e = self.require(elem, attrs, "euler", (3,))
            R = I3
            for letter, a in zip(self.eulerseq, e, strict=True):
                Rk = axis_angle_matrix(_AXES["xyz".index(letter.lower())], self.angle(a))
                R = mat_mul(R, Rk) if letter.islower() else mat_mul(Rk, R)
            return R
        if kind == "xyaxes":
            v = self.require(elem, attrs, "xyaxes", (6,))
            ex = self._direction(elem, attrs, "xyaxes", (v[0], v[1], v[2]))
            d = ex[0] * v[3] + ex[1] * v[4] + ex[2] * v[5]
            ey = self._direction(elem, attrs, "xyaxes", (v[3] - ex[0] * d, v[4] - ex[1] * d, v[5] - ex[2] * d),
                                 "the y axis is parallel to the x axis")
            ez = cross(ex, ey)
            return (ex[0], ey[0], ez[0], ex[1], ey[1], ez[1], ex[2], ey[2], ez[2])
        za = self.require(elem, attrs, "zaxis", (3,))
        return z_to_vector(self._direction(elem, attrs, "zaxis", (za[0], za[1], za[2])))

    def _direction(self, elem: Any, attrs: dict[str, str], name: str, v: Vec, why: str = "a zero vector") -> Vec:
        n = math.hypot(*v)  # without overflow or underflow
        if n == 1.0:  # ("0 0 1"): v / n is v
            return v
        if n < 1e-10:
            raise self.error(elem, f"{name}={quote(attrs[name])}: {why} is not a direction")
        return (v[0] / n, v[1] / n, v[2] / n)

    def pose(self, elem: Any, attrs: dict[str, str]) -> tuple[Mat, Vec]:
        """``(R, p)``: the element's orientation and ``pos`` in its parent's frame (:data:`I3`, :data:`Z3` when
        absent)."""
        p = self.floats(elem, attrs, "pos", (3,))
        R = I3 if _REPLACING.isdisjoint(attrs) else self.rotation(elem, attrs)  # (most elements: no orientation)
        return R, Z3 if p is None else p  # type: ignore[return-value]  # three floats


# ---------------------------------------------------------------------------
# 3×3 matrices and 3-vectors as tuples of floats
# ---------------------------------------------------------------------------
# A loader's geometry is a few dozen 3×3 products per body: on tuples they cost less than numpy's per-call
# overhead, and most frames are the identity — passed as the constants I3 and Z3 and skipped by identity tests.

#: A 3×3 matrix, row major.
Mat = tuple[float, float, float, float, float, float, float, float, float]
#: A 3-vector.
Vec = tuple[float, float, float]
I3: Mat = (1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)
Z3: Vec = (0.0, 0.0, 0.0)
_AXES: tuple[Vec, Vec, Vec] = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


def mat_mul(A: Mat, B: Mat) -> Mat:
    """``A B``."""
    if A is I3:
        return B
    if B is I3:
        return A
    a0, a1, a2, a3, a4, a5, a6, a7, a8 = A
    b0, b1, b2, b3, b4, b5, b6, b7, b8 = B
    return (a0 * b0 + a1 * b3 + a2 * b6, a0 * b1 + a1 * b4 + a2 * b7, a0 * b2 + a1 * b5 + a2 * b8,
            a3 * b0 + a4 * b3 + a5 * b6, a3 * b1 + a4 * b4 + a5 * b7, a3 * b2 + a4 * b5 + a5 * b8,
            a6 * b0 + a7 * b3 + a8 * b6, a6 * b1 + a7 * b4 + a8 * b7, a6 * b2 + a7 * b5 + a8 * b8)


def mat_vec(A: Mat, v: Vec) -> Vec:
    """``A v``."""
    if A is I3 or v is Z3:
        return v
    x, y, z = v
    return (A[0] * x + A[1] * y + A[2] * z, A[3] * x + A[4] * y + A[5] * z, A[6] * x + A[7] * y + A[8] * z)


def vec_add(a: Vec, b: Vec) -> Vec:
    """``a + b``."""
    if b is Z3:
        return a
    if a is Z3:
        return b
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def cross(a: Vec, b: Vec) -> Vec:
    """``a × b``."""
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def compose(R1: Mat, p1: Vec, R2: Mat, p2: Vec) -> tuple[Mat, Vec]:
    """``(R1, p1) ∘ (R2, p2) = (R1 R2, R1 p2 + p1)``: the pose ``(R2, p2)`` given in the frame posed ``(R1, p1)``."""
    if R1 is I3:  # most frames: the product and the rotation skipped
        return R2, (p2 if p1 is Z3 else vec_add(p2, p1))
    return mat_mul(R1, R2), vec_add(mat_vec(R1, p2), p1)


def rotate_symmetric(R: Mat, S: Mat) -> Mat:
    """``R S Rᵀ`` of a symmetric ``S`` (symmetric exactly: the upper triangle is computed and mirrored)."""
    if R is I3:
        return S
    r0, r1, r2, r3, r4, r5, r6, r7, r8 = R
    s0, s1, s2, _, s4, s5, _, _, s8 = S
    # T = R S (rows of R against the columns of S)
    t0, t1, t2 = r0 * s0 + r1 * s1 + r2 * s2, r0 * s1 + r1 * s4 + r2 * s5, r0 * s2 + r1 * s5 + r2 * s8
    t3, t4, t5 = r3 * s0 + r4 * s1 + r5 * s2, r3 * s1 + r4 * s4 + r5 * s5, r3 * s2 + r4 * s5 + r5 * s8
    t6, t7, t8 = r6 * s0 + r7 * s1 + r8 * s2, r6 * s1 + r7 * s4 + r8 * s5, r6 * s2 + r7 * s5 + r8 * s8
    xx, xy, xz = t0 * r0 + t1 * r1 + t2 * r2, t0 * r3 + t1 * r4 + t2 * r5, t0 * r6 + t1 * r7 + t2 * r8
    yy, yz = t3 * r3 + t4 * r4 + t5 * r5, t3 * r6 + t4 * r7 + t5 * r8
    zz = t6 * r6 + t7 * r7 + t8 * r8
    return (xx, xy, xz, xy, yy, yz, xz, yz, zz)


def rotate_diagonal(R: Mat, d: Vec) -> Mat:
    """``R diag(d) Rᵀ`` (symmetric exactly)."""
    if R is I3:
        return diagonal(d)
    r0, r1, r2, r3, r4, r5, r6, r7, r8 = R
    d0, d1, d2 = d
    a0, a1, a2 = r0 * d0, r1 * d1, r2 * d2  # row 0 of R diag(d)
    b0, b1, b2 = r3 * d0, r4 * d1, r5 * d2  # row 1
    xx, xy, xz = a0 * r0 + a1 * r1 + a2 * r2, a0 * r3 + a1 * r4 + a2 * r5, a0 * r6 + a1 * r7 + a2 * r8
    yy, yz = b0 * r3 + b1 * r4 + b2 * r5, b0 * r6 + b1 * r7 + b2 * r8
    zz = r6 * d0 * r6 + r7 * d1 * r7 + r8 * d2 * r8
    return (xx, xy, xz, xy, yy, yz, xz, yz, zz)


def diagonal(d: Vec) -> Mat:
    """``diag(d)``."""
    return (d[0], 0.0, 0.0, 0.0, d[1], 0.0, 0.0, 0.0, d[2])


def rows(A: Mat) -> tuple[Vec, Vec, Vec]:
    """The three rows of ``A`` (a `(3, 3)` nested sequence for numpy)."""
    return (A[0], A[1], A[2]), (A[3], A[4], A[5]), (A[6], A[7], A[8])


def given_value(attrs: dict[str, str], name: str) -> bool:
    """Whether the attribute is given with a value: MuJoCo reads an empty or blank number as not given."""
    text = attrs.get(name)
    return text is not None and text != "" and not text.isspace()


def _parse_decimals(text: str) -> tuple[tuple[float, ...], float]:
    """``(numbers, ceiling)`` of a whitespace-separated list of decimals: every magnitude is at most the ceiling;
    ``-1`` when a part is not a decimal. The ceiling is the largest magnitude, or ``1e59`` for a text shorter than
    60 characters without an exponent (no number there has 60 digits): the magnitudes need not be measured.

    ``float`` reads exactly the decimals of :data:`_NUMBER` plus ``inf``, ``infinity`` and ``nan`` (any case),
    digits grouped by ``_`` and non-ASCII digits: an ASCII text without ``_``, ``n`` and ``N`` that ``float``
    reads is a list of decimals (one pass in C instead of a regular expression)."""
    parts = text.split()
    if text.isascii() and "_" not in text and "n" not in text and "N" not in text:
        try:
            values = tuple(map(float, parts))
        except ValueError:
            return tuple(0.0 for _ in parts), -1.0
    elif all(_NUMBER.fullmatch(s) for s in parts):  # separated by non-ASCII white space, say
        values = tuple(map(float, parts))
    else:
        return tuple(0.0 for _ in parts), -1.0
    if len(values) == 3 and not any(values) and "-" not in text:  # "0 0 0": the zero vector, skipped as such
        values = Z3
    if len(text) < 60 and "e" not in text and "E" not in text:
        return values, _SHORT_CEILING
    return values, max(map(abs, values), default=0.0)


def quat_wxyz_matrix(q: tuple[float, float, float, float]) -> Mat:
    """Rotation matrix of a unit quaternion ``(w, x, y, z)``."""
    w, x, y, z = q
    return (1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
            2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
            2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y))


def axis_angle_matrix(axis: Vec, angle: float) -> Mat:
    """Rodrigues for a unit ``axis``: ``R = cos θ 1 + (1 − cos θ) a aᵀ + sin θ [a]×``."""
    if angle == 0.0:
        return I3
    x, y, z = axis
    c, s = math.cos(angle), math.sin(angle)
    t = 1 - c
    return (t * x * x + c, t * x * y - s * z, t * x * z + s * y,
            t * x * y + s * z, t * y * y + c, t * y * z - s * x,
            t * x * z - s * y, t * y * z + s * x, t * z * z + c)


def z_to_vector(v: Vec) -> Mat:
    """The smallest rotation taking ``(0, 0, 1)`` to the unit vector ``v`` (π about x when opposite), as MuJoCo."""
    s = math.hypot(v[0], v[1])  # |z × v|, z × v = (−v_y, v_x, 0)
    if s < 1e-14:
        return I3 if v[2] > 0 else (1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, -1.0)
    return axis_angle_matrix((-v[1] / s, v[0] / s, 0.0), math.atan2(s, v[2]))


# ---------------------------------------------------------------------------
# reading, includes
# ---------------------------------------------------------------------------


def tag_name(tag: Any) -> str:
    return tag if isinstance(tag, str) else ""


def read_mjcf_source(path_or_xml: Any) -> tuple[str, str, str | None]:
    """``(text, label for messages, path or None)`` of a file path, an XML string or XML bytes."""
    return read_source(path_or_xml, MJCFError, "MJCF", "load_mjcf")


def _read(path_or_xml: Any, source: tuple[str, str, str | None] | None = None,
          ) -> tuple[Any, tuple[ElementIndex, ElementLines], str, str | None]:
    """``(root, (each element's index in document order, the file's lines), label, path)`` (``source``: what
    :func:`read_mjcf_source` gave, if already read)."""
    text, label, path = read_mjcf_source(path_or_xml) if source is None else source
    root, index, lines = parse_elements(text, label, MJCFError, "MJCF")
    return root, (index, lines), label, path


def file_problem(path: Path) -> str | None:
    """``None`` where ``path`` is a regular file, else why it cannot be read: ``"no such file"``, the system's
    reason (``"File name too long"`` for a name longer than the file system takes, ...), or ``"not a regular
    file"``."""
    try:
        status = os.stat(path)
    except OSError as exc:
        return "no such file" if exc.errno == errno.ENOENT else (exc.strerror or str(exc))
    except ValueError as exc:  # a NUL in the name
        return str(exc)
    return None if stat.S_ISREG(status.st_mode) else "not a regular file"


def read_document(path_or_xml: Any, strict: bool, source: tuple[str, str, str | None] | None = None) -> Doc:
    """Parse the main file, check its root is ``<mujoco>``, expand every ``<include>``.

    Each pass replaces every ``<include>`` present by its file's content, so
    the passes are bounded by the include depth; each element remembers the
    chain of files that brought it (for cycles). ``source``: the main file's
    :func:`read_mjcf_source`, if already read.
    """
    root, where, label, path = _read(path_or_xml, source)
    if tag_name(root.tag) != "mujoco":
        tag = shorten(tag_name(root.tag) or "?")
        hint = {"robot": " (a URDF: use featherdyn.load_urdf or load_model)",
                "sdf": " (an SDFormat document: use featherdyn.load_sdf or load_model)"}.get(tag, "")
        raise MJCFError(f"{label}: expected the root element <mujoco>, got <{tag}>{hint}")
    doc = Doc(root, where, label, path, strict)
    # an element's tag is in the text after "<": a text without "<include" has none (a scan instead of a tree walk)
    text = where[1].text
    doc.may_replicate = "<replicate" in text
    if "<include" not in text or next(root.iter("include"), None) is None:
        return doc
    doc.may_replicate = True  # (the included files' elements: expand_replicates looks)
    chain_of: dict[Any, tuple[str, ...]] = {root: (str(Path(path).resolve()) if path else label,)}
    included = 0
    seen: set[str] = set()
    while True:
        includes = list(root.iter("include"))
        if not includes:
            return doc
        parent_of = {c: p for p in root.iter() for c in p}
        for inc in includes:
            up = inc
            while up not in chain_of:
                up = parent_of[up]
            chain = chain_of[up]
            file = inc.get("file")
            if file is None or not file.strip():
                raise doc.error(inc, "<include> needs a 'file' attribute")
            if len(inc):
                raise doc.error(inc, f"file={quote(file)}: an <include> cannot have children (MuJoCo refuses them)")
            target = (doc.model_dir / file).resolve()
            if str(target) in chain:
                raise doc.error(inc, f"file={quote(file)}: include cycle ("
                                + " -> ".join(quote(c) for c in (*chain, str(target))) + ")")
            if str(target) in seen:
                raise doc.error(inc, f"file={quote(file)}: already included (MuJoCo includes a file once)")
            seen.add(str(target))
            if len(chain) > MAX_INCLUDE_DEPTH:
                raise doc.error(inc, f"includes nested deeper than {MAX_INCLUDE_DEPTH} files (MAX_INCLUDE_DEPTH)")
            included += 1
            if included > MAX_INCLUDES:
                raise doc.error(inc, f"more than {MAX_INCLUDES} included files (MAX_INCLUDES)")
            problem = file_problem(target)
            if problem == "no such file":
                raise doc.error(inc, f"file={quote(file)}: the included file {quote(str(target))} does not exist")
            if problem is not None:
                raise doc.error(inc, f"file={quote(file)}: cannot read the included file {quote(str(target))}: "
                                f"{problem}")
            sub, sub_where, _, _ = _read(target)
            if tag_name(sub.tag) not in ("mujoco", "mujocoinclude"):  # <mujocoinclude>: MuJoCo's older root, still read
                raise doc.error(inc, f"file={quote(file)}: an included file's root must be <mujoco>, got "
                                f"<{shorten(tag_name(sub.tag) or '?')}>")
            if not len(sub):
                raise doc.error(inc, f"file={quote(file)}: the included file is empty (MuJoCo refuses it)")
            doc.sources.append(sub_where)
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
    for top in (e for e in doc.root if tag_name(e.tag) == "default"):
        name = top.get("class", "main")
        if name != "main":
            raise doc.error(top, f"class={quote(name)}: the top-level <default> is class 'main'")
        stack.append((top, "main"))
    while stack:
        elem, cls = stack.pop()
        table = doc.own_defaults[cls]
        for child in elem:
            kind = tag_name(child.tag)
            if kind == "default":
                name = child.get("class")
                if name is None or not name:
                    raise doc.error(child, "a nested <default> needs a 'class' attribute")
                if name in doc.own_defaults:
                    raise doc.error(child, f"class={quote(name)}: default class defined twice")
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
    if not _REPLACING.isdisjoint(top):
        for k in _REPLACING:
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
        if not doc.may_replicate or next(doc.root.iter("replicate"), None) is None:
            return
        parent_of = {c: p for p in doc.root.iter() for c in p}
        innermost = [e for e in doc.root.iter() if tag_name(e.tag) == "replicate"
                     and not any(tag_name(d.tag) == "replicate" for d in e.iter() if d is not e)]
        if not innermost:
            return
        for rep in innermost:
            attrs = dict(rep.attrib)
            count_text = attrs.get("count", "")
            if not count_text.strip().isdigit() or int(count_text) < 1:
                raise doc.error(rep, f"count={quote(count_text)}: expected a positive integer")
            count = int(count_text)
            for child in rep:
                if tag_name(child.tag) in ("joint", "freejoint", "inertial"):
                    raise doc.error(child, "a joint or inertial cannot be a direct child of <replicate> (MuJoCo)")
            size = sum(1 for _ in rep.iter()) - 1
            created += count * size
            if created > MAX_REPLICATED:
                raise doc.error(rep, f"<replicate> would create more than {MAX_REPLICATED} elements (MAX_REPLICATED)")
            off = doc.floats(rep, attrs, "offset", (3,))
            offset = Z3 if off is None else (off[0], off[1], off[2])
            step = doc.rotation(rep, {k: v for k, v in attrs.items() if k == "euler"})
            sep = attrs.get("sep", "")
            digits = len(str(count))
            parent = parent_of[rep]
            at = list(parent).index(rep)
            parent.remove(rep)
            R, p = I3, Z3
            for k in range(count):
                frame = type(rep)("frame", {
                    "pos": " ".join(repr(float(x)) for x in p),
                    "xyaxes": " ".join(repr(float(x)) for x in (R[0], R[3], R[6], R[1], R[4], R[7])),
                })
                if "childclass" in attrs:  # MuJoCo's reader takes it (undocumented): the copies' default class
                    frame.set("childclass", attrs["childclass"])
                doc.where_of[frame] = doc.locate(rep)
                suffix = f"{sep}{k:0{digits}d}"
                for child in rep:
                    clone = copy.deepcopy(child)
                    for orig, new in zip(child.iter(), clone.iter(), strict=True):
                        found = doc.locate(orig)
                        doc.where_of[new] = found if found[0] is not None else doc.locate(rep)
                        if new.get("name") is not None:
                            new.set("name", new.get("name") + suffix)
                    frame.append(clone)
                parent.insert(at + k, frame)
                R, p = compose(R, p, step, offset)
