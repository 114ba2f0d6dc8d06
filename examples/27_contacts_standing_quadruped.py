# needs: featherdyn[verify] (example-robot-data): pip install "featherdyn[verify]"
"""A quadruped standing on its feet: constrained dynamics, contact forces, an impact.

Solo12 with its four feet held (3D point contacts): the contact forces that
hold a robot at rest carry its weight exactly; an impact with the ground
removes the feet's velocity and never adds kinetic energy; the operational-space
inertia of a foot is ``(J M⁻¹ Jᵀ)⁻¹``.

Run: python examples/27_contacts_standing_quadruped.py
"""

# %% 0. the robot at rest
from __future__ import annotations

from _check import needs

needs("example-robot-data")  # first: a missing module is one line naming its install

import numpy as np
from _check import check, check_true, section, show

import featherdyn as fd

model = fd.load_robot("solo12", floating_base=True)
feet = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
contacts = [fd.PointContact(f, fd.LOCAL_WORLD_ALIGNED) for f in feet]
q = fd.neutral(model)
q[2] = 0.3  # the base above the ground (the feet wherever the legs put them)
zero = np.zeros(model.nv)

# %% 1. no torque: the robot sags, held by its feet
section("at rest, joints limp")
res = fd.constrained_dynamics(model, q, zero, zero, contacts)
show("foot forces (world axes, N)", np.array(res.forces))
check("the feet do not accelerate", fd.constraint_jacobian(model, q, contacts) @ res.ddq, np.zeros(12), 1e-9)

# %% 2. torques that hold the pose: the feet carry the weight
section("gravity compensated through the feet")
# τ such that q̈ = 0: M·0 + g = τ + Jᵀλ, with the base unactuated (τ_base = 0)
J = fd.constraint_jacobian(model, q, contacts)
g = fd.generalized_gravity(model, q)
lam, *_ = np.linalg.lstsq(J[:, :6].T, g[:6], rcond=None)   # the base rows fix the forces
tau = np.concatenate([np.zeros(6), g[6:] - J[:, 6:].T @ lam])
res = fd.constrained_dynamics(model, q, zero, tau, contacts, mu=1e-9)
check("the robot stays still", res.ddq, zero, 1e-6)
weight = model.total_mass * 9.81
check("the vertical forces carry the weight (N)", np.sum(np.array(res.forces)[:, 2]), weight, 1e-6)

# %% 3. landing: an impact with restitution 0 stops the feet, and energy is lost, never gained
section("an impact")
v = np.random.default_rng(1).normal(size=model.nv)
M = fd.crba(model, q)
for e in (0.0, 0.5, 1.0):
    imp = fd.impulse_dynamics(model, q, v, contacts, restitution=e)
    before, after = 0.5 * v @ M @ v, 0.5 * imp.v_plus @ M @ imp.v_plus
    check(f"e = {e}: J v⁺ = −e J v⁻", J @ imp.v_plus, -e * (J @ v), 1e-9)
    check_true(f"e = {e}: kinetic energy {before:.3f} → {after:.3f} J does not grow", after <= before * (1 + 1e-12))

# %% 4. the operational-space inertia of one foot
section("Λ of a foot")
Lam = fd.operational_space_inertia(model, q, "FL_FOOT", fd.LOCAL_WORLD_ALIGNED)
Jf = fd.frame_jacobian(model, q, "FL_FOOT", fd.LOCAL_WORLD_ALIGNED)
check("Λ = (J M⁻¹ Jᵀ)⁻¹", Lam, np.linalg.inv(Jf @ np.linalg.solve(M, Jf.T)), 1e-6 * np.abs(Lam).max())
