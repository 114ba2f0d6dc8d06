"""The compiled core's configuration maps (``core/cpp/configuration.hpp``) against the NumPy reference.

``fd.integrate``, ``fd.difference`` and their derivatives are declared algorithms: the core for float64, the
reference (``featherdyn/configuration.py``, joint by joint) otherwise. Here: the core equals the reference on every
joint kind (the random trees, solo12 and talos floating), in batches that broadcast, at rotations near zero, about
the series threshold and near π; the derivatives equal the reference's and central differences on the group; bad
input is worded by the public checks, naming ``q0`` or ``q1``.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pytest
from _models import TREES, library_robot, random_q, tree

import featherdyn as fd
from featherdyn import core
from featherdyn.errors import NonFiniteError, QuaternionNormError, ShapeError

#: core against reference, relative to the larger of 1 and the reference's magnitude
RTOL = 1e-13
#: central differences on the group (step 1e-6): truncation and rounding
FD_TOL = 1e-6

pytestmark = pytest.mark.skipif(not core.available(), reason="the compiled core is not built")


def _robots() -> list[tuple[str, fd.Model]]:
    models = [(s.name, tree(s.name)) for s in TREES]
    for name in ("solo12", "talos_full_v2"):
        m = library_robot(name, True)
        if m is not None:
            models.append((name, m))
    return models


ROBOTS = _robots()
IDS = [n for n, _ in ROBOTS]


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / max(1.0, float(np.abs(b).max()))) if a.size else 0.0


def _angular(model: fd.Model) -> list[slice]:
    """The velocity slices of every rotation (spherical ω, free-flyer ω, planar ω)."""
    out = []
    for i, joint in enumerate(model.joints):
        iv = model.idx_v[i]
        if joint.kind in ("spherical", "free_flyer"):
            out.append(slice(iv, iv + 3))
        elif joint.kind == "planar":
            out.append(slice(iv, iv + 1))
    return out


def _velocities(model: fd.Model, rng: np.random.Generator, angles: np.ndarray) -> np.ndarray:
    """Velocities `(len(angles), nv)` whose every rotation has the given angle (random axes, random linear parts)."""
    v = rng.normal(size=(len(angles), model.nv))
    for sl in _angular(model):
        axis = rng.normal(size=(len(angles), sl.stop - sl.start))
        axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
        v[:, sl] = angles[:, None] * axis
    return v


#: angles of the rotations: zero, tiny, about the series threshold (0.5 rad), ordinary, near π
ANGLES = np.array([0.0, 1e-12, 1e-8, 1e-5, 1e-3, 0.1, 0.3, 0.4999999, 0.5, 0.5000001, 1.0, 2.0, 2.5, 3.0,
                   np.pi - 1e-3, np.pi - 1e-7])


@pytest.mark.parametrize("name, model", ROBOTS, ids=IDS)
def test_integrate_and_difference_equal_the_reference(name: str, model: fd.Model) -> None:
    rng = np.random.default_rng(1)
    q = random_q(model, rng, (len(ANGLES),))
    v = _velocities(model, rng, ANGLES)
    q_next = fd.integrate(model, q, v)
    assert _rel(q_next, fd.integrate(model, q, v, backend="reference")) < RTOL, name
    assert fd.is_normalized(model, q_next).all()
    back = fd.difference(model, q, q_next)
    assert _rel(back, fd.difference(model, q, q_next, backend="reference")) < RTOL, name
    # the inverse map: difference(q, integrate(q, v)) = v below π (the planar angle and free-flyer alike)
    assert _rel(back, v) < 1e-9, name
    # two unrelated configurations: rotations of any angle up to π
    q1 = random_q(model, rng, (len(ANGLES),))
    assert _rel(fd.difference(model, q, q1), fd.difference(model, q, q1, backend="reference")) < RTOL, name


@pytest.mark.parametrize("name, model", ROBOTS, ids=IDS)
def test_derivatives_equal_the_reference(name: str, model: fd.Model) -> None:
    rng = np.random.default_rng(2)
    q = random_q(model, rng, (len(ANGLES),))
    v = _velocities(model, rng, ANGLES)
    for core_, ref in zip(fd.integrate_derivatives(model, q, v),
                          fd.integrate_derivatives(model, q, v, backend="reference"), strict=True):
        assert core_.shape == (len(ANGLES), model.nv, model.nv) and _rel(core_, ref) < RTOL, name
    q1 = fd.integrate(model, q, v, backend="reference")
    for core_, ref in zip(fd.difference_derivatives(model, q, q1),
                          fd.difference_derivatives(model, q, q1, backend="reference"), strict=True):
        assert _rel(core_, ref) < RTOL, name


def _central(f: Callable[[float], np.ndarray], base: np.ndarray, model: fd.Model, eps: float = 1e-6) -> np.ndarray:
    """``d/dε difference(base, f(ε))`` at 0 by central differences (``f(0) = base``)."""
    return (fd.difference(model, base, f(eps)) - fd.difference(model, base, f(-eps))) / (2 * eps)


@pytest.mark.parametrize("name, model", ROBOTS, ids=IDS)
@pytest.mark.parametrize("angle", [1e-9, 0.4999999, 0.7, 2.5])
def test_derivatives_are_central_differences_on_the_group(name: str, model: fd.Model, angle: float) -> None:
    """J_q, J_v of integrate and J_0, J_1 of difference, column by column, moving along fd.integrate's tangent."""
    rng = np.random.default_rng(3)
    q = random_q(model, rng)
    v = _velocities(model, rng, np.array([angle]))[0]
    Jq, Jv = fd.integrate_derivatives(model, q, v)
    q_next = fd.integrate(model, q, v)
    q1 = random_q(model, rng)
    q1 = fd.integrate(model, q, _velocities(model, rng, np.array([angle]))[0])  # (a difference of that angle)
    J0, J1 = fd.difference_derivatives(model, q, q1)
    d = fd.difference(model, q, q1)
    for j in range(model.nv):
        e = np.eye(model.nv)[j]
        col_q = _central(lambda s, e=e: fd.integrate(model, fd.integrate(model, q, s * e), v), q_next, model)
        col_v = _central(lambda s, e=e: fd.integrate(model, q, v + s * e), q_next, model)
        assert np.abs(Jq[:, j] - col_q).max() < FD_TOL and np.abs(Jv[:, j] - col_v).max() < FD_TOL, (name, j)
        col_0 = (fd.difference(model, fd.integrate(model, q, 1e-6 * e), q1)
                 - fd.difference(model, fd.integrate(model, q, -1e-6 * e), q1)) / 2e-6
        col_1 = (fd.difference(model, q, fd.integrate(model, q1, 1e-6 * e))
                 - fd.difference(model, q, fd.integrate(model, q1, -1e-6 * e))) / 2e-6
        assert np.abs(J0[:, j] - col_0).max() < FD_TOL * max(1.0, np.abs(d).max()), (name, j)
        assert np.abs(J1[:, j] - col_1).max() < FD_TOL * max(1.0, np.abs(d).max()), (name, j)


