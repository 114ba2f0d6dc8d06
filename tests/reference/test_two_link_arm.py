"""The chapter's appendix-D 2R arm: closed-form Lagrangian dynamics, the D.3 numbers, and a SymPy run.

Parameters (chapter D.1): l₁ = 1.0 m, m₁ = 3.0 kg, COM at 0.5 m, I_zz = 0.25 kg·m²;
l₂ = 0.8 m, m₂ = 2.0 kg, COM at 0.4 m, I_zz = 0.11 kg·m² (about the COMs);
state q = (30°, 45°), q̇ = (2, −1), q̈ = (0.5, −0.3).

The arm is built three ways with :class:`featherdyn.ModelBuilder`; body frames
sit on the joint axes (featherdyn's and Pinocchio's convention), links along
their body x axes, joint 2 at ``(l₁, 0, 0)`` in link 1:

* ``"vertical_xy"``: joints about z, arm in the xy plane, gravity −9.81 ŷ. This
  is the chapter's D.3 set-up: its planar base acceleration
  ``a₀ = (0; 0, 9.81)`` in ``(ω_z; v_x, v_y)`` is −g with g along −y.
* ``"vertical_xz"``: joints about y, arm in the xz plane, the default gravity
  −9.81 ẑ (a rotation about y by q takes x̂ to (cos q, 0, −sin q), so raising
  the arm means q < 0 and the gravity torque changes sign).
* ``"horizontal"``: joints about z, arm in the xy plane, gravity −9.81 ẑ along
  the joint axes: no gravity torque at all.

Closed form (standard 2R, derived from the Lagrangian; s₂ = sin q₂, c₁₂ = cos(q₁ + q₂))::

    M₁₁ = I₁ + I₂ + m₁ lc₁² + m₂ (l₁² + lc₂² + 2 l₁ lc₂ c₂)
    M₁₂ = I₂ + m₂ (lc₂² + l₁ lc₂ c₂),      M₂₂ = I₂ + m₂ lc₂²
    h   = −m₂ l₁ lc₂ s₂
    C q̇ = (h (2 q̇₁ q̇₂ + q̇₂²),  −h q̇₁²),   C = [[h q̇₂, h (q̇₁ + q̇₂)], [−h q̇₁, 0]]   (Christoffel)
    g(q) = σ g ((m₁ lc₁ + m₂ l₁) c₁ + m₂ lc₂ c₁₂,  m₂ lc₂ c₁₂),   σ = +1, −1, 0 for the three set-ups
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.testing import assert_close

L1, M1, LC1, IZZ1 = 1.0, 3.0, 0.5, 0.25
L2, M2, LC2, IZZ2 = 0.8, 2.0, 0.4, 0.11
G = 9.81
Q = np.deg2rad([30.0, 45.0])
QD = np.array([2.0, -1.0])
QDD = np.array([0.5, -0.3])

#: axis of the joints, gravity, and the sign σ of the gravity torque, per set-up
SETUPS: dict[str, tuple[list[float], tuple[float, float, float], float]] = {
    "vertical_xy": ([0.0, 0.0, 1.0], (0.0, -G, 0.0), 1.0),
    "vertical_xz": ([0.0, 1.0, 0.0], (0.0, 0.0, -G), -1.0),
    "horizontal": ([0.0, 0.0, 1.0], (0.0, 0.0, -G), 0.0),
}


def two_link_arm(setup: str) -> fd.Model:
    """The 2R arm in one of :data:`SETUPS` (the off-axis moments of inertia are arbitrary: they must not matter)."""
    axis, gravity, _ = SETUPS[setup]
    k = int(np.argmax(axis))  # the inertia entry about the joint axis

    def inertia(mass: float, lc: float, izz: float) -> fd.SpatialInertia:
        diag = [0.02, 0.03, 0.04]
        diag[k] = izz
        return fd.SpatialInertia(mass, [lc, 0.0, 0.0], np.diag(diag))

    b = fd.ModelBuilder(f"2R {setup}", gravity=gravity)
    link1 = b.add_body("link1", -1, fd.RevoluteJoint(axis), inertia=inertia(M1, LC1, IZZ1), joint_name="joint1")
    b.add_body("link2", link1, fd.RevoluteJoint(axis), placement=fd.PluckerTransform(np.eye(3), [L1, 0.0, 0.0]),
               inertia=inertia(M2, LC2, IZZ2), joint_name="joint2")
    b.add_frame("link1_tip", link1, fd.PluckerTransform(np.eye(3), [L1, 0.0, 0.0]))
    b.add_frame("link2_tip", 1, fd.PluckerTransform(np.eye(3), [L2, 0.0, 0.0]))
    return b.build()


def closed_form(q: np.ndarray, qd: np.ndarray, sigma: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(M, C q̇, C, g)`` of the module docstring."""
    c1, c2, s2, c12 = np.cos(q[0]), np.cos(q[1]), np.sin(q[1]), np.cos(q[0] + q[1])
    M11 = IZZ1 + IZZ2 + M1 * LC1**2 + M2 * (L1**2 + LC2**2 + 2 * L1 * LC2 * c2)
    M12 = IZZ2 + M2 * (LC2**2 + L1 * LC2 * c2)
    M22 = IZZ2 + M2 * LC2**2
    h = -M2 * L1 * LC2 * s2
    Cqd = np.array([h * (2 * qd[0] * qd[1] + qd[1] ** 2), -h * qd[0] ** 2])
    C = np.array([[h * qd[1], h * (qd[0] + qd[1])], [-h * qd[0], 0.0]])
    g = sigma * G * np.array([(M1 * LC1 + M2 * L1) * c1 + M2 * LC2 * c12, M2 * LC2 * c12])
    return np.array([[M11, M12], [M12, M22]]), Cqd, C, g


