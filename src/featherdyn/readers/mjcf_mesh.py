"""Mesh assets of an MJCF model (used by :mod:`featherdyn.readers.mjcf`): reading them safely, their exact mass properties.

Formats: binary and ASCII STL, OBJ (``v`` and ``f`` lines; polygons fanned
into triangles; negative indices), MuJoCo's binary MSH, and inline
``vertex``/``face`` attributes; the ``scale`` attribute. Files are bounded by
:data:`MAX_MESH_BYTES`, counts must agree with the file length, indices must
be in range and coordinates finite and at most
:data:`featherdyn.readers.urdf.MAX_LENGTH`.

Mass properties as MuJoCo's compiler defines them (``inertia`` of the mesh
asset: ``exact``, ``legacy`` (the default), ``shell``): pyramids on the
triangles (signed tetrahedra; divergence theorem), see
:func:`mesh_mass_properties`; ``exact`` is the exact volume integral of a
closed, outward-oriented surface, ``legacy`` takes each pyramid's volume
positive (differs on open or inconsistently oriented meshes), ``shell`` the
surface. Vertices are kept in float32 as MuJoCo does. ``inertia="convex"``
and meshes without faces (MuJoCo uses their convex hull) are refused.

Source: Mirtich (1996), "Fast and accurate computation of polyhedral mass
properties"; MuJoCo documentation, ``mesh/inertia``; the pyramid apexes and
the ``legacy`` rule as MuJoCo's compiler (``user_mesh.cc``) uses them.
"""

from __future__ import annotations

import math
import os
import re
import struct
import threading
import time
import warnings
from collections import OrderedDict
from pathlib import Path
from typing import cast

import numpy as np

from .mjcf_xml import Mat, Vec
from .urdf import MAX_LENGTH as _MAX_LENGTH
from .xml import read_regular_file

#: ``(measure, centre, I_c / ρ row by row)`` of a mesh (:func:`mass_properties`).
MassProperties = tuple[float, Vec, Mat]

__all__ = ["MAX_MESH_BYTES", "MESH_CACHE_SIZE", "MeshError", "clear_mesh_cache", "file_mass_properties",
           "mass_properties", "mesh_mass_properties", "read_mesh_file"]

#: Largest mesh file read, in bytes.
MAX_MESH_BYTES = 200_000_000


class MeshError(Exception):
    """A mesh that cannot be read or used (the loader turns it into an MJCFError naming the asset)."""


def _check_vertices(V: np.ndarray) -> np.ndarray:
    if V.size and not (np.all(np.isfinite(V)) and float(np.max(np.abs(V))) <= _MAX_LENGTH):
        raise MeshError(f"vertex coordinates must be finite and at most {_MAX_LENGTH:g}")
    return V


def _check_faces(F: np.ndarray, nv: int) -> np.ndarray:
    if F.size and (int(F.min()) < 0 or int(F.max()) >= nv):
        raise MeshError(f"a face index is outside 0..{nv - 1}")
    return F


