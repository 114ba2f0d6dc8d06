"""Constrained dynamics on closed chains and whole robots: scenes, the reference KKT, Pinocchio.

Oracles:

* **physics**: a planar four-bar linkage and a Delta-like parallel mechanism
  (built with ``fd.ModelBuilder``, loops closed by ``fd.LoopConstraint``) move
  under gravity with no actuation: integrated with RK4, their energy
  ``T + V`` stays constant and their loops stay closed. A wrong drift γ opens
  the loop within a step; a wrong force adds or removes energy;
* **the reference**: ``backend="reference"`` (``algorithms/constraints.py``, NumPy,
  the same LᵀL and Schur-complement algorithm) against the compiled core;
* **Pinocchio 4.1**: ``constraintDynamics`` with a 6D loop and talos with a hand on a wall.
"""

from __future__ import annotations

import dataclasses
import warnings
from collections.abc import Callable

import numpy as np
import pytest
from _models import library_robot

import featherdyn as fd
from featherdyn.algorithms import constraints as ref_kkt

FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]


def _rod(mass: float, tip: np.ndarray) -> fd.SpatialInertia:
    """A thin uniform rod from the body origin to ``tip``: centre of mass at ``tip / 2``."""
    tip = np.asarray(tip, dtype=float)
    length = float(np.linalg.norm(tip))
    u = tip / length
    I_c = mass * length**2 / 12.0 * (np.eye(3) - np.outer(u, u)) + 1e-4 * mass * np.outer(u, u)  # spin: small
    return fd.SpatialInertia(mass, tip / 2, I_c)


def _at(p: np.ndarray | list[float]) -> fd.PluckerTransform:
    return fd.PluckerTransform(np.eye(3), np.asarray(p, dtype=float))


# ---------------------------------------------------------------- the four-bar linkage

A, B, C, D = 1.0, 2.0, 1.5, 2.0  # crank, coupler, rocker, ground


def four_bar() -> tuple[fd.Model, list[fd.Constraint]]:
    """Crank (pivot at the origin), coupler, rocker (pivot at (D, 0)), in the x-y plane, gravity along −y."""
    b = fd.ModelBuilder("four_bar", gravity=(0.0, -9.81, 0.0))
    z = fd.RevoluteJoint([0, 0, 1])
    crank = b.add_body("crank", -1, z, inertia=_rod(1.0, [A, 0, 0]))
    coupler = b.add_body("coupler", crank, z, placement=_at([A, 0, 0]), inertia=_rod(2.0, [B, 0, 0]))
    rocker = b.add_body("rocker", -1, z, placement=_at([D, 0, 0]), inertia=_rod(1.5, [C, 0, 0]))
    b.add_frame("coupler_tip", coupler, _at([B, 0, 0]))
    b.add_frame("rocker_tip", rocker, _at([C, 0, 0]))
    loop = fd.LoopConstraint("coupler_tip", "rocker_tip", axes=(False, False, False, True, True, False))
    return b.build(), [loop]


def four_bar_configuration(theta: float) -> np.ndarray:
    """The closed configuration with crank angle ``theta`` (circle intersection, elbow up)."""
    P = np.array([A * np.cos(theta), A * np.sin(theta)])
    O2 = np.array([D, 0.0])
    d = np.linalg.norm(O2 - P)
    x = (d**2 + B**2 - C**2) / (2 * d)
    h = np.sqrt(B**2 - x**2)
    e = (O2 - P) / d
    Q = P + x * e + h * np.array([-e[1], e[0]])
    phi = np.arctan2(*(Q - P)[::-1])
    psi = np.arctan2(*(Q - O2)[::-1])
    return np.array([theta, phi - theta, psi])


# ---------------------------------------------------------------- a Delta-like parallel robot

