"""Constrained dynamics, impulses and operational space (``fd.constrained_dynamics`` & co.).

Oracles: the dense KKT system built from ``fd.crba``, ``fd.nonlinear_effects``
and the constraints' own rows; the definitions of the drift (point contact: the
classical acceleration of the frame's origin; frame contact: its spatial
acceleration; loop: the time derivative of the relative velocity, by central
differences); the impulse and operational-space identities.
"""

from __future__ import annotations

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


def _dense_kkt(model: fd.Model, q: np.ndarray, v: np.ndarray, tau: np.ndarray, J: np.ndarray, c: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    M, h = fd.crba(model, q), fd.nonlinear_effects(model, q, v)
    m = J.shape[0]
    K = np.block([[M, -J.T], [J, np.zeros((m, m))]])
    sol = np.linalg.solve(K, np.concatenate([tau - h, c]))
    return sol[: model.nv], sol[model.nv:]


@pytest.mark.parametrize("ref", REFS, ids=lambda r: r.name)
def test_point_and_loop_constraints_against_the_dense_kkt(solo: fd.Model, ref: fd.ReferenceFrame) -> None:
    q, v, tau = _state(solo, 1)
    cons = [fd.PointContact(f, ref, baumgarte=(10.0, 2.0)) for f in FEET[:3]] + \
        [fd.LoopConstraint("HR_FOOT", "FL_FOOT", axes=(False, False, True, True, False, True), reference=ref,
                           baumgarte=(5.0, 1.0))]
    res = fd.constrained_dynamics(solo, q, v, tau, cons)
    J = fd.constraint_jacobian(solo, q, cons)
    gamma = fd.constraint_drift(solo, q, v, cons)
    assert J.shape == (12, solo.nv) and gamma.shape == (12,)
    assert [f.shape for f in res.forces] == [(3,), (3,), (3,), (3,)]
    # c = −γ − K_p e − K_d J v; the contacts have e = 0, so their rows of c are known without e
    c_contacts = -gamma[:9] - 2.0 * (J[:9] @ v)
    qdd_ref, lam_ref = _dense_kkt(solo, q, v, tau, J, np.concatenate([c_contacts, J[9:] @ res.ddq]))
    np.testing.assert_allclose(res.ddq, qdd_ref, atol=1e-9 * max(1.0, np.abs(qdd_ref).max()))
    np.testing.assert_allclose(res.lagrange, lam_ref, atol=1e-9 * max(1.0, np.abs(lam_ref).max()))
    assert float(res.residual) < 1e-9


@pytest.mark.parametrize("ref", REFS, ids=lambda r: r.name)
def test_drift_definitions(solo: fd.Model, ref: fd.ReferenceFrame) -> None:
    q, v, _ = _state(solo, 2)
    qdd = np.random.default_rng(3).normal(size=solo.nv)
    point, frame = fd.PointContact("FL_FOOT", ref), fd.FrameContact("HR_FOOT", ref)
    for c, acc in ((point, fd.frame_classical_acceleration(solo, q, v, qdd, "FL_FOOT", ref).vector[3:]),
                   (frame, fd.frame_acceleration(solo, q, v, qdd, "HR_FOOT", ref).vector)):
        got = fd.constraint_jacobian(solo, q, c) @ qdd + fd.constraint_drift(solo, q, v, c)
        np.testing.assert_allclose(got, acc, atol=1e-12 * max(1.0, np.abs(acc).max()))
    loop = fd.LoopConstraint("FL_FOOT", "HR_FOOT", reference=ref)
    eps = 1e-6

    def Jv(x: np.ndarray) -> np.ndarray:
        return fd.constraint_jacobian(solo, x, loop) @ v

    numeric = (Jv(fd.integrate(solo, q, eps * v)) - Jv(fd.integrate(solo, q, -eps * v))) / (2 * eps)
    np.testing.assert_allclose(fd.constraint_drift(solo, q, v, loop), numeric, atol=1e-6 * max(1.0, np.abs(numeric).max()))


def test_contacts_hold_and_dependent_contacts_need_mu(solo: fd.Model) -> None:
    q, v, tau = _state(solo, 4)
    res = fd.constrained_dynamics(solo, q, v, tau, [fd.PointContact(f, fd.LOCAL_WORLD_ALIGNED) for f in FEET])
    for f in FEET:  # the feet do not accelerate (classical acceleration of the contact points)
        acc = fd.frame_classical_acceleration(solo, q, v, res.ddq, f, fd.LOCAL_WORLD_ALIGNED).vector[3:]
        assert np.abs(acc).max() < 1e-9
    twice = [fd.PointContact(f, fd.LOCAL_WORLD_ALIGNED) for f in FEET + ["FL_FOOT"]]  # FL_FOOT twice: dependent
    with pytest.raises(fd.ConstraintError, match="mu"):
        fd.constrained_dynamics(solo, q, v, tau, twice)
    res2 = fd.constrained_dynamics(solo, q, v, tau, twice, mu=1e-6, max_iter=500)
    assert float(res2.residual) < 1e-8
    np.testing.assert_allclose(res2.ddq, res.ddq, atol=1e-7 * max(1.0, np.abs(res.ddq).max()))
    np.testing.assert_allclose(res2.forces[0] + res2.forces[4], res.forces[0], rtol=1e-6, atol=1e-6)
    np.testing.assert_allclose(res2.forces[0], res2.forces[4], rtol=1e-5, atol=1e-5)  # the minimum-norm split
    frames = fd.constrained_dynamics(solo, q, v, tau, fd.FrameContact("FL_FOOT", fd.LOCAL))
    assert [f.shape for f in frames.forces] == [(6,)] and float(frames.residual) < 1e-9


def test_impulse_dynamics(solo: fd.Model) -> None:
    q, v, _ = _state(solo, 5)
    cons = [fd.PointContact(f, fd.LOCAL_WORLD_ALIGNED) for f in FEET[:2]]
    for e in (0.0, 0.5):
        res = fd.impulse_dynamics(solo, q, v, cons, restitution=e)
        J = fd.constraint_jacobian(solo, q, cons)
        np.testing.assert_allclose(J @ res.v_plus, -e * (J @ v), atol=1e-10)
        M = fd.crba(solo, q)
        np.testing.assert_allclose(M @ (res.v_plus - v), J.T @ res.lagrange, atol=1e-9)
    with pytest.raises(fd.ModelError, match="restitution"):
        fd.impulse_dynamics(solo, q, v, cons, restitution=1.5)


def test_operational_space_and_delassus(solo: fd.Model) -> None:
    q, v, _ = _state(solo, 6)
    frames = ["FL_FOOT", "HR_FOOT"]
    J = np.concatenate([fd.frame_jacobian(solo, q, f, fd.LOCAL_WORLD_ALIGNED) for f in frames])
    M = fd.crba(solo, q)
    Minv_Jt = np.linalg.solve(M, J.T)
    osc = fd.operational_space(solo, q, v, frames)
    # point feet: the angular rows of two 3-dof legs' Jacobians make J M⁻¹ Jᵀ singular — regularised Λ below
    D = J @ Minv_Jt
    np.testing.assert_allclose(osc.Lambda_inv, D, atol=1e-12 * np.abs(D).max())
    Lam = fd.operational_space_inertia(solo, q, frames, mu=1e-3)
    np.testing.assert_allclose(Lam, np.linalg.inv(D + 1e-3 * np.eye(12)), rtol=1e-8, atol=1e-8)
    cons = [fd.PointContact(f, fd.LOCAL) for f in frames]
    Jc = fd.constraint_jacobian(solo, q, cons)
    np.testing.assert_allclose(fd.delassus(solo, q, cons), Jc @ np.linalg.solve(M, Jc.T), atol=1e-12)
    np.testing.assert_allclose(osc.J_bar, Minv_Jt @ osc.Lambda, rtol=1e-6, atol=1e-6 * np.abs(osc.J_bar).max())


def test_operational_space_on_an_arm() -> None:
    model = library_robot("panda", False)
    assert model is not None
    q, v, _ = _state(model, 7)
    osc = fd.operational_space(model, q, v, "panda_hand")
    M, h, g = fd.crba(model, q), fd.nonlinear_effects(model, q, v), fd.generalized_gravity(model, q)
    J = fd.frame_jacobian(model, q, "panda_hand", fd.LOCAL_WORLD_ALIGNED)
    Jdot = fd.frame_jacobian_time_variation(model, q, v, "panda_hand", fd.LOCAL_WORLD_ALIGNED)
    Lam = np.linalg.inv(J @ np.linalg.solve(M, J.T))
    np.testing.assert_allclose(osc.Lambda, Lam, rtol=1e-8, atol=1e-8 * np.abs(Lam).max())
    J_bar = np.linalg.solve(M, J.T) @ Lam
    np.testing.assert_allclose(osc.J_bar, J_bar, rtol=1e-8, atol=1e-8 * np.abs(J_bar).max())
    np.testing.assert_allclose(J @ osc.J_bar, np.eye(6), atol=1e-8)
    np.testing.assert_allclose(osc.mu, Lam @ (J @ np.linalg.solve(M, h) - Jdot @ v), rtol=1e-7,
                               atol=1e-7 * max(1.0, np.abs(osc.mu).max()))
    np.testing.assert_allclose(osc.p, J_bar.T @ g, rtol=1e-7, atol=1e-7 * max(1.0, np.abs(osc.p).max()))


def test_bad_constraints_are_refused(solo: fd.Model) -> None:
    q, v, tau = _state(solo, 8)
    with pytest.raises(fd.ModelError, match="axes"):
        fd.LoopConstraint("FL_FOOT", "HR_FOOT", axes=(False,) * 6)
    with pytest.raises(fd.ModelError, match="baumgarte"):
        fd.PointContact("FL_FOOT", baumgarte=(-1.0, 0.0))
    with pytest.raises(fd.ModelError, match="expected fd.PointContact"):
        fd.constrained_dynamics(solo, q, v, tau, ["FL_FOOT"])  # type: ignore[list-item]
    with pytest.raises(fd.ModelError):
        fd.constraint_jacobian(solo, q, fd.PointContact("no such frame"))


def _pin_setup(model: fd.Model):  # type: ignore[no-untyped-def]
    import warnings

    pin = pytest.importorskip("pinocchio")
    from featherdyn.robots import robot_path
    from featherdyn.verify.bridge import JointMap

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pm = pin.buildModelFromUrdf(str(robot_path("solo12")), pin.JointModelFreeFlyer())
    return pin, pm, pm.createData(), JointMap(model, pm)


def _pin_contacts(pin, pm, frames: list[str], kind, ref):  # type: ignore[no-untyped-def]
    cms, cds = pin.StdVec_RigidConstraintModel(), pin.StdVec_RigidConstraintData()
    for f in frames:
        fr = pm.frames[pm.getFrameId(f)]
        cms.append(pin.RigidConstraintModel(kind, pm, fr.parentJoint, fr.placement, ref))
    for c in cms:
        cds.append(c.createData())
    return cms, cds


@pytest.mark.parametrize(("ref", "three_d"), [(fd.LOCAL, True), (fd.LOCAL_WORLD_ALIGNED, True), (fd.LOCAL, False)],
                         ids=["3D-LOCAL", "3D-LWA", "6D-LOCAL"])
def test_against_pinocchio_constraint_and_impulse_dynamics(solo: fd.Model, ref: fd.ReferenceFrame, three_d: bool) -> None:
    """Pinocchio 4.1's constraintDynamics / impulseDynamics (its 6D forces are [f; n]: swapped to [n; f])."""
    pin, pm, pd, jm = _pin_setup(solo)
    pin_ref = pin.LOCAL if ref is fd.LOCAL else pin.LOCAL_WORLD_ALIGNED
    frames = FEET if three_d else FEET[:1]
    kind = pin.ContactType.CONTACT_3D if three_d else pin.ContactType.CONTACT_6D
    cms, cds = _pin_contacts(pin, pm, frames, kind, pin_ref)
    q, v, tau = _state(solo, 9)
    pin.initConstraintDynamics(pm, pd, cms, cds)
    ddq = jm.v_from_pin(pin.constraintDynamics(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(tau), cms, cds,
                                               pin.ProximalSettings(1e-12, 0.0, 1)).copy())
    lam = pd.lambda_c.copy() if three_d else np.concatenate([pd.lambda_c[3:6], pd.lambda_c[:3]])
    cons = [fd.PointContact(f, ref) if three_d else fd.FrameContact(f, ref) for f in frames]
    res = fd.constrained_dynamics(solo, q, v, tau, cons)
    np.testing.assert_allclose(res.ddq, ddq, atol=1e-9 * max(1.0, np.abs(ddq).max()))
    np.testing.assert_allclose(res.lagrange, lam, atol=1e-9 * max(1.0, np.abs(lam).max()))
    vp = jm.v_from_pin(pin.impulseDynamics(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v), cms, cds, 0.0,
                                           pin.ProximalSettings(1e-12, 0.0, 1)).copy())
    np.testing.assert_allclose(fd.impulse_dynamics(solo, q, v, cons).v_plus, vp, atol=1e-9 * max(1.0, np.abs(vp).max()))


