"""``featherdyn.conventions``' derivative converters: Pinocchio's layout, the parent-frame tangent, coordinates."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from _models import random_state, tree

import featherdyn as fd
from featherdyn import conventions as C
from featherdyn.rotation import matrix_to_quat, quat_to_matrix, se3_exp

pin = pytest.importorskip("pinocchio")


def test_to_pinocchio_matches_computeRNEADerivatives_and_round_trips() -> None:
    from featherdyn.robots import robot_path
    from featherdyn.verify.bridge import JointMap

    model = fd.load_robot("solo12", floating_base=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        pm = pin.buildModelFromUrdf(str(robot_path("solo12")), pin.JointModelFreeFlyer())
    pd, jm = pm.createData(), JointMap(model, pm)
    assert [pm.names[i] for i in range(1, pm.njoints)] == list(model.joint_names)  # same joint order
    rng = np.random.default_rng(1)
    q = fd.random_configuration(model, rng)
    v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
    dq, dv, _ = fd.rnea_derivatives(model, q, v, a)
    pin.computeRNEADerivatives(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(a))
    np.testing.assert_allclose(C.derivatives_to_pinocchio(model, dq), pd.dtau_dq, atol=1e-12 * np.abs(dq).max())
    np.testing.assert_allclose(C.derivatives_to_pinocchio(model, dv), pd.dtau_dv, atol=1e-12 * np.abs(dv).max())
    assert np.array_equal(C.derivatives_from_pinocchio(model, C.derivatives_to_pinocchio(model, dq)), dq)
    dvf, _ = fd.frame_velocity_derivatives(model, q, v, "HR_FOOT", fd.LOCAL)
    pin.computeForwardKinematicsDerivatives(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(a))
    pv = pin.getFrameVelocityDerivatives(pm, pd, pm.getFrameId("HR_FOOT"), pin.LOCAL)[0]
    np.testing.assert_allclose(C.derivatives_to_pinocchio(model, dvf, rows="spatial"), pv, atol=1e-12)
    with pytest.raises(fd.ShapeError, match="rows"):
        C.derivatives_to_pinocchio(model, dq, rows="columns")


def _left_step(q: np.ndarray, d: np.ndarray) -> np.ndarray:
    """The root free-flyer moved by exp(d) on the left (a world-frame twist)."""
    T = se3_exp(d) @ fd.PluckerTransform(quat_to_matrix(q[3:7]), q[:3])
    out = q.copy()
    out[:3] = T.translation
    quat = matrix_to_quat(T.rotation)
    out[3:7] = quat if quat @ q[3:7] >= 0 else -quat
    return out


def test_parent_tangent_is_a_left_perturbation_of_the_root() -> None:
    model = tree("free_branch")
    st = random_state(model, 2)
    D = fd.rnea_derivatives(model, st.q, st.v, st.a)[0]
    Dp = C.derivatives_to_parent_tangent(model, st.q, D)
    eps = 1e-6
    cols = [(fd.rnea(model, _left_step(st.q, eps * e), st.v, st.a)
             - fd.rnea(model, _left_step(st.q, -eps * e), st.v, st.a)) / (2 * eps) for e in np.eye(6)]
    np.testing.assert_allclose(Dp[:, :6], np.stack(cols, -1), atol=1e-6 * max(1.0, np.abs(D).max()))
    unchanged = [model.idx_v[i] + k for i in range(model.nbodies) if (model.nqs[i], model.nvs[i]) not in ((7, 6), (4, 3))
                 for k in range(model.nvs[i])]
    assert unchanged and np.array_equal(Dp[:, unchanged], D[:, unchanged])  # revolute, prismatic, planar columns


@pytest.mark.parametrize("name", ["planar_root_branch", "free_branch", "fixed_branch_mixed"])
def test_coordinates_round_trip_and_chain_rule(name: str) -> None:
    model = tree(name)
    st = random_state(model, 3)
    D = fd.rnea_derivatives(model, st.q, st.v, st.a)[0]
    Dq = C.derivatives_to_coordinates(model, st.q, D)
    assert Dq.shape == (model.nv, model.nq)
    np.testing.assert_allclose(C.derivatives_from_coordinates(model, st.q, Dq), D, atol=1e-12 * np.abs(D).max())
    # along any coordinate direction that stays on the configuration manifold to first order, the
    # coordinate derivative predicts the change: take dq = d(q ⊕ δ)/dδ · δ for a random δ
    delta = np.random.default_rng(4).normal(size=model.nv)
    eps = 1e-6
    dq = (fd.integrate(model, st.q, eps * delta) - fd.integrate(model, st.q, -eps * delta)) / (2 * eps)
    np.testing.assert_allclose(Dq @ dq, D @ delta, rtol=1e-6, atol=1e-6 * np.abs(D).max())