def delta() -> tuple[fd.Model, list[fd.Constraint]]:
    """Three legs at 120°: a hinge at the base, a ball joint at the elbow; the platform hangs from leg 0's forearm
    by a ball joint, legs 1 and 2 close on it with 3D loops. Closed at the neutral configuration by construction."""
    b = fd.ModelBuilder("delta")
    base_r, arm, plat_r, drop = 0.3, 0.4, 0.1, 0.5
    us = [np.array([np.cos(a), np.sin(a), 0.0]) for a in (0.0, 2 * np.pi / 3, 4 * np.pi / 3)]
    tips = []
    for k, u in enumerate(us):
        hinge_axis = np.cross([0, 0, 1.0], u)
        upper = b.add_body(f"upper{k}", -1, fd.RevoluteJoint(hinge_axis), placement=_at(base_r * u),
                           inertia=_rod(0.3, arm * u))
        forearm_vec = (plat_r - base_r - arm) * u + np.array([0, 0, -drop])
        fore = b.add_body(f"fore{k}", upper, fd.SphericalJoint(), placement=_at(arm * u),
                          inertia=_rod(0.2, forearm_vec))
        tips.append((fore, forearm_vec))
    fore0, vec0 = tips[0]
    platform = b.add_body("platform", fore0, fd.SphericalJoint(), placement=_at(vec0),
                          inertia=fd.SpatialInertia(1.0, -plat_r * us[0], 1e-3 * np.eye(3)))
    loops = []
    for k in (1, 2):
        fore, vec = tips[k]
        b.add_frame(f"fore{k}_tip", fore, _at(vec))
        b.add_frame(f"platform_joint{k}", platform, _at(plat_r * (us[k] - us[0])))
        loops.append(fd.LoopConstraint(f"fore{k}_tip", f"platform_joint{k}", axes=(False,) * 3 + (True,) * 3))
    return b.build(), loops


# ---------------------------------------------------------------- integration

def _rk4(model: fd.Model, cons: list[fd.Constraint], q: np.ndarray, v: np.ndarray, dt: float, steps: int,
         backend: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """RK4 on the configuration manifold (``fd.integrate`` for the positions), τ = 0."""
    tau = np.zeros(model.nv)

    def acc(qq: np.ndarray, vv: np.ndarray) -> np.ndarray:
        return fd.constrained_dynamics(model, qq, vv, tau, cons, backend=backend).ddq

    for _ in range(steps):
        k1v, k1a = v, acc(q, v)
        q2, v2 = fd.integrate(model, q, 0.5 * dt * k1v), v + 0.5 * dt * k1a
        k2v, k2a = v2, acc(q2, v2)
        q3, v3 = fd.integrate(model, q, 0.5 * dt * k2v), v + 0.5 * dt * k2a
        k3v, k3a = v3, acc(q3, v3)
        q4, v4 = fd.integrate(model, q, dt * k3v), v + dt * k3a
        k4v, k4a = v4, acc(q4, v4)
        q = fd.integrate(model, q, dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v))
        v = v + dt / 6 * (k1a + 2 * k2a + 2 * k3a + k4a)
    return q, v


def _energy(model: fd.Model, q: np.ndarray, v: np.ndarray) -> float:
    return float(fd.kinetic_energy(model, q, v) + fd.potential_energy(model, q))


def _loop_error(model: fd.Model, q: np.ndarray, cons: list[fd.Constraint]) -> float:
    err = 0.0
    for c in cons:
        assert isinstance(c, fd.LoopConstraint)
        pa = fd.frame_placement(model, q, c.frame_a).translation
        pb = fd.frame_placement(model, q, c.frame_b).translation
        err = max(err, float(np.linalg.norm(pa - pb)))
    return err


def _admissible_velocity(model: fd.Model, q: np.ndarray, cons: list[fd.Constraint], seed: int) -> np.ndarray:
    J = fd.constraint_jacobian(model, q, cons)
    null = np.linalg.svd(J)[2][np.linalg.matrix_rank(J):].T
    return null @ np.random.default_rng(seed).normal(size=null.shape[1])


SCENES: dict[str, Callable[[], tuple[fd.Model, list[fd.Constraint], np.ndarray]]] = {
    "four_bar": lambda: (*four_bar(), four_bar_configuration(0.7)),
    "delta": lambda: (*delta(), fd.neutral(delta()[0])),
}


def test_the_four_bar_conserves_energy_and_stays_closed() -> None:
    """All hinges (a vector space): RK4 is fourth order, the drift is at round-off level."""
    model, cons, q = SCENES["four_bar"]()
    assert _loop_error(model, q, cons) < 1e-12  # closed at the start
    v = _admissible_velocity(model, q, cons, seed=1)
    assert np.abs(fd.constraint_jacobian(model, q, cons) @ v).max() < 1e-12
    E0 = _energy(model, q, v)
    q1, v1 = _rk4(model, cons, q, v, dt=2e-3, steps=250)  # 0.5 s of free motion under gravity
    assert np.abs(q1 - q).max() > 1e-1  # it did move
    assert abs(_energy(model, q1, v1) - E0) < 1e-8 * max(abs(E0), 1.0)
    assert _loop_error(model, q1, cons) < 1e-8
    assert np.abs(fd.constraint_jacobian(model, q1, cons) @ v1).max() < 1e-8


