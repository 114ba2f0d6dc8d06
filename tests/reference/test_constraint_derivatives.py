"""Derivatives of constrained dynamics and impulses (``fd.constrained_dynamics_derivatives``,
``fd.impulse_dynamics_derivatives``).

Oracles: Pinocchio 4.1's ``computeConstraintDynamicsDerivatives`` / ``computeImpulseDynamicsDerivatives``
(solo12 with four point contacts, one and two 6D contacts, talos_full_v2 on two soles; LOCAL and
LOCAL_WORLD_ALIGNED), and central differences of ``fd.constrained_dynamics`` / ``fd.impulse_dynamics``
along fd.integrate's tangent for what Pinocchio does not have (WORLD, loops, Baumgarte gains,
restitution, batches).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable

import numpy as np
import pytest
from _models import library_robot

import featherdyn as fd

FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
REFS = [fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED]


@pytest.fixture(scope="module")
def solo() -> fd.Model:
    model = library_robot("solo12", True)
    assert model is not None
    return model


def _state(model: fd.Model, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    return fd.random_configuration(model, rng), rng.normal(size=model.nv), rng.normal(size=model.nv)


def _central(model: fd.Model, f: Callable[[np.ndarray, np.ndarray], np.ndarray], q: np.ndarray, x: np.ndarray,
             along_q: bool, eps: float = 1e-6) -> np.ndarray:
    """Columns ``(f(q ⊕ ε e_k) − f(q ⊕ −ε e_k)) / 2ε`` (or along x, a vector)."""
    cols = []
    for k in range(model.nv):
        e = np.zeros(model.nv)
        e[k] = eps
        if along_q:
            cols.append((f(fd.integrate(model, q, e), x) - f(fd.integrate(model, q, -e), x)) / (2 * eps))
        else:
            cols.append((f(q, x + e) - f(q, x - e)) / (2 * eps))
    return np.stack(cols, axis=-1)


def _close(ours: np.ndarray, oracle: np.ndarray, rtol: float) -> None:
    np.testing.assert_allclose(ours, oracle, atol=rtol * max(1.0, float(np.abs(oracle).max())))


def _check_constrained(model: fd.Model, cons: list, seed: int, rtol: float = 2e-6, mu: float = 0.0,
                       forces: bool = True) -> None:
    q, v, tau = _state(model, seed)
    d = fd.constrained_dynamics_derivatives(model, q, v, tau, cons, mu=mu)

    def ddq(q_: np.ndarray, v_: np.ndarray) -> np.ndarray:
        return fd.constrained_dynamics(model, q_, v_, tau, cons, mu=mu).ddq

    def lam(q_: np.ndarray, v_: np.ndarray) -> np.ndarray:
        return fd.constrained_dynamics(model, q_, v_, tau, cons, mu=mu).lagrange

    def by_tau(q_: np.ndarray, t_: np.ndarray) -> np.ndarray:
        r = fd.constrained_dynamics(model, q_, v, t_, cons, mu=mu)
        return np.concatenate([r.ddq, r.lagrange])

    _close(d.ddq_dq, _central(model, ddq, q, v, True), rtol)
    _close(d.ddq_dv, _central(model, ddq, q, v, False), rtol)
    both = _central(model, by_tau, q, tau, False)
    _close(d.ddq_dtau, both[: model.nv], rtol)
    if forces:
        _close(d.forces_dq, _central(model, lam, q, v, True), rtol)
        _close(d.forces_dv, _central(model, lam, q, v, False), rtol)
        _close(d.forces_dtau, both[model.nv:], rtol)


@pytest.mark.parametrize("ref", REFS, ids=lambda r: r.value)
def test_contacts_against_central_differences(solo: fd.Model, ref: fd.ReferenceFrame) -> None:
    _check_constrained(solo, [fd.PointContact(f, ref, baumgarte=(5.0, 3.0)) for f in FEET], 1)
    _check_constrained(solo, [fd.FrameContact("FL_FOOT", ref, baumgarte=(0.0, 2.0)),
                              fd.PointContact("HR_FOOT", ref)], 2)


@pytest.mark.parametrize("ref", REFS, ids=lambda r: r.value)
def test_loops_against_central_differences(solo: fd.Model, ref: fd.ReferenceFrame) -> None:
    """Loops carry a position error e = log(ᵃM_b) (K_p acts) and a reference that turns with frame a."""
    _check_constrained(solo, [fd.LoopConstraint("FL_FOOT", "HR_FOOT", reference=ref, baumgarte=(2.0, 3.0))], 3)
    _check_constrained(solo, [fd.LoopConstraint("FL_FOOT", "HR_FOOT", axes=(True, False, False, True, True, False),
                                                reference=ref, baumgarte=(4.0, 1.0)),
                              fd.PointContact("FR_FOOT", ref)], 4)


@pytest.mark.parametrize("ref", REFS, ids=lambda r: r.value)
def test_impulses_against_central_differences(solo: fd.Model, ref: fd.ReferenceFrame) -> None:
    q, v, _ = _state(solo, 5)
    cons = [fd.PointContact("FL_FOOT", ref), fd.FrameContact("HR_FOOT", ref),
            fd.LoopConstraint("FR_FOOT", "HL_FOOT", axes=(False,) * 3 + (True,) * 3, reference=ref)]
    d = fd.impulse_dynamics_derivatives(solo, q, v, cons, restitution=0.4)

    def vp(q_: np.ndarray, v_: np.ndarray) -> np.ndarray:
        return fd.impulse_dynamics(solo, q_, v_, cons, restitution=0.4).v_plus

    def lam(q_: np.ndarray, v_: np.ndarray) -> np.ndarray:
        return fd.impulse_dynamics(solo, q_, v_, cons, restitution=0.4).lagrange

    _close(d.dv_plus_dq, _central(solo, vp, q, v, True), 2e-6)
    _close(d.dv_plus_dv, _central(solo, vp, q, v, False), 2e-6)
    _close(d.impulses_dq, _central(solo, lam, q, v, True), 2e-6)
    _close(d.impulses_dv, _central(solo, lam, q, v, False), 2e-6)


def test_dependent_contacts_with_mu(solo: fd.Model) -> None:
    """Dependent rows (a foot's point contact twice, in two references) with mu > 0: ∂q̈ is still exact; mu = 0
    refuses as fd.constrained_dynamics does."""
    cons = [fd.PointContact(f, fd.LOCAL_WORLD_ALIGNED) for f in FEET] + [fd.PointContact("FL_FOOT", fd.LOCAL)]
    _check_constrained(solo, cons, 6, mu=1e-3, forces=False)
    q, v, tau = _state(solo, 6)
    with pytest.raises(fd.ConstraintError):
        fd.constrained_dynamics_derivatives(solo, q, v, tau, cons)


def test_batches_equal_their_rows(solo: fd.Model) -> None:
    rng = np.random.default_rng(7)
    Q = fd.random_configuration(solo, rng, size=3)
    V, T = rng.normal(size=(3, solo.nv)), rng.normal(size=(3, solo.nv))
    cons = [fd.PointContact("FL_FOOT", fd.LOCAL_WORLD_ALIGNED),
            fd.LoopConstraint("HL_FOOT", "HR_FOOT", axes=(False,) * 3 + (True,) * 3, reference=fd.WORLD)]
    d = fd.constrained_dynamics_derivatives(solo, Q, V, T, cons)
    i = fd.impulse_dynamics_derivatives(solo, Q, V, cons, restitution=0.5)
    assert d.ddq_dq.shape == (3, solo.nv, solo.nv) and d.forces_dv.shape == (3, 6, solo.nv)
    for k in range(3):
        one = fd.constrained_dynamics_derivatives(solo, Q[k], V[k], T[k], cons)
        two = fd.impulse_dynamics_derivatives(solo, Q[k], V[k], cons, restitution=0.5)
        for name in ("ddq_dq", "ddq_dv", "ddq_dtau", "forces_dq", "forces_dv", "forces_dtau"):
            _close(getattr(d, name)[k], getattr(one, name), 1e-11)
        for name in ("dv_plus_dq", "dv_plus_dv", "impulses_dq", "impulses_dv"):
            _close(getattr(i, name)[k], getattr(two, name), 1e-11)


def test_f_ext_and_reference_backend(solo: fd.Model) -> None:
    """External forces enter ∂q̈ (central differences); the reference backend gives the core's numbers."""
    q, v, tau = _state(solo, 8)
    f = np.random.default_rng(8).normal(size=(solo.nbodies, 6))
    cons = [fd.PointContact(x, fd.LOCAL_WORLD_ALIGNED) for x in FEET[:3]]
    d = fd.constrained_dynamics_derivatives(solo, q, v, tau, cons, f_ext=f)

    def ddq(q_: np.ndarray, v_: np.ndarray) -> np.ndarray:
        return fd.constrained_dynamics(solo, q_, v_, tau, cons, f_ext=f).ddq

    _close(d.ddq_dq, _central(solo, ddq, q, v, True), 2e-6)
    r = fd.constrained_dynamics_derivatives(solo, q, v, tau, cons, f_ext=f, backend="reference")
    _close(r.ddq_dq, d.ddq_dq, 1e-10)
    _close(r.forces_dv, d.forces_dv, 1e-10)


def test_bad_input_gets_featherdyn_errors(solo: fd.Model) -> None:
    q, v, tau = _state(solo, 9)
    with pytest.raises(fd.ModelError, match="no such frame"):
        fd.constrained_dynamics_derivatives(solo, q, v, tau, fd.PointContact("no such frame"))
    with pytest.raises(fd.ShapeError):
        fd.constrained_dynamics_derivatives(solo, q[:-1], v, tau, fd.PointContact("FL_FOOT"))
    with pytest.raises(fd.ShapeError):
        fd.impulse_dynamics_derivatives(solo, q, v[:3], fd.PointContact("FL_FOOT"))
    with pytest.raises(fd.ModelError, match="restitution"):
        fd.impulse_dynamics_derivatives(solo, q, v, fd.PointContact("FL_FOOT"), restitution=2.0)
    with pytest.raises(fd.ModelError, match="restitution"):  # (not a number: was a raw ValueError)
        fd.impulse_dynamics_derivatives(solo, q, v, fd.PointContact("FL_FOOT"), restitution="x")
    with pytest.raises(fd.ConstraintError):
        fd.constrained_dynamics_derivatives(solo, q, v, tau, fd.PointContact("FL_FOOT"), mu=-1.0)
    with pytest.raises(fd.ModelError):
        fd.constrained_dynamics_derivatives(solo, q, v, tau, ["FL_FOOT"])  # type: ignore[list-item]


# --- Pinocchio -------------------------------------------------------------------------------------------------


def _pinocchio(name: str, model: fd.Model, frames: list[str], three_d: bool, ref: fd.ReferenceFrame):  # type: ignore[no-untyped-def]
    pin = pytest.importorskip("pinocchio")
    from featherdyn.robots import robot_path
    from featherdyn.verify.bridge import JointMap

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pm = pin.buildModelFromUrdf(str(robot_path(name)), pin.JointModelFreeFlyer())
    kind = pin.ContactType.CONTACT_3D if three_d else pin.ContactType.CONTACT_6D
    pin_ref = pin.LOCAL if ref is fd.LOCAL else pin.LOCAL_WORLD_ALIGNED
    cms, cds = pin.StdVec_RigidConstraintModel(), pin.StdVec_RigidConstraintData()
    for f in frames:
        fr = pm.frames[pm.getFrameId(f)]
        cms.append(pin.RigidConstraintModel(kind, pm, fr.parentJoint, fr.placement, pin_ref))
    for c in cms:
        cds.append(c.createData())
    pd = pm.createData()
    pin.initConstraintDynamics(pm, pd, cms, cds)
    return pin, pm, pd, JointMap(model, pm), cms, cds


CASES = [("solo12", FEET, True, fd.LOCAL), ("solo12", FEET, True, fd.LOCAL_WORLD_ALIGNED),
         ("solo12", FEET[:2], False, fd.LOCAL), ("solo12", FEET[1:2], False, fd.LOCAL_WORLD_ALIGNED),
         ("talos_full_v2", ["left_sole_link", "right_sole_link"], False, fd.LOCAL)]


@pytest.mark.parametrize(("name", "frames", "three_d", "ref"), CASES,
                         ids=[f"{c[0]}-{len(c[1])}x{'3D' if c[2] else '6D'}-{c[3].value}" for c in CASES])
def test_against_pinocchio(name: str, frames: list[str], three_d: bool, ref: fd.ReferenceFrame) -> None:
    """Pinocchio's rows: 6D forces [f; n] (swapped to [n; f]); its impulse ``ddq_dv`` is ∂(v⁺ − v⁻)/∂v⁻."""
    model = library_robot(name, True)
    assert model is not None
    pin, pm, pd, jm, cms, cds = _pinocchio(name, model, frames, three_d, ref)
    q, v, tau = _state(model, 10)
    qp, vp, tp = jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(tau)
    settings = pin.ProximalSettings(1e-12, 0.0, 1)
    swap = np.concatenate([np.arange(3 * i, 3 * i + 3) if three_d else np.r_[6 * i + 3:6 * i + 6, 6 * i:6 * i + 3]
                           for i in range(len(frames))])
    cons = [fd.PointContact(f, ref) if three_d else fd.FrameContact(f, ref) for f in frames]

    def rows(m: np.ndarray) -> np.ndarray:
        return jm.columns_from_pin(m.copy())[swap]

    pin.constraintDynamics(pm, pd, qp, vp, tp, cms, cds, settings)
    pin.computeConstraintDynamicsDerivatives(pm, pd, cms, cds, settings)
    d = fd.constrained_dynamics_derivatives(model, q, v, tau, cons)
    for ours, theirs in [(d.ddq_dq, jm.matrix_from_pin(pd.ddq_dq.copy())),
                         (d.ddq_dv, jm.matrix_from_pin(pd.ddq_dv.copy())),
                         (d.ddq_dtau, jm.matrix_from_pin(pd.ddq_dtau.copy())),
                         (d.forces_dq, rows(pd.dlambda_dq)), (d.forces_dv, rows(pd.dlambda_dv)),
                         (d.forces_dtau, rows(pd.dlambda_dtau))]:
        _close(ours, theirs, 1e-9)
    pin.impulseDynamics(pm, pd, qp, vp, cms, cds, 0.3, settings)
    pin.computeImpulseDynamicsDerivatives(pm, pd, cms, cds, 0.3, settings)
    i = fd.impulse_dynamics_derivatives(model, q, v, cons, restitution=0.3)
    for ours, theirs in [(i.dv_plus_dq, jm.matrix_from_pin(pd.ddq_dq.copy())),
                         (i.dv_plus_dv - np.eye(model.nv), jm.matrix_from_pin(pd.ddq_dv.copy())),
                         (i.impulses_dq, rows(pd.dlambda_dq)), (i.impulses_dv, rows(pd.dlambda_dv))]:
        _close(ours, theirs, 1e-9)


@pytest.mark.parametrize("ref", REFS, ids=lambda r: r.value)
def test_core_equals_reference_and_batches_on_the_pool(solo: fd.Model, ref: fd.ReferenceFrame) -> None:
    """Point and frame contacts take the core's kernel (contact_derivatives.hpp), one state and rows of a batch;
    the reference backend composes the same equations from its own functions."""
    rng = np.random.default_rng(11)
    Q = fd.random_configuration(solo, rng, size=4)
    V, T = rng.normal(size=(4, solo.nv)), rng.normal(size=(4, solo.nv))
    cons = [fd.PointContact("FL_FOOT", ref, baumgarte=(0.0, 2.0)), fd.FrameContact("HR_FOOT", ref)]
    d = fd.constrained_dynamics_derivatives(solo, Q, V, T, cons)
    i = fd.impulse_dynamics_derivatives(solo, Q, V, cons, restitution=0.2)
    one = (fd.constrained_dynamics_derivatives(solo, Q[0], V[0], T[0], cons),  # (the binding makes the record)
           fd.impulse_dynamics_derivatives(solo, Q[0], V[0], cons, restitution=0.2))
    for got, cls in zip((d, i, *one), (fd.ConstrainedDynamicsDerivatives, fd.ImpulseDynamicsDerivatives) * 2):
        assert type(got) is cls and len(got) == len(cls._fields)
    for got, batch in zip(one, (d, i)):
        for name in type(got)._fields:
            np.testing.assert_array_equal(getattr(got, name), getattr(batch, name)[0])
    for k in range(4):
        r = fd.constrained_dynamics_derivatives(solo, Q[k], V[k], T[k], cons, backend="reference")
        s = fd.impulse_dynamics_derivatives(solo, Q[k], V[k], cons, restitution=0.2, backend="reference")
        for name in ("ddq_dq", "ddq_dv", "ddq_dtau", "forces_dq", "forces_dv", "forces_dtau", "ddq", "lagrange"):
            _close(getattr(d, name)[k], getattr(r, name), 1e-10)
        for name in ("dv_plus_dq", "dv_plus_dv", "impulses_dq", "impulses_dv", "v_plus", "lagrange"):
            _close(getattr(i, name)[k], getattr(s, name), 1e-10)
