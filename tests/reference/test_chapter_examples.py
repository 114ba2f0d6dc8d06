"""The chapter's worked examples and exercises, executed.

Source: ``shared/seed/spatial-vector-algebra-chapter.zh.txt``. Expected numbers
are the chapter's where it prints them and are re-derived here by hand where
it does not. Where the chapter is wrong the test asserts what is true and the
docstring records the erratum (section, what it says, what holds).
"""

from __future__ import annotations

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.testing import assert_close

S2 = np.sqrt(2.0) / 2


def skew(w):
    x, y, z = w
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def Rz(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rpy(roll, pitch, yaw):
    """URDF / Pinocchio rpyToMatrix: Rz(yaw) Ry(pitch) Rx(roll)."""
    cr, sr, cp, sp = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch)
    Rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    Ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    return Rz(yaw) @ Ry @ Rx


# --------------------------------------------------------------------------
# §9.2 floating-base trunk
# --------------------------------------------------------------------------

M_TRUNK = 12.0
I_TRUNK = np.diag([0.1, 0.3, 0.35])
C_HIP = np.array([0.2, 0.1, 0.0])  # the front-left hip, from the trunk origin (= the CoM)
PARALLEL_AXIS_PRINTED = np.array([[0.12, -0.24, 0.0], [-0.24, 0.48, 0.0], [0.0, 0.0, 0.60]])


def test_9_2a_trunk_about_its_com():
    trunk = fd.SpatialInertia(M_TRUNK, np.zeros(3), I_TRUNK)
    expected = np.zeros((6, 6))
    expected[:3, :3] = I_TRUNK
    expected[3:, 3:] = 12.0 * np.eye(3)
    assert_close(trunk.matrix(), expected, "§9.2(a) block-diagonal inertia")
    trunk.check()


def test_9_2b_trunk_about_the_hip():
    """§9.2(b): the parallel-axis block printed by the chapter is right; mind the sign of c.

    The chapter moves the reference frame *to* the hip at offset
    c = (0.2, 0.1, 0) from the CoM, so seen from the hip the CoM is at −c:
    featherdyn's ``com`` is −c and the coupling block is m[−c]× = −m[c]×.
    The parallel-axis block m(|c|²1 − ccᵀ) is quadratic in c and equals the
    printed [[0.12, −0.24, 0], [−0.24, 0.48, 0], [0, 0, 0.60]] either way; the
    chapter's final 6×6 matrix is not printed (its display equation is lost),
    so its off-diagonal sign cannot be checked. Plugging c itself into
    RBDA (2.63) describes the *opposite* (rear-right) hip; the momentum check
    below tells the two apart.
    """
    hip = fd.SpatialInertia(M_TRUNK, -C_HIP, I_TRUNK)
    M = hip.matrix()
    assert_close(M[:3, :3] - I_TRUNK, PARALLEL_AXIS_PRINTED, "§9.2 parallel-axis block")
    assert_close(M[:3, 3:], -M_TRUNK * skew(C_HIP), "coupling block m[com]× with com = −c")
    assert_close(M[3:, :3], M[:3, 3:].T, "symmetry")
    # the same inertia by moving the frame: the trunk origin sits at −c in hip coordinates
    X_hip_trunk = fd.PluckerTransform(np.eye(3), -C_HIP)
    assert_close(X_hip_trunk.apply(fd.SpatialInertia(M_TRUNK, np.zeros(3), I_TRUNK)).matrix(), M, "X* I X⁻¹")
    # physics decides the sign: spinning about the CoM at ω, the hip point moves at ω × c,
    # and the momentum is pure angular, I_b ω, with no linear part
    w = np.array([0.0, 0.0, 1.5])
    v_hip = fd.SpatialMotion(w, np.cross(w, C_HIP))
    h = hip @ v_hip
    assert_close(h.linear, np.zeros(3), "linear momentum of a body spinning about its CoM")
    assert_close(h.angular, I_TRUNK @ w, "angular momentum I_b ω")
    wrong = fd.SpatialInertia(M_TRUNK, C_HIP, I_TRUNK) @ v_hip
    assert np.linalg.norm(wrong.linear) > 1.0  # +c would give the trunk a spurious linear momentum


# --------------------------------------------------------------------------
# §3.1 the motion transform
# --------------------------------------------------------------------------