def test_batches_equal_their_rows(solo: fd.Model) -> None:
    rng = np.random.default_rng(10)
    Q = fd.random_configuration(solo, rng, size=3)
    V, T = rng.normal(size=(3, solo.nv)), rng.normal(size=(3, solo.nv))
    cons = [fd.PointContact("FL_FOOT", fd.LOCAL_WORLD_ALIGNED),
            fd.LoopConstraint("HL_FOOT", "HR_FOOT", axes=(False,) * 3 + (True,) * 3)]
    res = fd.constrained_dynamics(solo, Q, V, T, cons)
    assert res.ddq.shape == (3, solo.nv) and [f.shape for f in res.forces] == [(3, 3), (3, 3)]
    for k in range(3):
        one = fd.constrained_dynamics(solo, Q[k], V[k], T[k], cons)
        # (batched and single matrix products round differently: equal to round-off, not bit for bit)
        np.testing.assert_allclose(res.ddq[k], one.ddq, rtol=1e-12, atol=1e-12 * np.abs(one.ddq).max())
        np.testing.assert_allclose(res.lagrange[k], one.lagrange, rtol=1e-12, atol=1e-12 * np.abs(one.lagrange).max())


def test_talos_double_support_and_delassus_against_pinocchio() -> None:
    """Two 6D soles on talos_full_v2: constraintDynamics and computeDelassusMatrix (rows [f; n] per contact there)."""
    import warnings

    pin = pytest.importorskip("pinocchio")
    from featherdyn.robots import robot_path
    from featherdyn.verify.bridge import JointMap

    model = library_robot("talos_full_v2", True)
    assert model is not None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pm = pin.buildModelFromUrdf(str(robot_path("talos_full_v2")), pin.JointModelFreeFlyer())
    pd, jm = pm.createData(), JointMap(model, pm)
    soles = ["left_sole_link", "right_sole_link"]
    cms, cds = _pin_contacts(pin, pm, soles, pin.ContactType.CONTACT_6D, pin.LOCAL)
    q, v, tau = _state(model, 11)
    pin.initConstraintDynamics(pm, pd, cms, cds)
    ddq = jm.v_from_pin(pin.constraintDynamics(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(tau), cms, cds,
                                               pin.ProximalSettings(1e-12, 0.0, 1)).copy())
    cons = [fd.FrameContact(f, fd.LOCAL) for f in soles]
    res = fd.constrained_dynamics(model, q, v, tau, cons)
    np.testing.assert_allclose(res.ddq, ddq, atol=1e-10 * np.abs(ddq).max())
    D = pin.computeDelassusMatrix(pm, pd, jm.q_to_pin(q), cms, cds, 0.0).copy()
    swap = np.r_[3:6, 0:3, 9:12, 6:9]  # [f; n] → [n; f] per contact
    ours = fd.delassus(model, q, cons)
    np.testing.assert_allclose(ours, D[np.ix_(swap, swap)], atol=1e-12 * np.abs(ours).max())


