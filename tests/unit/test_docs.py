"""The pitfalls of ``docs/conventions.md``, one test each, and the integrity of the docs' citations.

Each ``test_pitfall_*`` / ``test_trouble_*`` / ``test_table_*`` demonstrates
one row of the chapter's pitfall boxes (§7.3, §16, §18.3), of its
troubleshooting table, or of the notation table in ``docs/conventions.md``,
which cites them by name. The last tests check that every
``conventions.<name>`` cited in ``docs/conventions.md`` exists, and that
every path and test id cited in ``docs/errata.md`` and
``docs/conventions.md`` exists.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

import featherdyn as fd
from featherdyn import conventions
from featherdyn.rotation import quat_to_matrix, rpy_to_matrix

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"
P6 = np.block([[np.zeros((3, 3)), np.eye(3)], [np.eye(3), np.zeros((3, 3))]])


def _panda_pair(pin):
    from featherdyn.robots import robot_path
    from featherdyn.verify.bridge import JointMap

    model = fd.load_robot("panda")
    pmodel = pin.buildModelFromUrdf(str(robot_path("panda")))
    return model, pmodel, JointMap(model, pmodel)


def _free_body(gravity=(0.0, 0.0, -9.81)):
    b = fd.ModelBuilder("body", gravity=gravity)
    b.add_body("base", -1, fd.FreeFlyerJoint(),
               inertia=fd.SpatialInertia(2.0, [0.1, -0.05, 0.2], np.diag([0.03, 0.04, 0.05])))
    return b.build()


# --------------------------------------------------------------------------
# chapter pitfall boxes
# --------------------------------------------------------------------------


def test_pitfall_spatial_vs_classical_acceleration(pin):
    """§7.3: ``data.a[i]`` is the spatial acceleration; the classical one adds ω × v to the linear part."""
    model, pmodel, jmap = _panda_pair(pin)
    rng = np.random.default_rng(0)
    q, v, a = fd.random_configuration(model, rng), rng.normal(size=model.nv), rng.normal(size=model.nv)
    pdata = pmodel.createData()
    pin.forwardKinematics(pmodel, pdata, jmap.q_to_pin(q), jmap.v_to_pin(v), jmap.v_to_pin(a))
    j = pmodel.getJointId("panda_joint5")
    spatial = conventions.motion_from_pinocchio(pdata.a[j].vector).vector
    classical = conventions.motion_from_pinocchio(pin.getClassicalAcceleration(pmodel, pdata, j, pin.LOCAL).vector).vector
    vel = conventions.motion_from_pinocchio(pdata.v[j].vector)
    np.testing.assert_allclose(classical, conventions.spatial_to_classical_acceleration(spatial, vel), atol=1e-12)
    assert np.linalg.norm(classical[3:] - spatial[3:]) > 0.1  # not a rounding difference
    ours = fd.frame_classical_acceleration(model, q, v, a, "panda_link5", fd.LOCAL).vector
    np.testing.assert_allclose(ours, classical, atol=1e-12)
    back = conventions.classical_to_spatial_acceleration(classical, vel)
    np.testing.assert_allclose(back.vector, spatial, atol=1e-12)


def test_pitfall_force_moves_with_act_not_actinv(pin):
    """§16 pitfall 1 (right) vs the troubleshooting table row 2 (wrong): forces move with ``act``."""
    rng = np.random.default_rng(1)
    T = pin.SE3(rpy_to_matrix(rng.normal(size=3)), rng.normal(size=3))
    m, f = pin.Motion(rng.normal(size=6)), pin.Force(rng.normal(size=6))
    assert T.act(m).dot(T.act(f)) == pytest.approx(m.dot(f), abs=1e-12)
    assert abs(T.act(m).dot(T.actInv(f)) - m.dot(f)) > 1e-3
    X = conventions.transform_from_pinocchio_se3(T)
    mf, ff = conventions.from_pinocchio_motion(m), conventions.from_pinocchio_force(f)
    np.testing.assert_allclose(X.apply(ff).vector, conventions.from_pinocchio_force(T.act(f)).vector, atol=1e-12)
    np.testing.assert_allclose(X.apply_inverse(ff).vector, conventions.from_pinocchio_force(T.actInv(f)).vector,
                               atol=1e-12)
    assert X.apply(mf).dot(X.apply(ff)) == pytest.approx(mf.dot(ff), abs=1e-12)


def test_pitfall_spatial_vectors_are_not_concatenations():
    """§16 concept box: a motion and a force transform differently; featherdyn refuses to guess."""
    rng = np.random.default_rng(2)
    X = fd.PluckerTransform(rpy_to_matrix(rng.normal(size=3)), rng.normal(size=3))
    m = fd.SpatialMotion.from_vector(rng.normal(size=6))
    f = fd.SpatialForce.from_vector(rng.normal(size=6))
    wrong = fd.SpatialForce.from_vector(X.matrix() @ f.vector)  # a force moved like a motion
    assert abs(X.apply(m).dot(wrong) - m.dot(f)) > 1e-3
    assert X.apply(m).dot(X.apply(f)) == pytest.approx(m.dot(f), abs=1e-12)
    with pytest.raises(fd.SpatialTypeError):
        X.apply(rng.normal(size=6))
    with pytest.raises(TypeError):
        m + f


def test_pitfall_drake_shift_and_reexpress():
    """§16 thinking trap: Drake moves a velocity with Shift then re-expresses (R_AE * V); its acceleration is classical.

    For velocities and forces the two steps compose to featherdyn's Plücker
    transform; for accelerations they do not: Drake's ``SpatialAcceleration``
    is the classical acceleration, which is not moved by X.
    """
    rng = np.random.default_rng(3)
    R, p = rpy_to_matrix(rng.normal(size=3)), rng.normal(size=3)  # pose of A in B
    X = fd.PluckerTransform(R, p)
    V = fd.SpatialMotion.from_vector(rng.normal(size=6))
    F = fd.SpatialForce.from_vector(rng.normal(size=6))
    # expressed in A: the point B_o sits at −Rᵀp from A_o; shift there, then rotate into B's axes
    p_AoBo_A = -R.T @ p
    V_B = conventions.drake_reexpress(R, conventions.drake_shift_velocity(V, p_AoBo_A))
    F_B = conventions.drake_reexpress(R, conventions.drake_shift_force(F, p_AoBo_A))
    np.testing.assert_allclose(V_B.vector, X.apply(V).vector, atol=1e-12)
    np.testing.assert_allclose(F_B.vector, X.apply(F).vector, atol=1e-12)
    A_spatial = rng.normal(size=6)
    A_classical = conventions.spatial_to_classical_acceleration(A_spatial, V)
    shifted = conventions.drake_shift_acceleration(A_classical, p_AoBo_A, V.angular)
    via_plucker = conventions.spatial_to_classical_acceleration(
        fd.PluckerTransform(np.eye(3), -p_AoBo_A).apply(fd.SpatialMotion.from_vector(A_spatial)),
        fd.PluckerTransform(np.eye(3), -p_AoBo_A).apply(V))
    np.testing.assert_allclose(shifted, via_plucker, atol=1e-12)
    naive = fd.PluckerTransform(np.eye(3), -p_AoBo_A).matrix() @ A_classical  # X applied to a classical acceleration
    assert np.abs(naive - shifted).max() > 1e-3


def test_pitfall_ros_twist_is_linear_first():
    """§16 pitfall 4: a ROS Twist is (linear, angular); flattened it is [v; ω]."""
    m = fd.SpatialMotion([0.1, 0.2, 0.3], [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(conventions.twist_array_to_ros(m), [1.0, 2.0, 3.0, 0.1, 0.2, 0.3])
    msg = conventions.motion_to_ros_twist(m)
    np.testing.assert_array_equal(msg["linear"], m.linear)
    np.testing.assert_array_equal(msg["angular"], m.angular)
    np.testing.assert_array_equal(conventions.motion_from_ros_twist(msg).vector, m.vector)
    f = fd.SpatialForce([0.1, 0.2, 0.3], [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(conventions.wrench_array_to_ros(f), [1.0, 2.0, 3.0, 0.1, 0.2, 0.3])
    np.testing.assert_array_equal(conventions.force_from_ros_wrench(conventions.force_to_ros_wrench(f)).vector, f.vector)
    # reading the flat Twist as a Featherstone vector swaps rotation and translation
    assert not np.allclose(fd.SpatialMotion.from_vector(conventions.twist_array_to_ros(m)).vector, m.vector)


def test_pitfall_floating_base_nq_ne_nv():
    """§18.3 pitfall: nq = nv + 1 per free-flyer; a velocity of length nq is rejected."""
    model = _free_body()
    assert (model.nq, model.nv) == (7, 6)
    q = fd.neutral(model)
    with pytest.raises(fd.ShapeError, match="nv=6"):
        fd.rnea(model, q, np.zeros(model.nq), np.zeros(model.nv))
    with pytest.raises(fd.ShapeError, match="nq=7"):
        fd.rnea(model, np.zeros(model.nv), np.zeros(model.nv), np.zeros(model.nv))


def test_pitfall_pinocchio_6d_storage_is_linear_first(pin):
    """§10.1, §11, appendix G.1 say Pinocchio stores [ω; v]; it stores [v; ω] (and [f; n])."""
    m = pin.Motion(np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0]))  # (linear, angular)
    np.testing.assert_array_equal(m.vector, [1, 2, 3, 4, 5, 6])
    np.testing.assert_array_equal(m.linear, [1, 2, 3])
    fm = conventions.from_pinocchio_motion(m)
    np.testing.assert_array_equal(fm.vector, [4, 5, 6, 1, 2, 3])
    np.testing.assert_array_equal(conventions.motion_to_pinocchio(fm), m.vector)
    f = pin.Force(np.array([1.0, 2.0, 3.0]), np.array([4.0, 5.0, 6.0]))
    np.testing.assert_array_equal(conventions.force_from_pinocchio(f.vector).vector, [4, 5, 6, 1, 2, 3])
    T = pin.SE3(rpy_to_matrix([0.1, 0.2, 0.3]), np.array([0.4, 0.5, 0.6]))
    X = conventions.transform_from_pinocchio_se3(T)
    np.testing.assert_allclose(conventions.matrix6_to_pinocchio(X.matrix()), T.toActionMatrix(), atol=1e-15)


def test_pitfall_freeflyer_layouts(pin):
    """§18.3: Pinocchio's free-flyer q is [x y z, qx qy qz qw] (not quaternion first), v is [v; ω] (not [ω; v])."""
    ff = pin.Model()
    ff.appendBodyToJoint(ff.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "base"),
                         pin.Inertia(1.0, np.zeros(3), np.eye(3)), pin.SE3.Identity())
    q0 = pin.neutral(ff)
    np.testing.assert_array_equal(q0, [0, 0, 0, 0, 0, 0, 1])
    np.testing.assert_allclose(pin.integrate(ff, q0, np.array([1.0, 0, 0, 0, 0, 0])), [1, 0, 0, 0, 0, 0, 1], atol=1e-15)
    np.testing.assert_allclose(pin.integrate(ff, q0, np.array([0, 0, 0, np.pi, 0, 0]))[3:], [1, 0, 0, 0], atol=1e-15)
    yawed = pin.integrate(ff, q0, np.array([0, 0, 0, 0, 0, np.pi / 2]))
    np.testing.assert_allclose(pin.integrate(ff, yawed, np.array([1.0, 0, 0, 0, 0, 0]))[:3], [0, 1, 0], atol=1e-15)
    # featherdyn: same q, v = [ω; v] in the base frame; the converters bridge Pinocchio and MuJoCo
    model = _free_body()
    rng = np.random.default_rng(4)
    q, v = fd.random_configuration(model, rng), rng.normal(size=6)
    np.testing.assert_allclose(fd.integrate(model, q, v), pin.integrate(ff, q, conventions.freeflyer_v_to_pinocchio(v)),
                               atol=1e-12)
    np.testing.assert_array_equal(conventions.freeflyer_v_from_pinocchio(conventions.freeflyer_v_to_pinocchio(v)), v)
    qpos = conventions.freeflyer_q_to_mujoco(q)
    np.testing.assert_array_equal(qpos[3:], q[[6, 3, 4, 5]])  # MuJoCo: (w, x, y, z)
    qvel = conventions.freeflyer_v_to_mujoco(q, v)
    np.testing.assert_allclose(qvel[:3], quat_to_matrix(q[3:]) @ v[3:], atol=1e-15)  # linear, world axes
    np.testing.assert_allclose(qvel[3:], v[:3], atol=1e-15)  # angular, body axes
    np.testing.assert_allclose(conventions.freeflyer_v_from_mujoco(qpos, qvel), v, atol=1e-12)
    np.testing.assert_allclose(conventions.freeflyer_q_from_mujoco(qpos), q, atol=0)


