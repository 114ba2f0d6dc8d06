# needs: featherdyn[verify,symbolic] (Pinocchio, SymPy): pip install "featherdyn[verify,symbolic]"
"""§9.1 — spatial velocities of the planar 2R arm, the derivation the chapter "leaves as an exercise".

The chapter puts frame {1} at joint 2 (the end of link 1) and frame {2} at the
end of link 2, then uses S₁ = S₂ = (1, 0, 0) (planar ω_z; v_x, v_y). That S
holds only for a frame whose origin lies on the joint axis. Here the
derivation is finished both ways, symbolically (SymPy on featherdyn's own
transforms) and numerically (against Pinocchio):

* the chapter's frames: S₁ = (1; 0, ℓ₁) in {1}, S₂ = (1; 0, ℓ₂) in {2};
* Featherstone's frames (frame i on joint i's axis): S = (1; 0, 0).

Run: python examples/01_2r_spatial_velocities.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio", "sympy")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
import sympy as sp
from _check import check, check_true, section, show

import featherdyn as fd
from featherdyn import symbolic
from featherdyn.verify.bridge import pinocchio_model_from, to_pin6

q1, q2, dq1, dq2 = sp.symbols("q1 q2 dq1 dq2", real=True)
l1, l2 = sp.symbols("l1 l2", positive=True)


def obj(x):
    return np.array(x, dtype=object)


def rz(t):
    return obj([[sp.cos(t), -sp.sin(t), 0], [sp.sin(t), sp.cos(t), 0], [0, 0, 1]])


def planar(m):
    """(ω_z; v_x, v_y) of a 6D motion [ω; v]."""
    v = m.vector if hasattr(m, "vector") else m
    return sp.Matrix([v[2], v[3], v[4]])


# %% 1. the chapter's frames: {1} at joint 2, {2} at the end of link 2
section("1. chapter's frames, symbolic")
# pose of {1} in {0}: rotation q1, origin at joint 2 = l1 (cos q1, sin q1)
M_01 = fd.PluckerTransform(rz(q1), obj([l1 * sp.cos(q1), l1 * sp.sin(q1), 0]), validate=False)
# pose of {2} in {1}: rotation q2, origin at the tip of link 2 = l2 (cos q2, sin q2) from joint 2
M_12 = fd.PluckerTransform(rz(q2), obj([l2 * sp.cos(q2), l2 * sp.sin(q2), 0]), validate=False)
X_10, X_21 = M_01.inverse(), M_12.inverse()  # ¹X₀, ²X₁ move motion vectors from parent to child
# joint axes: joint 1 passes through (−l1, 0, 0) in {1}, joint 2 through (−l2, 0, 0) in {2}
z_axis = fd.SpatialMotion(obj([0, 0, 1]), obj([0, 0, 0]))
S1 = fd.PluckerTransform(np.eye(3, dtype=int).astype(object), obj([-l1, 0, 0]), validate=False).apply(z_axis)
S2 = fd.PluckerTransform(np.eye(3, dtype=int).astype(object), obj([-l2, 0, 0]), validate=False).apply(z_axis)
print("  S1 (planar) =", list(planar(S1)), "  — the chapter writes (1, 0, 0)")
print("  S2 (planar) =", list(planar(S2)))
v1 = S1 * dq1
v2 = X_21.apply(v1) + S2 * dq2
v1_planar = symbolic.canonical(planar(v1))
v2_planar = symbolic.canonical(planar(v2))
print("  v1 =", list(v1_planar))
print("  v2 =", list(v2_planar))
expected_v2 = sp.Matrix([dq1 + dq2, l1 * dq1 * sp.sin(q2), l1 * dq1 * sp.cos(q2) + l2 * (dq1 + dq2)])
check_true("v2 = (q̇1+q̇2; l1 q̇1 sin q2, l1 q̇1 cos q2 + l2 (q̇1+q̇2))", symbolic.is_zero(v2_planar - expected_v2))

# %% 2. the "more careful geometric verification": the linear part is the tip's velocity in {2}
section("2. geometric check: linear part of v2 = R2ᵀ d/dt p_tip")
t = sp.Symbol("t")
Q1, Q2 = sp.Function("Q1")(t), sp.Function("Q2")(t)
tip = sp.Matrix([l1 * sp.cos(Q1) + l2 * sp.cos(Q1 + Q2), l1 * sp.sin(Q1) + l2 * sp.sin(Q1 + Q2)])
tip_dot = tip.diff(t).subs({Q1.diff(t): dq1, Q2.diff(t): dq2}).subs({Q1: q1, Q2: q2})
c, s = sp.cos(q1 + q2), sp.sin(q1 + q2)
tip_in_2 = sp.Matrix([[c, s], [-s, c]]) * tip_dot  # world → {2} coordinates
check_true("v2 linear part == velocity of link 2's tip in {2}", symbolic.is_zero(tip_in_2 - v2_planar[1:, :]))
check_true("v2 angular part == q̇1 + q̇2", symbolic.is_zero(v2_planar[0] - dq1 - dq2))

# %% 3. Featherstone's frames (frame i on joint i): S = (1, 0, 0) is right there
section("3. frames on the joint axes: S = (1; 0, 0)")
X_10f = fd.PluckerTransform(rz(q1), obj([0, 0, 0]), validate=False).inverse()
X_21f = fd.PluckerTransform(rz(q2), obj([l1, 0, 0]), validate=False).inverse()
v1f = z_axis * dq1
v2f = X_21f.apply(v1f) + z_axis * dq2
v2f_planar = symbolic.canonical(planar(v2f))
print("  v1 =", list(symbolic.canonical(planar(v1f))), " v2 =", list(v2f_planar))
check_true("v2 = (q̇1+q̇2; l1 q̇1 sin q2, l1 q̇1 cos q2) (velocity of the joint-2 point)",
           symbolic.is_zero(v2f_planar - sp.Matrix([dq1 + dq2, l1 * dq1 * sp.sin(q2), l1 * dq1 * sp.cos(q2)])))
_ = X_10f  # ¹X₀ is a pure rotation: v₀ = 0 contributes nothing

# %% 4. numbers (appendix D's state) against featherdyn's algorithms and Pinocchio
section("4. numbers at q = (30°, 45°), q̇ = (2, −1), ℓ = (1.0, 0.8)")
arm = symbolic.two_link_arm(symbolic.APPENDIX_D)  # frames on the joints, a "tip" frame at (l2, 0, 0) on link 2
q = np.deg2rad([30.0, 45.0])
v = np.array([2.0, -1.0])
values = {q1: q[0], q2: q[1], dq1: v[0], dq2: v[1], l1: 1.0, l2: 0.8}
v2_num = np.array([float(e.subs(values)) for e in v2_planar])
v2f_num = np.array([float(e.subs(values)) for e in v2f_planar])
show("v2 (chapter's {2}, at the tip)", v2_num)
show("v2 (frame at joint 2)", v2f_num)
kin = fd.forward_kinematics(arm, q, v)
body2 = kin.velocities.vector[1]
check("featherdyn body velocity of link 2 (frame at joint 2)", body2[[2, 3, 4]], v2f_num, 1e-12)
tip_v = fd.frame_velocity(arm, q, v, "tip", fd.LOCAL).vector
check("featherdyn frame_velocity('tip', LOCAL) = chapter's v2", tip_v[[2, 3, 4]], v2_num, 1e-12)
pm = pinocchio_model_from(arm)
data = pm.createData()
pin.forwardKinematics(pm, data, q, v)
check("Pinocchio data.v[2] (linear first, converted)", to_pin6(data.v[2].vector), body2, 1e-12)
tip_pin = pin.SE3(np.eye(3), np.array([0.8, 0.0, 0.0])).actInv(data.v[2])
check("Pinocchio tip velocity (SE3 tip.actInv(v))", to_pin6(tip_pin.vector)[[2, 3, 4]], v2_num, 1e-12)
print("\nAll §9.1 checks passed.")
