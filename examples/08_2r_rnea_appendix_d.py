# needs: featherdyn[verify,symbolic] (Pinocchio, SymPy): pip install "featherdyn[verify,symbolic]"
"""Appendix D — the planar 2R arm's RNEA step by step, with the torques the chapter omits.

D.1: ℓ = (1.0, 0.8) m, m = (3, 2) kg, CoM at (0.5, 0.4) m from each joint,
I_zz = (0.25, 0.11) kg·m² about the CoM; q = (30°, 45°), q̇ = (2, −1) rad/s,
q̈ = (0.5, −0.3) rad/s²; gravity −9.81 along the base y axis (the chapter's
a₀ = (0; 0, 9.81)).

Errata measured here (planar vectors are (ω_z; v_x, v_y)):

* D.2 puts link 1's frame at joint 2 yet writes v₁ = S₁q̇₁ = (2; 0, 0). With
  the origin at joint 2 the linear part is ℓ₁q̇₁ = 2: v₁ = (2; 0, 2). Its
  numbers hold for frames *on* the joint axes (Featherstone's placement).
* D.3 prints ²X₁v₁ = (2; 1.414, −1.414); it is (2; 1.414, +1.414) (the
  (3,1) entry of its ²X₁ is +ℓ₁cos q₂, not −ℓ₁cos q₂).
* D.3 writes a₀ = "(0; 0, −g) = (0; 0, 9.81)": the value is right (−g with
  g = (0, −9.81)), and ¹X₀a₀ = (0; 4.905, 8.496) is right.

τ₁, τ₂ ("the numerical computation is long, here are the final torques" —
which the chapter then does not give) are computed by hand, by fd.rnea, by
Pinocchio, by the Lagrangian closed form, and with the chapter's own frame
placement (frames at the link ends): all agree, τ = (35.4452, 4.6628) N·m.

Run: python examples/08_2r_rnea_appendix_d.py
"""

# ruff: noqa: N816  (the chapter's frame subscripts, v_A, f_B, vJ, are kept on purpose)

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio", "sympy")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
import sympy as sp
from _check import check, differs, section, show

import featherdyn as fd
from featherdyn import symbolic
from featherdyn.verify.bridge import pinocchio_model_from

P = symbolic.APPENDIX_D
l1, l2 = P["l1"], P["l2"]
q = np.deg2rad([30.0, 45.0])
qd = np.array([2.0, -1.0])
qdd = np.array([0.5, -0.3])
arm = symbolic.two_link_arm(P)  # frames on the joint axes, gravity (0, −9.81, 0)
PL = [2, 3, 4]  # (ω_z; v_x, v_y) inside [ω; v]


def planar(m):
    return (m.vector if hasattr(m, "vector") else np.asarray(m))[PL]


def rz(t):
    c, s = np.cos(t), np.sin(t)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


z = fd.SpatialMotion([0.0, 0.0, 1.0], [0.0, 0.0, 0.0])  # S for a frame on the joint axis
I1, I2 = arm.inertias[0], arm.inertias[1]

# %% 1. Pass 1 with frames on the joint axes (the placement D.3's numbers belong to)
section("1. Pass 1: velocities and accelerations (frames on the joint axes)")
X_10 = fd.PluckerTransform(rz(q[0]), np.zeros(3)).inverse()  # ¹X₀: rotation q1
X_21 = fd.PluckerTransform(rz(q[1]), [l1, 0.0, 0.0]).inverse()  # ²X₁: joint 2 at (l1, 0) in link 1
a0 = fd.SpatialMotion(np.zeros(3), -arm.gravity)  # (0; 0, +9.81): the base accelerates up
v1 = z * qd[0]
show("v1", planar(v1))
check("v1 = (2; 0, 0) as printed", planar(v1), [2.0, 0.0, 0.0], 0.0)
X10a0 = X_10.apply(a0)
show("¹X₀ a₀", planar(X10a0))
check("¹X₀ a₀ = (0; 4.905, 8.496) as printed", planar(X10a0), [0.0, 4.905, 8.496], 5e-4)
check("v1 × S1 q̇1 = 0", planar(v1.cross(z * qd[0])), np.zeros(3), 0.0)
a1 = X10a0 + z * qdd[0] + v1.cross(z * qd[0])
show("a1", planar(a1))
X21v1 = X_21.apply(v1)
show("²X₁ v₁", planar(X21v1))
s2 = np.sqrt(2.0)
check("²X₁ v₁ = (2; 1.414, +1.414)", planar(X21v1), [2.0, s2, s2], 1e-12)
differs("chapter's ²X₁ v₁ = (2; 1.414, −1.414)", planar(X21v1), [2.0, 1.414, -1.414], 1.0)
X21_planar = X_21.matrix()[np.ix_(PL, PL)]
c45, s45 = np.cos(q[1]), np.sin(q[1])
chapter_X21 = np.array([[1.0, 0.0, 0.0], [l1 * s45, c45, s45], [-l1 * c45, -s45, c45]])
show("²X₁ (planar block)", X21_planar)
differs("chapter's ²X₁ (its (3,1) entry −ℓ₁cos q₂)", X21_planar, chapter_X21, 1.0)
v2 = X21v1 + z * qd[1]
a2 = X_21.apply(a1) + z * qdd[1] + v2.cross(z * qd[1])
show("v2", planar(v2))
show("a2", planar(a2))
kin = fd.forward_kinematics(arm, q, qd, qdd)
check("v1, v2 = fd.forward_kinematics", kin.velocities.vector, np.stack([v1.vector, v2.vector]), 1e-12)