# --------------------------------------------------------------------------
# the troubleshooting table
# --------------------------------------------------------------------------


def test_trouble_body_vs_world_frame(pin):
    """Row 1: ``data.v[i]`` is in the body frame; ``oMi.act(data.v[i])`` is the world-frame (spatial) velocity."""
    model, pmodel, jmap = _panda_pair(pin)
    rng = np.random.default_rng(5)
    q, v = fd.random_configuration(model, rng), rng.normal(size=model.nv)
    pdata = pmodel.createData()
    pin.forwardKinematics(pmodel, pdata, jmap.q_to_pin(q), jmap.v_to_pin(v))
    j = pmodel.getJointId("panda_joint7")
    local = conventions.from_pinocchio_motion(pdata.v[j]).vector
    world = conventions.from_pinocchio_motion(pdata.oMi[j].act(pdata.v[j])).vector
    np.testing.assert_allclose(fd.frame_velocity(model, q, v, "panda_link7", fd.LOCAL).vector, local, atol=1e-12)
    np.testing.assert_allclose(fd.frame_velocity(model, q, v, "panda_link7", fd.WORLD).vector, world, atol=1e-12)
    assert np.abs(local - world).max() > 0.1
    J_world = fd.frame_jacobian(model, q, "panda_link7", fd.WORLD)
    np.testing.assert_allclose(J_world @ v, world, atol=1e-12)