def test_the_delta_robot_conserves_energy_and_stays_closed_as_the_step_shrinks() -> None:
    """Ball joints: RK4 on SO(3) through ``fd.integrate`` is second order, so the drift must fall ~4× per halved
    step (a wrong drift γ or a wrong force would leave an error that does not vanish)."""
    model, cons, q = SCENES["delta"]()
    assert _loop_error(model, q, cons) < 1e-12
    v = _admissible_velocity(model, q, cons, seed=1)
    E0 = _energy(model, q, v)
    drift, opening = [], []
    for dt in (4e-3, 2e-3):
        q1, v1 = _rk4(model, cons, q, v, dt=dt, steps=round(0.25 / dt))
        drift.append(abs(_energy(model, q1, v1) - E0))
        opening.append(_loop_error(model, q1, cons))
    assert np.abs(q1 - q).max() > 1e-1
    assert drift[1] < drift[0] / 3 and opening[1] < opening[0] / 3, (drift, opening)
    assert drift[1] < 1e-4 * abs(E0) and opening[1] < 1e-4


def test_four_bar_moves_like_its_one_dof_lagrangian() -> None:
    """A closed-chain check with its own oracle: with q = q(θ) the loop's parametrisation, the crank's
    acceleration solves m(θ) θ̈ + ½ m'(θ) θ̇² + V'(θ) = 0, m(θ) = s(θ)ᵀ M s(θ), s = dq/dθ (finite differences)."""
    model, cons = four_bar()
    theta, eps = 0.7, 1e-5
    q = four_bar_configuration(theta)
    s = (four_bar_configuration(theta + eps) - four_bar_configuration(theta - eps)) / (2 * eps)

    def mass(t: float) -> float:
        st = (four_bar_configuration(t + eps) - four_bar_configuration(t - eps)) / (2 * eps)
        return float(st @ fd.crba(model, four_bar_configuration(t)) @ st)

    def potential(t: float) -> float:
        return float(fd.potential_energy(model, four_bar_configuration(t)))

    h = 1e-4
    m, dm = mass(theta), (mass(theta + h) - mass(theta - h)) / (2 * h)
    dV = (potential(theta + h) - potential(theta - h)) / (2 * h)
    for thetadot in (0.0, 1.3):
        expected = -(0.5 * dm * thetadot**2 + dV) / m
        res = fd.constrained_dynamics(model, q, s * thetadot, np.zeros(3), cons)
        assert res.ddq[0] == pytest.approx(expected, rel=1e-6, abs=1e-6)


# ---------------------------------------------------------------- the reference KKT against the core

@pytest.fixture(scope="module")
def solo() -> fd.Model:
    model = library_robot("solo12", True)
    assert model is not None
    return model


def test_the_tree_sparse_factor(solo: fd.Model) -> None:
    """M = Lᵀ L, L lower triangular and zero off the dofs' ancestors; the core's factor is the same."""
    q = fd.random_configuration(solo, np.random.default_rng(0), 3)
    M = fd.crba(solo, q)
    L, bad = ref_kkt.ltl_factor(solo, M)
    assert np.all(bad == -1)
    np.testing.assert_allclose(np.swapaxes(L, -1, -2) @ L, M, atol=1e-12 * np.abs(M).max())
    lam = ref_kkt.dof_parents(solo)
    for k in range(solo.nv):
        ancestors, i = set(), lam[k]
        while i != -1:
            ancestors.add(i)
            i = lam[i]
        outside = [j for j in range(solo.nv) if j != k and j not in ancestors]
        assert np.all(L[..., k, outside] == 0)
    np.testing.assert_allclose(L, fd.core.mass_matrix_factor(solo, q), rtol=1e-13, atol=1e-13)


def _close(a: np.ndarray, b: np.ndarray, rtol: float = 1e-10) -> None:
    np.testing.assert_allclose(a, b, atol=rtol * max(1.0, float(np.abs(b).max())))