def test_3_1_reference_point_change_sign():
    """§3.1 step 2: the formula ᴮv = R ᴬv + p × (R ω) is right, its explanation is not.

    The chapter explains it with r_OP = p and "v_B = v_A + ω × p = v_A − p × ω".
    But p is A's origin in B, so the vector from A's origin to B's is −p, and
    v_B = v_A + ω × (−p) = v_A + p × ω — the sign the displayed formula has.
    """
    p = np.array([1.0, 2.0, 3.0])
    w = np.array([0.3, -0.2, 1.0])
    v_A = np.array([0.5, 0.0, -0.4])
    X = fd.PluckerTransform(np.eye(3), p)
    got = X.apply(fd.SpatialMotion(w, v_A))
    assert_close(got.linear, v_A + np.cross(w, -p), "velocity of the body point at B's origin")
    assert_close(got.linear, v_A + np.cross(p, w), "ᴮv = ᴬv + p × ω")
    explained = v_A - np.cross(p, w)
    assert np.abs(got.linear - explained).max() > 1.0


# --------------------------------------------------------------------------
# §10.1–10.3 code verification
# --------------------------------------------------------------------------

W1, V1 = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
N1, F1 = np.array([0.0, 0.0, 5.0]), np.array([0.0, 10.0, 0.0])


def test_10_1_power():
    motion, force = fd.SpatialMotion(W1, V1), fd.SpatialForce(N1, F1)
    assert motion.dot(force) == pytest.approx(5.0, abs=1e-15)
    assert force.dot(motion) == pytest.approx(5.0, abs=1e-15)


def test_10_1_pinocchio_layout(pin):
    """§10.1's comment "Pinocchio stores and .vector use [angular; linear]" is wrong.

    ``pin.Motion(linear, angular).vector`` is [linear; angular], and
    "method 2", ``pin.Motion(np.concatenate([omega, v]))``, reads ω as the
    linear part: the two motions the chapter builds are not the same.
    """
    motion = pin.Motion(V1, W1)
    np.testing.assert_array_equal(motion.vector, np.r_[V1, W1])
    motion2 = pin.Motion(np.concatenate([W1, V1]))
    np.testing.assert_array_equal(motion2.linear, W1)
    np.testing.assert_array_equal(motion2.angular, V1)
    assert motion.dot(pin.Force(F1, N1)) == pytest.approx(5.0)


def test_10_2_transform_example(pin):
    R, p = Rz(np.pi / 4), np.array([1.0, 0.0, 0.0])
    X = fd.PluckerTransform(R, p)
    v_B = X.apply(fd.SpatialMotion(W1, V1))
    # by hand: R v = (√2/2, √2/2, 0), p × Rω = (1, 0, 0) × (0, 0, 1) = (0, −1, 0)
    assert_close(v_B.vector, [0.0, 0.0, 1.0, S2, S2 - 1.0, 0.0], "§10.2 v_B")
    f_B = X.apply(fd.SpatialForce(N1, F1))
    # R f = (−10·√2/2, 10·√2/2, 0), n_B = n + p × R f = (0, 0, 5 + 10·√2/2)
    assert_close(f_B.vector, [0.0, 0.0, 5.0 + 10 * S2, -10 * S2, 10 * S2, 0.0], "§10.2 f_B")
    assert v_B.dot(f_B) == pytest.approx(5.0, abs=1e-12)
    T = pin.SE3(pin.utils.rpyToMatrix(0.0, 0.0, np.pi / 4), p)
    np.testing.assert_allclose(T.rotation, R, atol=1e-15)
    ours = np.concatenate([v_B.linear, v_B.angular])
    assert_close(T.act(pin.Motion(V1, W1)).vector, ours, "pin SE3.act(Motion), linear first")


W2, V2 = np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])


def test_10_3_cross_products():
    """§10.3: the cross products are right; the printed duality check has the wrong sign.

    The chapter checks "(v1 × v2)ᵀ f == v2ᵀ (v1 ×* f)". From [v]×* = −[v]×ᵀ,
    v2 · (v1 ×* f) = −(v1 × v2) · f. With the chapter's f (gravity only) both
    sides are 0, so the printed check passes by accident; any f with a force
    along x shows the sign.
    """
    v1, v2 = fd.SpatialMotion(W1, V1), fd.SpatialMotion(W2, V2)
    v12 = v1.cross(v2)
    # ω1 × ω2 = (0, 1, 0); ω1 × v2 + v1 × ω2 = (−1, 0, 0) + 0
    assert_close(v12.vector, [0.0, 1.0, 0.0, -1.0, 0.0, 0.0], "§10.3 v1 × v2")
    gravity = fd.SpatialForce([0.0, 0.0, 0.0], [0.0, 0.0, 9.81])
    v1f = v1.cross(gravity)
    # v × f = (1, 0, 0) × (0, 0, 9.81) = (0, −9.81, 0); ω × f = 0
    assert_close(v1f.vector, [0.0, -9.81, 0.0, 0.0, 0.0, 0.0], "§10.3 v1 ×* f")
    assert v12.dot(gravity) == 0.0 and v2.dot(v1f) == 0.0  # the chapter's check: 0 == 0
    fx = fd.SpatialForce([0.0, 0.0, 0.0], [1.0, 0.0, 0.0])
    assert v12.dot(fx) == pytest.approx(-1.0)
    assert v2.dot(v1.cross(fx)) == pytest.approx(1.0)  # = −(v1 × v2)·f, not +