def test_trouble_invalid_inertia_detected():
    """Row 3: a non-physical inertia (triangle inequality, negative moment) is reported, not used silently."""
    good = fd.SpatialInertia(1.0, [0.0, 0.0, 0.1], np.diag([1.0, 1.0, 1.5]))
    good.check()
    assert good.is_physical()
    bad = fd.SpatialInertia(1.0, np.zeros(3), np.diag([1.0, 1.0, 3.0]))  # I1 + I2 < I3
    assert not bad.is_physical()
    with pytest.raises(fd.InertiaError, match="triangle"):
        bad.check()
    negative = fd.SpatialInertia(1.0, np.zeros(3), np.diag([1.0, -0.1, 1.0]))
    with pytest.raises(fd.InertiaError):
        negative.check()
    assert np.linalg.eigvalsh(good.matrix()).min() > 0


def test_trouble_torque_sign(pin):
    """Row 5: RNEA returns the torque the actuator applies (τ = Sᵀ f), e.g. −m g l to hold a pendulum level."""
    m, length, g = 2.0, 0.5, 9.81
    b = fd.ModelBuilder("pendulum", gravity=(0.0, 0.0, -g))
    b.add_body("link", -1, fd.RevoluteJoint([0, 1, 0]), inertia=fd.SpatialInertia.point_mass(m, [length, 0.0, 0.0]))
    model = b.build()
    q = np.zeros(1)
    tau = fd.generalized_gravity(model, q)
    # gravity's moment about +y is (l x̂) × (−m g ẑ) = +m g l ŷ; the joint must supply the opposite
    assert tau[0] == pytest.approx(-m * g * length)
    from featherdyn.verify.bridge import pinocchio_model_from

    pm = pinocchio_model_from(model)
    assert pin.computeGeneralizedGravity(pm, pm.createData(), q)[0] == pytest.approx(tau[0])
    assert fd.aba(model, q, np.zeros(1), tau)[0] == pytest.approx(0.0, abs=1e-12)  # that torque holds it