@pytest.mark.parametrize("mu", [0.0, 1e-6])
def test_reference_and_core_solve_the_same_system(solo: fd.Model, mu: float) -> None:
    rng = np.random.default_rng(5)
    q = fd.random_configuration(solo, rng, 4)
    v, tau = rng.normal(size=(2, 4, solo.nv))
    f_ext = rng.normal(size=(4, solo.nbodies, 6))
    cons = [fd.PointContact(f, fd.LOCAL_WORLD_ALIGNED, baumgarte=(4.0, 1.0)) for f in FEET[:3]] + \
        [fd.LoopConstraint("HR_FOOT", "FL_FOOT", axes=(False, False, True, True, False, True), baumgarte=(2.0, 0.5))]
    core = fd.constrained_dynamics(solo, q, v, tau, cons, f_ext=f_ext, mu=mu)
    ref = fd.constrained_dynamics(solo, q, v, tau, cons, f_ext=f_ext, mu=mu, backend="reference")
    _close(ref.ddq, core.ddq)
    _close(ref.lagrange, core.lagrange)
    assert np.all(ref.residual < 1e-9)
    _close(fd.delassus(solo, q, cons, backend="reference"), fd.delassus(solo, q, cons))
    for e in (0.0, 0.5):
        _close(fd.impulse_dynamics(solo, q, v, cons, restitution=e, backend="reference").v_plus,
               fd.impulse_dynamics(solo, q, v, cons, restitution=e).v_plus)
    a = fd.operational_space(solo, q, v, ["FL_FOOT", "HR_FOOT"], backend="reference")
    b = fd.operational_space(solo, q, v, ["FL_FOOT", "HR_FOOT"])
    for x, y in ((a.Lambda, b.Lambda), (a.J_bar, b.J_bar), (a.mu, b.mu), (a.p, b.p)):
        _close(x, y, rtol=1e-8)


def test_the_reference_keeps_float32_and_refuses_dependent_rows(solo: fd.Model) -> None:
    rng = np.random.default_rng(6)
    q = fd.random_configuration(solo, rng)
    v, tau = rng.normal(size=(2, solo.nv))
    cons = [fd.PointContact(f, fd.LOCAL_WORLD_ALIGNED) for f in FEET[:3]]
    r32 = fd.constrained_dynamics(solo, q.astype(np.float32), v.astype(np.float32), tau.astype(np.float32), cons)
    r64 = fd.constrained_dynamics(solo, q, v, tau, cons)
    assert r32.ddq.dtype == np.float32 and r32.lagrange.dtype == np.float32
    _close(r32.ddq.astype(float), r64.ddq, rtol=1e-3)
    four_6d = [fd.FrameContact(f) for f in FEET]  # 24 rows on 18 dofs: at rest, the robot is held in place
    rest = np.zeros(solo.nv)
    for backend in ("reference", "compiled"):
        with pytest.raises(fd.ConstraintError, match="pass mu > 0"):
            fd.constrained_dynamics(solo, q, rest, tau, four_6d, backend=backend)
        res = fd.constrained_dynamics(solo, q, rest, tau, four_6d, mu=1e-6, max_iter=500, backend=backend)
        assert float(res.residual) < 1e-8 and np.abs(res.ddq).max() < 1e-8


# ---------------------------------------------------------------- Pinocchio

def _pin(robot: str, model: fd.Model):  # type: ignore[no-untyped-def]
    pin = pytest.importorskip("pinocchio")
    from featherdyn.robots import robot_path
    from featherdyn.verify.bridge import JointMap

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pm = pin.buildModelFromUrdf(str(robot_path(robot)), pin.JointModelFreeFlyer())
    return pin, pm, pm.createData(), JointMap(model, pm)


def _pin_solve(pin, pm, pd, jm, cms, q, v, tau):  # type: ignore[no-untyped-def]
    cds = pin.StdVec_RigidConstraintData()
    for c in cms:
        cds.append(c.createData())
    pin.initConstraintDynamics(pm, pd, cms, cds)
    ddq = pin.constraintDynamics(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(tau), cms, cds,
                                 pin.ProximalSettings(1e-12, 0.0, 1))
    return jm.v_from_pin(ddq.copy()), pd.lambda_c.copy()


def test_a_6d_loop_against_pinocchio(solo: fd.Model) -> None:
    """A 6D loop between two feet, LOCAL: Pinocchio's two-joint RigidConstraintModel (forces [f; n] there)."""
    pin, pm, pd, jm = _pin("solo12", solo)
    rng = np.random.default_rng(3)
    q = fd.random_configuration(solo, rng)
    v, tau = rng.normal(size=(2, solo.nv))
    fa, fb = pm.frames[pm.getFrameId("FL_FOOT")], pm.frames[pm.getFrameId("HR_FOOT")]
    cms = pin.StdVec_RigidConstraintModel()
    cms.append(pin.RigidConstraintModel(pin.ContactType.CONTACT_6D, pm, fa.parentJoint, fa.placement, fb.parentJoint,
                                        fb.placement, pin.LOCAL))
    ddq, lam = _pin_solve(pin, pm, pd, jm, cms, q, v, tau)
    for backend in ("compiled", "reference"):
        res = fd.constrained_dynamics(solo, q, v, tau, fd.LoopConstraint("FL_FOOT", "HR_FOOT"), backend=backend)
        _close(res.ddq, ddq, rtol=1e-9)
        _close(res.lagrange, np.r_[lam[3:], lam[:3]], rtol=1e-9)