def read_mesh_file(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """``(V (n, 3), F (m, 3))`` of an STL, OBJ or MSH file."""
    return _parse(path, _read(path)[0])


def _read(path: Path) -> tuple[bytes, os.stat_result]:
    try:
        return read_regular_file(path, MAX_MESH_BYTES)
    except OSError as exc:
        raise MeshError(f"cannot read the mesh file {str(path)[:200]!r}: {exc.strerror or exc}") from None


def _parse(path: Path, data: bytes) -> tuple[np.ndarray, np.ndarray]:
    ext = path.suffix.lower()
    if ext == ".stl":
        return _stl(data)
    if ext == ".obj":
        return _obj(data)
    if ext == ".msh":
        return _msh(data)
    raise MeshError(f"unsupported mesh format {path.suffix[:20]!r} (STL, OBJ and MSH are read)")


#: Mass properties of mesh files kept between loads (the most recently used; see :func:`file_mass_properties`).
MESH_CACHE_SIZE = 1024
#: A mesh file is kept only if it was last written at least this long (ns) before it was read.
MESH_CACHE_SETTLE_NS = 1_000_000_000
_cache: OrderedDict[tuple[object, ...], MassProperties] = OrderedDict()
_cache_lock = threading.Lock()


def clear_mesh_cache() -> None:
    """Forget every mesh file's mass properties kept between loads (the next load reads the files again)."""
    with _cache_lock:
        _cache.clear()


def _cache_key(status: os.stat_result, scale: Vec, mode: str) -> tuple[object, ...]:
    return status.st_dev, status.st_ino, status.st_size, status.st_mtime_ns, status.st_ctime_ns, scale, mode


def file_mass_properties(path: Path, scale: Vec, mode: str) -> MassProperties:
    """:func:`mass_properties` of a mesh file, kept between loads as MuJoCo keeps the meshes it has read.

    A file's entry is found again only while its device, inode, size and
    modification and change times (``os.fstat``, nanoseconds) are those it
    was read with: a file written since, replaced or renamed over is read
    again (the change time moves on every write, even one that restores the
    modification time). File times advance in ticks of the kernel's coarse
    clock (milliseconds), so a file written again within the tick of its
    last write could keep its times: a file is therefore kept only if it was
    last written :data:`MESH_CACHE_SETTLE_NS` (1 s) or more before it was
    read (Git's rule for "racily clean" files). The key also holds ``scale``
    and ``mode``. Failures are not kept. At most :data:`MESH_CACHE_SIZE`
    entries (the least recently used leaves first); :func:`clear_mesh_cache`
    empties it.
    """
    try:
        status = os.stat(path)
    except OSError as exc:
        raise MeshError(f"cannot read the mesh file {str(path)[:200]!r}: {exc.strerror or exc}") from None
    with _cache_lock:
        got = _cache.get(_cache_key(status, scale, mode))
        if got is not None:
            _cache.move_to_end(_cache_key(status, scale, mode))
            return got
    now = time.time_ns()
    data, status = _read(path)  # the status of what was read: the key of what is kept
    V, F = _parse(path, data)
    got = mass_properties(V, F, scale, mode)
    settled = now - max(status.st_mtime_ns, status.st_ctime_ns) >= MESH_CACHE_SETTLE_NS
    if settled and status.st_ino:  # file systems without inode numbers: nothing kept
        with _cache_lock:
            _cache[_cache_key(status, scale, mode)] = got
            while len(_cache) > MESH_CACHE_SIZE:
                _cache.popitem(last=False)
    return got


def mass_properties(V: np.ndarray, F: np.ndarray, scale: Vec, mode: str) -> MassProperties:
    """``(measure, c, I_c / ρ)`` of a mesh asset, as tuples: vertices ``V`` `(n, 3)` read as float32 (as MuJoCo
    reads them) and scaled in double; the convex hull for ``mode="convex"`` (then ``exact``) or when ``F`` is
    empty; :func:`mesh_mass_properties` of the result."""
    with np.errstate(over="ignore"):
        V32 = np.asarray(V).astype(np.float32)
    if not np.all(np.isfinite(V32)):
        raise MeshError(f"a vertex coordinate is beyond float32's range ({float(np.finfo(np.float32).max):.4g}), in "
                        "which MuJoCo stores vertices")
    V64 = V32.astype(np.float64) * np.array(scale)  # then masses agree exactly
    if not F.size or mode == "convex":  # MuJoCo uses the convex hull (its faces are then outward)
        F = convex_hull(V64)
        mode = "exact" if mode == "convex" else mode
    with np.errstate(over="ignore", invalid="ignore"):  # huge scaled vertices: the finiteness checks say so
        measure, c, J = mesh_mass_properties(V64, F, mode)
    if not (np.all(np.isfinite(c)) and np.all(np.isfinite(J))):
        raise MeshError("the mesh's mass properties overflow (its scaled vertices are too large)")
    rows = cast(Mat, tuple(np.asarray(J, dtype=float).ravel().tolist()))
    return float(measure), (float(c[0]), float(c[1]), float(c[2])), rows


def _stl(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    if len(data) >= 84:
        (n,) = struct.unpack_from("<I", data, 80)
        if 84 + 50 * n == len(data):
            rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                count=n, offset=84)
            with np.errstate(invalid="ignore"):  # a signalling NaN: refused by the check
                V = rec["v"].reshape(-1, 3).astype(np.float64)
            return _check_vertices(V), np.arange(3 * n).reshape(n, 3)
    text = data.decode("ascii", errors="replace")
    if not text.lstrip().startswith("solid"):
        raise MeshError("not a binary STL (its length disagrees with its triangle count) nor an ASCII one")
    coords = re.findall(r"vertex\s+(\S+)\s+(\S+)\s+(\S+)", text)
    if len(coords) % 3:
        raise MeshError("ASCII STL: the vertex count is not a multiple of 3")
    try:
        V = np.array([[float(x) for x in c] for c in coords], dtype=np.float64).reshape(-1, 3)
    except ValueError:
        raise MeshError("ASCII STL: a vertex coordinate is not a number") from None
    return _check_vertices(V), np.arange(len(V)).reshape(-1, 3)


_SPACE, _NEWLINE = 32, 10
_NOT_READ_AT_ONCE = (b"\t", b"\r", b"\v", b"\f", b"\x1c", b"\x1d", b"\x1e", b"\n ")
_VERTEX_CHARS, _FACE_CHARS = b"0123456789+-.eE \nv", b"0123456789/ \nf"
_KEYWORD_TO_SPACE = bytes.maketrans(b"vf", b"  ")
_INDEX_TO_SPACE = bytes.maketrans(b"f/", b"  ")


def _lines_of(data: bytes, starts: np.ndarray, ends: np.ndarray, keep: np.ndarray) -> tuple[bytes, int]:
    """The lines ``keep`` marks, joined (runs of consecutive lines as one slice), and how many there are."""
    edges = np.flatnonzero(np.diff(np.concatenate(([False], keep, [False])).view(np.int8)))
    first, last = edges[0::2].tolist(), edges[1::2].tolist()
    return b"".join([data[starts[a]:ends[b - 1]] for a, b in zip(first, last, strict=True)]), int(np.count_nonzero(keep))


def _token_starts(b: np.ndarray) -> np.ndarray:
    """Positions of the words after the first on each line of ``b`` (bytes that are neither space nor newline,
    right after a space)."""
    return np.flatnonzero((b[1:] != _SPACE) & (b[1:] != _NEWLINE) & (b[:-1] == _SPACE)) + 1


def _three_per_line(b: np.ndarray, keyword: int, n: int) -> np.ndarray | None:
    """The word starts of ``b``, lines ``keyword w1 w2 w3``, if every one of the ``n`` lines has exactly three."""
    line_starts = np.flatnonzero(b == keyword)
    words = _token_starts(b)
    if len(line_starts) != n or len(words) != 3 * n:
        return None
    if not np.array_equal(np.searchsorted(words, line_starts), np.arange(0, 3 * n, 3)):
        return None
    return words


def _numbers(text: bytes, dtype: type, count: int) -> np.ndarray | None:
    """The ``count`` numbers of a text of numbers and white space, or None if it holds anything else."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            got: np.ndarray = np.fromstring(text, dtype=dtype, sep=" ")
    except (ValueError, DeprecationWarning):
        return None
    return got if len(got) == count else None


def _obj_fast(data: bytes) -> tuple[np.ndarray, np.ndarray] | None:
    """:func:`_obj_lines`' arrays for the usual file, its numbers converted all at once: ASCII, Unix or Windows
    line ends, no tab and no line that starts with white space (a line's first word is `v` exactly when it
    starts with "v "), every vertex line `v x y z`, every face a triangle `f a b c` of indices ≥ 1 (`k`, `k/t`,
    `k//n` or `k/t/n`). None for anything else: read line by line, which also words the errors.

    Why it is exact: the vertex (face) lines hold only the characters of numbers (of indices and "/"), one
    keyword each and three words after it (counted per line); each word then gives at least one number or
    stops the conversion, so `3 n` numbers means one per word. A face's first index is the number that starts
    its word."""
    if not data:
        return None
    if b"\r" in data:
        data = data.replace(b"\r\n", b"\n")
    if not data.isascii() or data[:1] == b" " or any(c in data for c in _NOT_READ_AT_ONCE):
        return None
    arr = np.frombuffer(data, np.uint8)
    ends = np.flatnonzero(arr == _NEWLINE) + 1
    starts = np.concatenate(([0], ends[:-1] if len(ends) and ends[-1] == len(arr) else ends))
    ends = np.concatenate((ends, [len(arr)]))[:len(starts)]
    first = arr[starts]
    second = np.frombuffer(data + b"\n", np.uint8)[starts + 1]
    bare = (second == _NEWLINE) & ((first == ord("v")) | (first == ord("f")))
    if bare.any():  # a bare keyword: an error, worded line by line
        return None
    is_v, is_f = (first == ord("v")) & (second == _SPACE), (first == ord("f")) & (second == _SPACE)
    if not is_v.any():
        return None
    vtext, nv = _lines_of(data, starts, ends, is_v)
    ftext, nf = _lines_of(data, starts, ends, is_f) if is_f.any() else (b"", 0)
    if vtext.translate(None, _VERTEX_CHARS) or ftext.translate(None, _FACE_CHARS):
        return None
    vb, fb = np.frombuffer(vtext, np.uint8), np.frombuffer(ftext, np.uint8)
    if _three_per_line(vb, ord("v"), nv) is None:
        return None
    V = _numbers(vtext.translate(_KEYWORD_TO_SPACE), np.float64, 3 * nv)
    if V is None:
        return None
    if nf:
        words = _three_per_line(fb, ord("f"), nf)
        if words is None or not np.all((fb[words] >= ord("0")) & (fb[words] <= ord("9"))):
            return None
        digit = (fb >= ord("0")) & (fb <= ord("9"))
        number_starts = np.flatnonzero(digit[1:] & ~digit[:-1]) + 1
        every = _numbers(ftext.translate(_INDEX_TO_SPACE), np.int64, len(number_starts))
        if every is None:
            return None
        F = every[fb[number_starts - 1] == _SPACE]
    else:
        F = np.zeros(0, dtype=np.int64)
    if F.size and int(F.min()) < 1:  # 0 is out of range, negative indices count back from the last vertex read
        return None
    V = V.reshape(-1, 3)
    return _check_vertices(V), _check_faces(F.reshape(-1, 3) - 1, len(V))


def _obj(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    fast = _obj_fast(data)
    if fast is not None:
        return fast
    return _obj_lines("\n".join(data.decode("utf-8", errors="replace").splitlines()))  # the line ends splitlines() sees


def _obj_lines(text: str) -> tuple[np.ndarray, np.ndarray]:
    """An OBJ text's vertices and triangles (polygons as fans), line by line."""
    verts: list[list[float]] = []
    faces: list[list[int]] = []
    for lineno, raw in enumerate(text.split("\n"), 1):
        parts = raw.split()
        if not parts:
            continue
        try:
            if parts[0] == "v":
                verts.append([float(x) for x in parts[1:4]])
                if len(verts[-1]) != 3:
                    raise ValueError
            elif parts[0] == "f":
                idx = []
                for p in parts[1:]:
                    k = int(p.split("/")[0])
                    idx.append(k - 1 if k > 0 else len(verts) + k)
                if len(idx) < 3:
                    raise ValueError
                faces += [[idx[0], idx[j], idx[j + 1]] for j in range(1, len(idx) - 1)]
        except ValueError:
            raise MeshError(f"OBJ line {lineno}: cannot read {raw[:100]!r}") from None
    V = _check_vertices(np.array(verts, dtype=np.float64).reshape(-1, 3))
    try:
        F = np.array(faces, dtype=np.int64).reshape(-1, 3)
    except OverflowError:  # an index beyond int64
        raise MeshError(f"a face index is outside 0..{len(V) - 1}") from None
    return V, _check_faces(F, len(V))


def _msh(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    if len(data) < 16:
        raise MeshError("MSH: shorter than its 16-byte header")
    nv, nn, nt, nf = struct.unpack_from("<4i", data, 0)
    if min(nv, nn, nt, nf) < 0 or 16 + 4 * (3 * nv + 3 * nn + 2 * nt + 3 * nf) != len(data):
        raise MeshError("MSH: the header's counts disagree with the file length")
    with np.errstate(invalid="ignore"):  # a signalling NaN: refused by the check
        V = np.frombuffer(data, "<f4", 3 * nv, 16).reshape(-1, 3).astype(np.float64)
    F = np.frombuffer(data, "<i4", 3 * nf, 16 + 4 * (3 * nv + 3 * nn + 2 * nt)).reshape(-1, 3).astype(np.int64)
    return _check_vertices(V), _check_faces(F, len(V))


_NEXT, _PREV = np.array([1, 2, 0]), np.array([2, 0, 1])


def _cross_rows(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``u × v`` row by row, `(..., 3)` (``np.cross`` without its axis handling, which costs more on small arrays)."""
    return u[..., _NEXT] * v[..., _PREV] - u[..., _PREV] * v[..., _NEXT]


def mesh_mass_properties(V: np.ndarray, F: np.ndarray, mode: str) -> tuple[float, np.ndarray, np.ndarray]:
    """``(measure, c, I_c / ρ)``: volume (or area), centre, rotational inertia per unit density about ``c``.

    ``mode``: ``"exact"``, ``"legacy"`` or ``"shell"`` (module doc). With ``f``
    the area-weighted centroid of the triangles, each triangle the base of a
    pyramid of apex ``f`` (signed volume; ``legacy``: its absolute value;
    ``shell``: its area), the centre is the weighted mean of the pyramids'
    centroids ``(3 t + f)/4``; then, about that centre ``c``, each triangle's
    pyramid of apex ``c`` gives the measure (recomputed) and::

        ∫ x xᵀ = Σ w (a aᵀ + b bᵀ + c cᵀ + s sᵀ) / k,   s = a + b + c,   k = 20 (solid) or 12 (shell)
    """
    shell = mode == "shell"

    def pieces(P: np.ndarray, apex: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        a, b, c = P[F[:, 0]], P[F[:, 1]], P[F[:, 2]]
        cross = _cross_rows(b - a, c - a)
        area = np.linalg.norm(cross, axis=1) / 2
        centre = (a + b + c) / 3
        if shell:
            w = area
        else:
            w = np.einsum("ti,ti->t", centre - apex, cross) / 6  # = height · area / 3
            if mode == "legacy":
                w = np.abs(w)
        return w, area, centre

    _, area, centre = pieces(V, np.zeros(3))
    total_area = float(area.sum())
    if not total_area > 1e-15:
        raise MeshError(f"the mesh's surface area is {total_area:g}, too small")
    facecen = (area[:, None] * centre).sum(axis=0) / total_area
    w, _, centre = pieces(V, facecen)
    measure = float(w.sum())
    if not (measure >= 1e-15 and math.isfinite(measure)):
        what = "area" if shell else "volume (are the faces oriented outwards?)"
        raise MeshError(f"the mesh's {what} is {measure:g}, not positive")
    com = (w[:, None] * (0.75 * centre + 0.25 * facecen)).sum(axis=0) / measure
    Vc = V - com
    w, _, _ = pieces(Vc, np.zeros(3))
    a, b, c = Vc[F[:, 0]], Vc[F[:, 1]], Vc[F[:, 2]]
    s_ = a + b + c
    outer = (np.einsum("ti,tj->tij", a, a) + np.einsum("ti,tj->tij", b, b) + np.einsum("ti,tj->tij", c, c)
             + np.einsum("ti,tj->tij", s_, s_))
    C = (w[:, None, None] * outer).sum(axis=0) / (12 if shell else 20)
    measure = float(w.sum())
    if not (measure >= 1e-15 and math.isfinite(measure)):
        raise MeshError(f"the mesh's measure about its centre is {measure:g}, not positive")
    return measure, com, np.trace(C) * np.eye(3) - C


#: Most vertices whose convex hull is computed (a mesh without faces, or ``inertia="convex"``); the
#: incremental hull costs O(n²): 2000 points on a sphere take about 1.5 s.
MAX_HULL_VERTICES = 5_000


def convex_hull(V: np.ndarray) -> np.ndarray:
    """Outward-oriented triangles `(m, 3)` of the convex hull of the points ``V`` `(n, 3)` (incremental).

    Points on the hull's surface within round-off are left out; the
    triangulation of coplanar facets is arbitrary, which changes no mass
    property of the (convex) solid.
    """
    n = len(V)
    if n < 4:
        raise MeshError(f"a convex hull needs at least 4 vertices, got {n}")
    if n > MAX_HULL_VERTICES:
        raise MeshError(f"convex hull of {n} vertices, more than MAX_HULL_VERTICES = {MAX_HULL_VERTICES}")
    scale = float(np.max(np.abs(V - V.mean(axis=0)))) or 1.0
    eps = 1e-10 * scale
    # an initial tetrahedron of four extreme points
    i0 = int(np.argmin(V[:, 0]))
    i1 = int(np.argmax(np.linalg.norm(V - V[i0], axis=1)))
    d = V[i1] - V[i0]
    i2 = int(np.argmax(np.linalg.norm(_cross_rows(V - V[i0], d), axis=1)))
    normal = _cross_rows(d, V[i2] - V[i0])
    i3 = int(np.argmax(np.abs((V - V[i0]) @ normal)))
    if abs(float((V[i3] - V[i0]) @ normal)) <= eps * scale * scale or len({i0, i1, i2, i3}) < 4:
        raise MeshError("the vertices are coplanar or collinear: their convex hull has no volume")
    inside = V[[i0, i1, i2, i3]].mean(axis=0)
    faces: list[tuple[int, int, int]] = []
    for a, b, c in ((i0, i1, i2), (i0, i1, i3), (i0, i2, i3), (i1, i2, i3)):
        nrm = _cross_rows(V[b] - V[a], V[c] - V[a])
        faces.append((a, b, c) if float(nrm @ (V[a] - inside)) > 0 else (a, c, b))
    for p in range(n):
        if p in (i0, i1, i2, i3):
            continue
        F = np.array(faces)
        A = V[F[:, 0]]
        N = _cross_rows(V[F[:, 1]] - A, V[F[:, 2]] - A)
        lengths = np.linalg.norm(N, axis=1)
        visible = np.einsum("ij,ij->i", N, V[p] - A) > eps * lengths
        if not np.any(visible):
            continue
        edges: dict[tuple[int, int], int] = {}
        for a, b, c in F[visible].tolist():
            for e in ((a, b), (b, c), (c, a)):
                if (e[1], e[0]) in edges:
                    del edges[(e[1], e[0])]
                else:
                    edges[e] = 1
        faces = [f for f, vis in zip(faces, visible.tolist(), strict=True) if not vis]
        faces += [(a, b, p) for a, b in edges]
    return np.array(faces, dtype=np.int64)
