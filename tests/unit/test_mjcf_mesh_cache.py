"""Mesh files between loads: their mass properties are kept while the file is unchanged, as MuJoCo keeps the
meshes it has read, and read again when it changes; special files are refused rather than read forever."""

from __future__ import annotations

import os
import time
from pathlib import Path

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.errors import MJCFError
from featherdyn.readers import mjcf_mesh


def _box_obj(a: float, b: float, c: float) -> str:
    """A closed, outward box of sides a, b, c with a corner at the origin."""
    v = [(x, y, z) for x in (0.0, a) for y in (0.0, b) for z in (0.0, c)]
    quads = [(1, 2, 4, 3), (5, 7, 8, 6), (1, 5, 6, 2), (3, 4, 8, 7), (1, 3, 7, 5), (2, 6, 8, 4)]
    tris = [t for q in quads for t in ((q[0], q[1], q[2]), (q[0], q[2], q[3]))]
    return "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in v) + "".join(f"f {i} {j} {k}\n" for i, j, k in tris)


def _model(folder: Path) -> Path:
    path = folder / "m.xml"
    path.write_text('<mujoco><asset><mesh name="box" file="box.obj"/></asset><worldbody><body><joint/>'
                    '<geom type="mesh" mesh="box" density="1000"/></body></worldbody></mujoco>')
    return path


def _mass(path: Path) -> float:
    return float(fd.load_mjcf(path).inertias[0].mass)


@pytest.fixture
def reads(monkeypatch: pytest.MonkeyPatch) -> list[Path]:
    """Every mesh file read, with a clean cache and files kept however recently written."""
    got: list[Path] = []
    read = mjcf_mesh._read

    def counting(path: Path) -> tuple[bytes, os.stat_result]:
        got.append(path)
        return read(path)

    monkeypatch.setattr(mjcf_mesh, "_read", counting)
    monkeypatch.setattr(mjcf_mesh, "MESH_CACHE_SETTLE_NS", 0)
    fd.mjcf.clear_mesh_cache()
    yield got
    fd.mjcf.clear_mesh_cache()


def test_an_unchanged_file_is_read_once(tmp_path: Path, reads: list[Path]) -> None:
    (tmp_path / "box.obj").write_text(_box_obj(0.25, 0.5, 0.75))
    model = _model(tmp_path)
    first, again = _mass(model), _mass(model)
    assert first == again == pytest.approx(1000 * 0.25 * 0.5 * 0.75, rel=1e-12)
    assert len(reads) == 1


def test_a_changed_file_is_read_again(tmp_path: Path, reads: list[Path]) -> None:
    mesh = tmp_path / "box.obj"
    mesh.write_text(_box_obj(0.25, 0.5, 0.75))
    model = _model(tmp_path)
    assert _mass(model) == pytest.approx(93.75, rel=1e-12)
    time.sleep(0.05)  # past the tick of the file clock
    mesh.write_text(_box_obj(0.25, 0.5, 0.25))  # other numbers
    assert _mass(model) == pytest.approx(31.25, rel=1e-12)
    assert len(reads) == 2


def test_a_rewrite_that_restores_the_modification_time_is_seen(tmp_path: Path, reads: list[Path]) -> None:
    mesh = tmp_path / "box.obj"
    mesh.write_text(_box_obj(0.25, 0.5, 0.75))
    model = _model(tmp_path)
    _mass(model)
    before = os.stat(mesh)
    time.sleep(0.05)
    mesh.write_text(_box_obj(0.25, 0.5, 0.25))  # the same length
    os.utime(mesh, ns=(before.st_atime_ns, before.st_mtime_ns))  # the change time still moves
    assert os.stat(mesh).st_mtime_ns == before.st_mtime_ns and os.stat(mesh).st_size == before.st_size
    assert _mass(model) == pytest.approx(31.25, rel=1e-12)


def test_scale_and_inertia_mode_are_part_of_the_key(tmp_path: Path, reads: list[Path]) -> None:
    (tmp_path / "box.obj").write_text(_box_obj(0.25, 0.5, 0.75))
    plain = _model(tmp_path)
    scaled = tmp_path / "scaled.xml"
    scaled.write_text(plain.read_text().replace('file="box.obj"', 'file="box.obj" scale="2 1 1"'))
    shell = tmp_path / "shell.xml"
    shell.write_text(plain.read_text().replace('file="box.obj"', 'file="box.obj" inertia="shell"'))
    assert _mass(plain) == pytest.approx(93.75, rel=1e-12)
    assert _mass(scaled) == pytest.approx(187.5, rel=1e-12)
    assert _mass(shell) == pytest.approx(1000 * 2 * (0.25 * 0.5 + 0.25 * 0.75 + 0.5 * 0.75), rel=1e-12)
    assert _mass(plain) == pytest.approx(93.75, rel=1e-12)
    assert len(reads) == 3


def test_recently_written_files_are_not_kept(tmp_path: Path, reads: list[Path],
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(mjcf_mesh, "MESH_CACHE_SETTLE_NS", 10**12)  # everything is recent
    (tmp_path / "box.obj").write_text(_box_obj(0.25, 0.5, 0.75))
    model = _model(tmp_path)
    _mass(model), _mass(model)
    assert len(reads) == 2


def test_the_cache_keeps_the_most_recently_used(tmp_path: Path, reads: list[Path],
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(mjcf_mesh, "MESH_CACHE_SIZE", 2)
    models = []
    for k in range(3):
        folder = tmp_path / str(k)
        folder.mkdir()
        (folder / "box.obj").write_text(_box_obj(0.25, 0.5, 0.25 * (k + 1)))
        models.append(_model(folder))
    masses = [_mass(m) for m in models]  # 0 is dropped when 2 comes in
    assert np.allclose(masses, [31.25, 62.5, 93.75], rtol=1e-12)
    _mass(models[2]), _mass(models[1])
    assert len(reads) == 3
    assert _mass(models[0]) == pytest.approx(31.25, rel=1e-12)
    assert len(reads) == 4 and len(mjcf_mesh._cache) == 2
    fd.mjcf.clear_mesh_cache()
    _mass(models[1])
    assert len(reads) == 5


def test_a_failure_is_not_kept(tmp_path: Path, reads: list[Path]) -> None:
    mesh = tmp_path / "box.obj"
    mesh.write_text(_box_obj(0.25, 0.5, 0.75).replace("f 1 2 4", "f 1 2 44"))
    model = _model(tmp_path)
    with pytest.raises(MJCFError, match="face index"):
        _mass(model)
    time.sleep(0.05)
    mesh.write_text(_box_obj(0.25, 0.5, 0.75))
    assert _mass(model) == pytest.approx(93.75, rel=1e-12)


@pytest.mark.skipif(not hasattr(os, "mkfifo") or not os.path.exists("/dev/zero"), reason="POSIX special files")
@pytest.mark.parametrize("special", ["fifo", "/dev/zero", "directory"])
def test_special_files_are_refused_not_read_forever(tmp_path: Path, special: str) -> None:
    if special == "fifo":
        target = tmp_path / "pipe"
        os.mkfifo(target)
    elif special == "directory":
        target = tmp_path / "folder"
        target.mkdir()
    else:
        target = Path(special)
    with pytest.raises(MJCFError, match="cannot read"):
        fd.load_mjcf(target)
    with pytest.raises(fd.errors.URDFError, match="cannot read"):
        fd.load_urdf(target)
    with pytest.raises(mjcf_mesh.MeshError, match="cannot read"):
        mjcf_mesh.read_mesh_file(target)