def test_trouble_crba_full_symmetric(pin):
    """Row 6: ``pin.crba`` from Python already returns the full symmetric M (pin 4.1); so does fd.crba."""
    model, pmodel, jmap = _panda_pair(pin)
    rng = np.random.default_rng(6)
    q = fd.random_configuration(model, rng)
    M = pin.crba(pmodel, pmodel.createData(), jmap.q_to_pin(q))
    assert np.abs(M - M.T).max() == 0.0
    assert np.abs(np.tril(M, -1)).max() > 0.1
    np.testing.assert_allclose(fd.crba(model, q), jmap.matrix_from_pin(M), atol=1e-10)


def test_trouble_gravity_sign_and_energy(pin):
    """Row 7: gravity enters as a base acceleration −g (a body at rest needs +m g up); with τ = 0 energy is conserved."""
    model = _free_body()
    q = fd.neutral(model)
    tau = fd.rnea(model, q, np.zeros(6), np.zeros(6))
    np.testing.assert_allclose(tau[3:], [0.0, 0.0, 2.0 * 9.81], atol=1e-12)  # base frame = world here
    # a 2R arm swinging freely: RK4 with ABA keeps kinetic + potential energy
    from featherdyn import symbolic

    arm = symbolic.two_link_arm(symbolic.APPENDIX_D)

    def f(x):
        return np.concatenate([x[2:], fd.aba(arm, x[:2], x[2:], np.zeros(2))])

    def energy(x):
        return fd.kinetic_energy(arm, x[:2], x[2:]) + fd.potential_energy(arm, x[:2])

    x, h = np.array([0.3, -0.5, 1.0, 0.0]), 2e-3
    e0 = energy(x)
    for _ in range(150):
        k1 = f(x)
        k2 = f(x + h / 2 * k1)
        k3 = f(x + h / 2 * k2)
        k4 = f(x + h * k3)
        x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    assert abs(energy(x) - e0) < 1e-7 * abs(e0)
    assert np.abs(x[:2] - [0.3, -0.5]).max() > 0.05  # it did move