def test_gauss_principle_and_impacts_never_add_energy(solo: fd.Model) -> None:
    """q̈ minimises (q̈ − q̈_free)ᵀ M (q̈ − q̈_free) among the accelerations that satisfy the constraints; an impact
    with restitution e ∈ [0, 1] never increases the kinetic energy."""
    q, v, tau = _state(solo, 12)
    cons = [fd.PointContact(f, fd.LOCAL_WORLD_ALIGNED) for f in FEET[:3]]
    res = fd.constrained_dynamics(solo, q, v, tau, cons)
    M = fd.crba(solo, q)
    free = fd.aba(solo, q, v, tau)
    J = fd.constraint_jacobian(solo, q, cons)
    null = np.linalg.svd(J)[2][J.shape[0]:].T  # directions that keep J q̈ unchanged
    rng = np.random.default_rng(13)

    def cost(x: np.ndarray) -> float:
        return float((x - free) @ M @ (x - free))

    best = cost(res.ddq)
    assert all(cost(res.ddq + null @ rng.normal(size=null.shape[1]) * s) > best for s in (1e-3, 1e-1, 10.0))
    T0 = 0.5 * v @ M @ v
    for e in (0.0, 0.3, 1.0):
        vp = fd.impulse_dynamics(solo, q, v, cons, restitution=e).v_plus
        assert 0.5 * vp @ M @ vp <= T0 * (1 + 1e-12), e


@pytest.mark.parametrize("backend", [None, "reference"])
def test_operational_space_inertia_at_a_singular_configuration_names_the_singularity(backend: str | None) -> None:
    """Issue 32 item 7: panda at q = 0 (a kinematic singularity) gave NumPy's LinAlgError from inside NumPy; it is a
    ConstraintError that says so and points to the damped form, which then works (both backends alike)."""
    model = fd.load_robot("panda")
    q = np.zeros(model.nq)
    with pytest.raises(fd.ConstraintError, match="singular.*mu > 0"):
        fd.operational_space_inertia(model, q, ["panda_hand"], backend=backend)
    L = fd.operational_space_inertia(model, q, ["panda_hand"], mu=1e-8, backend=backend)
    assert L.shape == (6, 6) and np.all(np.isfinite(L))
    assert np.allclose(L, L.T, rtol=1e-6, atol=1e-6 * np.abs(L).max())