def _states() -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    rng = np.random.default_rng(2024)
    return [(Q, QD, QDD)] + [tuple(rng.uniform(-3, 3, (3, 2))) for _ in range(5)]  # type: ignore[misc]


STATES = _states()


@pytest.mark.parametrize("setup", list(SETUPS))
@pytest.mark.parametrize("k", range(len(STATES)), ids=["chapter"] + [f"random{k}" for k in range(1, len(STATES))])
def test_dynamics_match_the_closed_form(setup: str, k: int) -> None:
    m = two_link_arm(setup)
    q, qd, qdd = STATES[k]
    M, Cqd, C, g = closed_form(q, qd, SETUPS[setup][2])
    where = f"{setup}, state {k}"
    assert_close(fd.crba(m, q), M, "M(q)", where=where)
    assert_close(fd.generalized_gravity(m, q), g, "g(q)", where=where, scale=G)
    assert_close(fd.nonlinear_effects(m, q, qd), Cqd + g, "C(q, q̇) q̇ + g(q)", where=where, scale=G)
    assert_close(fd.coriolis_matrix(m, q, qd), C, "C(q, q̇) (Christoffel)", where=where)
    tau = M @ qdd + Cqd + g
    assert_close(fd.rnea(m, q, qd, qdd), tau, "τ", where=where, scale=G)
    assert_close(fd.aba(m, q, qd, tau), qdd, "q̈ = aba(τ)", where=where)
    assert_close(fd.kinetic_energy(m, q, qd), 0.5 * qd @ M @ qd, "T", where=where)