# --------------------------------------------------------------------------
# first exercise list
# --------------------------------------------------------------------------


def test_exercises_1_to_3_first_list():
    X_rot = fd.PluckerTransform(rpy(0.3, -0.2, 1.1), np.zeros(3)).matrix()
    assert_close(np.linalg.inv(X_rot), X_rot.T, "X_rot⁻¹ = X_rotᵀ")
    X = fd.PluckerTransform(rpy(0.3, -0.2, 1.1), [0.5, 0.0, 0.0]).matrix()
    assert np.abs(np.linalg.inv(X) - X.T).max() > 0.1  # not orthogonal once p ≠ 0
    assert np.linalg.det(X) == pytest.approx(1.0)
    C = fd.crm([0.0, 0.0, 1.0, 1.0, 0.0, 0.0])
    assert np.abs(C + C.T).max() == 1.0  # not skew-symmetric: the v× block sits alone below
    a, b = np.array([0.0, 0.0, 1.0, 1.0, 0.0, 0.0]), np.array([0.3, -1.0, 0.2, 0.0, 2.0, 1.0])
    assert_close(fd.crm(a) @ b, -fd.crm(b) @ a, "[v1]× v2 = −[v2]× v1")


# --------------------------------------------------------------------------
# second exercise list
# --------------------------------------------------------------------------

TAU_O, F_O = np.array([0.0, 0.0, 10.0]), np.array([5.0, 0.0, 0.0])
OMEGA, V_O = np.array([0.0, 0.0, 2.0]), np.array([1.0, 0.0, 0.0])


def _power_at(r_OP):
    """(correct power at P, power with the wrong moment formula τ_P = τ_O + r × f)."""
    X_PO = fd.PluckerTransform(np.eye(3), -np.asarray(r_OP))  # O sits at −r_OP from P
    f_P = X_PO.apply(fd.SpatialForce(TAU_O, F_O))
    v_P = X_PO.apply(fd.SpatialMotion(OMEGA, V_O))
    assert_close(f_P.angular, TAU_O - np.cross(r_OP, F_O), "τ_P = τ_O − r_OP × f")
    assert_close(v_P.linear, V_O + np.cross(OMEGA, r_OP), "v_P = v_O + ω × r_OP")
    wrong_tau = TAU_O + np.cross(r_OP, F_O)
    return v_P.dot(f_P), wrong_tau @ OMEGA + F_O @ v_P.linear


def test_exercise_1_power_at_O_and_P():
    """Exercise 1 (second list): P is the same at O and P; with the chapter's data the wrong formula is too.

    (a) P_O = 10·2 + 5·1 = 25. (b, c) with r_OP = (0.5, 0, 0): τ_P = (0, 0, 10),
    v_P = (1, 1, 0), P_P = 25. (d) The wrong formula changes the power by
    2 (r_OP × f)·ω — which is 0 here because r_OP ∥ f: the exercise's numbers
    cannot show the pitfall it asks about. With r_OP = (0, 0.5, 0) the wrong
    formula gives 15 instead of 25.
    """
    assert fd.SpatialMotion(OMEGA, V_O).dot(fd.SpatialForce(TAU_O, F_O)) == pytest.approx(25.0)
    correct, wrong = _power_at(np.array([0.5, 0.0, 0.0]))
    assert correct == pytest.approx(25.0)
    assert wrong - correct == pytest.approx(0.0)  # the exercise's data: no difference
    r = np.array([0.0, 0.5, 0.0])
    correct, wrong = _power_at(r)
    assert correct == pytest.approx(25.0)
    assert wrong == pytest.approx(15.0)
    assert wrong - correct == pytest.approx(2 * np.cross(r, F_O) @ OMEGA) == pytest.approx(-10.0)


