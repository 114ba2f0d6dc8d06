"""Mutation fuzzing of the mesh readers: an OBJ mutant read at once gives exactly the line reader's arrays, and
every mutant of an OBJ, STL or MSH file gives arrays or a MeshError — never another exception or a warning —
and its mass properties are finite numbers or a MeshError.

The OBJ seeds are of the usual form (read at once); each example applies one to four edits: a character from a
set that matters to the readers (separators, line ends, signs, exponents, keywords, slashes, NUL, non-ASCII)
inserted, replaced or deleted somewhere, a line duplicated, deleted or swapped with another.
"""

from __future__ import annotations

import struct

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from featherdyn.readers.mjcf_mesh import MeshError, _msh, _obj, _obj_fast, _obj_lines, _stl, mass_properties

_CUBE_V = [f"v {x} {y} {z}" for x in (0.0, 1.5) for y in (0.0, 2.0) for z in (-1.0, 1e-3)]
_TRIS = ["f 1 3 2", "f 2 3 4", "f 5 6 7", "f 6 8 7", "f 1 2 5", "f 2 6 5", "f 3 7 4", "f 4 7 8", "f 1 5 3",
         "f 3 5 7", "f 2 4 6", "f 4 8 6"]
OBJ_SEEDS = [
    "\n".join(_CUBE_V + _TRIS) + "\n",
    "# cube\nmtllib m.mtl\no cube\n" + "\n".join(_CUBE_V) + "\nvn 0 0 1\nvt 0.5 0.5\nusemtl x\ns off\n"
    + "\n".join(t.replace(" ", "/1/1 ").replace("f/1/1", "f") + "/1/1" for t in _TRIS),
    "\n".join(v + "\nvn 1 0 0" for v in _CUBE_V) + "\n" + "\n".join(t.replace(" ", "//1 ").replace("f//1", "f")
                                                                     + "//1" for t in _TRIS),
]
CHARS = [" ", "  ", "\t", "\n", "\r", "\r\n", "/", "//", "-", "+", ".", "e", "E", "v", "f", "vn", "#", "0", "9",
         "1e999", "nan", "\x00", "\u00e9", "\x0c", "\x1c", "\u2028", "99999999999999999999", "-1"]


def _mutate_obj(text: str, data: st.DataObject) -> bytes:
    for _ in range(data.draw(st.integers(1, 4))):
        kind = data.draw(st.sampled_from(["insert", "replace", "delete", "dup", "drop", "swap"]))
        lines = text.split("\n")
        if kind in ("dup", "drop", "swap") and len(lines) > 1:
            i, j = data.draw(st.integers(0, len(lines) - 1)), data.draw(st.integers(0, len(lines) - 1))
            if kind == "dup":
                lines.insert(j, lines[i])
            elif kind == "drop":
                del lines[i]
            else:
                lines[i], lines[j] = lines[j], lines[i]
            text = "\n".join(lines)
        elif text:
            k = data.draw(st.integers(0, len(text) - 1))
            c = data.draw(st.sampled_from(CHARS))
            text = (text[:k] + c + text[k:] if kind == "insert" else text[:k] + c + text[k + 1:] if kind == "replace"
                    else text[:k] + text[k + 1:])
    return text.encode("utf-8")


def _check_mass_properties(V: np.ndarray, F: np.ndarray) -> None:
    for mode in ("legacy", "exact", "shell"):
        try:
            measure, c, J = mass_properties(V, F, (1.0, 1.0, 1.0), mode)
        except MeshError:
            continue
        assert np.isfinite(measure) and measure > 0 and np.all(np.isfinite(c)) and np.all(np.isfinite(J))


@pytest.mark.filterwarnings("error")  # numpy's warnings included: a hostile mesh is an error, never a warning
@settings(max_examples=600, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(seed=st.sampled_from(range(len(OBJ_SEEDS))), data=st.data())
def test_obj_mutants_read_at_once_equal_the_line_reader(seed: int, data: st.DataObject) -> None:
    raw = _mutate_obj(OBJ_SEEDS[seed], data)
    text = "\n".join(raw.decode("utf-8", errors="replace").splitlines())
    try:
        slow: tuple[np.ndarray, np.ndarray] | None = _obj_lines(text)
        slow_error = None
    except MeshError as exc:
        slow, slow_error = None, str(exc)
    try:
        fast = _obj_fast(raw)
    except MeshError as exc:  # the checks both readers share (finite, bounded coordinates; indices in range)
        assert str(exc) == slow_error
        return
    if fast is not None:
        assert slow is not None, f"read at once, but the line reader refuses it: {slow_error}"
        assert all(a.dtype == b.dtype and a.shape == b.shape and np.array_equal(a, b)
                   for a, b in zip(fast, slow, strict=True))
    try:
        got = _obj(raw)
    except MeshError as exc:
        assert str(exc) == slow_error
        return
    assert slow is not None and all(np.array_equal(a, b) for a, b in zip(got, slow, strict=True))
    _check_mass_properties(*got)


def _binary_stl(V: np.ndarray) -> bytes:
    tris = V.reshape(-1, 9).astype("<f4")
    return b"\0" * 80 + struct.pack("<I", len(tris)) + b"".join(b"\0" * 12 + t.tobytes() + b"\0\0" for t in tris)


_CUBE = np.array([[float(c) for c in v.split()[1:]] for v in _CUBE_V])
_F = np.array([[int(k) - 1 for k in t.split()[1:]] for t in _TRIS])
STL = _binary_stl(_CUBE[_F])
MSH = (struct.pack("<4i", 8, 0, 0, 12) + _CUBE.astype("<f4").tobytes() + _F.astype("<i4").tobytes())


@pytest.mark.filterwarnings("error")
@settings(max_examples=400, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(which=st.sampled_from(["stl", "msh", "ascii"]), data=st.data())
def test_binary_mutants_give_arrays_or_a_mesh_error(which: str, data: st.DataObject) -> None:
    seed = {"stl": STL, "msh": MSH, "ascii": ("solid x\n" + "".join(
        "facet normal 0 0 0\nouter loop\n" + "".join(f"vertex {a} {b} {c}\n" for a, b, c in _CUBE[t])
        + "endloop\nendfacet\n" for t in _F) + "endsolid x\n").encode()}[which]
    raw = bytearray(seed)
    for _ in range(data.draw(st.integers(1, 4))):
        k = data.draw(st.integers(0, len(raw) - 1))
        kind = data.draw(st.sampled_from(["byte", "cut", "grow", "float"]))
        if kind == "byte":
            raw[k] = data.draw(st.integers(0, 255))
        elif kind == "cut":
            del raw[k:k + data.draw(st.integers(1, 64))]
        elif kind == "grow":
            raw[k:k] = bytes(data.draw(st.integers(1, 64)))
        elif k + 4 <= len(raw):
            raw[k:k + 4] = struct.pack("<f", data.draw(st.sampled_from([np.nan, np.inf, -np.inf, 3e38, -1e-45, 0.0])))
    reader = {"stl": _stl, "ascii": _stl, "msh": _msh}[which]
    try:
        V, F = reader(bytes(raw))
    except MeshError:
        return
    assert V.ndim == 2 and V.shape[1] == 3 and np.all(np.isfinite(V))
    assert F.ndim == 2 and F.shape[1] == 3 and (F.size == 0 or (F.min() >= 0 and F.max() < len(V)))
    if F.size:
        _check_mass_properties(V, F)
