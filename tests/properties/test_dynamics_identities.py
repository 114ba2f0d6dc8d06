"""Identities that the dynamics must satisfy, with no oracle: one algorithm checked against another.

Random trees and states come from ``_models`` (every joint type, fixed and
floating base, chains and branches); hypothesis draws the tree and the seed of
the state (deterministic profile). Sources: RBDA (2008) ch. 5–7; chapter §8;
Pinocchio's own consistency tests (a CRBA column is an RNEA difference).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from _models import TREES, State, integrate, random_state, random_tree, tree
from hypothesis import given, settings
from hypothesis import strategies as st

import featherdyn as fd
from featherdyn.testing import assert_close

PROPERTY = settings(derandomize=True, deadline=None, max_examples=25)
_TREE_NAMES = [s.name for s in TREES]
trees = st.sampled_from(_TREE_NAMES)
seeds = st.integers(0, 2**31 - 1)
REFERENCES = (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED)

#: step of the central finite differences along q(t) = q ⊕ t·v: truncation ~h²·|x'''| ≈ 1e-10,
#: rounding ~eps·|x|/h ≈ 1e-11 for unit-size quantities, so 1e-7 (times the scale) is a safe bound
FD_STEP = 1e-5
FD_TOL = 1e-7


def _scale(*xs: Any) -> float:
    return max(1.0, *(float(np.max(np.abs(x), initial=0.0)) for x in xs))


def _deepest_tool(model: fd.Model) -> str:
    """The tool frame of the last body (the longest support in a chain; a random placement)."""
    return f"{model.body_names[-1]}_tool"


def _along_motion(model: fd.Model, q: np.ndarray, v: np.ndarray, fn: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """``d/dt fn(q(t))`` at ``t = 0`` for ``q(t) = q ⊕ t v``, by a central difference."""
    plus = fn(integrate(model, q, FD_STEP * v))
    minus = fn(integrate(model, q, -FD_STEP * v))
    return (plus - minus) / (2 * FD_STEP)


# ---------------------------------------------------------------------------------------------------------------
# mass matrix
# ---------------------------------------------------------------------------------------------------------------


@PROPERTY
@given(name=trees, seed=seeds)
def test_crba_columns_are_rnea_differences(name: str, seed: int) -> None:
    """``M[:, j] = rnea(q, 0, e_j) − rnea(q, 0, 0)`` (gravity off, and gravity on where it cancels)."""
    m = tree(name)
    s = random_state(m, seed)
    M = fd.crba(m, s.q)
    E = np.eye(m.nv)  # a batch of nv accelerations, q broadcast against it
    zero = np.zeros(m.nv)
    rows = fd.rnea(m, s.q, zero, E, gravity=False) - fd.rnea(m, s.q, zero, zero, gravity=False)
    assert_close(M, rows.T, "crba vs rnea columns (gravity off)", where=name, scale=_scale(M))
    rows_g = fd.rnea(m, s.q, zero, E) - fd.rnea(m, s.q, zero, zero)
    assert_close(M, rows_g.T, "crba vs rnea columns (gravity on)", where=name, scale=_scale(M))


@PROPERTY
@given(name=trees, seed=seeds)
def test_mass_matrix_is_symmetric_positive_definite(name: str, seed: int) -> None:
    m = tree(name)
    M = fd.crba(m, random_state(m, seed).q)
    assert_close(M, M.T, "M − Mᵀ", where=name, scale=_scale(M))
    eig = np.linalg.eigvalsh(M)
    assert eig[0] > 1e-9 * eig[-1], f"{name}: M not positive definite, eigenvalues {eig}"
    np.linalg.cholesky(M)


@PROPERTY
@given(name=trees, seed=seeds)
def test_kinetic_energy_is_half_vMv(name: str, seed: int) -> None:
    m = tree(name)
    s = random_state(m, seed)
    M = fd.crba(m, s.q)
    T = fd.kinetic_energy(m, s.q, s.v)
    assert_close(T, 0.5 * s.v @ M @ s.v, "kinetic energy vs ½ vᵀMv", where=name, scale=_scale(M) * (s.v @ s.v))
    assert T > 0


# ---------------------------------------------------------------------------------------------------------------
# equations of motion
# ---------------------------------------------------------------------------------------------------------------


@PROPERTY
@given(name=trees, seed=seeds)
def test_rnea_is_M_a_plus_nle(name: str, seed: int) -> None:
    m = tree(name)
    s = random_state(m, seed)
    tau = fd.rnea(m, s.q, s.v, s.a)
    expected = fd.crba(m, s.q) @ s.a + fd.nonlinear_effects(m, s.q, s.v)
    assert_close(tau, expected, "rnea vs M a + h", where=name, scale=_scale(tau))


@PROPERTY
@given(name=trees, seed=seeds)
def test_nle_is_C_v_plus_g(name: str, seed: int) -> None:
    m = tree(name)
    s = random_state(m, seed)
    h = fd.nonlinear_effects(m, s.q, s.v)
    C = fd.coriolis_matrix(m, s.q, s.v)
    g = fd.generalized_gravity(m, s.q)
    assert_close(h, C @ s.v + g, "nle vs C v + g", where=name, scale=_scale(h, g))
    assert_close(g, fd.rnea(m, s.q, np.zeros(m.nv), np.zeros(m.nv)), "g vs rnea(q, 0, 0)", where=name, scale=_scale(g))


@PROPERTY
@given(name=trees, seed=seeds)
def test_aba_and_rnea_are_inverse(name: str, seed: int) -> None:
    m = tree(name)
    s = random_state(m, seed)
    ddq = fd.aba(m, s.q, s.v, s.tau)
    assert_close(fd.rnea(m, s.q, s.v, ddq), s.tau, "rnea(aba(τ)) vs τ", where=name, scale=_scale(s.tau), atol=1e-9)
    tau = fd.rnea(m, s.q, s.v, s.a)
    assert_close(fd.aba(m, s.q, s.v, tau), s.a, "aba(rnea(a)) vs a", where=name, scale=_scale(s.a), atol=1e-9)
    # with external forces on every body
    tau_f = fd.rnea(m, s.q, s.v, s.a, s.f_ext)
    assert_close(fd.aba(m, s.q, s.v, tau_f, s.f_ext), s.a, "aba(rnea(a, f), f) vs a", where=name,
                 scale=_scale(s.a), atol=1e-9)
    # and ABA solves M q̈ = τ − h
    M, h = fd.crba(m, s.q), fd.nonlinear_effects(m, s.q, s.v)
    assert_close(ddq, np.linalg.solve(M, s.tau - h), "aba vs M⁻¹(τ − h)", where=name, scale=_scale(ddq), atol=1e-9)


@PROPERTY
@given(name=trees, seed=seeds)
def test_Mdot_minus_2C_is_skew_symmetric(name: str, seed: int) -> None:
    """``Ṁ − 2C`` skew, with ``Ṁ = d/dt M(q ⊕ t v)`` by central differences; also ``Ṁ = C + Cᵀ``."""
    m = tree(name)
    s = random_state(m, seed)
    C = fd.coriolis_matrix(m, s.q, s.v)
    Mdot = _along_motion(m, s.q, s.v, lambda q: fd.crba(m, q))
    N = Mdot - 2 * C
    scale = _scale(Mdot, C)
    assert_close(N, -N.T, "Ṁ − 2C skew-symmetry", where=name, scale=scale, atol=FD_TOL)
    assert_close(C + C.T, Mdot, "C + Cᵀ vs Ṁ", where=name, scale=scale, atol=FD_TOL)
    assert np.abs(Mdot).max() > 1e-3  # the motion does change M: the identity is not 0 = 0


@PROPERTY
@given(name=trees, seed=seeds)
def test_external_forces_enter_through_the_jacobian_transpose(name: str, seed: int) -> None:
    """Power invariance: ``rnea(q, v, a, f) = rnea(q, v, a) − Σ_i J_iᵀ f_i`` (body frames, and in world frame)."""
    m = tree(name)
    s = random_state(m, seed)
    tau0 = fd.rnea(m, s.q, s.v, s.a)
    tau_f = fd.rnea(m, s.q, s.v, s.a, s.f_ext)
    kin = fd.forward_kinematics(m, s.q)
    local = np.zeros(m.nv)
    world = np.zeros(m.nv)
    for i, body in enumerate(m.body_names):
        f_i = s.f_ext[i]
        local += fd.frame_jacobian(m, s.q, body, fd.LOCAL).T @ f_i
        f_world = kin.placements[i].apply(fd.SpatialForce.from_vector(f_i)).vector  # ⁰X_i^* f_i
        world += fd.frame_jacobian(m, s.q, body, fd.WORLD).T @ f_world
    scale = _scale(tau0, tau_f)
    assert_close(tau_f, tau0 - local, "rnea(f) vs rnea − Σ ᶦJᵀ f (LOCAL)", where=name, scale=scale)
    assert_close(tau_f, tau0 - world, "rnea(f) vs rnea − Σ ⁰Jᵀ ⁰f (WORLD)", where=name, scale=scale)
    # the power of the forces is the same in every frame: Σ f_i · v_i = τ_f-part · v
    v_bodies = fd.forward_kinematics(m, s.q, s.v).velocities.vector
    power = sum(float(f @ v) for f, v in zip(s.f_ext, v_bodies, strict=True))
    assert_close(local @ s.v, power, "Σ (Jᵀf)·q̇ vs Σ f·v", where=name, scale=scale * _scale(s.v))


# ---------------------------------------------------------------------------------------------------------------
# Jacobians
# ---------------------------------------------------------------------------------------------------------------


@PROPERTY
@given(name=trees, seed=seeds)
def test_jacobian_times_v_is_frame_velocity(name: str, seed: int) -> None:
    m = tree(name)
    s = random_state(m, seed)
    for frame in (_deepest_tool(m), m.body_names[-1], "world_marker"):
        for ref in REFERENCES:
            J = fd.frame_jacobian(m, s.q, frame, ref)
            vf = fd.frame_velocity(m, s.q, s.v, frame, ref).vector
            assert_close(J @ s.v, vf, f"J v vs frame velocity {ref.name}", where=f"{name}, {frame}", scale=_scale(vf))


@PROPERTY
@given(name=trees, seed=seeds)
def test_accelerations_are_J_a_plus_Jdot_v(name: str, seed: int) -> None:
    """Spatial acceleration = J q̈ + J̇ q̇ in LOCAL and WORLD; classical acceleration in LOCAL_WORLD_ALIGNED."""
    m = tree(name)
    s = random_state(m, seed)
    frame = _deepest_tool(m)
    for ref, fn in ((fd.LOCAL, fd.frame_acceleration), (fd.WORLD, fd.frame_acceleration),
                    (fd.LOCAL_WORLD_ALIGNED, fd.frame_classical_acceleration)):
        J = fd.frame_jacobian(m, s.q, frame, ref)
        dJ = fd.frame_jacobian_time_variation(m, s.q, s.v, frame, ref)
        acc = fn(m, s.q, s.v, s.a, frame, ref).vector
        assert_close(J @ s.a + dJ @ s.v, acc, f"J a + J̇ v vs {fn.__name__} {ref.name}", where=name, scale=_scale(acc))
    # the classical and spatial accelerations differ by ω × v: the check above is not vacuous
    spatial = fd.frame_acceleration(m, s.q, s.v, s.a, frame, fd.LOCAL_WORLD_ALIGNED).vector
    classical = fd.frame_classical_acceleration(m, s.q, s.v, s.a, frame, fd.LOCAL_WORLD_ALIGNED).vector
    assert np.abs(spatial - classical).max() > 1e-6


@PROPERTY
@given(name=trees, seed=seeds)
def test_jacobian_time_variation_is_the_derivative_of_the_jacobian(name: str, seed: int) -> None:
    m = tree(name)
    s = random_state(m, seed)
    frame = _deepest_tool(m)
    for ref in REFERENCES:
        dJ = fd.frame_jacobian_time_variation(m, s.q, s.v, frame, ref)
        dJ_fd = _along_motion(m, s.q, s.v, lambda q, ref=ref: fd.frame_jacobian(m, q, frame, ref))
        assert_close(dJ, dJ_fd, f"J̇ vs finite-difference dJ/dt {ref.name}", where=name, scale=_scale(dJ),
                     atol=FD_TOL)


# ---------------------------------------------------------------------------------------------------------------
# centre of mass and momentum
# ---------------------------------------------------------------------------------------------------------------


@PROPERTY
@given(name=trees, seed=seeds)
def test_centroidal_linear_momentum_is_mass_times_com_velocity(name: str, seed: int) -> None:
    m = tree(name)
    s = random_state(m, seed)
    h = fd.centroidal_momentum(m, s.q, s.v)
    com = fd.center_of_mass(m, s.q, s.v)
    assert_close(h.linear, m.total_mass * com.velocity, "p vs m ċ", where=name, scale=_scale(h.linear))
    # ċ is the time derivative of c along the motion
    c_dot = _along_motion(m, s.q, s.v, lambda q: fd.center_of_mass(m, q))
    assert_close(com.velocity, c_dot, "ċ vs d/dt c", where=name, scale=_scale(c_dot), atol=FD_TOL)
    # the angular part: the sum of the body momenta, moved to the CoM
    kin = fd.forward_kinematics(m, s.q, s.v)
    total = np.zeros(6)
    for i in range(m.nbodies):
        I_i = m.inertias[i]
        h_body = (I_i @ fd.SpatialMotion.from_vector(kin.velocities.vector[i]))
        total += kin.placements[i].apply(h_body).vector  # about the world origin, world axes
    k_G = total[:3] - np.cross(com.position, total[3:])
    assert_close(h.angular, k_G, "k_G vs Σ momenta about the CoM", where=name, scale=_scale(k_G))


# ---------------------------------------------------------------------------------------------------------------
# energy balance along a simulated motion
# ---------------------------------------------------------------------------------------------------------------


def _rk4_energy_error(model: fd.Model, q0: np.ndarray, v0: np.ndarray, tau: np.ndarray, dt: float,
                      steps: int) -> tuple[float, float]:
    """Simulate ``q̈ = aba(q, q̇, τ)`` with RK4, carrying the work ``W = ∫ q̇ᵀτ dt`` as an extra state.

    Returns ``(ΔE − W, W)`` with ``E = T + U``. Only for vector-space joints (q̇ = v).
    """

    def f(x: np.ndarray) -> np.ndarray:
        q, v = x[: model.nq], x[model.nq : model.nq + model.nv]
        return np.concatenate([v, fd.aba(model, q, v, tau), [v @ tau]])

    def energy(x: np.ndarray) -> float:
        q, v = x[: model.nq], x[model.nq : model.nq + model.nv]
        return float(fd.kinetic_energy(model, q, v) + fd.potential_energy(model, q))

    x = np.concatenate([q0, v0, [0.0]])
    E0 = energy(x)
    for _ in range(steps):
        k1 = f(x)
        k2 = f(x + dt / 2 * k1)
        k3 = f(x + dt / 2 * k2)
        k4 = f(x + dt * k3)
        x = x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return energy(x) - E0 - x[-1], x[-1]


@pytest.mark.parametrize("name", ["revolute_chain", "prismatic_revolute_branch"])
def test_power_balance_along_a_simulation(name: str) -> None:
    """``d(T + U)/dt = q̇ᵀτ``: over 0.1 s the energy change equals the work of τ.

    RK4's global error is O(dt⁴). Measured on these trees: |ΔE − W| ≈ 1e-8 at
    dt = 5 ms and ≈ 6e-10 at 2.5 ms for a work of ~1 J, so the bounds below
    (1e-7 and 1e-8 of the energy scale) leave a 10× margin; halving dt must
    shrink the discrepancy ≥ 8× (the O(dt⁴) signature of integration error —
    a wrong term in ABA, the energies or the gravity sign gives an O(1)
    discrepancy that does not shrink).
    """
    # joints with q̇ = v only (revolute, prismatic), so RK4 can integrate q directly
    m = tree(name) if name in _TREE_NAMES else random_tree(21, 5, root="prismatic", kinds=("revolute", "prismatic"))
    s = random_state(m, 7)
    tau = s.tau
    err1, work = _rk4_energy_error(m, s.q, s.v, tau, 5e-3, 20)
    err2, _ = _rk4_energy_error(m, s.q, s.v, tau, 2.5e-3, 40)
    E_scale = max(1.0, abs(work), float(fd.kinetic_energy(m, s.q, s.v)))
    assert abs(work) > 1e-2, "τ must do work for the balance to mean something"
    assert abs(err1) < 1e-7 * E_scale, f"{name}: ΔE − W = {err1:.3g} (dt = 5 ms)"
    assert abs(err2) < 1e-8 * E_scale, f"{name}: ΔE − W = {err2:.3g} (dt = 2.5 ms)"
    assert abs(err2) < abs(err1) / 8, f"{name}: not O(dt⁴): {err1:.3g} → {err2:.3g}"


# ---------------------------------------------------------------------------------------------------------------
# batch == loop, float32
# ---------------------------------------------------------------------------------------------------------------


def _frame_refs(fn: Callable[..., Any]) -> Callable[..., Any]:
    return lambda *args: tuple(_arr(fn(*args, ref)) for ref in REFERENCES)


def _arr(x: Any) -> Any:
    if isinstance(x, fd.PluckerTransform):
        return x.homogeneous()
    if isinstance(x, (fd.SpatialMotion, fd.SpatialForce)):
        return x.vector
    if isinstance(x, fd.CenterOfMass):
        return (x.position, x.velocity)
    if isinstance(x, fd.Kinematics):
        return (x.placements.homogeneous(), x.velocities.vector, x.accelerations.vector)
    return x


TOOL = "b8_tool"  # on the last body of free_branch
FUNCTIONS: dict[str, Callable[[fd.Model, State], Any]] = {
    "forward_kinematics": lambda m, s: fd.forward_kinematics(m, s.q, s.v, s.a),
    "rnea": lambda m, s: fd.rnea(m, s.q, s.v, s.a),
    "rnea_f_ext": lambda m, s: fd.rnea(m, s.q, s.v, s.a, s.f_ext),
    "rnea_no_gravity": lambda m, s: fd.rnea(m, s.q, s.v, s.a, gravity=False),
    "crba": lambda m, s: fd.crba(m, s.q),
    "aba": lambda m, s: fd.aba(m, s.q, s.v, s.tau),
    "aba_f_ext": lambda m, s: fd.aba(m, s.q, s.v, s.tau, s.f_ext),
    "nonlinear_effects": lambda m, s: fd.nonlinear_effects(m, s.q, s.v),
    "generalized_gravity": lambda m, s: fd.generalized_gravity(m, s.q),
    "coriolis_matrix": lambda m, s: fd.coriolis_matrix(m, s.q, s.v),
    "joint_jacobians": lambda m, s: fd.joint_jacobians(m, s.q),
    "frame_placement": lambda m, s: fd.frame_placement(m, s.q, TOOL),
    "frame_velocity": lambda m, s: _frame_refs(fd.frame_velocity)(m, s.q, s.v, TOOL),
    "frame_acceleration": lambda m, s: _frame_refs(fd.frame_acceleration)(m, s.q, s.v, s.a, TOOL),
    "frame_classical_acceleration": lambda m, s: _frame_refs(fd.frame_classical_acceleration)(m, s.q, s.v, s.a, TOOL),
    "frame_jacobian": lambda m, s: _frame_refs(fd.frame_jacobian)(m, s.q, TOOL),
    "frame_jacobian_time_variation": lambda m, s: _frame_refs(fd.frame_jacobian_time_variation)(m, s.q, s.v, TOOL),
    "kinetic_energy": lambda m, s: fd.kinetic_energy(m, s.q, s.v),
    "potential_energy": lambda m, s: fd.potential_energy(m, s.q),
    "center_of_mass": lambda m, s: fd.center_of_mass(m, s.q),
    "center_of_mass_v": lambda m, s: fd.center_of_mass(m, s.q, s.v),
    "centroidal_momentum_matrix": lambda m, s: fd.centroidal_momentum_matrix(m, s.q),
    "centroidal_momentum": lambda m, s: fd.centroidal_momentum(m, s.q, s.v),
}


def _flat(x: Any) -> list[np.ndarray]:
    x = _arr(x)
    if isinstance(x, tuple):
        return [a for item in x for a in _flat(item)]
    return [np.asarray(x)]


def _index(s: State, idx: tuple[int, ...]) -> State:
    return State(s.q[idx], s.v[idx], s.a[idx], s.tau[idx], s.f_ext[idx], s.w[idx])


@pytest.mark.parametrize("batch", [(3,), (2, 2)], ids=["batch3", "batch2x2"])
@pytest.mark.parametrize("fn_name", list(FUNCTIONS))
def test_batch_equals_loop(fn_name: str, batch: tuple[int, ...]) -> None:
    m = tree("free_branch")
    fn = FUNCTIONS[fn_name]
    s = random_state(m, 99, size=batch)
    batched = _flat(fn(m, s))
    for idx in np.ndindex(*batch):
        single = _flat(fn(m, _index(s, idx)))
        assert len(single) == len(batched)
        for k, (b, one) in enumerate(zip(batched, single, strict=True)):
            assert b.shape == batch + one.shape, f"{fn_name}[{k}]: batched shape {b.shape}, single {one.shape}"
            assert_close(b[idx], one, f"{fn_name}[{k}] batch vs loop", where=f"index {idx}", scale=_scale(one))


def test_batch_axes_broadcast_between_arguments() -> None:
    """``q`` `(3, nq)` with ``v`` `(nv,)` and ``a`` `(2, 1, nv)` gives a `(2, 3)` batch."""
    m = tree("free_branch")
    s = random_state(m, 5, size=(3,))
    a = np.random.default_rng(5).normal(size=(2, 1, m.nv))
    tau = fd.rnea(m, s.q, s.v[0], a)
    assert tau.shape == (2, 3, m.nv)
    for i, j in np.ndindex(2, 3):
        assert_close(tau[i, j], fd.rnea(m, s.q[j], s.v[0], a[i, 0]), "rnea broadcast", where=f"index {(i, j)}",
                     scale=_scale(tau))
    ddq = fd.aba(m, s.q, s.v[0], tau)
    assert_close(ddq, np.broadcast_to(a, ddq.shape), "aba broadcast", scale=_scale(a), atol=1e-9)


@pytest.mark.parametrize("fn_name", list(FUNCTIONS))
def test_float32_stays_float32_and_is_close_to_float64(fn_name: str) -> None:
    m = tree("free_branch")
    fn = FUNCTIONS[fn_name]
    s64 = random_state(m, 123)
    s32 = State(*(x.astype(np.float32) for x in (s64.q, s64.v, s64.a, s64.tau, s64.f_ext, s64.w)))
    out64, out32 = _flat(fn(m, s64)), _flat(fn(m, s32))
    for k, (a, b) in enumerate(zip(out32, out64, strict=True)):
        assert a.dtype == np.float32, f"{fn_name}[{k}]: float32 input gave {a.dtype}"
        assert b.dtype == np.float64, f"{fn_name}[{k}]: float64 input gave {b.dtype}"
        assert_close(a, b, f"{fn_name}[{k}] float32 vs float64", scale=_scale(b))
