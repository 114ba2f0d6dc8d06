"""``out=`` of the functions whose result is a record: an array for each output the call forms.

The generic forms (one state, batches, an ``out`` over ``q``, ``fd.compile``'s methods, bad arrays) are in
``tests/reference/test_declared_front_ends.py`` for every declaration; here the parts that only some have: outputs
formed only with an optional input (``fd.forward_kinematics``' ``vel`` and ``acc``, ``fd.center_of_mass``'s ``ċ``),
``fd.kinematics_derivatives`` at a point (its own front end), the reference backend, and Dask arrays.
"""

from __future__ import annotations

import numpy as np
import pytest
from _models import library_robot

import featherdyn as fd
from featherdyn.errors import ShapeError


@pytest.fixture(scope="module")
def talos() -> fd.Model:
    model = library_robot("talos_full_v2", True)
    assert model is not None, "example-robot-data is a test dependency"
    return model


def _state(model: fd.Model, seed: int, size: tuple[int, ...] = ()) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    q = fd.random_configuration(model, rng, size=size) if size else fd.random_configuration(model, rng)
    return q, rng.normal(size=size + (model.nv,)), rng.normal(size=size + (model.nv,))


def test_forward_kinematics_takes_an_array_for_each_output_formed(talos: fd.Model) -> None:
    q, v, a = _state(talos, 1)
    nb = talos.nbodies
    for given, extra in (((), 2), ((v,), 3), ((v, a), 4)):
        out = tuple(np.full((nb, 4, 4) if k < 2 else (nb, 6), np.nan) for k in range(extra))
        r = fd.forward_kinematics(talos, q, *given, out=out)
        fresh = fd.forward_kinematics(talos, q, *given)
        assert np.array_equal(r.placements.rotation, fresh.placements.rotation)
        assert np.array_equal(out[0][:, :3, :3], fresh.placements.rotation)  # H's blocks: ⁰R_i, ⁰p_i
        assert np.array_equal(out[0][:, :3, 3], fresh.placements.translation)
        if given:
            assert np.array_equal(out[2], fresh.velocities.vector)
            assert np.array_equal(r.velocities.vector, fresh.velocities.vector)
        else:
            assert r.velocities is None
        # one array too many or too few: named
        with pytest.raises(ShapeError, match=f"out: expected {extra} arrays for H, Hp"):
            fd.forward_kinematics(talos, q, *given, out=out + (np.empty((nb, 6)),))
        with pytest.raises(ShapeError, match=f"out: expected {extra} arrays"):
            fd.forward_kinematics(talos, q, *given, out=out[:-1])


def test_center_of_mass_takes_one_array_bare_or_two(talos: fd.Model) -> None:
    q, v, _ = _state(talos, 2, (3,))
    c = np.empty((3, 3))
    assert fd.center_of_mass(talos, q, out=c) is c
    assert np.array_equal(c, fd.center_of_mass(talos, q))
    cd = np.empty((3, 3))
    r = fd.center_of_mass(talos, q, v, out=(c, cd))
    fresh = fd.center_of_mass(talos, q, v)
    assert r.position is c and r.velocity is cd
    assert np.array_equal(c, fresh.position) and np.array_equal(cd, fresh.velocity)
    with pytest.raises(ShapeError, match="out: expected 2 arrays for position, velocity, got ndarray"):
        fd.center_of_mass(talos, q, v, out=c)


