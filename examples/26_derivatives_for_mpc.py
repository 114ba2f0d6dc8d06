# needs: featherdyn[verify] (example-robot-data): pip install "featherdyn[verify]"
"""Analytical derivatives of the dynamics, as an MPC or trajectory optimiser uses them.

Linearising q̈ = ABA(q, q̇, τ) around a state gives the A and B matrices of a
discrete-time model; featherdyn's ``aba_derivatives`` gives them exactly. The
derivative with respect to q is along the tangent of ``fd.integrate`` (a free
flyer's quaternion is never differentiated coordinate by coordinate), so the
finite-difference check below moves q with ``fd.integrate`` as well.

Run: python examples/26_derivatives_for_mpc.py
"""

# %% 0. a floating-base quadruped in a random state
from __future__ import annotations

from _check import needs

needs("example-robot-data")  # first: a missing module is one line naming its install

import numpy as np
from _check import check, section

import featherdyn as fd

model = fd.load_robot("solo12", floating_base=True)
rng = np.random.default_rng(3)
q = fd.random_configuration(model, rng)
v, tau = rng.normal(size=model.nv), rng.normal(size=model.nv)
nv = model.nv

# %% 1. the derivatives and the identities that tie them together
section("∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ = M⁻¹")
ddq_dq, ddq_dv, Minv = fd.aba_derivatives(model, q, v, tau)
dtau_dq, dtau_dv, M = fd.rnea_derivatives(model, q, v, fd.aba(model, q, v, tau))
check("M⁻¹ M = 1", Minv @ M, np.eye(nv), 1e-9)
check("∂q̈/∂q = −M⁻¹ ∂τ/∂q", ddq_dq, -Minv @ dtau_dq, 1e-8)
check("∂q̈/∂q̇ = −M⁻¹ ∂τ/∂q̇", ddq_dv, -Minv @ dtau_dv, 1e-8)

# %% 2. against central differences on the configuration manifold
section("central differences along q ⊕ ε e_j (fd.integrate)")
eps = 1e-6
fd_dq = np.stack([(fd.aba(model, fd.integrate(model, q, eps * e), v, tau)
                   - fd.aba(model, fd.integrate(model, q, -eps * e), v, tau)) / (2 * eps) for e in np.eye(nv)], axis=1)
scale = max(1.0, float(np.abs(ddq_dq).max()))
check("∂q̈/∂q vs finite differences (relative)", ddq_dq / scale, fd_dq / scale, 1e-6)

# %% 3. a discrete-time linear model for MPC: x = (q ⊖ q*, v), semi-implicit Euler with step h
section("A, B of the linearised dynamics (h = 10 ms)")
h = 0.01
A = np.block([[np.eye(nv) + h * h * ddq_dq, h * (np.eye(nv) + h * ddq_dv)], [h * ddq_dq, np.eye(nv) + h * ddq_dv]])
B = np.vstack([h * h * Minv, h * Minv])
print(f"  A {A.shape}, B {B.shape}")
# one step of the nonlinear model against the linear one, for a small torque change
du = 1e-4 * rng.normal(size=nv)
v_next = v + h * fd.aba(model, q, v, tau + du)
v_lin = v + h * fd.aba(model, q, v, tau) + h * Minv @ du
check("the linear model predicts the velocity step", v_next, v_lin, 1e-9)