@pytest.mark.parametrize("setup", list(SETUPS))
def test_potential_energy_closed_form(setup: str) -> None:
    """U = σ g (m₁ lc₁ s₁ + m₂ (l₁ s₁ + lc₂ s₁₂)), and ∂U/∂q = g(q)."""
    m = two_link_arm(setup)
    sigma = SETUPS[setup][2]
    for q, _, _ in STATES:
        s1, s12 = np.sin(q[0]), np.sin(q[0] + q[1])
        U = sigma * G * (M1 * LC1 * s1 + M2 * (L1 * s1 + LC2 * s12))
        assert_close(fd.potential_energy(m, q), U, "U(q)", where=setup, scale=G)
        h = 1e-6
        dU = [(fd.potential_energy(m, q + h * e) - fd.potential_energy(m, q - h * e)) / (2 * h) for e in np.eye(2)]
        assert_close(dU, fd.generalized_gravity(m, q), "∂U/∂q vs g(q)", where=setup, scale=G, atol=1e-8)


def test_chapter_torques_in_the_vertical_plane() -> None:
    """The chapter's D.5 prints τ for its state but never gives the numbers; these are they.

    Computed here from the closed form (independently of featherdyn): with
    gravity −9.81 ŷ in the arm's plane, τ ≈ (35.445, 4.663) N·m; without
    gravity (or with gravity along the joint axes) τ ≈ (3.679, 2.632) N·m.
    """
    M, Cqd, _, g = closed_form(Q, QD, 1.0)
    tau_vertical = M @ QDD + Cqd + g
    tau_horizontal = M @ QDD + Cqd
    assert_close(fd.rnea(two_link_arm("vertical_xy"), Q, QD, QDD), tau_vertical, "τ vertical_xy", scale=G)
    assert_close(fd.rnea(two_link_arm("horizontal"), Q, QD, QDD), tau_horizontal, "τ horizontal")
    np.testing.assert_allclose(tau_vertical, [35.4452, 4.6628], atol=5e-4)
    np.testing.assert_allclose(tau_horizontal, [3.6790, 2.6316], atol=5e-4)


# ---------------------------------------------------------------------------------------------------------------
# the chapter's D.3 intermediate numbers (planar reduction: (ω_z; v_x, v_y) = entries 2, 3, 4 of [ω; v])
# ---------------------------------------------------------------------------------------------------------------

PLANAR = [2, 3, 4]


def _planar(x: Any) -> np.ndarray:
    return np.asarray(getattr(x, "vector", x))[..., PLANAR]


def test_chapter_D3_velocity_of_link1() -> None:
    """v₁ = ¹X₀·0 + S₁ q̇₁ = (2; 0, 0) — true with the body frame on joint 1's axis."""
    kin = fd.forward_kinematics(two_link_arm("vertical_xy"), Q, QD, QDD)
    assert_close(_planar(kin.velocities.vector[0]), [2.0, 0.0, 0.0], "v₁")
    np.testing.assert_array_equal(kin.velocities.vector[0][[0, 1, 5]], 0.0)  # the motion stays in the plane


def test_chapter_D2_frame_origin_claim_contradicts_D3() -> None:
    """D.2 says link 1's frame origin is at joint 2 (link 1's tip); D.3 then uses v₁ = (2; 0, 0).

    A frame with its origin at joint 2 moves with v = ω × l₁ x̂ = (0, 2): its
    planar velocity is (2; 0, 2), not (2; 0, 0). D.3's numbers (and its ²X₁
    with the translation l₁) hold for a frame on joint 1's axis.
    """
    m = two_link_arm("vertical_xy")
    tip = fd.frame_velocity(m, Q, QD, "link1_tip", fd.LOCAL)
    assert_close(_planar(tip), [2.0, 0.0, L1 * QD[0]], "velocity of a link-1 frame at joint 2")
    assert np.abs(_planar(tip) - [2.0, 0.0, 0.0]).max() > 1.0


