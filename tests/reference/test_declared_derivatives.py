"""The declared derivatives ``fd.generalized_gravity_derivatives`` and ``fd.static_torque_derivatives``.

Against Pinocchio 4.1's ``computeGeneralizedGravityDerivatives`` / ``computeStaticTorqueDerivatives``
(joints mapped by name, the free-flyer's ``[v; ω]`` converted, forces in the joints' LOCAL frames) and
against central finite differences along ``fd.integrate``'s tangent. Their front ends, as every declared
algorithm's: ``test_declared_front_ends.py``.
"""

from __future__ import annotations

import numpy as np
import pytest
from _models import library_robot, pinocchio_pair

import featherdyn as fd

pin = pytest.importorskip("pinocchio")

PAIRS = [("panda", False), ("solo12", True), ("ur5_robot", False), ("anymal-kinova", True), ("talos_full_v2", True)]


_pin_pair = pinocchio_pair


def _pin_forces(model: fd.Model, pm, f_ext: np.ndarray) -> list:  # type: ignore[no-untyped-def]
    """featherdyn body-frame forces ``[n; f]`` `(nb, 6)` → Pinocchio's joint-frame forces ``[f; n]`` (0: universe)."""
    out = [pin.Force.Zero() for _ in range(pm.njoints)]
    for i, name in enumerate(model.joint_names):
        out[pm.getJointId(name)] = pin.Force(np.concatenate([f_ext[i, 3:], f_ext[i, :3]]))
    return out


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / max(1.0, np.abs(b).max()))


@pytest.mark.parametrize("backend", [None, "reference"])
@pytest.mark.parametrize(("name", "floating"), PAIRS)
def test_against_pinocchio(name: str, floating: bool, backend: str | None) -> None:
    model, pm, pd, jm = _pin_pair(name, floating)
    rng = np.random.default_rng(5)
    q = fd.random_configuration(model, rng)
    f_ext = rng.normal(size=(model.nbodies, 6))
    qp = jm.q_to_pin(q)
    dg = fd.generalized_gravity_derivatives(model, q, backend=backend)
    dg_pin = jm.matrix_from_pin(pin.computeGeneralizedGravityDerivatives(pm, pd, qp).copy())
    assert _rel(dg, dg_pin) < 1e-12, (name, _rel(dg, dg_pin))
    ds = fd.static_torque_derivatives(model, q, f_ext, backend=backend)
    ds_pin = jm.matrix_from_pin(pin.computeStaticTorqueDerivatives(pm, pd, qp, _pin_forces(model, pm, f_ext)).copy())
    assert _rel(ds, ds_pin) < 1e-12, (name, _rel(ds, ds_pin))
    # and not merely the gravity part: the forces change the result
    assert _rel(ds, dg) > 1e-6


@pytest.mark.parametrize(("name", "floating"), [("solo12", True), ("panda", False)])
def test_finite_differences_on_the_group(name: str, floating: bool) -> None:
    model = library_robot(name, floating)
    assert model is not None
    rng = np.random.default_rng(8)
    q = fd.random_configuration(model, rng)
    f_ext = rng.normal(size=(model.nbodies, 6))
    zero = np.zeros(model.nv)
    eps = 1e-6
    dg = fd.generalized_gravity_derivatives(model, q)
    ds = fd.static_torque_derivatives(model, q, f_ext)
    for j in range(model.nv):
        step = np.zeros(model.nv)
        step[j] = eps
        qp, qm = fd.integrate(model, q, step), fd.integrate(model, q, -step)
        fd_g = (fd.generalized_gravity(model, qp) - fd.generalized_gravity(model, qm)) / (2 * eps)
        fd_s = (fd.rnea(model, qp, zero, zero, f_ext) - fd.rnea(model, qm, zero, zero, f_ext)) / (2 * eps)
        assert np.abs(dg[:, j] - fd_g).max() < 1e-6 * max(1.0, np.abs(dg).max()), j
        assert np.abs(ds[:, j] - fd_s).max() < 1e-6 * max(1.0, np.abs(ds).max()), j