# %% 2. the chapter's frame origin: link 1's frame at joint 2
section("2. D.2's placement (frame 1 at joint 2): v1 is not (2; 0, 0)")
M_0_1end = fd.PluckerTransform(rz(q[0]), l1 * np.array([np.cos(q[0]), np.sin(q[0]), 0.0]))  # frame at joint 2
S1_end = fd.PluckerTransform(np.eye(3), [-l1, 0.0, 0.0]).apply(z)  # joint 1's axis at (−l1, 0) in that frame
show("S1 in a frame at joint 2", planar(S1_end))
v1_end = S1_end * qd[0]
show("v1 in a frame at joint 2", planar(v1_end))
differs("chapter: v1 = (2; 0, 0) with the origin at joint 2", planar(v1_end), [2.0, 0.0, 0.0], 1.0)
check("v1 = (2; 0, ℓ₁q̇₁) = (2; 0, 2)", planar(v1_end), [2.0, 0.0, 2.0], 1e-12)
X_end_joint = fd.PluckerTransform(np.eye(3), [-l1, 0.0, 0.0])  # joint-1 frame seen from joint 2 (same axes)
check("the same motion re-expressed at joint 2", X_end_joint.apply(v1).vector, v1_end.vector, 1e-12)

# %% 3. Pass 2: forces and the torques
section("3. Pass 2: f_i = I_i a_i + v_i ×* I_i v_i,  τ_i = S_iᵀ f_i")
f2 = I2 @ a2 + v2.cross(I2 @ v2)
tau2 = z.dot(f2)
f1 = I1 @ a1 + v1.cross(I1 @ v1) + X_21.apply_inverse(f2)  # ¹X₂* f₂
tau1 = z.dot(f1)
show("f2 (n_z; f_x, f_y)", planar(f2))
show("f1 (n_z; f_x, f_y)", planar(f1))
tau = np.array([tau1, tau2])
print(f"  τ₁ = {tau1:.4f} N·m,  τ₂ = {tau2:.4f} N·m")
check("τ = (35.4452, 4.6628) N·m", tau, [35.4452, 4.6628], 5e-5)

# %% 4. the same torques, four more ways
section("4. cross-checks")
check("fd.rnea", fd.rnea(arm, q, qd, qdd), tau, 1e-12)
pmodel = pinocchio_model_from(arm)
check("Pinocchio rnea (pinocchio_model_from)", pin.rnea(pmodel, pmodel.createData(), q, qd, qdd), tau, 1e-12)
lag = symbolic.lagrangian_two_link(P)
values = {lag.q[0]: q[0], lag.q[1]: q[1], lag.v[0]: qd[0], lag.v[1]: qd[1]}
M = np.array(lag.M.subs(values).evalf(), dtype=float)
C = np.array(lag.C.subs(values).evalf(), dtype=float)
g = np.array(lag.g.subs(values).evalf(), dtype=float)[:, 0]
print("  Lagrangian: M =", sp.sstr(lag.M), "\n              g =", sp.sstr(lag.g.T))
check("Lagrangian closed form M q̈ + C q̇ + g", M @ qdd + C @ qd + g, tau, 1e-12)
# the chapter's own placement: frames at the link ends (c₂ = −0.4 as D.4 says), S with a lever arm
X_1e0 = M_0_1end.inverse()
X_2e1e = fd.PluckerTransform(rz(q[1]), l2 * np.array([np.cos(q[1]), np.sin(q[1]), 0.0])).inverse()
S2_end = fd.PluckerTransform(np.eye(3), [-l2, 0.0, 0.0]).apply(z)
I1e = fd.SpatialInertia(P["m1"], [P["c1"] - l1, 0.0, 0.0], P["I1"] * np.eye(3))
I2e = fd.SpatialInertia(P["m2"], [P["c2"] - l2, 0.0, 0.0], P["I2"] * np.eye(3))  # c₂ = −0.4
v1e = S1_end * qd[0]
a1e = X_1e0.apply(a0) + S1_end * qdd[0] + v1e.cross(S1_end * qd[0])
v2e = X_2e1e.apply(v1e) + S2_end * qd[1]
a2e = X_2e1e.apply(a1e) + S2_end * qdd[1] + v2e.cross(S2_end * qd[1])
f2e = I2e @ a2e + v2e.cross(I2e @ v2e)
f1e = I1e @ a1e + v1e.cross(I1e @ v1e) + X_2e1e.apply_inverse(f2e)
check("frames at the link ends (the chapter's placement, S with lever arms)", [S1_end.dot(f1e), S2_end.dot(f2e)], tau, 1e-12)
print("\nAll appendix D checks passed.")
