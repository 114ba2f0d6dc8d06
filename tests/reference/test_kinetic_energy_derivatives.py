"""``fd.kinetic_energy_derivatives``: the kinetic energy's gradient in O(nb), and the mass matrix's vector-Jacobian
product made of it (api/jacobians.py's ``mass_matrix_vjp``, featherdyn.torch's backward of ``crba``).

Oracles: Pinocchio's RNEA derivatives at rest without gravity (``M(q) q̇ = RNEA(q, 0, q̇)``, so
``∂T/∂q = ½ q̇ᵀ ∂τ/∂q`` and ``∂T/∂q̇ = M q̇``), central differences of ``fd.kinetic_energy`` along ``fd.integrate``'s
tangent on trees of every joint kind, and the second-order tensor ``∂M/∂q`` of ``fd.rnea_second_derivatives``.
The function's front ends (batch, out=, Dask, dtype spellings), as every declared algorithm's, are tested by the
suites that run over all declarations.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from _models import TREES, pinocchio_pair, random_q, tree

import featherdyn as fd
from featherdyn.errors import ShapeError


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / max(1.0, np.abs(b).max()))


@pytest.mark.parametrize("backend", [None, "reference"])
@pytest.mark.parametrize(("name", "floating"), [("panda", False), ("solo12", True), ("talos_full_v2", True)])
def test_against_pinocchio(name: str, floating: bool, backend: str | None) -> None:
    pin = pytest.importorskip("pinocchio")
    model, pm, pd, jm = pinocchio_pair(name, floating)
    pm.gravity = pin.Motion.Zero()
    rng = np.random.default_rng(3)
    q, v = fd.random_configuration(model, rng), rng.normal(size=model.nv)
    qp, vp = jm.q_to_pin(q), jm.v_to_pin(v)
    pin.computeRNEADerivatives(pm, pd, qp, np.zeros(pm.nv), vp)  # τ = M(q) q̇ at rest, no gravity
    dtau_dq = jm.matrix_from_pin(pd.dtau_dq.copy())
    M = jm.matrix_from_pin(pin.crba(pm, pd, qp).copy())
    M = np.triu(M) + np.triu(M, 1).T
    dT_dq, dT_dv = fd.kinetic_energy_derivatives(model, q, v, backend=backend)
    assert _rel(dT_dq, 0.5 * v @ dtau_dq) < 1e-12, _rel(dT_dq, 0.5 * v @ dtau_dq)
    assert _rel(dT_dv, M @ v) < 1e-12
    assert np.abs(dT_dq).max() > 1e-3  # (not a zero gradient: the test could fail)


@pytest.mark.parametrize("spec", TREES, ids=lambda s: s.name)
def test_central_differences_on_the_group(spec) -> None:  # type: ignore[no-untyped-def]
    model = tree(spec.name)
    rng = np.random.default_rng(11)
    q, v = random_q(model, rng), rng.normal(size=model.nv)
    dT_dq, dT_dv = fd.kinetic_energy_derivatives(model, q, v)
    h = 1e-6
    E = np.eye(model.nv)
    fdq = np.array([(fd.kinetic_energy(model, fd.integrate(model, q, h * e), v)
                     - fd.kinetic_energy(model, fd.integrate(model, q, -h * e), v)) / (2 * h) for e in E])
    fdv = np.array([(fd.kinetic_energy(model, q, v + h * e) - fd.kinetic_energy(model, q, v - h * e)) / (2 * h)
                    for e in E])
    assert _rel(dT_dq, fdq) < 1e-7, _rel(dT_dq, fdq)
    assert _rel(dT_dv, fdv) < 1e-7
    ref = fd.kinetic_energy_derivatives(model, q, v, backend="reference")
    assert _rel(dT_dq, ref[0]) < 1e-13 and _rel(dT_dv, ref[1]) < 1e-13


@pytest.mark.parametrize(("name", "floating"), [("solo12", True), ("talos_full_v2", True)])
def test_against_the_second_order_tensor(name: str, floating: bool) -> None:
    """``∂T/∂q_k = ½ q̇ᵀ (∂M/∂q_k) q̇`` with ``∂M/∂q`` from ``fd.rnea_second_derivatives`` (another kernel)."""
    model = fd.load_robot(name, floating_base=floating)
    rng = np.random.default_rng(4)
    q, v = fd.random_configuration(model, rng), rng.normal(size=model.nv)
    dM_dq = fd.rnea_second_derivatives(model, q, np.zeros(model.nv), np.zeros(model.nv)).dM_dq
    dT_dq, _ = fd.kinetic_energy_derivatives(model, q, v)
    expected = 0.5 * np.einsum("i,ijk,j->k", v, dM_dq, v)
    assert _rel(dT_dq, expected) < 1e-12


def test_armature_enters_the_velocity_gradient_only() -> None:
    """``T`` has ``½ Σ armature_k q̇_k²``: ``∂T/∂q̇ = (M + diag(armature)) q̇`` (``fd.crba`` includes it), ``∂T/∂q``
    unchanged."""
    model = tree("free_branch")
    rng = np.random.default_rng(6)
    armed = dataclasses.replace(model, armature=rng.uniform(0.1, 1.0, model.nv))
    q, v = random_q(model, rng), rng.normal(size=model.nv)
    plain, with_rotors = fd.kinetic_energy_derivatives(model, q, v), fd.kinetic_energy_derivatives(armed, q, v)
    assert _rel(with_rotors[0], plain[0]) < 1e-14
    assert _rel(with_rotors[1], fd.crba(armed, q) @ v) < 1e-13
    assert _rel(with_rotors[1], plain[1]) > 1e-3


def test_batch_and_errors() -> None:
    model = fd.load_robot("panda")
    rng = np.random.default_rng(2)
    q = np.stack([fd.random_configuration(model, rng) for _ in range(5)])
    v = rng.normal(size=(5, model.nv))
    dq, dv = fd.kinetic_energy_derivatives(model, q, v)
    for i in range(5):
        one = fd.kinetic_energy_derivatives(model, q[i], v[i])
        assert np.array_equal(dq[i], one[0]) and np.array_equal(dv[i], one[1])
    with pytest.raises(ShapeError, match="v"):
        fd.kinetic_energy_derivatives(model, q[0], v[0, :3])


def test_mass_matrix_vjp_contracts_the_second_order_tensor() -> None:
    """``Σ_ij W_ij ∂M_ij/∂q`` by polarisation of kinetic-energy gradients (api/jacobians.py) against the contraction
    of ``∂M/∂q`` itself, with PyTorch as the framework; rows of ``W`` of very different sizes and a zero row (the
    balancing ``s_i``)."""
    torch = pytest.importorskip("torch")
    import featherdyn.torch as ft
    from featherdyn.api.jacobians import mass_matrix_vjp

    model = fd.load_robot("solo12", floating_base=True)
    rng = np.random.default_rng(9)
    q = np.stack([fd.random_configuration(model, rng) for _ in range(3)])
    W = rng.normal(size=(3, model.nv, model.nv)) * np.logspace(-6, 6, model.nv)[:, None]
    W[:, 4] = 0.0
    dM_dq = fd.rnea_second_derivatives(model, q, np.zeros((3, model.nv)), np.zeros((3, model.nv))).dM_dq
    expected = np.einsum("bij,bijk->bk", W, dM_dq)
    got = mass_matrix_vjp(ft._fw(torch.as_tensor(q)), model, torch.as_tensor(q), torch.as_tensor(W)).numpy()
    assert _rel(got, expected) < 1e-10, _rel(got, expected)


def test_mass_matrix_vjp_carries_a_non_finite_cotangent() -> None:
    """A NaN or inf in ``W`` gives a non-finite gradient in that state, as the Jacobian's product would — not an
    error about an internal call's ``v`` (the kinetic-energy kernel refuses non-finite velocities) — and the
    other states' gradients are unchanged."""
    torch = pytest.importorskip("torch")
    import featherdyn.torch as ft
    from featherdyn.api.jacobians import mass_matrix_vjp

    model = fd.load_robot("panda")
    rng = np.random.default_rng(10)
    q = torch.as_tensor(np.stack([fd.random_configuration(model, rng) for _ in range(3)]))
    W = torch.as_tensor(rng.normal(size=(3, model.nv, model.nv)))
    clean = mass_matrix_vjp(ft._fw(q), model, q, W)
    W[1, 2, 3], W[2, 0, 0] = float("nan"), float("inf")
    got = mass_matrix_vjp(ft._fw(q), model, q, W)
    assert torch.equal(got[0], clean[0])
    assert not torch.isfinite(got[1]).any() and not torch.isfinite(got[2]).any()