@pytest.mark.parametrize("hand", ["3D", "6D"])
def test_talos_with_a_hand_on_a_wall_against_pinocchio(hand: str) -> None:
    """talos_full_v2 in double support (two 6D soles) with its left gripper held (a 3D or 6D contact)."""
    model = library_robot("talos_full_v2", True)
    assert model is not None
    pin, pm, pd, jm = _pin("talos_full_v2", model)
    frames = ["left_sole_link", "right_sole_link", "gripper_left_base_link"]
    kinds = [pin.ContactType.CONTACT_6D] * 2 + [pin.ContactType.CONTACT_3D if hand == "3D" else pin.ContactType.CONTACT_6D]
    cms = pin.StdVec_RigidConstraintModel()
    for f, kind in zip(frames, kinds, strict=True):
        fr = pm.frames[pm.getFrameId(f)]
        cms.append(pin.RigidConstraintModel(kind, pm, fr.parentJoint, fr.placement, pin.LOCAL))
    rng = np.random.default_rng(21)
    q = fd.random_configuration(model, rng)
    v, tau = rng.normal(size=(2, model.nv))
    ddq, lam = _pin_solve(pin, pm, pd, jm, cms, q, v, tau)
    cons: list[fd.Constraint] = [fd.FrameContact(f) for f in frames[:2]]
    cons.append(fd.PointContact(frames[2]) if hand == "3D" else fd.FrameContact(frames[2]))
    res = fd.constrained_dynamics(model, q, v, tau, cons)
    _close(res.ddq, ddq, rtol=1e-9)
    swap = np.r_[3:6, 0:3, 9:12, 6:9]
    ours = np.concatenate([res.forces[0], res.forces[1]])
    _close(ours, lam[:12][swap], rtol=1e-9)
    hand_pin = lam[12:] if hand == "3D" else np.r_[lam[15:18], lam[12:15]]
    _close(res.forces[2], hand_pin, rtol=1e-9)


def test_constraints_with_nothing_to_hold_are_named() -> None:
    """A contact on a frame fixed to the world, a loop within one body: clear errors, not 'dependent rows'."""
    panda = fd.load_robot("panda")
    q, zero = fd.neutral(panda), np.zeros(panda.nv)
    cases = [(fd.PointContact("panda_link0"), "PointContact('panda_link0'): the frame is fixed to the world"),
             (fd.FrameContact("panda_link0"), "FrameContact('panda_link0'): the frame is fixed to the world"),
             (fd.LoopConstraint("panda_hand", "panda_hand_tcp"), "both frames are fixed to body 'panda_link7'")]
    for c, words in cases:
        for backend in ("compiled", "reference"):
            with pytest.raises(fd.ConstraintError, match=words.replace("(", r"\(").replace(")", r"\)")):
                fd.constrained_dynamics(panda, q, zero, zero, [c], backend=backend)
        with pytest.raises(fd.ConstraintError):
            fd.constraint_jacobian(panda, q, c)
    # a frame fixed to the world may close a loop with a moving one: that is a contact written as a loop
    J = fd.constraint_jacobian(panda, q, fd.LoopConstraint("panda_hand", "panda_link0"))
    np.testing.assert_allclose(J, fd.frame_jacobian(panda, q, "panda_hand", fd.LOCAL), atol=1e-12)


@pytest.mark.parametrize("ref", [fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED], ids=lambda r: r.name)
def test_contacts_in_one_core_call_equal_the_rows_built_in_python(solo: fd.Model, ref: fd.ReferenceFrame) -> None:
    """Point and frame contacts take the core's contacts.hpp (rows, drift and solve in C++): the same numbers as
    the rows built from fd.frame_jacobian / fd.frame_*acceleration and solved by the reference, one state and
    batched, with damping gains and external forces."""
    rng = np.random.default_rng(17)
    q = fd.random_configuration(solo, rng, 3)
    v, tau = rng.normal(size=(2, 3, solo.nv))
    f_ext = rng.normal(size=(3, solo.nbodies, 6))
    cons = [fd.PointContact("FL_FOOT", ref, baumgarte=(0.0, 3.0)), fd.PointContact("FR_FOOT", ref),
            fd.FrameContact("HL_FOOT", ref, baumgarte=(1.0, 0.5))]
    fast = fd.constrained_dynamics(solo, q, v, tau, cons, f_ext=f_ext)
    ref_res = fd.constrained_dynamics(solo, q, v, tau, cons, f_ext=f_ext, backend="reference")
    _close(fast.ddq, ref_res.ddq)
    _close(fast.lagrange, ref_res.lagrange)
    J = fd.constraint_jacobian(solo, q, cons)
    gamma = fd.constraint_drift(solo, q, v, cons)
    kd = np.r_[[3.0] * 3, [0.0] * 3, [0.5] * 6]
    np.testing.assert_allclose((J @ fast.ddq[..., None])[..., 0], -gamma - kd * (J @ v[..., None])[..., 0],
                               atol=1e-8 * max(1.0, float(np.abs(gamma).max())))
    for k in range(3):  # the one-state entry point
        one = fd.constrained_dynamics(solo, q[k], v[k], tau[k], cons, f_ext=f_ext[k])
        _close(one.ddq, fast.ddq[k], rtol=1e-12)
        assert [f.shape for f in one.forces] == [(3,), (3,), (6,)] and np.ndim(one.residual) == 0


