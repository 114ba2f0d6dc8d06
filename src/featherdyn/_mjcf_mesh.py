"""Mesh assets of an MJCF model (private to :mod:`featherdyn.mjcf`): reading them safely, their exact mass properties.

Formats: binary and ASCII STL, OBJ (``v`` and ``f`` lines; polygons fanned
into triangles; negative indices), MuJoCo's binary MSH, and inline
``vertex``/``face`` attributes; the ``scale`` attribute. Files are bounded by
:data:`MAX_MESH_BYTES`, counts must agree with the file length, indices must
be in range and coordinates finite and at most
:data:`featherdyn._mjcf_xml.MAX_LENGTH`.

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
import re
import struct
from pathlib import Path

import numpy as np

from .urdf import MAX_LENGTH as _MAX_LENGTH

__all__ = ["MAX_MESH_BYTES", "MeshError", "read_mesh_file", "mesh_mass_properties"]

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
    try:
        size = path.stat().st_size
    except OSError as exc:
        raise MeshError(f"cannot read the mesh file {str(path)[:200]!r}: {exc.strerror or exc}") from None
    if size > MAX_MESH_BYTES:
        raise MeshError(f"mesh file of {size} bytes, more than MAX_MESH_BYTES = {MAX_MESH_BYTES}")
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise MeshError(f"cannot read the mesh file {str(path)[:200]!r}: {exc.strerror or exc}") from None
    ext = path.suffix.lower()
    if ext == ".stl":
        return _stl(data)
    if ext == ".obj":
        return _obj(data)
    if ext == ".msh":
        return _msh(data)
    raise MeshError(f"unsupported mesh format {path.suffix[:20]!r} (STL, OBJ and MSH are read)")


def _stl(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    if len(data) >= 84:
        (n,) = struct.unpack_from("<I", data, 80)
        if 84 + 50 * n == len(data):
            rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                count=n, offset=84)
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


def _obj_fast(text: str) -> tuple[np.ndarray, np.ndarray] | None:
    """:func:`_obj_lines`' arrays for the usual file, with the numbers of all lines converted at once: no tab and
    no line that starts with white space (so a line's first word is `v` exactly when it starts with "v "), every
    vertex line `v x y z`, every face a triangle `f a b c` of indices ≥ 1 (`k`, `k/t`, `k//n` or `k/t/n`).
    None for anything else: read line by line, which also words the errors."""
    if "\t" in text or "\n " in text or text[:1] == " ":
        return None
    lines = text.split("\n")
    vlines = [line for line in lines if line[:2] == "v "]
    flines = [line for line in lines if line[:2] == "f "]
    if "v" in lines or "f" in lines:  # a bare keyword: an error, worded line by line
        return None
    vt, ft = " ".join(vlines).split(), " ".join(flines).split()
    if (len(vt) != 4 * len(vlines) or vt[0::4].count("v") != len(vlines)
            or len(ft) != 4 * len(flines) or ft[0::4].count("f") != len(flines)):
        return None
    del vt[0::4], ft[0::4]
    if "/" in text:
        ft = [k.partition("/")[0] for k in ft]
    try:
        V = np.array(list(map(float, vt)), dtype=np.float64).reshape(-1, 3)
        F = np.array(list(map(int, ft)), dtype=np.int64).reshape(-1, 3)
    except ValueError:
        return None
    if F.size and int(F.min()) < 1:  # 0 is out of range, negative indices count back from the last vertex read
        return None
    return _check_vertices(V), _check_faces(F - 1, len(V))


def _obj(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    text = "\n".join(data.decode("utf-8", errors="replace").splitlines())  # the line ends splitlines() sees
    fast = _obj_fast(text)
    return fast if fast is not None else _obj_lines(text)


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
    return V, _check_faces(np.array(faces, dtype=np.int64).reshape(-1, 3), len(V))


def _msh(data: bytes) -> tuple[np.ndarray, np.ndarray]:
    if len(data) < 16:
        raise MeshError("MSH: shorter than its 16-byte header")
    nv, nn, nt, nf = struct.unpack_from("<4i", data, 0)
    if min(nv, nn, nt, nf) < 0 or 16 + 4 * (3 * nv + 3 * nn + 2 * nt + 3 * nf) != len(data):
        raise MeshError("MSH: the header's counts disagree with the file length")
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