def test_derivatives_are_block_diagonal_by_joint() -> None:
    model = tree("free_branch")
    rng = np.random.default_rng(4)
    q, v = random_q(model, rng), rng.normal(size=model.nv)
    mask = np.zeros((model.nv, model.nv), dtype=bool)
    for i in range(model.nbodies):
        sl = slice(model.idx_v[i], model.idx_v[i] + model.nvs[i])
        mask[sl, sl] = True
    for J in (*fd.integrate_derivatives(model, q, v), *fd.difference_derivatives(model, q, random_q(model, rng))):
        assert np.all(J[~mask] == 0.0) and np.abs(J[mask]).max() > 0.1


def test_near_pi_the_difference_takes_the_shorter_way() -> None:
    """A spherical or free-flyer rotation of π − δ and of π + δ: |ω| ≤ π, and the reference agrees."""
    model = tree("free_branch")
    rng = np.random.default_rng(5)
    q = random_q(model, rng)
    for delta in (1e-3, 1e-7, -1e-7, -1e-3):
        v = _velocities(model, rng, np.array([np.pi - delta]))[0]
        v[[sl.start for sl in _angular(model) if sl.stop - sl.start == 1]] = 0.0  # (planar: wrapped differently)
        q1 = fd.integrate(model, q, v, backend="reference")
        d = fd.difference(model, q, q1)
        assert _rel(d, fd.difference(model, q, q1, backend="reference")) < RTOL
        for sl in _angular(model):
            if sl.stop - sl.start == 3:
                assert np.linalg.norm(d[sl]) <= np.pi + 1e-12
                expected = v[sl] if delta > 0 else -v[sl] / np.linalg.norm(v[sl]) * (np.pi + delta)
                assert np.abs(d[sl] - expected).max() < 1e-8