def test_the_contact_entry_point_raises_the_general_path_words(solo: fd.Model) -> None:
    q, v, tau = fd.random_configuration(solo, np.random.default_rng(2)), np.zeros(solo.nv), np.zeros(solo.nv)
    cons = [fd.PointContact(f) for f in FEET]
    bad = q.copy()
    bad[7] = np.nan
    with pytest.raises(fd.errors.NonFiniteError, match="q"):
        fd.constrained_dynamics(solo, bad, v, tau, cons)
    with pytest.raises(fd.errors.ShapeError, match="tau"):
        fd.constrained_dynamics(solo, q, v, tau[:-1], cons)
    unnormalised = q.copy()
    unnormalised[3:7] *= 2
    with pytest.raises(fd.errors.QuaternionNormError):
        fd.constrained_dynamics(solo, unnormalised, v, tau, cons)


@pytest.mark.parametrize(("robot", "floating", "frames"), [("panda", False, ["panda_hand"]),
                                                           ("talos_full_v2", True, ["gripper_left_base_link",
                                                                                    "gripper_right_base_link"])])
def test_operational_space_inertia_one_state_equals_the_dense_definition(robot: str, floating: bool,
                                                                         frames: list[str]) -> None:
    """The core's one-state Λ (contacts.hpp: J M⁻¹ Jᵀ on M's factor, inverted through its Cholesky factor) against
    (J M⁻¹ Jᵀ + μ1)⁻¹ formed densely from fd.crba and fd.frame_jacobian, and against the batched path."""
    model = library_robot(robot, floating)
    assert model is not None
    rng = np.random.default_rng(4)
    Q = fd.random_configuration(model, rng, 2)
    for mu in (0.0, 1e-3):
        for ref in (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED):
            batch = fd.operational_space_inertia(model, Q, frames, ref, mu=mu)
            for k in range(2):
                one = fd.operational_space_inertia(model, Q[k], frames, ref, mu=mu)
                J = np.concatenate([fd.frame_jacobian(model, Q[k], f, ref) for f in frames])
                dense = np.linalg.inv(J @ np.linalg.solve(fd.crba(model, Q[k]), J.T) + mu * np.eye(len(J)))
                assert np.array_equal(one, one.T)
                _close(one, dense, rtol=1e-8)
                _close(one, batch[k], rtol=1e-9)


def test_a_constraint_list_changed_in_place_is_not_served_a_stale_plan(solo: fd.Model) -> None:
    """The one-state path remembers the last list of contacts by identity: replacing an item, appending or
    removing one must change the answer."""
    q, v, tau = fd.random_configuration(solo, np.random.default_rng(8)), np.zeros(solo.nv), np.zeros(solo.nv)
    cons: list[fd.Constraint] = [fd.PointContact("FL_FOOT")]
    assert [f.shape for f in fd.constrained_dynamics(solo, q, v, tau, cons).forces] == [(3,)]
    cons[0] = fd.FrameContact("FL_FOOT")
    assert [f.shape for f in fd.constrained_dynamics(solo, q, v, tau, cons).forces] == [(6,)]
    cons.append(fd.PointContact("HR_FOOT"))
    res = fd.constrained_dynamics(solo, q, v, tau, cons)
    assert [f.shape for f in res.forces] == [(6,), (3,)]
    _close(res.ddq, fd.constrained_dynamics(solo, q, v, tau, list(cons), backend="reference").ddq)
    cons.pop(0)
    assert [f.shape for f in fd.constrained_dynamics(solo, q, v, tau, cons).forces] == [(3,)]


