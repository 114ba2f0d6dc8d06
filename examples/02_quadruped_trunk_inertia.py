# needs: featherdyn[verify] (Pinocchio): pip install "featherdyn[verify]"
"""§9.2 — the spatial inertia of a quadruped trunk, at its CoM and at the front-left hip.

Trunk: m = 12 kg, I_b = diag(0.1, 0.3, 0.35) kg·m², CoM at the body origin;
the hip sits at c = (0.2, 0.1, 0) m from the CoM.

What the chapter prints: the parallel-axis block −m[c]×[c]× = m(|c|²1 − ccᵀ)
= [[0.12, −0.24, 0], [−0.24, 0.48, 0], [0, 0, 0.60]] — right. Its §5.1
formula takes c as the vector *from the reference point to the CoM*; seen
from the hip that vector is −c, so the coupling block is m[−c]× = −m[c]×.
(The final 6×6 display of §9.2 is lost in the text; plugging +c describes
the rear-right hip instead.) Section 3 tells the two apart by physics.

Run: python examples/02_quadruped_trunk_inertia.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
from _check import P6, check, check_true, differs, section, show

import featherdyn as fd

m = 12.0
I_b = np.diag([0.1, 0.3, 0.35])
c = np.array([0.2, 0.1, 0.0])  # the hip, seen from the CoM
PRINTED_BLOCK = np.array([[0.12, -0.24, 0.0], [-0.24, 0.48, 0.0], [0.0, 0.0, 0.60]])

# %% 1. (a) at the CoM: block diagonal
section("1. (a) spatial inertia about the CoM")
trunk = fd.SpatialInertia(m, np.zeros(3), I_b)
show("I_com", trunk.matrix())
check("I_com = diag(I_b, m 1)", trunk.matrix(), np.block([[I_b, np.zeros((3, 3))], [np.zeros((3, 3)), m * np.eye(3)]]))
check_true("physically valid (positive definite, triangle inequality)", trunk.is_physical())

# %% 2. (b) the parallel-axis block printed by the chapter
section("2. (b) parallel-axis block m(|c|² 1 − c cᵀ)")
block = m * (c @ c * np.eye(3) - np.outer(c, c))
show("m(|c|²1 − ccᵀ)", block)
check("printed [[0.12, −0.24, 0], [−0.24, 0.48, 0], [0, 0, 0.60]]", block, PRINTED_BLOCK, 1e-12)
hip = fd.SpatialInertia(m, -c, I_b)  # seen from the hip, the CoM is at −c
I_hip = hip.matrix()
show("I_hip", I_hip)
check("upper-left block = I_b + printed block", I_hip[:3, :3], I_b + PRINTED_BLOCK, 1e-12)
check("coupling block = m[−c]× = −m[c]×", I_hip[:3, 3:], -m * fd.skew(c), 1e-12)
check("symmetric", I_hip, I_hip.T, 0.0)
# the same by moving the frame: the trunk origin sits at −c in hip coordinates
X_hip_trunk = fd.PluckerTransform(np.eye(3), -c)
check("X* I_com X⁻¹ with the trunk origin at −c in the hip frame", X_hip_trunk.apply(trunk).matrix(), I_hip, 1e-12)

# %% 3. the off-diagonal sign, decided by physics
section("3. which sign? spin about the CoM: the momentum must be purely angular")
w = np.array([0.0, 0.0, 1.5])
v_hip = fd.SpatialMotion(w, np.cross(w, c))  # the body point at the hip moves with ω × c
h = hip @ v_hip
show("h (com = −c)", h.vector)
check("linear momentum of a body spinning about its CoM = 0", h.linear, np.zeros(3), 1e-12)
check("angular momentum about the hip = I_b ω (no orbit)", h.angular, I_b @ w, 1e-12)
wrong = fd.SpatialInertia(m, +c, I_b) @ v_hip
differs("plugging +c into §5.1's formula (the rear-right hip)", wrong.linear, np.zeros(3), 1.0)

# %% 4. Pinocchio
section("4. against Pinocchio (linear-first matrices)")
theirs = pin.Inertia(m, -c, I_b).matrix()
check("pin.Inertia(m, −c, I_b).matrix() (swapped to angular first)", P6 @ theirs @ P6, I_hip, 1e-12)
moved = pin.SE3(np.eye(3), -c).act(pin.Inertia(m, np.zeros(3), I_b)).matrix()
check("pin.SE3(1, −c).act(I_com)", P6 @ moved @ P6, I_hip, 1e-12)
check_true("eigenvalues positive", np.all(np.linalg.eigvalsh(I_hip) > 0))
print("\nAll §9.2 checks passed.")