def test_exercise_2_cylinder(pin):
    m, r, h = 2.0, 0.1, 0.4
    c = np.array([0.0, 0.0, 0.2])
    cyl = fd.SpatialInertia.cylinder(m, r, h)
    side = m * (3 * r * r + h * h) / 12
    assert_close(cyl.inertia_com, np.diag([side, side, m * r * r / 2]), "I_c")
    I_O = fd.SpatialInertia(m, c, cyl.inertia_com).matrix()
    expected = np.zeros((6, 6))
    expected[:3, :3] = np.diag([side + m * 0.04, side + m * 0.04, m * r * r / 2])
    expected[0, 4], expected[1, 3] = -0.4, 0.4  # m [c]×
    expected[4, 0], expected[3, 1] = -0.4, 0.4  # m [c]×ᵀ
    expected[3:, 3:] = m * np.eye(3)
    assert_close(I_O, expected, "§ex.2 I_O")
    assert np.all(np.linalg.eigvalsh(I_O) > 0)
    theirs = pin.Inertia(m, c, cyl.inertia_com).matrix()
    P = np.block([[np.zeros((3, 3)), np.eye(3)], [np.eye(3), np.zeros((3, 3))]])
    assert_close(I_O, P @ theirs @ P, "pin.Inertia.matrix() permuted")


def test_exercise_3_act_vs_actInv(pin):
    """Exercise 3 / §11 pitfall: forces move with act, not actInv.

    The troubleshooting table (row "power changes with the frame", §2.3)
    says to "confirm motions use act and forces use actInv"; that breaks power
    invariance. Both move with act (the pitfall box in §16 says so correctly).
    """
    T = pin.SE3(Rz(np.pi / 6), np.array([1.0, 0.0, 0.0]))
    v_A, f_A = pin.Motion(V1, W1), pin.Force(F1, N1)
    assert T.act(v_A).dot(T.act(f_A)) == pytest.approx(v_A.dot(f_A))
    wrong = T.act(v_A).dot(T.actInv(f_A))
    assert abs(wrong - v_A.dot(f_A)) > 1.0
    X = fd.PluckerTransform(Rz(np.pi / 6), [1.0, 0.0, 0.0])
    P = np.block([[np.zeros((3, 3)), np.eye(3)], [np.eye(3), np.zeros((3, 3))]])
    assert_close(X.matrix(), P @ T.toActionMatrix() @ P, "X vs toActionMatrix")
    assert_close(X.dual_matrix(), P @ np.linalg.inv(T.toActionMatrix()).T @ P, "X⁻ᵀ")


def test_exercise_4_cross_product_duality(pin, samples):
    v1 = fd.SpatialMotion([0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
    # (a) written out: ω× for ω = z, v× for v = x
    crm_expected = np.array(
        [
            [0, -1, 0, 0, 0, 0],
            [1, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, 0, 0],
            [0, 0, 0, 0, -1, 0],
            [0, 0, -1, 1, 0, 0],
            [0, 1, 0, 0, 0, 0],
        ],
        dtype=float,
    )
    assert_close(fd.crm(v1), crm_expected, "ex.4(a) [v1]×")
    # (b) [v1]×* = −[v1]×ᵀ, and it is not [v1]×
    assert_close(fd.crf(v1), -crm_expected.T, "ex.4(b) [v1]×*")
    assert np.abs(fd.crf(v1) - fd.crm(v1)).max() == 1.0
    # (c) the force cross product does no work: v · (v ×* f) = 0 for every f
    for f in (samples.force(), samples.force((5,)), fd.SpatialForce([1.0, 2.0, 3.0], [4.0, 5.0, 6.0])):
        assert_close(v1.dot(v1.cross(f)), np.zeros(f.shape), "ex.4(c) v·(v ×* f)")
    # (d) the same in Pinocchio
    pv = pin.Motion(np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0]))
    pf = pin.Force(np.array([4.0, 5.0, 6.0]), np.array([1.0, 2.0, 3.0]))
    assert pv.cross(pf).dot(pv) == pytest.approx(0.0, abs=1e-14)


# --------------------------------------------------------------------------
# appendices
# --------------------------------------------------------------------------


def test_appendix_C2_inertia_transform(pin):
    m, c, Ic = 5.0, np.array([0.1, -0.05, 0.02]), np.diag([0.01, 0.02, 0.03])
    R, p = rpy(0.3, -0.1, 0.5), np.array([0.5, 0.2, -0.1])
    np.testing.assert_allclose(pin.utils.rpyToMatrix(0.3, -0.1, 0.5), R, atol=1e-15)
    X = np.block([[R, np.zeros((3, 3))], [skew(p) @ R, R]])
    X_inv = np.block([[R.T, np.zeros((3, 3))], [-R.T @ skew(p), R.T]])  # as printed in C.2
    assert_close(X_inv @ X, np.eye(6), "C.2 X⁻¹")
    I_A = fd.SpatialInertia(m, c, Ic)
    I_B = fd.PluckerTransform(R, p).apply(I_A)
    assert_close(I_B.matrix(), X_inv.T @ I_A.matrix() @ X_inv, "C.2 X⁻ᵀ I_A X⁻¹")
    P = np.block([[np.zeros((3, 3)), np.eye(3)], [np.eye(3), np.zeros((3, 3))]])
    assert_close(I_B.matrix(), P @ pin.SE3(R, p).act(pin.Inertia(m, c, Ic)).matrix() @ P, "C.2 vs Pinocchio")
    v = fd.SpatialMotion([0.3, -1.0, 0.5], [0.2, 0.1, -0.7])
    X_fd = fd.PluckerTransform(R, p)
    assert_close(I_B.kinetic_energy(X_fd.apply(v)), I_A.kinetic_energy(v), "C.2 kinetic energy invariance")