def test_chapter_D3_gravity_term_of_link1() -> None:
    """¹X₀ a₀ = (0; 9.81 sin 30°, 9.81 cos 30°) = (0; 4.905, 8.496), and a₁ = (0.5; 4.905, 8.496)."""
    m = two_link_arm("vertical_xy")
    kin = fd.forward_kinematics(m, Q, QD, QDD)
    a0 = fd.SpatialMotion([0.0, 0.0, 0.0], -np.asarray(m.gravity))  # the RNEA trick: a₀ = −g
    X_up1 = kin.parent_placements[0].inverse()  # ¹X₀
    Xa0 = X_up1.apply(a0)
    assert_close(_planar(Xa0), [0.0, G * np.sin(Q[0]), G * np.cos(Q[0])], "¹X₀ a₀")
    np.testing.assert_allclose(_planar(Xa0), [0.0, 4.905, 8.496], atol=5e-4)  # the chapter's rounding
    v1 = kin.velocities[0]
    assert_close(fd.cross_motion(v1, v1).vector, np.zeros(6), "v₁ × S₁q̇₁")
    a1 = kin.accelerations.vector[0] + Xa0.vector  # body acceleration with gravity = without + ¹X₀ a₀ (linear)
    np.testing.assert_allclose(_planar(a1), [0.5, 4.905, 8.496], atol=5e-4)


def test_chapter_D3_transform_from_link1_to_link2() -> None:
    """²X₁ in the planar reduction is [[1, 0, 0], [l₁ s, c, s], [l₁ c, −s, c]] (c, s of q₂).

    The chapter prints −l₁ cos 45° in row 3, column 1, and hence
    ²X₁ v₁ = (2; 1.414, −1.414). The point of link 1 at joint 2 moves with
    ω × l₁ x̂ = (0, 2) in link-1 axes, i.e. (2 sin 45°, 2 cos 45°) = (1.414, 1.414)
    in link-2 axes: the entry is +l₁ cos 45° and ²X₁ v₁ = (2; 1.414, 1.414).
    """
    m = two_link_arm("vertical_xy")
    kin = fd.forward_kinematics(m, Q, QD, QDD)
    X21 = kin.parent_placements[1].inverse()  # ²X₁ (motion, link 1 → link 2)
    c, s = np.cos(Q[1]), np.sin(Q[1])
    planar_X = X21.matrix()[np.ix_(PLANAR, PLANAR)]
    assert_close(planar_X, [[1.0, 0.0, 0.0], [L1 * s, c, s], [L1 * c, -s, c]], "²X₁ (planar)")
    chapter_X = np.array([[1.0, 0.0, 0.0], [L1 * s, c, s], [-L1 * c, -s, c]])
    assert np.abs(planar_X - chapter_X).max() > 1.0  # the chapter's sign is wrong
    X_v1 = X21.apply(kin.velocities[0])
    r = 2 * np.sin(np.pi / 4)
    assert_close(_planar(X_v1), [2.0, r, r], "²X₁ v₁")
    # and v₂ = ²X₁ v₁ + S₂ q̇₂
    assert_close(_planar(kin.velocities.vector[1]), [2.0 + QD[1], r, r], "v₂")
    # the same from first principles: velocity of the point at joint 2, rotated into link-2 axes
    p_dot = np.cross([0.0, 0.0, QD[0]], [L1, 0.0, 0.0])
    assert_close(X_v1.linear, _rz(Q[1]).T @ p_dot, "²X₁ v₁ (points)")


def _rz(t: float) -> np.ndarray:
    return np.array([[np.cos(t), -np.sin(t), 0.0], [np.sin(t), np.cos(t), 0.0], [0.0, 0.0, 1.0]])