# --------------------------------------------------------------------------
# the notation table
# --------------------------------------------------------------------------


def test_table_lynch_park_operators():
    """Featherstone ↔ Modern Robotics: [Ad_T] = X, [Ad_T]⁻ᵀ = X*, [ad_V] = crm(V), −[ad_V]ᵀ = crf(V); twists equal."""
    rng = np.random.default_rng(7)
    X = fd.PluckerTransform(rpy_to_matrix(rng.normal(size=3)), rng.normal(size=3))
    V = rng.normal(size=6)
    np.testing.assert_allclose(conventions.adjoint_matrix(X.homogeneous()), X.matrix(), atol=1e-15)
    np.testing.assert_allclose(conventions.wrench_transform_matrix(X), np.linalg.inv(X.matrix()).T, atol=1e-13)
    np.testing.assert_allclose(conventions.ad_matrix(V), fd.crm(V), atol=0)
    np.testing.assert_allclose(-conventions.ad_matrix(V).T, fd.crf(V), atol=0)
    np.testing.assert_array_equal(conventions.twist_to_mr(conventions.twist_from_mr(V)), V)
    np.testing.assert_array_equal(conventions.wrench_to_mr(conventions.wrench_from_mr(V)), V)
    V_s = conventions.body_twist_to_spatial_twist(X, V)
    np.testing.assert_allclose(V_s.vector, X.matrix() @ V, atol=1e-13)
    np.testing.assert_allclose(conventions.spatial_twist_to_body_twist(X, V_s).vector, V, atol=1e-13)
    # MR's Newton–Euler F = G dV − [ad_V]ᵀ G V is Featherstone's f = I a + v ×* I v
    I = fd.SpatialInertia(1.5, [0.1, 0.2, -0.1], np.diag([0.02, 0.03, 0.04])).matrix()
    a = rng.normal(size=6)
    np.testing.assert_allclose(I @ a - conventions.ad_matrix(V).T @ I @ V, I @ a + fd.crf(V) @ I @ V, atol=1e-13)


