"""Armature (reflected rotor inertia): ``M + diag(armature)`` in every algorithm, both backends, against Pinocchio.

Pinocchio's ``model.armature`` is added to the mass matrix's diagonal by its
``crba``, ``rnea`` (``τ += armature ∘ q̈``) and ``aba``; the same random
armature is set on a featherdyn model (``dataclasses.replace``) and on
Pinocchio's model of the same URDF, and RNEA, CRBA, ABA, ``∂τ/∂q̈``, ``M⁻¹``
and the ABA derivatives are compared for both backends.
"""

from __future__ import annotations

import dataclasses
import pickle

import numpy as np
import pytest

import featherdyn as fd
from featherdyn.errors import ModelError
from featherdyn.testing import assert_close

pin = pytest.importorskip("pinocchio")

ROBOTS = [("two_link_arm", False), ("panda", False), ("solo12", True)]


def _models(name: str, floating: bool, seed: int):
    from featherdyn.verify.bridge import JointMap

    try:
        model = fd.load_robot(name, floating_base=floating)
    except fd.MissingDependencyError:
        pytest.skip("example-robot-data is not installed")
    pm = (pin.buildModelFromUrdf(model.source, pin.JointModelFreeFlyer()) if floating
          else pin.buildModelFromUrdf(model.source))
    jm = JointMap(model, pm)
    rng = np.random.default_rng(seed)
    armature = rng.uniform(0.05, 2.0, model.nv)
    pm.armature = jm.v_to_pin(armature)
    return dataclasses.replace(model, armature=armature), pm, jm, rng


def test_armature_defaults_to_zero_and_urdf_leaves_it_zero() -> None:
    model = fd.load_robot("two_link_arm")
    assert model.armature.shape == (model.nv,)
    assert model.armature.dtype == np.float64
    assert not np.any(model.armature)
    assert not model.armature.flags.writeable


def test_armature_pickles_and_is_checked() -> None:
    model = dataclasses.replace(fd.load_robot("two_link_arm"), armature=[0.5, 0.25])
    again = pickle.loads(pickle.dumps(model))
    assert again.armature.tolist() == [0.5, 0.25]
    with pytest.raises(ModelError, match="armature"):
        dataclasses.replace(model, armature=[1.0])
    with pytest.raises(ModelError, match="armature"):
        dataclasses.replace(model, armature=[1.0, -1.0])
    with pytest.raises(ModelError, match="armature"):
        dataclasses.replace(model, armature=[1.0, np.nan])


def test_builder_armature() -> None:
    b = fd.ModelBuilder("one")
    b.add_body("a", -1, fd.RevoluteJoint([0, 0, 1]), inertia=fd.SpatialInertia(1.0, [0.1, 0, 0], np.eye(3)),
               armature=0.7)
    b.add_body("b", 0, fd.SphericalJoint(), inertia=fd.SpatialInertia(1.0, [0.1, 0, 0], np.eye(3)),
               armature=[0.1, 0.2, 0.3])
    model = b.build()
    assert model.armature.tolist() == [0.7, 0.1, 0.2, 0.3]
    q = fd.neutral(model)
    bare = dataclasses.replace(model, armature=None)
    assert_close(fd.crba(model, q, backend="reference") - fd.crba(bare, q, backend="reference"),
                 np.diag([0.7, 0.1, 0.2, 0.3]), "M - M_bare")


@pytest.mark.parametrize("backend", ["reference", "compiled"])
@pytest.mark.parametrize(("name", "floating"), ROBOTS)
def test_armature_matches_pinocchio(name: str, floating: bool, backend: str) -> None:
    model, pm, jm, rng = _models(name, floating, 7)
    pd = pm.createData()
    for _ in range(3):
        q = fd.random_configuration(model, rng)
        v, a = rng.normal(size=model.nv), rng.normal(size=model.nv)
        qp, vp, ap = jm.q_to_pin(q), jm.v_to_pin(v), jm.v_to_pin(a)
        where = f"robot {name!r}, {backend}"
        tau_pin = jm.v_from_pin(pin.rnea(pm, pd, qp, vp, ap))
        M_pin = jm.matrix_from_pin(pin.crba(pm, pd, qp))
        M_pin = np.triu(M_pin) + np.triu(M_pin, 1).T
        tau = fd.rnea(model, q, v, a, backend=backend)
        assert_close(tau, tau_pin, "rnea with armature", where=where)
        assert_close(fd.crba(model, q, backend=backend), M_pin, "crba with armature", where=where)
        assert_close(fd.aba(model, q, v, tau_pin, backend=backend), a, "aba with armature", where=where)
        Minv_pin = np.linalg.inv(M_pin)
        assert_close(fd.mass_matrix_inverse(model, q, backend=backend), Minv_pin, "M^-1 with armature",
                     where=where)
        _, _, dtau_da = fd.rnea_derivatives(model, q, v, a, backend=backend)
        assert_close(dtau_da, M_pin, "dtau/da with armature", where=where)
        _, _, dddq_dtau = fd.aba_derivatives(model, q, v, tau_pin, backend=backend)
        assert_close(dddq_dtau, Minv_pin, "dddq/dtau with armature", where=where)


def test_armature_leaves_gravity_and_nle_alone() -> None:
    model, _, _, rng = _models("panda", False, 3)
    bare = dataclasses.replace(model, armature=None)
    q, v = fd.random_configuration(model, rng), rng.normal(size=model.nv)
    for backend in ("reference", "compiled"):
        assert_close(fd.generalized_gravity(model, q, backend=backend), fd.generalized_gravity(bare, q, backend=backend),
                     "gravity")
        assert_close(fd.nonlinear_effects(model, q, v, backend=backend),
                     fd.nonlinear_effects(bare, q, v, backend=backend), "nle")


def test_kinetic_energy_counts_the_armature_and_the_regressor_leaves_it_out() -> None:
    """T = ½ q̇ᵀ M q̇ with M's armature (Pinocchio's computeKineticEnergy adds ½ Σ armature q̇² too); the regressor
    holds the bodies' parameters only, so τ = Y π + armature ∘ q̈."""
    model, pm, jm, rng = _models("panda", False, 4)
    bare = dataclasses.replace(model, armature=None)
    q, v, a = fd.random_configuration(model, rng), rng.normal(size=model.nv), rng.normal(size=model.nv)
    pd = pm.createData()
    pin_energy = pin.computeKineticEnergy(pm, pd, jm.q_to_pin(q), jm.v_to_pin(v))
    for backend in ("reference", "compiled"):
        ours = fd.kinetic_energy(model, q, v, backend=backend)
        assert ours == pytest.approx(pin_energy, rel=1e-12)
        assert ours == pytest.approx(0.5 * v @ fd.crba(model, q, backend=backend) @ v, rel=1e-12)
        assert ours == pytest.approx(fd.kinetic_energy(bare, q, v, backend=backend) + 0.5 * np.sum(model.armature * v * v),
                                     rel=1e-14)
    Y = fd.joint_torque_regressor(model, q, v, a)
    assert_close(Y @ fd.dynamic_parameters(model) + model.armature * a, fd.rnea(model, q, v, a), "Y pi + armature a")