@pytest.mark.parametrize(("kwargs", "words"), [
    ({"mu": -1.0}, "mu: expected a finite number >= 0"), ({"mu": float("nan")}, "mu: expected"),
    ({"mu": float("inf")}, "mu: expected"), ({"max_iter": 0}, "max_iter: expected an integer >= 1"),
    ({"max_iter": 2.5}, "max_iter an integer"), ({"tol": -1e-9}, "tol: expected a finite number > 0"),
    ({"tol": "small"}, "expected numbers"),
])
def test_solver_arguments_out_of_range_are_named(solo: fd.Model, kwargs: dict, words: str) -> None:
    q, zero = fd.neutral(solo), np.zeros(solo.nv)
    for backend in ("compiled", "reference"):
        with pytest.raises(fd.ConstraintError, match=words):
            fd.constrained_dynamics(solo, q, zero, zero, [fd.PointContact("FL_FOOT")], backend=backend, **kwargs)
    if "mu" in kwargs:
        with pytest.raises(fd.ConstraintError, match=words):
            fd.operational_space_inertia(solo, q, "FL_FOOT", **kwargs)
        with pytest.raises(fd.ConstraintError, match=words):
            fd.impulse_dynamics(solo, q, zero, [fd.PointContact("FL_FOOT")], **kwargs)


@pytest.mark.parametrize("scene", sorted(SCENES))
def test_closed_chains_against_the_dense_kkt(scene: str) -> None:
    """On the four-bar and the Delta robot: q̈ and λ of both backends against the dense KKT system formed from
    fd.crba, fd.nonlinear_effects and the loop rows (M q̈ − Jᵀλ = τ − h, J q̈ = −γ)."""
    model, cons, q = SCENES[scene]()
    rng = np.random.default_rng(12)
    v = _admissible_velocity(model, q, cons, seed=2)
    tau = rng.normal(size=model.nv)
    M, h = fd.crba(model, q), fd.nonlinear_effects(model, q, v)
    J, gamma = fd.constraint_jacobian(model, q, cons), fd.constraint_drift(model, q, v, cons)
    m = J.shape[0]
    K = np.block([[M, -J.T], [J, np.zeros((m, m))]])
    sol = np.linalg.solve(K, np.concatenate([tau - h, -gamma]))
    for backend in ("compiled", "reference"):
        res = fd.constrained_dynamics(model, q, v, tau, cons, backend=backend)
        _close(res.ddq, sol[: model.nv], rtol=1e-9)
        _close(res.lagrange, sol[model.nv:], rtol=1e-9)


# ---------------------------------------------------------------- the contact kernel on every tree shape


def two_trees_every_joint() -> fd.Model:
    """Two trees (a free-flying torso with two branches, a fixed planar-prismatic arm beside it), every joint type,
    frames off the body origins, and armature: what contacts.hpp's packed factor and chain-held rows must handle
    (several roots, multi-dof joints inside a chain, branches that share a prefix of the chain)."""
    b = fd.ModelBuilder("two_trees")
    rng = np.random.default_rng(3)

    def inertia(mass: float) -> fd.SpatialInertia:
        A = rng.normal(size=(3, 3))
        return fd.SpatialInertia(mass, rng.normal(scale=0.1, size=3), 0.05 * (A @ A.T) + 0.02 * np.eye(3))

    def at(p: list[float], angle: float = 0.3) -> fd.PluckerTransform:
        c, s = np.cos(angle), np.sin(angle)
        return fd.PluckerTransform(np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]), np.asarray(p, dtype=float))

    torso = b.add_body("torso", -1, fd.FreeFlyerJoint(), inertia=inertia(3.0))
    shoulder = b.add_body("shoulder", torso, fd.SphericalJoint(), placement=at([0.2, 0.1, 0.3]), inertia=inertia(1.0))
    elbow = b.add_body("elbow", shoulder, fd.RevoluteJoint([0.0, 0.6, 0.8]), placement=at([0.0, 0.0, 0.4]),
                       inertia=inertia(0.8))
    hip = b.add_body("hip", torso, fd.RevoluteJoint([1.0, 0.0, 0.0]), placement=at([-0.1, 0.0, -0.3], -0.4),
                     inertia=inertia(1.2))
    knee = b.add_body("knee", hip, fd.PrismaticJoint([0.0, 0.0, 1.0]), placement=at([0.0, 0.05, -0.4]),
                      inertia=inertia(0.9))
    cart = b.add_body("cart", -1, fd.PlanarJoint([0.0, 0.0, 1.0]), placement=at([2.0, 0.0, 0.0]),
                      inertia=inertia(2.0))
    slider = b.add_body("slider", cart, fd.PrismaticJoint([0.0, 0.0, 1.0]), placement=at([0.1, 0.2, 0.0]),
                        inertia=inertia(0.5))
    b.add_frame("hand", elbow, at([0.1, -0.05, 0.3], 0.7))
    b.add_frame("foot", knee, at([0.02, 0.0, -0.1], -0.2))
    b.add_frame("torso_point", torso, at([0.0, 0.2, 0.0]))
    wrist = b.add_body("wrist", slider, fd.SphericalJoint(), placement=at([0.2, 0.0, 0.1]), inertia=inertia(0.4))
    b.add_frame("tool", wrist, at([0.3, 0.0, 0.05], 1.1))
    model = b.build()
    return dataclasses.replace(model, armature=np.linspace(0.0, 0.3, model.nv))