def test_table_drake_world_velocity_is_local_world_aligned():
    """§6 table: Drake's ``V_WB_W`` is the velocity of B's origin in world axes — featherdyn's
    LOCAL_WORLD_ALIGNED — not Featherstone's spatial velocity ⁰v (reference point the world origin, WORLD)."""
    b = fd.ModelBuilder("arm")
    l1 = b.add_body("l1", -1, fd.RevoluteJoint([0, 0, 1]), inertia=fd.SpatialInertia(1.0, [0.3, 0, 0], np.eye(3) * 0.01))
    b.add_body("l2", l1, fd.RevoluteJoint([0, 1, 0]), inertia=fd.SpatialInertia(1.0, [0.3, 0, 0], np.eye(3) * 0.01),
               placement=fd.PluckerTransform(np.eye(3), [0.5, 0.2, 0.1]))
    model = b.build()
    q, v = np.array([0.4, -0.9]), np.array([1.2, -0.7])
    V_WB_B = fd.frame_velocity(model, q, v, "l2", fd.LOCAL)
    R_WB = fd.frame_placement(model, q, "l2").rotation
    V_WB_W = conventions.drake_reexpress(R_WB, V_WB_B)  # Drake: R_WB * V_WB_B
    np.testing.assert_allclose(V_WB_W.vector, fd.frame_velocity(model, q, v, "l2", fd.LOCAL_WORLD_ALIGNED).vector,
                               atol=1e-14)
    world = fd.frame_velocity(model, q, v, "l2", fd.WORLD)  # MR's V_s, Featherstone's ⁰v
    assert np.abs(V_WB_W.linear - world.linear).max() > 0.1
    np.testing.assert_allclose(V_WB_W.angular, world.angular, atol=1e-14)


def test_table_inertia_transform(pin):
    """I_B = X* I_A X⁻¹ (§5.2); MR's G_a = [Ad_T_ba]ᵀ G_b [Ad_T_ba]; Pinocchio's SE3.act(Inertia) with the P M P swap."""
    rng = np.random.default_rng(8)
    X = fd.PluckerTransform(rpy_to_matrix(rng.normal(size=3)), rng.normal(size=3))  # ᴮX_A
    I_A = fd.SpatialInertia(1.5, [0.1, 0.2, -0.1], np.diag([0.02, 0.03, 0.04]))
    I_B = X.apply(I_A).matrix()
    np.testing.assert_allclose(I_B, X.dual_matrix() @ I_A.matrix() @ X.inverse().matrix(), atol=1e-13)
    Ad_AB = conventions.adjoint_matrix(X.inverse())  # T_ab: pose of B in A
    np.testing.assert_allclose(Ad_AB.T @ I_A.matrix() @ Ad_AB, I_B, atol=1e-13)
    theirs = conventions.transform_to_pinocchio_se3(X).act(conventions.to_pinocchio_inertia(I_A))
    np.testing.assert_allclose(conventions.matrix6_from_pinocchio(theirs.matrix()), I_B, atol=1e-13)
    np.testing.assert_allclose(conventions.from_pinocchio_inertia(theirs).matrix(), I_B, atol=1e-13)