def test_batches_broadcast_and_equal_the_loop_bit_for_bit() -> None:
    model = tree("free_branch")
    rng = np.random.default_rng(6)
    Q = random_q(model, rng, (2, 3))
    v = rng.normal(size=model.nv)
    Q1 = random_q(model, rng, (3,))
    out = fd.integrate(model, Q, v)
    d = fd.difference(model, Q, Q1)
    J0, J1 = fd.difference_derivatives(model, Q1, Q)
    assert out.shape == (2, 3, model.nq) and d.shape == (2, 3, model.nv) and J0.shape == (2, 3, model.nv, model.nv)
    for i in range(2):
        for k in range(3):
            assert np.array_equal(out[i, k], fd.integrate(model, Q[i, k], v))
            assert np.array_equal(d[i, k], fd.difference(model, Q[i, k], Q1[k]))
            one = fd.difference_derivatives(model, Q1[k], Q[i, k])
            assert np.array_equal(J0[i, k], one[0]) and np.array_equal(J1[i, k], one[1])
    # the core's functions and fd.compile's methods are the same kernels
    assert np.array_equal(core.difference(model, Q, Q1), d)
    cm = fd.compile(model, warmup=False)
    assert np.array_equal(cm.integrate(Q[0, 0], v), out[0, 0])
    assert np.array_equal(cm.difference(Q[1, 2], Q1[2]), d[1, 2])


def test_out_and_float32() -> None:
    model = library_robot("solo12", True)
    assert model is not None
    rng = np.random.default_rng(7)
    q, q1 = random_q(model, rng, (4,)), random_q(model, rng, (4,))
    out = np.empty((4, model.nv))
    assert fd.difference(model, q, q1, out=out) is out and np.array_equal(out, fd.difference(model, q, q1))
    r32 = fd.difference(model, q.astype(np.float32), q1.astype(np.float32))
    assert r32.dtype == np.float32 and _rel(r32.astype(np.float64), out) < 1e-4


def test_bad_input_names_q0_and_q1() -> None:
    model = library_robot("solo12", True)
    assert model is not None
    rng = np.random.default_rng(8)
    q = random_q(model, rng, (3,))
    with pytest.raises(ShapeError, match=r"^q1: expected trailing dimension nq=19, got shape \(3, 18\)$"):
        fd.difference(model, q, q[:, :-1])
    with pytest.raises(ShapeError, match=r"^q0: expected trailing dimension nq=19"):
        fd.difference_derivatives(model, q[0, :5], q[0])
    bad = q.copy()
    bad[2, 4] = np.nan
    with pytest.raises(NonFiniteError, match=r"^q1: .*index \(2, 4\)"):
        fd.difference(model, q, bad)
    with pytest.raises(NonFiniteError, match=r"^q1: "):
        fd.difference(model, q[0], bad[2])  # (one state: the core declines, the checks word it)
    bad = q.copy()
    bad[1, 3:7] *= 1.01
    with pytest.raises(QuaternionNormError, match=r"^q1: joint .*\(free_flyer, q1\[3:7\]\).*batch index \(1,\)"):
        fd.difference(model, q, bad)
    with pytest.raises(QuaternionNormError, match=r"^q0: joint "):
        fd.difference_derivatives(model, bad[1], q[0])
    with pytest.raises(QuaternionNormError, match=r"^q: joint "):
        fd.integrate(model, bad, np.zeros(model.nv))
    # the core alone (its batch path, which words a failing row by the same checks)
    with pytest.raises(QuaternionNormError, match=r"^q1: joint "):
        core.difference(model, q, bad)