def test_kinematics_derivatives_at_a_point(talos: fd.Model) -> None:
    """The point's own front end writes as the declared one: one state and a batch, an array for each of the
    record's eight fields (J in three of them), bad arrays."""
    frame = talos.frames[-1].name
    for size in ((), (4,)):
        q, v, a = _state(talos, 3, size)
        point = np.array([0.05, -0.02, 0.1])
        fresh = fd.kinematics_derivatives(talos, q, v, a, frame, fd.LOCAL_WORLD_ALIGNED, point)
        out = tuple(np.full(size + (6, talos.nv), np.nan) for _ in range(8))
        r = fd.kinematics_derivatives(talos, q, v, a, frame, fd.LOCAL_WORLD_ALIGNED, point, out=out)
        assert all(np.array_equal(x, y) for x, y in zip(r, fresh, strict=True))
        assert all(x is y for x, y in zip(r, out, strict=True))
        assert np.array_equal(r.da_da, r.dv_dv) and np.array_equal(r.dac_da, r.dv_dv)  # (J, written three times)
        assert not np.isnan(r.dv_dv).any()
    with pytest.raises(ShapeError, match="out: expected 8 arrays"):
        fd.kinematics_derivatives(talos, q, v, a, frame, fd.WORLD, point, out=out[:6])
    with pytest.raises(ShapeError, match="out: expected shape"):
        fd.kinematics_derivatives(talos, q, v, a, frame, fd.WORLD, point, out=tuple(x[0] for x in out))


def test_the_reference_backend_writes_the_same(talos: fd.Model) -> None:
    q, v, a = _state(talos, 4)
    fresh = fd.centroidal_dynamics_derivatives(talos, q, v, a, backend="reference")
    out = tuple(np.empty((6, talos.nv)) for _ in range(4))
    r = fd.centroidal_dynamics_derivatives(talos, q, v, a, out=out, backend="reference")
    assert all(x is y for x, y in zip(r, out, strict=True))
    assert all(np.array_equal(x, y) for x, y in zip(r, fresh, strict=True))
    H = np.empty((talos.nbodies, 4, 4))
    r = fd.forward_kinematics(talos, q, out=(H, np.empty_like(H)), backend="reference")
    fresh_fk = fd.forward_kinematics(talos, q, backend="reference")
    assert np.array_equal(r.placements.translation, fresh_fk.placements.translation)
    with pytest.raises(ShapeError, match="out: expected 2 arrays"):
        fd.forward_kinematics(talos, q, out=(H,), backend="reference")


def test_float64_results_refused_into_float32_and_dask_refused(talos: fd.Model) -> None:
    q, v, a = _state(talos, 5)
    out = tuple(np.empty((talos.nv,) * 3, dtype=np.float32) for _ in range(4))
    with pytest.raises(fd.DTypeError, match="out: cannot write float64 results for d2tau_dq2"):
        fd.rnea_second_derivatives(talos, q, v, a, out=out)
    da = pytest.importorskip("dask.array")
    with pytest.raises(ShapeError, match="out: not supported with Dask arrays"):
        fd.center_of_mass_derivatives(talos, da.from_array(q[None]), v[None], out=(np.empty((1, 3, talos.nv)),
                                                                                   np.empty((1, 3, talos.nv))))


def test_bad_out_forms_are_named(talos: fd.Model) -> None:
    """Not a sequence, an element that is not an array (None, a NumPy scalar, an np.matrix), arrays sharing memory:
    a ShapeError naming the output, never a raw TypeError."""
    q, v, a = _state(talos, 6)
    n = talos.nv
    with pytest.raises(ShapeError, match=r"out: expected 4 arrays for d2tau_dq2, .*got int"):
        fd.rnea_second_derivatives(talos, q, v, a, out=5)
    with pytest.raises(ShapeError, match="out: expected a NumPy array for position, got int"):
        fd.center_of_mass(talos, q, out=7)
    for bad in (None, np.float64(1.0), np.matrix(np.zeros((n, n * n)))):
        with pytest.raises(ShapeError, match=f"out: expected a NumPy array for d2tau_dv2, got {type(bad).__name__}"):
            fd.rnea_second_derivatives(talos, q, v, a, out=(np.empty((n, n, n)), bad, np.empty((n, n, n)),
                                                            np.empty((n, n, n))))
    x = np.empty((n, n, n))
    with pytest.raises(ShapeError, match="out: the arrays for d2tau_dq2 and d2tau_dv2 share memory"):
        fd.rnea_second_derivatives(talos, q, v, a, out=(x, x[:], np.empty_like(x), np.empty_like(x)))
