# needs: featherdyn[verify] (Pinocchio, example-robot-data): pip install "featherdyn[verify]"
"""Exercise 4 (first list) — Panda: data.v[3] by the recursion, and spatial vs classical acceleration.

(a) the spatial velocity of joint 3 (``data.v[3]``, body coordinates);
(b) rebuilt by hand, v₃ = ³X₂ v₂ + S₃ q̇₃, with featherdyn's transforms —
    and with Pinocchio's ``liMi``, which must be used with ``actInv``;
(c) ``data.a[3]`` is the *spatial* acceleration; the classical acceleration
    of the frame origin adds ω × v to its linear part (§7.2).

Run: python examples/13_ex4_panda_velocity_recursion.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio", "example-robot-data")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
from _check import check, section, show

import featherdyn as fd
from featherdyn.robots import robot_path
from featherdyn.verify.bridge import JointMap, to_pin6

model = fd.load_robot("panda")
pmodel = pin.buildModelFromUrdf(str(robot_path("panda")))
pdata = pmodel.createData()
jmap = JointMap(model, pmodel)
rng = np.random.default_rng(4)
q = fd.random_configuration(model, rng)
v = rng.normal(size=model.nv)
a = rng.normal(size=model.nv)
pin.forwardKinematics(pmodel, pdata, jmap.q_to_pin(q), jmap.v_to_pin(v), jmap.v_to_pin(a))
j3 = pmodel.getJointId("panda_joint3")  # = 3: joint 0 is Pinocchio's universe
b3 = model.body_id("panda_link3")  # = 2 in featherdyn (bodies from 0)

# %% 1. (a) data.v[3]
section("1. (a) data.v[3]")
v3_pin = pdata.v[j3]
show("Pinocchio data.v[3] (linear; angular)", v3_pin.vector)
kin = fd.forward_kinematics(model, q, v, a)
v3_fd = kin.velocities.vector[b3]
show("featherdyn v[panda_link3] (angular; linear)", v3_fd)
check("same motion", v3_fd, to_pin6(v3_pin.vector), 1e-12)

# %% 2. (b) v₃ = ³X₂ v₂ + S₃ q̇₃
section("2. (b) the recursion by hand")
b2 = model.parents[b3]
X_32 = kin.parent_placements[b3].inverse()  # ³X₂: the pose of 3 in 2, inverted
S3 = model.joints[b3].S
qd3 = v[model.idx_v[b3]:model.idx_v[b3] + model.nvs[b3]]
v2 = fd.SpatialMotion.from_vector(kin.velocities.vector[b2])
v3_manual = X_32.apply(v2) + fd.SpatialMotion.from_vector(S3 @ qd3)
show("S3ᵀ", S3.T)
check("³X₂ v₂ + S₃ q̇₃ = v₃", v3_manual.vector, v3_fd, 1e-12)
S3_pin = np.asarray(pdata.joints[j3].S).reshape(6, -1)
v3_pin_manual = pdata.liMi[j3].actInv(pdata.v[j3 - 1]).vector + S3_pin @ jmap.v_to_pin(v)[pmodel.idx_vs[j3]:pmodel.idx_vs[j3] + 1]
check("Pinocchio: liMi[3].actInv(v[2]) + S q̇ = data.v[3]", v3_pin_manual, v3_pin.vector, 1e-12)

# %% 3. (c) spatial vs classical acceleration
section("3. (c) data.a[3] (spatial) vs classical acceleration of the frame origin")
a3_spatial = to_pin6(pdata.a[j3].vector)
a3_classical = to_pin6(pin.getClassicalAcceleration(pmodel, pdata, j3, pin.LOCAL).vector)
show("spatial a (angular; linear)", a3_spatial)
show("classical a (angular; linear)", a3_classical)
w, lin = v3_fd[:3], v3_fd[3:]
check("classical = spatial + (0; ω × v)", a3_classical, a3_spatial + np.concatenate([np.zeros(3), np.cross(w, lin)]), 1e-12)
check("angular parts equal", a3_classical[:3], a3_spatial[:3], 1e-12)
show("|ω × v| (the difference)", np.linalg.norm(np.cross(w, lin)))
check("featherdyn kin.accelerations = data.a", kin.accelerations.vector[b3], a3_spatial, 1e-12)
check("fd.frame_acceleration(LOCAL) = data.a[3]",
      fd.frame_acceleration(model, q, v, a, "panda_link3", fd.LOCAL).vector, a3_spatial, 1e-12)
check("fd.frame_classical_acceleration(LOCAL) = getClassicalAcceleration",
      fd.frame_classical_acceleration(model, q, v, a, "panda_link3", fd.LOCAL).vector, a3_classical, 1e-12)
# the classical acceleration is the second derivative of the origin's position (central differences)
h = 1e-4


def origin(t):
    qt = fd.integrate(model, q, v * t + 0.5 * a * t * t)
    return fd.frame_placement(model, qt, "panda_link3").translation


acc_fd = (origin(h) - 2 * origin(0.0) + origin(-h)) / h**2
R3 = fd.frame_placement(model, q, "panda_link3").rotation
check("classical linear part = R₃ᵀ d²p/dt² (finite differences)", a3_classical[3:], R3.T @ acc_fd, 1e-5)
print("\nExercise 4 done.")
