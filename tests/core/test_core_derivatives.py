"""The core's derivatives (``cpp/derivatives.hpp``) against Pinocchio 4.1, central differences and identities.

* ∂τ/∂q, ∂τ/∂q̇ (forward-mode differentiation of the RNEA template) against
  ``computeRNEADerivatives``; ∂q̈/∂q, ∂q̈/∂q̇, M⁻¹ against ``computeABADerivatives``
  (free-flyer columns mapped to Pinocchio's ``[v; ω]`` layout; both take q's
  derivative along the body-frame tangent);
* on the random trees — every joint type, planar included — against central
  differences along ``fd.integrate`` (∂/∂q) and along q̇;
* M⁻¹ M = 1; ∂q̈/∂q = −M⁻¹ ∂τ/∂q at q̈ = ABA(q, q̇, τ); a batch equals its rows bit for bit.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from _core_helpers import assert_rel, robot
from _models import TREES, random_state, tree

import featherdyn as fd
from featherdyn import core

pin = pytest.importorskip("pinocchio")


@pytest.mark.parametrize(("name", "floating"), [("panda", False), ("solo12", True), ("talos_full_v2", True),
                                                ("ur5_robot", False), ("anymal-kinova", True)])
def test_against_pinocchio(name: str, floating: bool) -> None:
    from featherdyn.robots import robot_path
    from featherdyn.verify.bridge import JointMap

    model = robot(name, floating)
    assert model is not None
    path = str(robot_path(name))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(path)
    pd = pm.createData()
    jm = JointMap(model, pm)
    rng = np.random.default_rng(4)
    q = fd.random_configuration(model, rng)
    v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
    f = rng.normal(size=(model.nbodies, 6))
    dq, dv, M = core.rnea_derivatives(model, q, v, a)
    pin.computeRNEADerivatives(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(a))
    assert_rel(dq, jm.matrix_from_pin(pd.dtau_dq.copy()), f"{name}: dtau_dq")
    assert_rel(dv, jm.matrix_from_pin(pd.dtau_dv.copy()), f"{name}: dtau_dv")
    assert_rel(M, fd.crba(model, q), f"{name}: dtau_da = M")
    tau = fd.rnea(model, q, v, a)
    ddq_dq, ddq_dv, Minv = core.aba_derivatives(model, q, v, tau)
    pin.computeABADerivatives(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(tau))
    scale = float(np.linalg.cond(M))  # ABA's derivatives carry M⁻¹: relative error up to cond(M) × round-off
    assert_rel(ddq_dq, jm.matrix_from_pin(pd.ddq_dq.copy()), f"{name}: ddq_dq", rtol=1e-14 * scale)
    assert_rel(ddq_dv, jm.matrix_from_pin(pd.ddq_dv.copy()), f"{name}: ddq_dv", rtol=1e-14 * scale)
    Mi = pd.Minv.copy()
    assert_rel(Minv, jm.matrix_from_pin(np.triu(Mi) + np.triu(Mi, 1).T), f"{name}: Minv", rtol=1e-14 * scale)
    # with external forces (body frames, Pinocchio's LOCAL fext)
    dq_f, _, _ = core.rnea_derivatives(model, q, v, a, f_ext=f)
    fd_dq = _central(lambda x: fd.rnea(model, x, v, a, f_ext=f), model, q)
    assert_rel(dq_f, fd_dq, f"{name}: dtau_dq with f_ext vs central differences", rtol=1e-6)


def _central(fun, model: fd.Model, q: np.ndarray, eps: float = 1e-6) -> np.ndarray:  # type: ignore[no-untyped-def]
    cols = [(fun(fd.integrate(model, q, eps * e)) - fun(fd.integrate(model, q, -eps * e))) / (2 * eps)
            for e in np.eye(model.nv)]
    return np.stack(cols, axis=-1)


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_against_central_differences_on_every_joint_type(spec) -> None:  # type: ignore[no-untyped-def]
    model = tree(spec.name)
    st = random_state(model, 21)
    dq, dv, _ = core.rnea_derivatives(model, st.q, st.v, st.a, f_ext=st.f_ext)
    assert_rel(dq, _central(lambda x: fd.rnea(model, x, st.v, st.a, st.f_ext), model, st.q), f"{spec.name}: dtau_dq",
               rtol=1e-6)
    dv_fd = np.stack([(fd.rnea(model, st.q, st.v + 1e-6 * e, st.a, st.f_ext)
                       - fd.rnea(model, st.q, st.v - 1e-6 * e, st.a, st.f_ext)) / 2e-6 for e in np.eye(model.nv)], -1)
    assert_rel(dv, dv_fd, f"{spec.name}: dtau_dv", rtol=1e-6)
    M = fd.crba(model, st.q)
    Minv = core.mass_matrix_inverse(model, st.q)
    assert_rel(Minv @ M, np.eye(model.nv), f"{spec.name}: Minv M", rtol=1e-10)
    assert np.array_equal(Minv, Minv.T)
    tau = fd.rnea(model, st.q, st.v, st.a)
    ddq_dq, ddq_dv, _ = core.aba_derivatives(model, st.q, st.v, tau)
    assert_rel(ddq_dq, -Minv @ core.rnea_derivatives(model, st.q, st.v, fd.aba(model, st.q, st.v, tau))[0],
               f"{spec.name}: ddq_dq = -Minv dtau_dq", rtol=1e-12)
    ddq_fd = _central(lambda x: fd.aba(model, x, st.v, tau), model, st.q)
    assert_rel(ddq_dq, ddq_fd, f"{spec.name}: ddq_dq vs central differences", rtol=1e-5)


def test_a_batch_equals_its_rows() -> None:
    model = tree("free_branch")
    st = random_state(model, 22, (5,))
    dq, dv, M = core.rnea_derivatives(model, st.q, st.v, st.a)
    for k in range(5):
        one = core.rnea_derivatives(model, st.q[k], st.v[k], st.a[k])
        assert np.array_equal(dq[k], one[0]) and np.array_equal(dv[k], one[1]) and np.array_equal(M[k], one[2])
    Minv = core.mass_matrix_inverse(model, st.q)
    assert all(np.array_equal(Minv[k], core.mass_matrix_inverse(model, st.q[k])) for k in range(5))


def test_bad_input_and_singular_mass_matrix() -> None:
    model = tree("free_chain")
    st = random_state(model, 23)
    with pytest.raises(fd.errors.ShapeError, match="^v"):
        core.rnea_derivatives(model, st.q, st.v[:-1], st.a)
    bad = st.q.copy()
    bad[3:7] *= 2
    with pytest.raises(fd.errors.QuaternionNormError):
        core.aba_derivatives(model, bad, st.v, st.a)
    b = fd.ModelBuilder("massless")
    b.add_body("link", parent=-1, joint=fd.RevoluteJoint([0, 0, 1]), joint_name="j",
               inertia=fd.SpatialInertia(0.0, [0, 0, 0], np.zeros((3, 3))))
    with pytest.warns(fd.PhysicalityWarning):
        massless = b.build()
    with pytest.raises(fd.errors.SingularMassMatrixError, match="'j'") as info:
        core.mass_matrix_inverse(massless, np.zeros(1))
    with pytest.raises(fd.errors.SingularMassMatrixError) as ref:
        fd.aba(massless, np.zeros(1), np.zeros(1), np.zeros(1), backend="reference")
    assert str(info.value) == str(ref.value)
    with pytest.raises(fd.errors.SingularMassMatrixError, match="'j'"):  # a batch: packed lanes, then row by row
        core.aba_derivatives(massless, np.zeros((19, 1)), np.zeros((19, 1)), np.zeros((19, 1)))


@pytest.mark.parametrize(("name", "floating", "frame"), [("panda", False, "panda_hand"), ("solo12", True, "HR_FOOT")])
def test_frame_motion_derivatives_against_pinocchio(name: str, floating: bool, frame: str) -> None:
    """LOCAL and WORLD: Pinocchio's getFrame{Velocity,Acceleration}Derivatives to round-off. LOCAL_WORLD_ALIGNED:
    ours is the derivative of ``fd.frame_velocity(…, LOCAL_WORLD_ALIGNED)`` itself, whose reference point (the
    frame's origin) moves with q; Pinocchio keeps the point fixed, so its linear rows lack ``ω × J_v[:, j]``
    (velocity) and ``ω̇ × J_v[:, j]`` (acceleration)."""
    from featherdyn.robots import robot_path
    from featherdyn.verify.bridge import JointMap

    model = robot(name, floating)
    assert model is not None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        path = str(robot_path(name))
        pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(path)
    pd, jm = pm.createData(), JointMap(model, pm)
    rng = np.random.default_rng(6)
    q = fd.random_configuration(model, rng)
    v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
    pin.computeForwardKinematicsDerivatives(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(a))
    fid = pm.getFrameId(frame)

    def ours_layout(m_pin: np.ndarray) -> np.ndarray:  # rows [v; ω] → [ω; v], columns to featherdyn's joints
        m_pin = np.asarray(m_pin).copy()
        return jm.columns_from_pin(np.concatenate([m_pin[3:], m_pin[:3]], axis=0))

    for ref, pin_ref in ((fd.LOCAL, pin.LOCAL), (fd.WORLD, pin.WORLD), (fd.LOCAL_WORLD_ALIGNED, pin.LOCAL_WORLD_ALIGNED)):
        dv_dq, dv_dv = core.frame_velocity_derivatives(model, q, v, frame, ref)
        da_dq, da_dv, da_da = core.frame_acceleration_derivatives(model, q, v, a, frame, ref)
        pv = [ours_layout(x) for x in pin.getFrameVelocityDerivatives(pm, pd, fid, pin_ref)]
        pa = [ours_layout(x) for x in pin.getFrameAccelerationDerivatives(pm, pd, fid, pin_ref)]
        if ref is fd.LOCAL_WORLD_ALIGNED:
            J = fd.frame_jacobian(model, q, frame, ref)
            w = (J @ v)[:3]
            wdot = fd.frame_acceleration(model, q, v, a, frame, ref).vector[:3]
            pv[0][3:] += np.cross(w, J[3:].T).T
            pa[1][3:] += np.cross(wdot, J[3:].T).T
        label = f"{name} {ref.name}"
        assert_rel(dv_dq, pv[0], f"{label}: dv_dq")
        assert_rel(dv_dv, pv[1], f"{label}: dv_dv")
        assert_rel(da_dq, pa[1], f"{label}: da_dq")
        assert_rel(da_dv, pa[2], f"{label}: da_dv")
        assert_rel(da_da, pa[3], f"{label}: da_da")
        assert_rel(dv_dv, fd.frame_jacobian(model, q, frame, ref), f"{label}: dv_dv = J")
        assert_rel(da_da, fd.frame_jacobian(model, q, frame, ref), f"{label}: da_da = J")


@pytest.mark.parametrize("spec", TREES[2:5], ids=lambda s: s.name)
def test_frame_motion_derivatives_against_central_differences(spec) -> None:  # type: ignore[no-untyped-def]
    model = tree(spec.name)
    st = random_state(model, 24)
    frame = model.frames[-1].name
    for ref in (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED):
        dv_dq, _ = core.frame_velocity_derivatives(model, st.q, st.v, frame, ref)
        da_dq, da_dv, _ = core.frame_acceleration_derivatives(model, st.q, st.v, st.a, frame, ref)
        assert_rel(dv_dq, _central(lambda x: fd.frame_velocity(model, x, st.v, frame, ref).vector, model, st.q),
                   f"{spec.name} {ref.name}: dv_dq", rtol=1e-6)
        assert_rel(da_dq, _central(lambda x: fd.frame_acceleration(model, x, st.v, st.a, frame, ref).vector, model,
                                   st.q), f"{spec.name} {ref.name}: da_dq", rtol=1e-6)
        dv = np.stack([(fd.frame_acceleration(model, st.q, st.v + 1e-6 * e, st.a, frame, ref).vector
                        - fd.frame_acceleration(model, st.q, st.v - 1e-6 * e, st.a, frame, ref).vector) / 2e-6
                       for e in np.eye(model.nv)], -1)
        assert_rel(da_dv, dv, f"{spec.name} {ref.name}: da_dv", rtol=1e-6)


@pytest.mark.parametrize(("name", "floating"), [("panda", False), ("solo12", True)])
def test_regressor_against_pinocchio(name: str, floating: bool) -> None:
    """Rows mapped to featherdyn's v, column blocks of ten to featherdyn's bodies by joint name."""
    from featherdyn.robots import robot_path
    from featherdyn.verify.bridge import JointMap

    model = robot(name, floating)
    assert model is not None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        path = str(robot_path(name))
        pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else pin.buildModelFromUrdf(path)
    pd, jm = pm.createData(), JointMap(model, pm)
    rng = np.random.default_rng(8)
    q = fd.random_configuration(model, rng)
    v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
    Y = core.joint_torque_regressor(model, q, v, a)
    Yp = pin.computeJointTorqueRegressor(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(a)).copy()
    rows = np.stack([jm.v_from_pin(Yp[:, c]) for c in range(Yp.shape[1])], axis=1)
    blocks = [rows[:, 10 * (pm.getJointId(n) - 1): 10 * pm.getJointId(n)] for n in model.joint_names]
    assert_rel(Y, np.concatenate(blocks, axis=1), f"{name}: regressor")


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_regressor_times_parameters_is_rnea(spec) -> None:  # type: ignore[no-untyped-def]
    model = tree(spec.name)
    st = random_state(model, 25, (3,))
    pi = np.concatenate([model.inertias[i].to_dynamic_parameters() for i in range(model.nbodies)])
    Y = core.joint_torque_regressor(model, st.q, st.v, st.a)
    assert Y.shape == (3, model.nv, 10 * model.nbodies)
    assert_rel(Y @ pi, fd.rnea(model, st.q, st.v, st.a), f"{spec.name}: Y π = τ")


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_analytical_rnea_derivatives_equal_forward_mode_differentiation(spec) -> None:  # type: ignore[no-untyped-def]
    """Two independent derivations in the core: the hand-written analytical algorithm and the RNEA template
    on Dual numbers (one does not know the other's formulas) agree to round-off on every joint type."""
    from featherdyn.core import _core

    model = tree(spec.name)
    st = random_state(model, 26)
    dq, dv, _ = core.rnea_derivatives(model, st.q, st.v, st.a)
    dq_dual, dv_dual = np.empty(model.nv * model.nv), np.empty(model.nv * model.nv)
    assert _core.rnea_derivatives_dual(core._view(model).cm, st.q, st.v, st.a, dq_dual, dv_dual) == 0
    assert_rel(dq, dq_dual.reshape(model.nv, model.nv), f"{spec.name}: dtau_dq", rtol=1e-13)
    assert_rel(dv, dv_dual.reshape(model.nv, model.nv), f"{spec.name}: dtau_dv", rtol=1e-13)


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_complex_step_through_the_complex_instantiation(spec) -> None:  # type: ignore[no-untyped-def]
    """∂τ/∂q by the complex step through the RNEA template's std::complex<double> instantiation: q moved by
    i h along the tangent's coordinate directions (d(q ⊕ δ)/dδ; a unit quaternion's direction is orthogonal
    to it, so its norm is unchanged to first order); h = 1e-30 leaves no truncation error."""
    from featherdyn.conventions.derivatives import _tangent_to_coordinates

    model = tree(spec.name)
    st = random_state(model, 27)
    Q = _tangent_to_coordinates(model, st.q)
    h = 1e-30
    cols = [np.imag(core.rnea_complex(model, st.q + 1j * h * Q[:, j], st.v, st.a)) / h for j in range(model.nv)]
    dq, _, _ = core.rnea_derivatives(model, st.q, st.v, st.a)
    assert_rel(np.stack(cols, axis=-1), dq, f"{spec.name}: complex step vs analytical RNEA derivatives", rtol=1e-12)


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_batched_derivatives_use_the_simd_lanes_and_equal_the_rows(spec) -> None:  # type: ignore[no-untyped-def]
    """19 states: full packs of 2, 4 or 8 lanes and a tail; every row equals its one-state derivative."""
    model = tree(spec.name)
    st = random_state(model, 28, (19,))
    dq, dv, _ = core.rnea_derivatives(model, st.q, st.v, st.a, f_ext=st.f_ext)
    for k in range(19):
        one = core.rnea_derivatives(model, st.q[k], st.v[k], st.a[k], f_ext=st.f_ext[k])
        assert np.array_equal(dq[k], one[0]) and np.array_equal(dv[k], one[1]), (spec.name, k)
    tau = fd.rnea(model, st.q, st.v, st.a)
    abad = core.aba_derivatives(model, st.q, st.v, tau, f_ext=st.f_ext)
    for k in range(19):
        one = core.aba_derivatives(model, st.q[k], st.v[k], tau[k], f_ext=st.f_ext[k])
        assert all(np.array_equal(x[k], y) for x, y in zip(abad, one)), (spec.name, k)


def test_batched_derivatives_write_into_out() -> None:
    """``out=``: the three arrays given are the results (equal to fresh ones bit for bit); wrong outputs are
    refused before any work."""
    model = tree("free_branch")
    st = random_state(model, 29, (6,))
    tau = fd.rnea(model, st.q, st.v, st.a)
    cm = fd.compile(model)
    nv = model.nv
    for method, third in ((cm.rnea_derivatives_batch, st.a), (cm.aba_derivatives_batch, tau)):
        fresh = method(st.q, st.v, third)
        outs = tuple(np.full((6, nv, nv), np.nan) for _ in range(3))
        got = method(st.q, st.v, third, out=outs)
        assert all(g is o for g, o in zip(got, outs))
        assert all(np.array_equal(g, f) for g, f in zip(got, fresh))
        with pytest.raises(fd.errors.ShapeError, match="expected 3 arrays"):
            method(st.q, st.v, third, out=outs[0])
        with pytest.raises(fd.errors.ShapeError, match=r"out: expected shape \(6, "):
            method(st.q, st.v, third, out=(outs[0], outs[1], np.empty((5, nv, nv))))
        with pytest.raises(fd.errors.DTypeError, match="float64 results .* float32"):
            method(st.q, st.v, third, out=(outs[0], outs[1], np.empty((6, nv, nv), np.float32)))
        with pytest.raises(fd.errors.ShapeError, match="share memory"):
            method(st.q, st.v, third, out=(outs[0], outs[0], outs[2]))


def _two_trees() -> fd.Model:
    """Two trees hanging from the world (a spherical root with a revolute child, a prismatic root with a
    revolute child and armature): each tree's quantities live in its own root body's coordinates."""
    b = fd.ModelBuilder("two_trees")
    box = fd.SpatialInertia.box(1.3, [0.2, 0.1, 0.3])
    a = b.add_body("a0", -1, fd.SphericalJoint(), inertia=box, placement=fd.xlt([0.3, -0.2, 0.5]))
    b.add_body("a1", a, fd.RevoluteJoint([0, 1, 0]), inertia=box, placement=fd.xlt([0.0, 0.0, 0.4]))
    c = b.add_body("b0", -1, fd.PrismaticJoint([1, 0, 0]), inertia=box, placement=fd.rotz(0.7))
    b.add_body("b1", c, fd.RevoluteJoint([0, 0, 1]), inertia=box, placement=fd.xlt([0.2, 0.1, 0.0]), armature=0.05)
    return b.build()


def test_two_root_trees_against_forward_mode_and_the_reference() -> None:
    from featherdyn.core import _core

    model = _two_trees()
    st = random_state(model, 31)
    dq, dv, M = core.rnea_derivatives(model, st.q, st.v, st.a)
    dq_dual, dv_dual = np.empty(model.nv * model.nv), np.empty(model.nv * model.nv)
    assert _core.rnea_derivatives_dual(core._view(model).cm, st.q, st.v, st.a, dq_dual, dv_dual) == 0
    assert_rel(dq, dq_dual.reshape(model.nv, model.nv), "two trees: dtau_dq", rtol=1e-13)
    assert_rel(dv, dv_dual.reshape(model.nv, model.nv), "two trees: dtau_dv", rtol=1e-13)
    assert_rel(M, fd.crba(model, st.q), "two trees: M (with armature)", rtol=1e-14)
    ref = fd.rnea_derivatives(model, st.q, st.v, st.a, backend="reference")
    assert_rel(dq, ref[0], "two trees: reference dtau_dq", rtol=1e-13)
    assert_rel(dv, ref[1], "two trees: reference dtau_dv", rtol=1e-13)
    tau = fd.rnea(model, st.q, st.v, st.a)
    ddq_dq, ddq_dv, Minv = core.aba_derivatives(model, st.q, st.v, tau)
    assert_rel(Minv @ M, np.eye(model.nv), "two trees: M⁻¹ M", rtol=1e-13)
    assert_rel(ddq_dq, -Minv @ dq, "two trees: ddq_dq", rtol=1e-12)
    assert_rel(ddq_dv, -Minv @ dv, "two trees: ddq_dv", rtol=1e-12)


def test_a_floating_base_far_from_the_origin_changes_no_digit_that_matters() -> None:
    """Uniform gravity: translating the whole robot changes neither τ nor its derivatives along the body-frame
    tangent. Every quantity lives in the root body's coordinates, so 10⁶ m away loses no digits (a world-frame
    formulation carries lever arms of 10⁶ m into every product)."""
    model = robot("solo12", floating=True)
    st = random_state(model, 32)
    tau = fd.rnea(model, st.q, st.v, st.a)
    near = core.rnea_derivatives(model, st.q, st.v, st.a), core.aba_derivatives(model, st.q, st.v, tau)
    far_q = st.q.copy()
    far_q[:3] += [1e6, -2e6, 3e5]
    far = core.rnea_derivatives(model, far_q, st.v, st.a), core.aba_derivatives(model, far_q, st.v, tau)
    for x, y in zip(near[0] + near[1], far[0] + far[1]):
        assert_rel(y, x, "solo12 10⁶ m away", rtol=1e-12)


def test_batched_aba_derivatives_of_a_long_chain_equal_the_rows() -> None:
    """70 dofs: above the packed-solve size the batch factors and solves lane by lane; rows still equal their
    one-state results bit for bit."""
    b = fd.ModelBuilder("chain70")
    parent = -1
    for k in range(70):
        axis = np.eye(3)[k % 3]
        parent = b.add_body(f"l{k}", parent, fd.RevoluteJoint(axis), placement=fd.xlt([0.0, 0.05, 0.1]),
                            inertia=fd.SpatialInertia.box(0.5, [0.05, 0.04, 0.1]))
    model = b.build()
    st = random_state(model, 33, (9,))
    tau = fd.rnea(model, st.q, st.v, st.a)
    batch = core.aba_derivatives(model, st.q, st.v, tau)
    for k in range(9):
        one = core.aba_derivatives(model, st.q[k], st.v[k], tau[k])
        assert all(np.array_equal(x[k], y) for x, y in zip(batch, one)), k
    assert_rel(batch[2][0] @ fd.crba(model, st.q[0]), np.eye(70), "chain70: M⁻¹ M", rtol=1e-9)


_ONE_STATE_SCRIPT = """
import hashlib, sys
import numpy as np
sys.path.insert(0, {tests!r})
from _models import library_robot
import featherdyn as fd
from featherdyn import core
print(core._core.simd()[0])
h = hashlib.sha256()
def take(*arrays):
    for a in arrays:
        h.update(np.ascontiguousarray(a, dtype=np.float64).tobytes())
rng = np.random.default_rng(3)
model = library_robot("solo12", True)
feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
for k in range(3):
    q = fd.random_configuration(model, rng)
    v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
    tau = fd.rnea(model, q, v, a) * 0.5
    take(*fd.rnea_derivatives(model, q, v, a), *fd.aba_derivatives(model, q, v, tau), fd.mass_matrix_inverse(model, q))
    take(*fd.rnea_second_derivatives(model, q, v, a), *fd.aba_second_derivatives(model, q, v, tau))
    for ref in (fd.LOCAL, fd.LOCAL_WORLD_ALIGNED, fd.WORLD):
        points = [fd.PointContact(f, reference=ref) for f in feet]
        frames = [fd.FrameContact(f, reference=ref) for f in feet[:2]]
        for cons in (points, frames):
            d = fd.constrained_dynamics_derivatives(model, q, v, tau, cons)
            take(d.ddq_dq, d.ddq_dv, d.ddq_dtau, d.forces_dq, d.forces_dv, d.forces_dtau)
            i = fd.impulse_dynamics_derivatives(model, q, v, cons, restitution=0.3)
            take(i.dv_plus_dq, i.dv_plus_dv, i.impulses_dq, i.impulses_dv, i.v_plus)
print(h.hexdigest())
"""


def test_one_state_kernels_are_the_same_bits_under_every_instruction_set() -> None:
    """The one-state kernels compiled per instruction set (groups.hpp: the RNEA and ABA derivatives, M⁻¹, the
    contacts' derivatives, the second order) give the same bits with the baseline, AVX2 and AVX-512 builds
    (FEATHERDYN_SIMD in fresh processes; a set the CPU lacks falls back to a narrower one): each entry sees the
    same operations in the same order, only the registers' width differs."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    tests = str(Path(__file__).resolve().parents[1])
    digests = {}
    for isa in ("baseline", "avx2", "avx512"):
        res = subprocess.run([sys.executable, "-c", _ONE_STATE_SCRIPT.format(tests=tests)],
                             env=dict(os.environ, FEATHERDYN_SIMD=isa), capture_output=True, text=True, timeout=300)
        assert res.returncode == 0, res.stderr[-2000:]
        used, digest = res.stdout.split()
        digests[used] = digest
    assert "baseline" in digests
    assert len(set(digests.values())) == 1, digests
