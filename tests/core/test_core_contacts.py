"""The contact kernel's batches (``contacts.hpp`` on SIMD packs): every row equals its one-state call, bit for bit.

* q̈, λ, the iterations and the residual of each row of a batch equal the one-state call's exactly, for batch
  sizes around the pack width (tails run row by row, full groups on packs), every reference frame, point and
  frame contacts, f_ext, broadcast rows, ``mu = 0`` (one solve) and ``mu > 0`` (proximal iterations, each
  lane stopping at its own iteration, or not converging);
* a row whose contacts are dependent (``mu = 0``: a singular J M⁻¹ Jᵀ) fails alone: its one-state status
  (iterations −1) and the other rows of its group unchanged; a non-finite row is named;
* Λ of frames (``fd.operational_space_inertia``) on rows: each equal to its one-state call, bit for bit;
* the constrained dynamics' derivatives (``contact_derivatives.hpp`` on packs) likewise, every reference, K_d,
  ``mu = 0`` and ``mu > 0``; a batch with a row of dependent contacts raises that row's error;
* the same with the baseline and AVX2 kernels (``FEATHERDYN_SIMD``, in a fresh process).
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from _models import library_robot

import featherdyn as fd
from featherdyn import core

WIDTH = core._core.simd()[1]
SIZES = sorted({1, WIDTH - 1, WIDTH, WIDTH + 1, 2 * WIDTH + 3})
SCENES = {  # robot: (frames, rows per contact)
    "solo12": (["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"], 3),
    "talos_full_v2": (["left_sole_link", "right_sole_link"], 6),
}


def _model(name: str, floating: bool = True) -> fd.Model:
    model = library_robot(name, floating)
    if model is None:
        pytest.skip(f"{name} is not in the robot library")
    return model


def _specs(model: fd.Model, frames: list[str], rows: int, ref: int, kd: float) -> np.ndarray:
    return np.array([[rows, model.resolve_frame(f), ref, kd] for f in frames], dtype=np.float64)


def _states(model: fd.Model, seed: int, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return (fd.random_configuration(model, rng, size=n), rng.normal(size=(n, model.nv)),
            rng.normal(size=(n, model.nv)), rng.normal(size=(n, model.nbodies, 6)))


def _assert_rows_are_one_state_calls(model: fd.Model, Q: np.ndarray, V: np.ndarray, T: np.ndarray,
                                     FX: np.ndarray | None, specs: np.ndarray, **solver: float) -> np.ndarray:
    batch = core.contact_dynamics(model, Q, V, T, specs, FX, **solver)
    n = Q.shape[0]
    for k in range(n):
        one = core.contact_dynamics(model, Q[k], V[k if V.shape[0] == n else 0], T[k],
                                    specs, None if FX is None else FX[k], **solver)
        for what, b, o in zip(("q̈", "λ", "iterations", "residual"), batch, one, strict=True):
            assert np.array_equal(b[k], o), f"row {k} of {n}: {what} differs from the one-state call"
    return batch[2]


@pytest.mark.parametrize("name", SCENES)
@pytest.mark.parametrize("n", SIZES)
@pytest.mark.parametrize("ref", [0, 1, 2], ids=["LOCAL", "WORLD", "LWA"])
def test_rows_equal_one_state_calls_bit_for_bit(name: str, n: int, ref: int) -> None:
    model = _model(name)
    frames, rows = SCENES[name]
    Q, V, T, FX = _states(model, 20 + n + 7 * ref, n)
    specs = _specs(model, frames, rows, ref, 0.5)
    its = _assert_rows_are_one_state_calls(model, Q, V, T, FX, specs)
    assert np.all(its == 1)
    its = _assert_rows_are_one_state_calls(model, Q, V, T, None, specs, mu=1e-3, max_iter=40)
    assert np.all(its >= 1)


@pytest.mark.parametrize("name", SCENES)
def test_proximal_lanes_stop_at_their_own_iteration(name: str) -> None:
    """mu > 0: the rows of one pack need different numbers of iterations; with too few, some do not converge."""
    model = _model(name)
    frames, rows = SCENES[name]
    Q, V, T, _ = _states(model, 3, 3 * WIDTH + 10)
    specs = _specs(model, frames, rows, 2, 0.0)
    its = _assert_rows_are_one_state_calls(model, Q, V, T, None, specs, mu=1e-3, max_iter=50, tol=1e-12)
    assert len(set(its.tolist())) > 1, f"every row took {its[0]} iterations: the test shows nothing"
    few = int(its.max()) - 1  # the slowest rows stop short, the others converge
    its = _assert_rows_are_one_state_calls(model, Q, V, T, None, specs, mu=1e-3, max_iter=few, tol=1e-12)
    assert np.any(its == -2) and np.any(its > 0), its


def test_broadcast_rows() -> None:
    """One row of v (and of the contacts' gains) for the whole batch: stride-0 rows gathered into every lane."""
    model = _model("solo12")
    frames, rows = SCENES["solo12"]
    Q, V, T, _ = _states(model, 5, WIDTH + 3)
    specs = _specs(model, frames, rows, 1, 2.0)
    _assert_rows_are_one_state_calls(model, Q, V[:1], T, None, specs)
    _assert_rows_are_one_state_calls(model, Q, V[:1], T, None, specs, mu=1e-4)


def test_public_batches_equal_public_one_state_calls() -> None:
    """fd.constrained_dynamics on (N, nq) rows (the core's batch as it is) and on a batch shape (N1, N2, nq)."""
    model = _model("talos_full_v2")
    frames, _ = SCENES["talos_full_v2"]
    cons = [fd.FrameContact(f, fd.LOCAL, baumgarte=(0.0, 1.0)) for f in frames]
    Q, V, T, _ = _states(model, 6, 2 * WIDTH + 1)
    for shape in [(2 * WIDTH + 1,), (1, 2 * WIDTH + 1)]:
        res = fd.constrained_dynamics(model, Q.reshape(*shape, -1), V.reshape(*shape, -1), T.reshape(*shape, -1),
                                      cons)
        assert res.ddq.shape == (*shape, model.nv) and res.forces[1].shape == (*shape, 6)
        for k in range(Q.shape[0]):
            one = fd.constrained_dynamics(model, Q[k], V[k], T[k], cons)
            assert np.array_equal(res.ddq.reshape(-1, model.nv)[k], one.ddq), k
            assert np.array_equal(res.lagrange.reshape(-1, 12)[k], one.lagrange), k
            assert np.array_equal(res.residual.reshape(-1)[k], one.residual), k


def _singular_row_batch() -> tuple[fd.Model, np.ndarray, np.ndarray, np.ndarray, np.ndarray, int]:
    """panda with its hand held by a frame contact: J M⁻¹ Jᵀ is singular at q = 0 (joints 1 and 3 coaxial)."""
    model = _model("panda", False)
    n, bad = 2 * WIDTH + 1, WIDTH // 2
    rng = np.random.default_rng(8)
    Q = fd.random_configuration(model, rng, size=n)
    Q[bad] = 0.0
    V, T = rng.normal(size=(n, model.nv)), rng.normal(size=(n, model.nv))
    return model, Q, V, T, _specs(model, ["panda_hand"], 6, 0, 0.0), bad


def test_a_row_with_dependent_contacts_fails_alone() -> None:
    model, Q, V, T, specs, bad = _singular_row_batch()
    qdd, lam, its, res = core.contact_dynamics(model, Q, V, T, specs)
    one = core.contact_dynamics(model, Q[bad], V[bad], T[bad], specs)
    assert one[2] == -1 and its[bad] == -1, "the test needs a row with dependent contacts"
    ok = [k for k in range(Q.shape[0]) if k != bad]
    assert np.all(its[ok] == 1)
    _assert_rows_are_one_state_calls(model, Q[ok], V[ok], T[ok], None, specs)
    for k in ok:  # the failing row's group mates get their own one-state results
        o = core.contact_dynamics(model, Q[k], V[k], T[k], specs)
        assert np.array_equal(qdd[k], o[0]) and np.array_equal(lam[k], o[1]) and res[k] == o[3], k
    with pytest.raises(fd.ConstraintError, match="mu"):
        fd.constrained_dynamics(model, Q, V, T, fd.FrameContact("panda_hand", fd.LOCAL))
    # mu > 0 takes the same row: every row equal to its one-state call
    its = _assert_rows_are_one_state_calls(model, Q, V, T, None, specs, mu=1e-6, max_iter=200)
    assert its[bad] != -1


def test_a_bad_row_is_named() -> None:
    """A non-finite row inside a full pack: the error names that row, as the batch's checks do for every kernel."""
    model = _model("solo12")
    frames = SCENES["solo12"][0]
    Q, V, T, _ = _states(model, 9, 2 * WIDTH)
    T[WIDTH + 1, 4] = np.nan
    with pytest.raises(fd.NonFiniteError, match=rf"tau: .* at index \({WIDTH + 1}, 4\)"):
        fd.constrained_dynamics(model, Q, V, T, [fd.PointContact(f) for f in frames])


OSI_SCENES = {"panda": (False, ["panda_hand"]),
              "talos_full_v2": (True, ["gripper_left_base_link", "gripper_right_base_link"])}


def _assert_lambda_rows_are_one_state_calls(name: str, n: int, seed: int) -> None:
    floating, frames = OSI_SCENES[name]
    model = _model(name, floating)
    Q = fd.random_configuration(model, np.random.default_rng(seed), size=n)
    for ref in (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED):
        for mu in (0.0, 1e-3):
            batch = fd.operational_space_inertia(model, Q, frames, ref, mu=mu)
            assert batch.shape == (n, 6 * len(frames), 6 * len(frames))
            for k in range(n):
                one = fd.operational_space_inertia(model, Q[k], frames, ref, mu=mu)
                assert np.array_equal(batch[k], one), f"{name} {ref.name} mu={mu}: row {k} of {n} differs"


@pytest.mark.parametrize("name", OSI_SCENES)
@pytest.mark.parametrize("n", SIZES)
def test_lambda_rows_equal_one_state_calls_bit_for_bit(name: str, n: int) -> None:
    _assert_lambda_rows_are_one_state_calls(name, n, 30 + n)


DERIVATIVES = ("ddq_dq", "ddq_dv", "ddq_dtau", "forces_dq", "forces_dv", "forces_dtau", "ddq", "lagrange")
IMPULSE_DERIVATIVES = ("dv_plus_dq", "dv_plus_dv", "impulses_dq", "impulses_dv", "v_plus", "lagrange")
REFERENCES = {0: fd.LOCAL, 1: fd.WORLD, 2: fd.LOCAL_WORLD_ALIGNED}


def _assert_derivative_rows_are_one_state_calls(name: str, ref: int, n: int, seed: int, mu: float = 0.0) -> None:
    """``fd.constrained_dynamics_derivatives`` on n rows (the core's batch: full groups on Packs, the tail row by
    row) against its one-state calls, bit for bit."""
    model = _model(name)
    frames, rows = SCENES[name]
    Q, V, T, _ = _states(model, seed, n)
    kind = fd.PointContact if rows == 3 else fd.FrameContact
    cons = [kind(f, REFERENCES[ref], baumgarte=(0.0, 0.5)) for f in frames]
    batch = fd.constrained_dynamics_derivatives(model, Q, V, T, cons, mu=mu)
    for k in range(n):
        one = fd.constrained_dynamics_derivatives(model, Q[k], V[k], T[k], cons, mu=mu)
        for what in DERIVATIVES:
            assert np.array_equal(getattr(batch, what)[k], getattr(one, what)), f"{name} row {k} of {n}: {what}"


def _assert_impulse_rows_are_one_state_calls(name: str, ref: int, n: int, seed: int, e: float) -> None:
    """``fd.impulse_dynamics_derivatives`` and ``fd.impulse_dynamics`` on n rows (full groups on Packs, the tail row by
    row) against their one-state calls, bit for bit."""
    model = _model(name)
    frames, rows = SCENES[name]
    Q, V, _, _ = _states(model, seed, n)
    kind = fd.PointContact if rows == 3 else fd.FrameContact
    cons = [kind(f, REFERENCES[ref]) for f in frames]
    for call, fields in ((fd.impulse_dynamics_derivatives, IMPULSE_DERIVATIVES),
                         (fd.impulse_dynamics, ("v_plus", "lagrange"))):
        batch = call(model, Q, V, cons, restitution=e)
        for k in range(n):
            one = call(model, Q[k], V[k], cons, restitution=e)
            for what in fields:
                assert np.array_equal(getattr(batch, what)[k], getattr(one, what)), f"{name} row {k} of {n}: {what}"


@pytest.mark.parametrize("name", SCENES)
@pytest.mark.parametrize("n", [WIDTH, 2 * WIDTH + 3])
@pytest.mark.parametrize("ref", [0, 1, 2], ids=["LOCAL", "WORLD", "LWA"])
def test_derivative_rows_equal_one_state_calls_bit_for_bit(name: str, n: int, ref: int) -> None:
    """The constrained dynamics' and the impulses' derivatives in SIMD lanes (contact_derivatives.hpp on Packs), and
    the impact alone (contacts.hpp on Packs): every reference (the forces' turn in WORLD and LWA), K_d, mu = 0 and
    mu > 0 (each lane's own proximal iterations), restitution 0 and 0.4."""
    _assert_derivative_rows_are_one_state_calls(name, ref, n, 60 + n + ref)
    _assert_derivative_rows_are_one_state_calls(name, ref, n, 70 + n + ref, mu=1e-3)
    _assert_impulse_rows_are_one_state_calls(name, ref, n, 90 + n + ref, 0.0)
    _assert_impulse_rows_are_one_state_calls(name, ref, n, 100 + n + ref, 0.4)


def test_a_derivative_batch_with_dependent_contacts_raises_as_its_row() -> None:
    """A lane whose D is singular fails its group; the batch then raises the one-state call's error, and the
    other rows alone equal their one-state calls."""
    model, Q, V, T, _, bad = _singular_row_batch()
    cons = fd.FrameContact("panda_hand", fd.LOCAL)
    with pytest.raises(fd.ConstraintError) as one:
        fd.constrained_dynamics_derivatives(model, Q[bad], V[bad], T[bad], cons)
    with pytest.raises(fd.ConstraintError) as batch:
        fd.constrained_dynamics_derivatives(model, Q, V, T, cons)
    assert type(batch.value) is type(one.value)
    ok = [k for k in range(Q.shape[0]) if k != bad]
    rows = fd.constrained_dynamics_derivatives(model, Q[ok], V[ok], T[ok], cons)
    for i, k in enumerate(ok):
        single = fd.constrained_dynamics_derivatives(model, Q[k], V[k], T[k], cons)
        for what in DERIVATIVES:
            assert np.array_equal(getattr(rows, what)[i], getattr(single, what)), (k, what)


@pytest.mark.parametrize("name", ["impulse_dynamics", "impulse_dynamics_derivatives"])
def test_an_impulse_batch_with_dependent_contacts_raises_as_its_row(name: str) -> None:
    """As above for the impulses' group kernels (the impact alone, and with its derivatives): the lane whose D is
    singular fails its group; the other rows are their one-state calls' bits."""
    call = getattr(fd, name)
    model, Q, V, _, _, bad = _singular_row_batch()
    cons = fd.FrameContact("panda_hand", fd.LOCAL)
    with pytest.raises(fd.ConstraintError) as one:
        call(model, Q[bad], V[bad], cons, restitution=0.3)
    with pytest.raises(fd.ConstraintError) as batch:
        call(model, Q, V, cons, restitution=0.3)
    assert type(batch.value) is type(one.value)
    ok = [k for k in range(Q.shape[0]) if k != bad]
    rows = call(model, Q[ok], V[ok], cons, restitution=0.3)
    fields = IMPULSE_DERIVATIVES if name.endswith("derivatives") else ("v_plus", "lagrange")
    for i, k in enumerate(ok):
        single = call(model, Q[k], V[k], cons, restitution=0.3)
        for what in fields:
            assert np.array_equal(getattr(rows, what)[i], getattr(single, what)), (k, what)


@pytest.mark.parametrize("name", sorted(SCENES))
def test_impulse_dynamics_in_the_core(name: str) -> None:
    """fd.impulse_dynamics on point and frame contacts runs the core's kernel (``impulse_dynamics``: the constrained
    dynamics' KKT solve on M's packed factor, contacts.hpp): v⁺ and Λ agree with the reference backend (the dense
    KKT solve) and with the impulse derivatives' (their own dense solve, contact_derivatives.hpp) to round-off, one
    state and a (2, W + 1) stack (each state the bits of its one-state call), with and without restitution; the
    impact law holds (J v⁺ = −e J v⁻, M (v⁺ − v⁻) = Jᵀ Λ); dependent contacts raise as before (mu = 0) or take the
    proximal general path (mu > 0)."""
    model = _model(name)
    frames, rows = SCENES[name]
    cons = [fd.PointContact(f) if rows == 3 else fd.FrameContact(f) for f in frames]
    rng = np.random.default_rng(11)
    Q = np.asarray(fd.random_configuration(model, rng, size=(2, WIDTH + 1)))
    V = rng.normal(size=(2, WIDTH + 1, model.nv))
    for e in (0.0, 0.6):
        stacked = fd.impulse_dynamics(model, Q, V, cons, restitution=e)  # (in SIMD lanes: groups of W states)
        assert stacked.v_plus.shape == (2, WIDTH + 1, model.nv) and len(stacked.impulses) == len(cons)
        for i, k in np.ndindex(2, WIDTH + 1):
            one = fd.impulse_dynamics(model, Q[i, k], V[i, k], cons, restitution=e)
            assert np.array_equal(stacked.v_plus[i, k], one.v_plus) and np.array_equal(stacked.lagrange[i, k],
                                                                                         one.lagrange), (i, k)
        for i, k in ((0, 0), (1, WIDTH)):
            one = fd.impulse_dynamics(model, Q[i, k], V[i, k], cons, restitution=e)
            ref = fd.impulse_dynamics(model, Q[i, k], V[i, k], cons, restitution=e, backend="reference")
            d = fd.impulse_dynamics_derivatives(model, Q[i, k], V[i, k], cons, restitution=e)
            assert np.array_equal(stacked.v_plus[i, k], one.v_plus)
            assert np.array_equal(stacked.lagrange[i, k], one.lagrange)
            for x, y in zip(stacked.impulses, one.impulses, strict=True):
                assert np.array_equal(x[i, k], y)
            scale = max(1.0, float(np.abs(ref.v_plus).max()), float(np.abs(ref.lagrange).max()))
            np.testing.assert_allclose(one.v_plus, ref.v_plus, rtol=0, atol=1e-10 * scale)
            np.testing.assert_allclose(one.lagrange, ref.lagrange, rtol=0, atol=1e-10 * scale)
            np.testing.assert_allclose(one.v_plus, d.v_plus, rtol=0, atol=1e-12 * scale)
            np.testing.assert_allclose(one.lagrange, d.lagrange, rtol=0, atol=1e-12 * scale)
            assert not np.array_equal(one.v_plus, V[i, k])  # the impact changed the velocity
            J = np.concatenate([fd.frame_jacobian(model, Q[i, k], f, fd.LOCAL)[3 if rows == 3 else 0:] for f in frames])
            M = fd.crba(model, Q[i, k])
            np.testing.assert_allclose(J @ one.v_plus, -e * (J @ V[i, k]), rtol=0, atol=1e-9 * scale)
            np.testing.assert_allclose(M @ (one.v_plus - V[i, k]), J.T @ one.lagrange, rtol=0, atol=1e-9 * scale)
    # dependent contacts: the same contact twice
    twice = [cons[0], cons[0]]
    with pytest.raises(fd.ConstraintError):
        fd.impulse_dynamics(model, Q[0, 0], V[0, 0], twice)
    prox = fd.impulse_dynamics(model, Q[0, 0], V[0, 0], twice, mu=1e-6)
    ref = fd.impulse_dynamics(model, Q[0, 0], V[0, 0], twice, mu=1e-6, backend="reference")
    np.testing.assert_allclose(prox.v_plus, ref.v_plus, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("which", ["constrained", "impulse"])
def test_a_derivative_batch_with_a_non_finite_row_names_it(which: str) -> None:
    """A NaN in a row of a full group of lanes: the batch's error names the argument and the row (every row is
    checked before a group runs), the same error a one-state call of that row raises about its own entry."""
    model = _model("solo12")
    frames = SCENES["solo12"][0]
    Q, V, T, _ = _states(model, 17, 2 * WIDTH + 1)
    cons = [fd.PointContact(f) for f in frames]
    bad = WIDTH + 1
    V[bad, 4] = np.nan

    def call(q: np.ndarray, v: np.ndarray, t: np.ndarray) -> Any:
        if which == "constrained":
            return fd.constrained_dynamics_derivatives(model, q, v, t, cons)
        return fd.impulse_dynamics_derivatives(model, q, v, cons, restitution=0.3)

    with pytest.raises(fd.NonFiniteError, match=rf"v: .* at index \({bad}, 4\)"):
        call(Q, V, T)
    with pytest.raises(fd.NonFiniteError, match=r"v: .* at index \(4,\)"):
        call(Q[bad], V[bad], T[bad])


_SIMD_SCRIPT = """
import sys
sys.path.insert(0, {tests!r})
sys.path.insert(0, {core_tests!r})
import test_core_contacts as t
from featherdyn import core
print(core._core.simd()[0])
for name in t.SCENES:
    model = t._model(name)
    frames, rows = t.SCENES[name]
    for ref in (0, 1, 2):
        Q, V, T, FX = t._states(model, 40 + ref, 2 * t.WIDTH + 1)
        specs = t._specs(model, frames, rows, ref, 0.5)
        t._assert_rows_are_one_state_calls(model, Q, V, T, FX, specs)
        t._assert_rows_are_one_state_calls(model, Q, V, T, None, specs, mu=1e-3, max_iter=6)
        t._assert_derivative_rows_are_one_state_calls(name, ref, 2 * t.WIDTH + 1, 80 + ref)
        t._assert_impulse_rows_are_one_state_calls(name, ref, 2 * t.WIDTH + 1, 110 + ref, 0.4)
t.test_a_row_with_dependent_contacts_fails_alone()
t.test_a_derivative_batch_with_dependent_contacts_raises_as_its_row()
t.test_an_impulse_batch_with_dependent_contacts_raises_as_its_row("impulse_dynamics")
t.test_an_impulse_batch_with_dependent_contacts_raises_as_its_row("impulse_dynamics_derivatives")
for name in t.OSI_SCENES:
    t._assert_lambda_rows_are_one_state_calls(name, 2 * t.WIDTH + 1, 50)
print("ok")
"""


@pytest.mark.parametrize("isa", ["baseline", "avx2"])
def test_every_simd_build_is_bit_identical_too(isa: str) -> None:
    """FEATHERDYN_SIMD=baseline|avx2 in a fresh process (the default, the widest the CPU has, runs above)."""
    here = Path(__file__).resolve().parent
    env = dict(os.environ, FEATHERDYN_SIMD=isa)
    res = subprocess.run([sys.executable, "-c", _SIMD_SCRIPT.format(tests=str(here.parent), core_tests=str(here))],
                         env=env, capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stderr[-3000:]
    used, verdict = res.stdout.split()
    assert verdict == "ok"
    assert used == isa or (isa == "avx2" and used == "baseline"), (isa, used)


def test_public_batch_that_does_not_converge_raises() -> None:
    """The public batch path hands a failed row to the general path, which raises the one-state call's error."""
    model = _model("solo12")
    frames = SCENES["solo12"][0]
    Q, V, T, _ = _states(model, 12, WIDTH + 2)
    cons = [fd.PointContact(f) for f in frames]
    with pytest.raises(fd.ConstraintError) as one:
        fd.constrained_dynamics(model, Q[3], V[3], T[3], cons, mu=1e-3, max_iter=1)
    with pytest.raises(fd.ConstraintError) as batch:
        fd.constrained_dynamics(model, Q, V, T, cons, mu=1e-3, max_iter=1)
    assert str(batch.value) == str(one.value)


def test_bad_contact_specs_are_a_shape_error_naming_them() -> None:
    model = _model("solo12")
    q, v, tau, _ = _states(model, 3, 1)
    for specs in (np.array([[5.0, 0.0, 0.0, 0.0]]), [[3, 0, 0]], np.array([[3.0, 1e6, 0.0, 0.0]])):
        with pytest.raises(fd.ShapeError, match="specs"):
            core.contact_dynamics(model, q[0], v[0], tau[0], specs)