def test_table_joint_layouts(pin):
    """Continuous and planar joints: featherdyn stores θ, Pinocchio (cos θ, sin θ); Jacobians swap rows."""
    theta = np.array([0.3, -2.0])
    cs = conventions.continuous_q_to_pinocchio(theta)
    np.testing.assert_allclose(cs, np.stack([np.cos(theta), np.sin(theta)], axis=-1), atol=1e-15)
    np.testing.assert_allclose(conventions.continuous_q_from_pinocchio(cs), theta, atol=1e-15)
    qp = np.array([0.1, 0.2, 0.7])
    np.testing.assert_allclose(conventions.planar_q_to_pinocchio(qp), [0.1, 0.2, np.cos(0.7), np.sin(0.7)], atol=1e-15)
    np.testing.assert_allclose(conventions.planar_q_from_pinocchio(conventions.planar_q_to_pinocchio(qp)), qp, atol=1e-15)
    np.testing.assert_array_equal(conventions.planar_v_to_pinocchio([3.0, 1.0, 2.0]), [1.0, 2.0, 3.0])
    np.testing.assert_array_equal(conventions.planar_v_from_pinocchio([1.0, 2.0, 3.0]), [3.0, 1.0, 2.0])
    J = np.arange(12.0).reshape(6, 2)
    np.testing.assert_array_equal(conventions.jacobian_to_pinocchio(J), J[[3, 4, 5, 0, 1, 2]])
    np.testing.assert_array_equal(conventions.jacobian_from_pinocchio(conventions.jacobian_to_pinocchio(J)), J)
    q = np.array([0.0, 0.0, 0.0, 0.0, 0.0, np.sin(0.2), np.cos(0.2)])
    np.testing.assert_allclose(conventions.quat_wxyz_to_xyzw(conventions.quat_xyzw_to_wxyz(q[3:])), q[3:], atol=0)


# --------------------------------------------------------------------------
# the docs cite only what exists
# --------------------------------------------------------------------------


def _read(name: str) -> str:
    path = DOCS / name
    assert path.is_file(), f"missing {path}"
    return path.read_text(encoding="utf-8")


def test_conventions_md_names_exist():
    text = _read("conventions.md")
    names = set(re.findall(r"conventions\.([A-Za-z_][A-Za-z0-9_]*)", text)) - {"py", "md"}
    assert len(names) >= 30, "docs/conventions.md should cite the converters by name"
    missing = sorted(n for n in names if not hasattr(conventions, n))
    assert not missing, f"docs/conventions.md cites conventions.{missing}, which do not exist"


def _cited_paths(text: str) -> set[str]:
    return set(re.findall(r"((?:examples|tests|src|docs)/[A-Za-z0-9_./-]+\.(?:py|md))", text))


def _cited_test_ids(text: str) -> set[tuple[str, str]]:
    return set(re.findall(r"(tests/[A-Za-z0-9_/]+\.py)::([A-Za-z_][A-Za-z0-9_]*)", text))


@pytest.mark.parametrize("doc", ["errata.md", "conventions.md"])
def test_cited_paths_and_tests_exist(doc):
    text = _read(doc)
    paths = _cited_paths(text)
    assert paths, f"docs/{doc} cites no scripts or tests"
    missing = sorted(p for p in paths if not (ROOT / p).is_file())
    assert not missing, f"docs/{doc} cites missing files: {missing}"
    for path, test in _cited_test_ids(text):
        source = (ROOT / path).read_text(encoding="utf-8")
        assert re.search(rf"^def {re.escape(test)}\(", source, re.M), f"docs/{doc}: {path}::{test} not found"


def test_every_erratum_cites_evidence():
    """Each ``### `` entry of docs/errata.md names a script or a test."""
    text = _read("errata.md")
    entries = re.split(r"^### ", text, flags=re.M)[1:]
    assert len(entries) >= 15
    for entry in entries:
        title = entry.splitlines()[0]
        assert _cited_paths(entry), f"erratum {title!r} cites no script or test"


def test_conventions_md_cites_every_pitfall_test():
    text = _read("conventions.md")
    here = Path(__file__).read_text(encoding="utf-8")
    tests = set(re.findall(r"^def (test_(?:pitfall|trouble|table)_[a-z0-9_]+)\(", here, re.M))
    missing = sorted(t for t in tests if t not in text)
    assert not missing, f"docs/conventions.md does not cite {missing}"
