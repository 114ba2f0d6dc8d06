"""OBJ meshes: the whole-text reader (``_obj_fast``) gives the line-by-line reader's arrays exactly, and hands
every text it does not read the usual way (tabs, indented lines, polygons, relative or zero indices, extra
vertex numbers, bad numbers, words the count per line would miss) to the line-by-line reader, which reads it or
words the error (an index past the last vertex is refused by the check both share, with the same message)."""

from __future__ import annotations

import numpy as np
import pytest

from featherdyn.readers.mjcf_mesh import MeshError, _obj, _obj_fast, _obj_lines

CUBE_V = "\n".join(f"v {x} {y} {z}" for x in (0.0, 1.5) for y in (0.0, 2.0) for z in (-1.0, 1e-3))
TRIS = "f 1 2 3\nf 2 4 3\nf 5 6 7\nf 6 8 7\nf 1 5 2\nf 2 5 6"
USUAL = [
    CUBE_V + "\n" + TRIS,
    "# exported\no cube\nmtllib a.mtl\n" + CUBE_V + "\nvn 0 0 1\nvt 0.5 0.5\ns off\nusemtl m\n" + TRIS + "\n",
    CUBE_V + "\n" + TRIS.replace("f 1 2 3", "f 1/1 2/2 3/3").replace("f 2 4 3", "f 2//1 4//1 3//1"),
    CUBE_V.replace("v 0.0", "v  0.0") + "\n" + TRIS.replace("f 5 6 7", "f 5/1/2 6/2/3 7/3/4"),
    CUBE_V.replace("\n", " \n") + "\n" + TRIS.replace("\n", "  \n") + "\n\n",       # spaces at line ends
    CUBE_V.replace("\n", "\nvn 0 0 1\n") + "\n" + TRIS.replace("\n", "\nvt 0 1\n"),  # interleaved lines
    CUBE_V + "\n" + TRIS.replace("f 1 2 3", "f 1/1/1 2//2 3/7"),                   # forms mixed in a face
    CUBE_V + "\n" + TRIS.replace("f 1 2 3", "f 001 +2 3").replace("+2", "2"),       # leading zeros
    CUBE_V.replace("1.5", "+15e-1").replace("2.0", "2.").replace("0.001", ".1E-2") + "\n" + TRIS,
]
ODD = [
    CUBE_V.replace("\n", "\n\t", 1) + "\n" + TRIS,              # a tab
    " " + CUBE_V + "\n" + TRIS,                                  # an indented first line
    CUBE_V + "\n f 1 2 3\n" + TRIS,                              # an indented face
    CUBE_V + "\nf 1 2 3 4\n" + TRIS,                             # a quad (a fan of two triangles)
    CUBE_V + "\nf -1 -2 -3\n" + TRIS,                            # relative indices
    CUBE_V.replace("v 0.0 0.0 -1.0", "v 0.0 0.0 -1.0 1.0") + "\n" + TRIS,  # a fourth vertex number
    "# caf\u00e9\n" + CUBE_V + "\n" + TRIS,                                  # not ASCII
    CUBE_V + "\n" + TRIS + "\nf 1 2 3\x0c",                                    # a form feed (a line end to splitlines)
]
BAD = [
    CUBE_V + "\nf 0 1 2\n" + TRIS,       # index 0
    CUBE_V + "\nf 1 2 99\n" + TRIS,      # past the last vertex
    CUBE_V + "\nv 1 2\n" + TRIS,         # two numbers
    CUBE_V + "\nv 1 two 3\n" + TRIS,     # not a number
    CUBE_V + "\nf 1 2\n" + TRIS,         # two indices
    CUBE_V + "\nf\n" + TRIS,             # a bare keyword
    CUBE_V + "\nf 1 x 3\n" + TRIS,       # not an index
    CUBE_V + "\nv 1 2 3 4\nv 1 2\n" + TRIS,  # four numbers and two: six, but not three per line
    CUBE_V + "\nf 1 2 3 4\nf 1 2\n" + TRIS,  # likewise for faces
    CUBE_V + "\nf 1 2 /3\n" + TRIS,      # an index without its vertex number
    CUBE_V + "\nv 1 2-3 4\n" + TRIS,     # a word of two numbers
    CUBE_V + "\nv 1 2e 3\n" + TRIS,      # half a number
    CUBE_V + "\nv 1 0x1p3 3\n" + TRIS,   # hexadecimal
    CUBE_V + "\nv 1 nan 3\n" + TRIS,     # not finite
    CUBE_V + "\nv 1 1e999 3\n" + TRIS,   # too large
    CUBE_V + "\nf 1 2 99999999999999999999999\n" + TRIS,   # an index beyond int64
    CUBE_V + "\nf 1 2 -99999999999999999999999\n" + TRIS,  # a relative one
    CUBE_V + "\nv\n" + TRIS,             # a bare keyword among vertices
    CUBE_V + "\n" + TRIS + "\nf",         # a bare keyword at the very end
]


def _same(a: tuple[np.ndarray, np.ndarray], b: tuple[np.ndarray, np.ndarray]) -> bool:
    return all(x.dtype == y.dtype and x.shape == y.shape and np.array_equal(x, y) for x, y in zip(a, b, strict=True))


@pytest.mark.parametrize("text", USUAL)
def test_the_usual_file_is_read_at_once_with_the_same_arrays(text: str) -> None:
    fast = _obj_fast(text.encode())
    assert fast is not None
    assert _same(fast, _obj_lines(text))
    assert fast[0].shape == (8, 3) and fast[1].shape == (6, 3)


@pytest.mark.parametrize("text", ODD)
def test_other_files_are_read_line_by_line(text: str) -> None:
    assert _obj_fast(text.encode()) is None
    V, F = _obj(text.encode())
    assert _same((V, F), _obj_lines(text))
    assert len(V) == 8


@pytest.mark.parametrize("text", BAD)
def test_errors_are_the_line_readers(text: str) -> None:
    with pytest.raises(MeshError) as fast_way:
        _obj(text.encode())
    with pytest.raises(MeshError) as long_way:
        _obj_lines("\n".join(text.splitlines()))
    assert str(fast_way.value) == str(long_way.value)


def test_line_ends_are_those_splitlines_sees() -> None:
    text = USUAL[0]
    crlf = text.replace("\n", "\r\n").encode()
    assert _same(_obj(crlf), _obj(text.encode()))


@pytest.mark.filterwarnings("error")
def test_vertices_beyond_float32_and_overflowing_scales_are_mesh_errors() -> None:
    from featherdyn.readers.mjcf_mesh import mass_properties

    V, F = _obj((CUBE_V + "\n" + TRIS).encode())
    with pytest.raises(MeshError, match="beyond float32's range"):
        mass_properties(V * 1e39, F, (1.0, 1.0, 1.0), "legacy")  # finite in double, inf in float32
    with pytest.raises(MeshError, match="overflow|not positive"):
        mass_properties(V * 1e30, F, (1e60, 1e60, 1e60), "legacy")  # (|x| ~ 1e90)⁵ overflows
    measure, c, J = mass_properties(V, F, (2.0, 1.0, 1.0), "legacy")  # an ordinary scale: finite numbers
    assert measure > 0 and np.all(np.isfinite(c)) and np.all(np.isfinite(J))
