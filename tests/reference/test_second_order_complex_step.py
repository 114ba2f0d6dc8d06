"""``fd.rnea_second_derivatives``' ∂²τ/∂q² (and ∂²τ/∂q∂q̇, ∂²τ/∂q̇²) against complex steps of the analytical first
order through the core's complex instantiation (``rnea_derivatives_complex`` of the binding: the template of
``fd.rnea_derivatives``' kernel on ``std::complex<double>``).

Along a revolute or prismatic coordinate ``q ⊕ ε e_k = q + ε e_iq``, so
``Im ∂τ/∂q(q + i h e_iq) / h = d2tau_dq2[:, :, k]`` to rounding (h = 1e-30: no subtraction); along any q̇ column
``Im ∂τ/∂q(q, q̇ + i h e_k) / h = d2tau_dqdv[:, :, k]`` and ``Im ∂τ/∂q̇(...) / h = d2tau_dv2[:, :, k]``. The q
columns of free-flyers and spherical joints need a complex exponential map, which the binding does not
expose: those are checked against central differences (``test_second_order.py``).
"""

from __future__ import annotations

import numpy as np
import pytest
from _models import library_robot

import featherdyn as fd
from featherdyn.core import _core, _view


def _first_order(model: fd.Model, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    nv = model.nv
    dq, dv = np.empty((nv, nv), np.complex128), np.empty((nv, nv), np.complex128)
    status = _core.rnea_derivatives_complex(_view(model).cm, np.asarray(q, np.complex128), np.asarray(v, np.complex128),
                                            np.asarray(a, np.complex128), dq, dv)
    assert status == 0
    return dq, dv


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / max(1.0, np.abs(b).max()))


@pytest.mark.parametrize(("name", "floating"), [("panda", False), ("ur5_robot", False), ("solo12", True),
                                                ("talos_full_v2", True)])
def test_second_order_against_complex_steps_of_the_first(name: str, floating: bool) -> None:
    model = library_robot(name, floating)
    assert model is not None
    rng = np.random.default_rng(17)
    q, v, a = fd.random_configuration(model, rng), rng.normal(size=model.nv), rng.normal(size=model.nv)
    s = fd.rnea_second_derivatives(model, q, v, a)
    real_dq, real_dv = _first_order(model, q, v, a)
    ref_dq, ref_dv, _ = fd.rnea_derivatives(model, q, v, a)
    assert _rel(real_dq.real, ref_dq) < 1e-13 and _rel(real_dv.real, ref_dv) < 1e-13  # the same template
    h, nv = 1e-30, model.nv
    cols = [(model.idx_v[i], model.idx_q[i]) for i, j in enumerate(model.joints)
            if isinstance(j, (fd.joints.RevoluteJoint, fd.joints.PrismaticJoint))]
    assert len(cols) >= 6
    worst = 0.0
    for k, iq in cols:
        e = np.zeros(model.nq, np.complex128)
        e[iq] = 1j * h
        dq, _ = _first_order(model, q + e, v, a)
        worst = max(worst, _rel(s.d2tau_dq2[:, :, k], dq.imag / h))
    for k in range(nv):
        e = np.zeros(nv, np.complex128)
        e[k] = 1j * h
        dq, dv = _first_order(model, q, v + e, a)
        worst = max(worst, _rel(s.d2tau_dqdv[:, :, k], dq.imag / h), _rel(s.d2tau_dv2[:, :, k], dv.imag / h))
    assert worst < 1e-11, worst