def _planar_rnea(q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
    """The chapter's D.3–D.4 recursion in 3D planar vectors (RBDA §2.16), independent of featherdyn.

    Frames on the joint axes; motion (ω; v_x, v_y), force (n; f_x, f_y); a₀ = (0; 0, g).
    """

    def X(theta: float, r: tuple[float, float]) -> np.ndarray:  # child frame at r in parent, rotated by theta
        c, s = np.cos(theta), np.sin(theta)
        return np.array([[1.0, 0.0, 0.0], [s * r[0] - c * r[1], c, s], [c * r[0] + s * r[1], -s, c]])

    def crm(v: np.ndarray) -> np.ndarray:
        return np.array([[0.0, 0.0, 0.0], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])

    def inertia(mass: float, cx: float, izz: float) -> np.ndarray:  # COM at (cx, 0)
        return np.array([[izz + mass * cx * cx, 0.0, mass * cx], [0.0, mass, 0.0], [mass * cx, 0.0, mass]])

    S = np.array([1.0, 0.0, 0.0])
    Xup = [X(q[0], (0.0, 0.0)), X(q[1], (L1, 0.0))]
    Is = [inertia(M1, LC1, IZZ1), inertia(M2, LC2, IZZ2)]
    v_prev, a_prev = np.zeros(3), np.array([0.0, 0.0, G])
    f = []
    for i in range(2):
        vJ = S * qd[i]
        v = Xup[i] @ v_prev + vJ
        a = Xup[i] @ a_prev + S * qdd[i] + crm(v) @ vJ
        f.append(Is[i] @ a - crm(v).T @ (Is[i] @ v))  # v ×* (I v) = −crm(v)ᵀ I v
        v_prev, a_prev = v, a
    f[0] = f[0] + Xup[1].T @ f[1]
    return np.array([S @ f[0], S @ f[1]])


def test_chapter_D4_force_recursion_by_hand() -> None:
    """D.4's recursion written out in planar vectors gives featherdyn's τ (and the closed form)."""
    m = two_link_arm("vertical_xy")
    for q, qd, qdd in STATES:
        assert_close(fd.rnea(m, q, qd, qdd), _planar_rnea(q, qd, qdd), "τ vs planar RNEA by hand", scale=G)


def test_chapter_D4_link2_inertia_at_the_tip() -> None:
    """D.4 takes link 2's inertia about its tip with c₂ = −0.4 x̂: the distal-frame convention.

    That is the same body (moving the reference point from joint 2 to the tip
    0.8 m out turns c₂ = +0.4 into −0.4), but D.3's ²X₁ uses the proximal
    frames (translation l₁ from joint 1 to joint 2), so the chapter mixes the
    two conventions.
    """
    m = two_link_arm("vertical_xy")
    I2_joint = m.inertias[1]
    tip_in_link2 = fd.PluckerTransform(np.eye(3), [L2, 0.0, 0.0])  # pose of the tip frame in link 2
    I2_tip = tip_in_link2.inverse().apply(I2_joint)
    assert_close(I2_joint.com, [LC2, 0.0, 0.0], "c₂ about joint 2")
    assert_close(I2_tip.com, [LC2 - L2, 0.0, 0.0], "c₂ about the tip (the chapter's −0.4)")


# ---------------------------------------------------------------------------------------------------------------
# SymPy: the reference algorithms on symbols reproduce the Lagrangian
# ---------------------------------------------------------------------------------------------------------------


def test_symbolic_crba_and_rnea_equal_the_lagrangian() -> None:
    sp = pytest.importorskip("sympy")
    q1, q2, qd1, qd2, qdd1, qdd2, t = sp.symbols("q1 q2 qd1 qd2 qdd1 qdd2 t", real=True)
    R = sp.Rational
    l1, m1, lc1, i1 = R(1), R(3), R(1, 2), R(1, 4)
    m2, lc2, i2 = R(2), R(2, 5), R(11, 100)
    g = R(981, 100)

    # Lagrangian from scratch: COM positions in the (vertical) plane, gravity −g ŷ
    th1, th2 = sp.Function("th1")(t), sp.Function("th2")(t)
    p1 = sp.Matrix([lc1 * sp.cos(th1), lc1 * sp.sin(th1)])
    p2 = sp.Matrix([l1 * sp.cos(th1) + lc2 * sp.cos(th1 + th2), l1 * sp.sin(th1) + lc2 * sp.sin(th1 + th2)])
    v1, v2 = p1.diff(t), p2.diff(t)
    T = (m1 * v1.dot(v1) + m2 * v2.dot(v2) + i1 * th1.diff(t) ** 2 + i2 * (th1.diff(t) + th2.diff(t)) ** 2) / 2
    U = g * (m1 * p1[1] + m2 * p2[1])
    L = T - U
    subs = {th1.diff(t, 2): qdd1, th2.diff(t, 2): qdd2, th1.diff(t): qd1, th2.diff(t): qd2}
    subs_q = {th1: q1, th2: q2}
    tau_lagrange = [
        (L.diff(th.diff(t)).diff(t) - L.diff(th)).subs(subs).subs(subs_q) for th in (th1, th2)
    ]
    qdd_syms = (qdd1, qdd2)
    M_lagrange = sp.Matrix(2, 2, lambda i, j: sp.diff(sp.expand(tau_lagrange[i]), qdd_syms[j]))

    m = two_link_arm("vertical_xy")
    q = np.array([q1, q2], dtype=object)
    qd = np.array([qd1, qd2], dtype=object)
    qdd = np.array([qdd1, qdd2], dtype=object)
    M_sym = fd.crba(m, q)
    tau_sym = fd.rnea(m, q, qd, qdd)
    assert M_sym.dtype == object and tau_sym.dtype == object

    s1, c1, s2, c2 = sp.symbols("s1 c1 s2 c2", real=True)
    trig = {sp.sin(q1): s1, sp.cos(q1): c1, sp.sin(q2): s2, sp.cos(q2): c2}
    pythagoras = [s1**2 + c1**2 - 1, s2**2 + c2**2 - 1]

    def difference(expr: Any, closed: Any) -> Any:
        """``simplify(expr − closed)``, made fast by doing the trigonometry as polynomial algebra first.

        The model stores floats (0.4 → 0.4000000000000000222…): they are read
        back as the decimals they were. cos(q1 + q2) is expanded, sin/cos
        become symbols, and the polynomial is reduced modulo sᵢ² + cᵢ² − 1
        (exact; plain ``simplify`` reaches the same 0 in ~8 s).
        """
        exact = sp.nsimplify(sp.expand(expr), rational=True, tolerance=1e-12)
        poly = sp.expand(sp.expand_trig(exact - closed)).subs(trig)
        _, remainder = sp.reduced(poly, pythagoras, s1, s2, c1, c2, qd1, qd2, qdd1, qdd2)
        return sp.simplify(remainder)

    for i in range(2):
        for j in range(2):
            assert difference(M_sym[i, j], M_lagrange[i, j]) == 0, f"M[{i},{j}]: {M_sym[i, j]}"
        assert difference(tau_sym[i], tau_lagrange[i]) == 0, f"τ[{i}]: {tau_sym[i]}"

    # the Lagrangian agrees with the closed form of the module docstring ...
    state = {q1: Q[0], q2: Q[1], qd1: QD[0], qd2: QD[1], qdd1: QDD[0], qdd2: QDD[1]}
    M_cf, Cqd, _, g_cf = closed_form(Q, QD, 1.0)
    tau_cf = M_cf @ QDD + Cqd + g_cf
    assert_close(np.array(M_lagrange.subs(state), dtype=float), M_cf, "Lagrangian M vs closed form")
    assert_close([float(e.subs(state)) for e in tau_lagrange], tau_cf, "Lagrangian τ vs closed form", scale=G)
    # ... and featherdyn's symbolic results, evaluated, equal its numeric ones
    assert_close(np.array([[float(sp.sympify(e).subs(state)) for e in row] for row in M_sym]), fd.crba(m, Q), "symbolic M at the state")
    assert_close([float(sp.sympify(e).subs(state)) for e in tau_sym], fd.rnea(m, Q, QD, QDD), "symbolic τ at the state", scale=G)
