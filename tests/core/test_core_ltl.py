"""The tree-sparse LᵀL factorisation of M (``cpp/ltl.hpp``): M = LᵀL with the tree's sparsity, solves, Delassus."""

from __future__ import annotations

import numpy as np
import pytest
from _core_helpers import assert_rel, robot
from _models import TREES, random_state, tree

import featherdyn as fd
from featherdyn import core


def _dof_ancestors(model: fd.Model) -> list[set[int]]:
    """For each dof, itself and the dofs it hangs from (its joint's earlier dofs and every ancestor joint's)."""
    out = []
    for i in range(model.nbodies):
        for c in range(model.nvs[i]):
            anc = {model.idx_v[i] + k for k in range(c + 1)}
            j = model.parents[i]
            while j != -1:
                anc |= {model.idx_v[j] + k for k in range(model.nvs[j])}
                j = model.parents[j]
            out.append(anc)
    return out


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_factor_solve_and_delassus_on_every_joint_type(spec) -> None:  # type: ignore[no-untyped-def]
    model = tree(spec.name)
    st = random_state(model, 31, (2,))
    M = fd.crba(model, st.q)
    L = core.mass_matrix_factor(model, st.q)
    assert_rel(np.swapaxes(L, -1, -2) @ L, M, f"{spec.name}: LᵀL = M")
    anc = _dof_ancestors(model)
    for k in range(model.nv):
        for j in range(model.nv):
            if j not in anc[k]:
                assert np.all(L[..., k, j] == 0.0), (spec.name, k, j)
    b = np.random.default_rng(1).normal(size=(2, model.nv))
    x = core.mass_solve(model, st.q, b)
    assert_rel(np.einsum("nij,nj->ni", M, x), b, f"{spec.name}: M x = b")
    J = np.random.default_rng(2).normal(size=(2, 5, model.nv))
    D = core.delassus(model, st.q, J)
    assert_rel(D, J @ np.linalg.solve(M, np.swapaxes(J, -1, -2)), f"{spec.name}: J M⁻¹ Jᵀ")
    assert np.array_equal(D, np.swapaxes(D, -1, -2))


def test_on_a_humanoid_and_errors() -> None:
    model = robot("talos_full_v2", True)
    assert model is not None
    q = fd.random_configuration(model, np.random.default_rng(3))
    L = core.mass_matrix_factor(model, q)
    assert_rel(L.T @ L, fd.crba(model, q), "talos: LᵀL = M")
    with pytest.raises(fd.errors.ShapeError, match="J: expected shape"):
        core.delassus(model, q, np.zeros((3, model.nv + 1)))
    b = fd.ModelBuilder("massless")
    b.add_body("link", parent=-1, joint=fd.RevoluteJoint([0, 0, 1]), joint_name="j",
               inertia=fd.SpatialInertia(0.0, [0, 0, 0], np.zeros((3, 3))))
    with pytest.warns(fd.PhysicalityWarning):
        massless = b.build()
    with pytest.raises(fd.errors.SingularMassMatrixError, match="'j'"):
        core.mass_matrix_factor(massless, np.zeros(1))


def _feet_state(seed: int) -> tuple[fd.Model, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    model = robot("solo12", True)
    assert model is not None
    rng = np.random.default_rng(seed)
    q = fd.random_configuration(model, rng)
    v, tau = rng.normal(size=model.nv), rng.normal(size=model.nv)
    J = np.concatenate([fd.frame_jacobian(model, q, f, fd.LOCAL_WORLD_ALIGNED)[3:]
                        for f in ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT")])
    return model, q, v, tau, J, rng.normal(size=12)


def test_constrained_solve_equals_the_dense_kkt_system() -> None:
    model, q, v, tau, J, c = _feet_state(41)
    f = np.random.default_rng(5).normal(size=(model.nbodies, 6))
    qdd, lam, res = core.constrained_solve(model, q, v, tau, J, c, f_ext=f)
    M, h = fd.crba(model, q), fd.rnea(model, q, v, np.zeros(model.nv), f_ext=f)
    K = np.block([[M, -J.T], [J, np.zeros((12, 12))]])
    sol = np.linalg.solve(K, np.concatenate([tau - h, c]))
    assert_rel(qdd, sol[: model.nv], "q̈", rtol=1e-10)
    assert_rel(lam, sol[model.nv:], "λ", rtol=1e-10)
    assert float(res) <= 1e-10 * max(1.0, float(np.abs(c).max()))
    # a batch of two states (J and c broadcast) equals its rows
    Q = np.stack([q, fd.random_configuration(model, np.random.default_rng(6))])
    Qdd, Lam, _ = core.constrained_solve(model, Q, v, tau, J, c)
    for k in range(2):
        one = core.constrained_solve(model, Q[k], v, tau, J, c)
        assert np.array_equal(Qdd[k], one[0]) and np.array_equal(Lam[k], one[1])


def test_dependent_rows_need_mu_and_then_give_the_minimum_norm_forces() -> None:
    model, q, v, tau, J, c = _feet_state(42)
    qdd, lam, _ = core.constrained_solve(model, q, v, tau, J, c)
    J2, c2 = np.concatenate([J, J[:3]]), np.concatenate([c, c[:3]])  # the first foot constrained twice
    with pytest.raises(fd.ConstraintError, match="pass mu > 0"):
        core.constrained_solve(model, q, v, tau, J2, c2)
    qdd2, lam2, res2 = core.constrained_solve(model, q, v, tau, J2, c2, mu=1e-6, max_iter=500)
    assert_rel(qdd2, qdd, "q̈ with a duplicated contact", rtol=1e-8)
    assert_rel(lam2[:3] + lam2[12:], lam[:3], "the duplicated contact's total force", rtol=1e-8)
    assert_rel(lam2[:3], lam2[12:], "the minimum-norm split: half each", rtol=1e-6)
    with pytest.raises(fd.ConstraintError, match="did not converge"):
        core.constrained_solve(model, q, v, tau, J2, c2, mu=1.0, max_iter=2)
    with pytest.raises(fd.errors.ShapeError, match="c: expected shape"):
        core.constrained_solve(model, q, v, tau, J, c[:-1])
