"""The public derivatives (``fd.rnea_derivatives`` & co.) against Pinocchio 4.1, finite differences and identities.

Both implementations are checked: the compiled core (float64, the default) and
the NumPy reference (``backend="reference"``), each against Pinocchio's
``computeRNEADerivatives`` / ``computeABADerivatives`` / ``computeMinverse`` /
``computeJointTorqueRegressor`` with joints mapped by name and the
free-flyer's ``[v; ω]`` converted; on every library robot the cheap identities
``Y π = τ`` and ``∂τ/∂q̈ = M``.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from _models import TREES, library_robot, library_robot_names, pinocchio_pair, random_state, tree

import featherdyn as fd
from featherdyn.testing import assert_close

pin = pytest.importorskip("pinocchio")

PAIRS = [("panda", False), ("solo12", True), ("ur5_robot", False), ("anymal-kinova", True), ("talos_full_v2", True)]


_pin_pair = pinocchio_pair


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / max(1.0, np.abs(b).max()))


@pytest.mark.parametrize("backend", [None, "reference"])
@pytest.mark.parametrize(("name", "floating"), PAIRS)
def test_against_pinocchio(name: str, floating: bool, backend: str | None) -> None:
    model, pm, pd, jm = _pin_pair(name, floating)
    rng = np.random.default_rng(11)
    q = fd.random_configuration(model, rng)
    v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
    qp, vp, ap = jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(a)
    dq, dv, da = fd.rnea_derivatives(model, q, v, a, backend=backend)
    pin.computeRNEADerivatives(pm, pd, qp, vp, ap)
    assert _rel(dq, jm.matrix_from_pin(pd.dtau_dq.copy())) < 1e-12
    assert _rel(dv, jm.matrix_from_pin(pd.dtau_dv.copy())) < 1e-12
    assert _rel(da, fd.crba(model, q)) < 1e-13
    tau = fd.rnea(model, q, v, a)
    ddq_dq, ddq_dv, Minv = fd.aba_derivatives(model, q, v, tau, backend=backend)
    pin.computeABADerivatives(pm, pd, qp, vp, jm.v_to_pin(tau))
    cond = float(np.linalg.cond(da))
    assert _rel(ddq_dq, jm.matrix_from_pin(pd.ddq_dq.copy())) < 1e-14 * cond
    assert _rel(ddq_dv, jm.matrix_from_pin(pd.ddq_dv.copy())) < 1e-14 * cond
    Mi = pin.computeMinverse(pm, pd, qp).copy()
    assert _rel(fd.mass_matrix_inverse(model, q, backend=backend), jm.matrix_from_pin(np.triu(Mi) + np.triu(Mi, 1).T)) \
        < 1e-14 * cond
    assert _rel(Minv, fd.mass_matrix_inverse(model, q)) < 1e-14 * cond
    Y = fd.joint_torque_regressor(model, q, v, a, backend=backend)
    Yp = pin.computeJointTorqueRegressor(pm, pd, qp, vp, ap).copy()
    rows = np.stack([jm.v_from_pin(Yp[:, c]) for c in range(Yp.shape[1])], axis=1)
    blocks = [rows[:, 10 * (pm.getJointId(n) - 1): 10 * pm.getJointId(n)] for n in model.joint_names]
    assert _rel(Y, np.concatenate(blocks, axis=1)) < 1e-12


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_reference_equals_core_on_every_joint_type(spec) -> None:  # type: ignore[no-untyped-def]
    model = tree(spec.name)
    st = random_state(model, 12, (2,))
    for ref, comp in zip(fd.rnea_derivatives(model, st.q, st.v, st.a, st.f_ext, backend="reference"),
                         fd.rnea_derivatives(model, st.q, st.v, st.a, st.f_ext), strict=True):
        assert_close(ref, comp, f"{spec.name}: rnea_derivatives", scale=max(1.0, float(np.abs(comp).max())))
    tau = fd.rnea(model, st.q, st.v, st.a)
    for ref, comp in zip(fd.aba_derivatives(model, st.q, st.v, tau, backend="reference"),
                         fd.aba_derivatives(model, st.q, st.v, tau), strict=True):
        assert _rel(ref, comp) < 1e-9, spec.name
    assert _rel(fd.joint_torque_regressor(model, st.q, st.v, st.a, backend="reference"),
                fd.joint_torque_regressor(model, st.q, st.v, st.a)) < 1e-12


@pytest.mark.parametrize("floating", [False, True], ids=["fixed", "floating"])
def test_regressor_times_parameters_is_rnea_on_every_robot(floating: bool) -> None:
    checked = 0
    for name in library_robot_names():
        model = library_robot(name, floating)
        if model is None or model.nv == 0:
            continue
        rng = np.random.default_rng(13)
        q = fd.random_configuration(model, rng)
        v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
        tau = fd.rnea(model, q, v, a)
        Y = fd.joint_torque_regressor(model, q, v, a)
        assert _rel(Y @ fd.dynamic_parameters(model), tau) < 1e-12, name
        assert _rel(fd.rnea_derivatives(model, q, v, a)[2], fd.crba(model, q)) < 1e-13, name
        checked += 1
    assert checked >= 60


def test_float32_batches_and_bad_input() -> None:
    model = tree("free_branch")
    st = random_state(model, 14, (3,))
    dq64 = fd.rnea_derivatives(model, st.q, st.v, st.a)[0]
    dq32 = fd.rnea_derivatives(model, st.q.astype(np.float32), st.v.astype(np.float32), st.a.astype(np.float32))[0]
    assert dq32.dtype == np.float32 and dq32.shape == (3, model.nv, model.nv)
    assert _rel(dq32.astype(np.float64), dq64) < 1e-3
    assert np.array_equal(fd.rnea_derivatives(model, st.q[1], st.v[1], st.a[1])[0], dq64[1])
    with pytest.raises(fd.ShapeError, match="^v"):
        fd.rnea_derivatives(model, st.q, st.v[..., :-1], st.a)
    with pytest.raises(fd.NonFiniteError):
        fd.aba_derivatives(model, st.q, np.full_like(st.v, np.nan), st.a)
    for ref_frame in (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED):  # the two implementations agree
        name = model.frames[-1].name
        for x, y in zip(fd.frame_acceleration_derivatives(model, st.q, st.v, st.a, name, ref_frame, backend="reference"),
                        fd.frame_acceleration_derivatives(model, st.q, st.v, st.a, name, ref_frame), strict=True):
            assert _rel(x, y) < 1e-12
        for x, y in zip(fd.frame_velocity_derivatives(model, st.q, st.v, name, ref_frame, backend="reference"),
                        fd.frame_velocity_derivatives(model, st.q, st.v, name, ref_frame), strict=True):
            assert _rel(x, y) < 1e-12
    with pytest.raises(fd.ModelError):
        fd.frame_velocity_derivatives(model, st.q, st.v, "no such frame")


def test_frame_derivatives_public_equal_the_core() -> None:
    from featherdyn import core

    model = tree("fixed_branch_mixed")
    st = random_state(model, 15)
    frame = model.frames[-1].name
    for ref in (fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED):
        pub = fd.frame_acceleration_derivatives(model, st.q, st.v, st.a, frame, ref)
        mine = core.frame_acceleration_derivatives(model, st.q, st.v, st.a, frame, ref)
        assert all(np.array_equal(x, y) for x, y in zip(pub, mine, strict=True))
        dv_dq, dv_dv = fd.frame_velocity_derivatives(model, st.q, st.v, frame, ref)
        assert _rel(dv_dv, fd.frame_jacobian(model, st.q, frame, ref)) < 1e-14


def test_integrate_and_difference_derivatives_against_pinocchio() -> None:
    model, pm, _, jm = _pin_pair("solo12", True)
    rng = np.random.default_rng(16)
    for scale in (1.0, 1e-3, 0.0):  # an ordinary step, a small one (the series branch), none
        q = fd.random_configuration(model, rng)
        v = scale * rng.normal(size=model.nv)
        q1 = fd.integrate(model, q, v)
        Jq, Jv = fd.integrate_derivatives(model, q, v)
        J0, J1 = fd.difference_derivatives(model, q, q1)
        qp, vp, q1p = jm.q_to_pin(q), jm.v_to_pin(v), jm.q_to_pin(q1)
        for mine, arg, fun, b in ((Jq, pin.ARG0, pin.dIntegrate, vp), (Jv, pin.ARG1, pin.dIntegrate, vp),
                                  (J0, pin.ARG0, pin.dDifference, q1p), (J1, pin.ARG1, pin.dDifference, q1p)):
            # (difference first recovers v by a logarithm: round-off of order 1e-12 near the identity)
            assert _rel(mine, jm.matrix_from_pin(fun(pm, qp, b, arg).copy())) < 1e-10, (scale, fun.__name__, arg)


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_integrate_and_difference_derivatives_against_central_differences(spec) -> None:  # type: ignore[no-untyped-def]
    """Every joint type, spherical and planar included (Pinocchio's URDF robots have neither)."""
    model = tree(spec.name)
    st = random_state(model, 17)
    eps = 1e-6
    E = np.eye(model.nv)
    q1 = fd.integrate(model, st.q, st.v)

    def central(fun):  # type: ignore[no-untyped-def]
        return np.stack([(fun(eps * e) - fun(-eps * e)) / (2 * eps) for e in E], axis=-1)

    Jq, Jv = fd.integrate_derivatives(model, st.q, st.v)
    J0, J1 = fd.difference_derivatives(model, st.q, q1)
    assert _rel(Jq, central(lambda d: fd.difference(model, q1, fd.integrate(model, fd.integrate(model, st.q, d),
                                                                              st.v)))) < 1e-7
    assert _rel(Jv, central(lambda d: fd.difference(model, q1, fd.integrate(model, st.q, st.v + d)))) < 1e-7
    assert _rel(J0, central(lambda d: fd.difference(model, fd.integrate(model, st.q, d), q1))) < 1e-7
    assert _rel(J1, central(lambda d: fd.difference(model, st.q, fd.integrate(model, q1, d)))) < 1e-7
    assert _rel(J1 @ Jv, np.eye(model.nv)) < 1e-12  # difference(q, integrate(q, v)) = v


@pytest.mark.parametrize("floating", [False, True], ids=["fixed", "floating"])
def test_every_library_robot_against_pinocchio(floating: bool) -> None:
    """The compiled derivatives (the default for float64) against Pinocchio on every robot of the library."""
    from featherdyn.robots import robot_path
    from featherdyn.verify.bridge import JointMap

    checked = 0
    for name in library_robot_names():
        model = library_robot(name, floating)
        if model is None or model.nv == 0:
            continue
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            path = str(robot_path(name))
            try:
                pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if floating else \
                    pin.buildModelFromUrdf(path)
                jm = JointMap(model, pm)
            except (ValueError, RuntimeError, fd.FeatherdynError):
                continue  # a model Pinocchio reads differently (test_models_vs_pinocchio covers the loaders)
        pd = pm.createData()
        rng = np.random.default_rng(18)
        q = fd.random_configuration(model, rng)
        v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
        dq, dv, _ = fd.rnea_derivatives(model, q, v, a)
        pin.computeRNEADerivatives(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(a))
        assert _rel(dq, jm.matrix_from_pin(pd.dtau_dq.copy())) < 1e-11, name
        assert _rel(dv, jm.matrix_from_pin(pd.dtau_dv.copy())) < 1e-11, name
        tau = fd.rnea(model, q, v, a)
        try:
            ddq_dq, ddq_dv, _ = fd.aba_derivatives(model, q, v, tau)
        except fd.errors.SingularMassMatrixError:  # robots with massless moving links (Pinocchio's ABA divides by 0)
            continue
        pin.computeABADerivatives(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(tau))
        cond = float(np.linalg.cond(fd.crba(model, q)))
        assert _rel(ddq_dq, jm.matrix_from_pin(pd.ddq_dq.copy())) < 1e-13 * max(1.0, cond), name
        assert _rel(ddq_dv, jm.matrix_from_pin(pd.ddq_dv.copy())) < 1e-13 * max(1.0, cond), name
        checked += 1
    assert checked >= 55, checked