@pytest.mark.parametrize("ref", [fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED], ids=lambda r: r.name)
@pytest.mark.parametrize("mu", [0.0, 1e-6])
def test_the_contact_kernel_on_two_trees_with_every_joint_equals_the_reference(ref: fd.ReferenceFrame,
                                                                               mu: float) -> None:
    """contacts.hpp (one pass, M packed along the dof chains, rows kept on their chains) against the reference
    backend's rows and solve, one state and batched, with f_ext, damping gains and armature; and Λ at a frame
    of each tree against (J M⁻¹ Jᵀ)⁻¹ from fd.crba and fd.frame_jacobian."""
    model = two_trees_every_joint()
    rng = np.random.default_rng(21)
    q = fd.random_configuration(model, rng, 3)
    v, tau = rng.normal(size=(2, 3, model.nv))
    f_ext = rng.normal(size=(3, model.nbodies, 6))
    cons = [fd.PointContact("hand", ref, baumgarte=(0.0, 2.0)), fd.PointContact("foot", ref),
            fd.PointContact("torso_point", ref, baumgarte=(1.0, 0.5)), fd.FrameContact("tool", ref)]
    if ref is fd.WORLD:  # in WORLD a point contact's rows move the body point at the world origin: on one tree,
        del cons[2]      # three of them are dependent (rank 8 of 9)
    batch = fd.constrained_dynamics(model, q, v, tau, cons, f_ext=f_ext, mu=mu)
    ref_res = fd.constrained_dynamics(model, q, v, tau, cons, f_ext=f_ext, mu=mu, backend="reference")
    _close(batch.ddq, ref_res.ddq)
    _close(batch.lagrange, ref_res.lagrange)
    for k in range(3):
        one = fd.constrained_dynamics(model, q[k], v[k], tau[k], cons, f_ext=f_ext[k], mu=mu)
        _close(one.ddq, ref_res.ddq[k])
        _close(one.lagrange, ref_res.lagrange[k])
        assert one.residual < 1e-9
        # Λ eliminates the dofs off the frames' chains by articulated inertias: off the hand's chain the hip and
        # knee (one dof each), off the foot's the spherical shoulder and the elbow (a multi-dof joint)
        for frames in (["hand", "tool"], ["foot", "tool"]):
            J = np.concatenate([fd.frame_jacobian(model, q[k], f, ref) for f in frames])
            dense = np.linalg.inv(J @ np.linalg.solve(fd.crba(model, q[k]), J.T) + mu * np.eye(12))
            _close(fd.operational_space_inertia(model, q[k], frames, ref, mu=mu), dense, rtol=1e-8)


def test_a_list_with_an_array_where_a_constraint_belongs_is_named_after_a_cached_plan(solo: fd.Model) -> None:
    """The remembered plan compares the new list with the last one item by item; an array in it (whose == is
    elementwise) must still reach the general path's words, not a NumPy truth-value error."""
    q, zero = fd.neutral(solo), np.zeros(solo.nv)
    cons: list[object] = [fd.PointContact("FL_FOOT"), fd.PointContact("FR_FOOT")]
    fd.constrained_dynamics(solo, q, zero, zero, cons)  # type: ignore[arg-type]
    cons[1] = np.zeros(3)
    with pytest.raises(fd.ModelError, match=r"expected fd\.PointContact"):
        fd.constrained_dynamics(solo, q, zero, zero, cons)  # type: ignore[arg-type]
    q = fd.random_configuration(solo, np.random.default_rng(6))
    fd.operational_space_inertia(solo, q, ["FL_FOOT", "FR_FOOT"])
    with pytest.raises((fd.FeatherdynError, TypeError)):
        fd.operational_space_inertia(solo, q, ["FL_FOOT", np.zeros(2)])  # type: ignore[list-item]
