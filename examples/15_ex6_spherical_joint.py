# needs: featherdyn[verify] (Pinocchio): pip install "featherdyn[verify]"
"""Exercise 6 (first list) — the spherical joint: S = [1₃; 0], SᵀS = 1₃, and the quaternion.

With a quaternion q (nq = 4) and v = ω in the child frame (nv = 3), S does
not change: it maps the *velocity* v, not q̇. What the quaternion changes is
the map from v to q̇ (4 × 3), q̇ = ½ q ⊗ (ω, 0), and the integration rule
q' = q ⊗ exp(ω/2). Checked against Pinocchio's JointModelSpherical.

Run: python examples/15_ex6_spherical_joint.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
from _check import check, section, show

import featherdyn as fd
from featherdyn.rotation import quat_multiply, quat_to_matrix
from featherdyn.verify.bridge import JointMap, pinocchio_model_from, to_pin6

b = fd.ModelBuilder("ball")
b.add_body("ball", -1, fd.SphericalJoint(), inertia=fd.SpatialInertia(2.0, [0.1, 0.0, 0.3], np.diag([0.02, 0.03, 0.04])))
model = b.build()
pmodel = pinocchio_model_from(model)
pdata = pmodel.createData()
jmap = JointMap(model, pmodel)

# %% 1. S and SᵀS
section("1. S = [1₃; 0]")
S = fd.SphericalJoint().S
show("S", S)
check("S = [1₃; 0]", S, np.vstack([np.eye(3), np.zeros((3, 3))]), 0.0)
check("SᵀS = 1₃", S.T @ S, np.eye(3), 0.0)
check("Pinocchio's S (linear first)", np.asarray(pmodel.joints[1].createData().S), np.vstack([np.zeros((3, 3)), np.eye(3)]), 0.0)

# %% 2. with a quaternion: nq = 4, nv = 3, S unchanged
section("2. quaternion parametrisation")
print(f"  nq = {model.nq}, nv = {model.nv}  (Pinocchio: nq = {pmodel.nq}, nv = {pmodel.nv})")
rng = np.random.default_rng(6)
q = fd.random_configuration(model, rng)
w = rng.normal(size=3)
kin = fd.forward_kinematics(model, q, w)
check("v = S ω at any q", kin.velocities.vector[0], S @ w, 0.0)
pin.forwardKinematics(pmodel, pdata, jmap.q_to_pin(q), jmap.v_to_pin(w))
check("Pinocchio data.v = S ω", to_pin6(pdata.v[1].vector), S @ w, 1e-14)


# %% 3. q̇ = ½ q ⊗ (ω, 0): the 4×3 map is where the quaternion shows
section("3. q̇ = ½ q ⊗ (ω, 0) and integration")
h = 1e-6
qdot_numeric = (fd.integrate(model, q, h * w) - fd.integrate(model, q, -h * w)) / (2 * h)
qdot = 0.5 * quat_multiply(q, np.concatenate([w, [0.0]]))
show("q̇", qdot)
check("central difference of fd.integrate", qdot_numeric, qdot, 1e-9)
check("fd.integrate = pin.integrate", fd.integrate(model, q, w), jmap.q_from_pin(pin.integrate(pmodel, jmap.q_to_pin(q), jmap.v_to_pin(w))), 1e-12)
R0, R1 = quat_to_matrix(q), quat_to_matrix(fd.integrate(model, q, w))
check("R' = R exp([ω]×) (ω in the child frame)", R1, R0 @ fd.rotation.so3_exp(w), 1e-12)
print("\nExercise 6 done.")