def test_appendix_F3_inertia_transform_rows():
    """Appendix F.3 rows 3–4 print I_B = X_BA*ᵀ I_A X_BA*; the right form is X_BA* I_A X_BA⁻¹.

    X*ᵀ = X⁻¹, so the printed product is X_BA⁻¹ I_A X_BA⁻ᵀ = X_AB I_A X_ABᵀ.
    For a pure rotation that moves I_A the wrong way (it is X_AB* I_A X_AB⁻¹,
    the transform from B to A); with a translation it is no rigid-body
    inertia at all (its lower-right block is not m·1). §5.2 has it right,
    I_B = X* I_A X⁻¹ (equivalently I_A = X_BAᵀ I_B X_BA). The composite-inertia
    row Σ X_i*ᵀ I_i X_i* has the same error.
    """
    R, p = rpy(0.2, 0.4, -0.3), np.array([0.3, -0.6, 0.2])
    I_A = fd.SpatialInertia(2.0, [0.1, 0.0, -0.1], np.diag([0.05, 0.06, 0.08]))
    X = fd.PluckerTransform(R, p)
    correct = X.dual_matrix() @ I_A.matrix() @ np.linalg.inv(X.matrix())
    assert_close(X.apply(I_A).matrix(), correct, "§5.2 X* I X⁻¹")
    printed = X.dual_matrix().T @ I_A.matrix() @ X.dual_matrix()
    assert np.abs(printed - correct).max() > 0.1
    with pytest.raises(fd.InertiaError, match="lower-right block"):
        fd.SpatialInertia.from_matrix(printed)
    Xr = fd.PluckerTransform(R, np.zeros(3))
    printed_rot = Xr.dual_matrix().T @ I_A.matrix() @ Xr.dual_matrix()
    assert_close(printed_rot, Xr.inverse().apply(I_A).matrix(), "printed form = the B → A transform")
    assert np.abs(printed_rot - Xr.apply(I_A).matrix()).max() > 0.01


def test_appendix_D3_planar_2R_velocity():
    """Appendix D.3: ²X₁ v₁ is (2; 1.414, +1.414), not (2; 1.414, −1.414).

    Link 1 spins at q̇₁ = 2 rad/s about joint 1; joint 2 sits at (ℓ₁, 0) = (1, 0)
    in link 1's frame, so it moves at ω × r = (0, 2) there; in link 2's frame
    (rotated by q₂ = 45°) that reads (2 sin 45°, 2 cos 45°) = (1.414, 1.414).
    The chapter's planar matrix has −ℓ₁cos 45° in its third row where
    spatial_v2's ``plnr`` has +ℓ₁cos 45°. (D.3 also places frame 1 at the end of
    link 1 while using v₁ = S₁q̇₁ = (2; 0, 0), which holds only for a frame at
    joint 1; the numbers here use Featherstone's placement, frame i at joint i.)
    The gravity term ¹X₀a₀ = (0; 4.905, 8.496) is right.
    """
    X_21 = fd.rotz(np.pi / 4) @ fd.xlt([1.0, 0.0, 0.0])
    v1 = fd.SpatialMotion([0.0, 0.0, 2.0], [0.0, 0.0, 0.0])
    v2 = X_21.apply(v1)
    assert_close(v2.vector, [0.0, 0.0, 2.0, 2 * S2, 2 * S2, 0.0], "D.3 ²X₁ v₁")
    a0 = fd.SpatialMotion([0.0, 0.0, 0.0], [0.0, 9.81, 0.0])
    a1 = (fd.rotz(np.pi / 6) @ fd.xlt([0.0, 0.0, 0.0])).apply(a0)
    assert_close(a1.linear[:2], [4.905, 9.81 * np.cos(np.pi / 6)], "D.3 ¹X₀ a₀")
    assert a1.linear[1] == pytest.approx(8.496, abs=5e-4)
