# needs: featherdyn[verify] (Pinocchio): pip install "featherdyn[verify]"
"""Exercise 8 (first list) — a 3-DOF spatial arm: S_i, ⁱX_{i−1}, link velocities, end-effector velocity.

Joint 1 about z, joint 2 about y, joint 3 about x, links ℓ = 0.5 m. The
chapter does not fix where the joints sit; here (a choice, stated): joint 1
at the base origin, joint 2 at (0, 0, ℓ) on link 1 (a vertical column),
joint 3 at (ℓ, 0, 0) on link 2, the end effector at (ℓ, 0, 0) on link 3.
q = (30°, 45°, 0°), q̇ = (1, 0.5, −0.3) rad/s.

Run: python examples/17_ex8_3dof_arm.py
"""

# ruff: noqa: N816  (the chapter's frame subscripts, v_A, f_B, vJ, are kept on purpose)

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
from _check import check, section, show

import featherdyn as fd
from featherdyn.verify.bridge import pinocchio_model_from, to_pin6

ell = 0.5
rod = fd.SpatialInertia(1.0, [0.0, 0.0, 0.0], np.diag([0.02, 0.02, 0.001]))
b = fd.ModelBuilder("3dof")
l1 = b.add_body("link1", -1, fd.RevoluteJoint([0, 0, 1]), inertia=rod, joint_name="joint1")
l2 = b.add_body("link2", l1, fd.RevoluteJoint([0, 1, 0]), inertia=rod, joint_name="joint2",
                placement=fd.PluckerTransform(np.eye(3), [0.0, 0.0, ell]))
l3 = b.add_body("link3", l2, fd.RevoluteJoint([1, 0, 0]), inertia=rod, joint_name="joint3",
                placement=fd.PluckerTransform(np.eye(3), [ell, 0.0, 0.0]))
b.add_frame("ee", l3, fd.PluckerTransform(np.eye(3), [ell, 0.0, 0.0]))
model = b.build()
q = np.deg2rad([30.0, 45.0, 0.0])
qd = np.array([1.0, 0.5, -0.3])

# %% 1. (a) S_i and ⁱX_{i−1}
section("1. (a) motion subspaces and link-to-link transforms")
for i in range(3):
    show(f"S{i + 1}ᵀ", model.joints[i].S.T)
kin = fd.forward_kinematics(model, q, qd)
X_up = [kin.parent_placements[i].inverse() for i in range(3)]
for i in range(3):
    show(f"{i + 1}X{i}", X_up[i].matrix(), 3)
# by hand: ²X₁ = rot_y(q2) · xlt((0, 0, ℓ)) in spatial_v2's notation
check("²X₁ = roty(q₂) @ xlt((0, 0, ℓ)) (spatial_v2 style)", X_up[1].matrix(),
      (fd.roty(q[1]) @ fd.xlt([0.0, 0.0, ell])).matrix(), 1e-14)

# %% 2. (b) link velocities by the recursion
section("2. (b) v_i = ⁱX_{i−1} v_{i−1} + S_i q̇_i")
vel = []
for i in range(3):
    vJ = fd.SpatialMotion.from_vector(model.joints[i].S[:, 0] * qd[i])
    vel.append(vJ if i == 0 else X_up[i].apply(vel[-1]) + vJ)
    show(f"v{i + 1} (ω; v_O) in link {i + 1}", vel[-1].vector)
check("recursion = fd.forward_kinematics", np.stack([v.vector for v in vel]), kin.velocities.vector, 1e-14)
# by hand for link 2: ω₂ = R_y(q₂)ᵀ (0, 0, q̇₁) + (0, q̇₂, 0); the origin of link 2 is on joint 1's axis → v_O = 0
c2, s2 = np.cos(q[1]), np.sin(q[1])
check("v2 by hand", vel[1].vector, [-s2 * qd[0], qd[1], c2 * qd[0], 0.0, 0.0, 0.0], 1e-14)

# %% 3. (c) end-effector velocity: classical (ω, ṗ) = J(q) q̇
section("3. (c) end effector: (ω, ṗ) in world axes = J q̇")
v_ee = fd.frame_velocity(model, q, qd, "ee", fd.LOCAL_WORLD_ALIGNED)
show("ω_ee (world)", v_ee.angular)
show("ṗ_ee (world)", v_ee.linear)
J = fd.frame_jacobian(model, q, "ee", fd.LOCAL_WORLD_ALIGNED)
check("J(q) q̇ = frame velocity", J @ qd, v_ee.vector, 1e-14)
h = 1e-6
Tp = fd.frame_placement(model, q + h * qd, "ee")
Tm = fd.frame_placement(model, q - h * qd, "ee")
check("ṗ = central difference of the FK position", (Tp.translation - Tm.translation) / (2 * h), v_ee.linear, 1e-9)
Rdot = (Tp.rotation - Tm.rotation) / (2 * h)
W = Rdot @ fd.frame_placement(model, q, "ee").rotation.T
check("[ω]× = Ṙ Rᵀ", fd.unskew((W - W.T) / 2), v_ee.angular, 1e-9)
v_local = fd.frame_velocity(model, q, qd, "ee", fd.LOCAL)
check("LOCAL velocity = ᵉᵉX₃ v₃", v_local.vector,
      fd.PluckerTransform(np.eye(3), [ell, 0.0, 0.0]).apply_inverse(vel[2]).vector, 1e-14)

# %% 4. (d) Pinocchio
section("4. (d) Pinocchio")
pm = pinocchio_model_from(model)
fid = pm.addFrame(pin.Frame("ee", pm.getJointId("joint3"), pin.SE3(np.eye(3), np.array([ell, 0.0, 0.0])),
                            pin.FrameType.OP_FRAME))
pd = pm.createData()
pin.forwardKinematics(pm, pd, q, qd)
pin.updateFramePlacements(pm, pd)
for i in range(3):
    check(f"data.v[{i + 1}] = v{i + 1}", to_pin6(pd.v[i + 1].vector), vel[i].vector, 1e-14)
check("getFrameVelocity(LOCAL_WORLD_ALIGNED)", to_pin6(pin.getFrameVelocity(pm, pd, fid, pin.LOCAL_WORLD_ALIGNED).vector),
      v_ee.vector, 1e-14)
Jp = pin.computeFrameJacobian(pm, pd, q, fid, pin.LOCAL_WORLD_ALIGNED)
check("computeFrameJacobian(LOCAL_WORLD_ALIGNED)", to_pin6(Jp.T).T, J, 1e-14)
print("\nExercise 8 done.")
