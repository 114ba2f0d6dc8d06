# needs: featherdyn[verify,symbolic] (Pinocchio, SymPy): pip install "featherdyn[verify,symbolic]"
"""Exercise 1 (first list) — det X = 1 for every Plücker transform.

The hint's block formula det([[A, B], [C, D]]) = det A · det(D − C A⁻¹ B)
with A = D = R, B = 0 gives det X = det(R)² = 1. Checked numerically on
random transforms (featherdyn and Pinocchio's action matrix) and proved
symbolically for a general rotation (unit quaternion and roll-pitch-yaw) and
a general translation.

Run: python examples/10_ex1_plucker_determinant.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio", "sympy")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
from _check import check, check_true, section, show

import featherdyn as fd
from featherdyn import symbolic
from featherdyn.rotation import quat_normalize, quat_to_matrix

rng = np.random.default_rng(1)
R = quat_to_matrix(quat_normalize(rng.normal(size=(200, 4))))
p = rng.uniform(-2.0, 2.0, size=(200, 3))
X = fd.PluckerTransform(R, p)

# %% 1. numerically, 200 random transforms
section("1. det X on 200 random transforms")
dets = np.linalg.det(X.matrix())
show("min, max det X", [dets.min(), dets.max()])
check("det X = 1", dets, np.ones(200), 1e-12)
check("det X* = 1", np.linalg.det(X.dual_matrix()), np.ones(200), 1e-12)

# %% 2. the hint's block formula
section("2. block formula: det A · det(D − C A⁻¹ B), B = 0")
Xm = X.matrix()[0]
A, B, C, D = Xm[:3, :3], Xm[:3, 3:], Xm[3:, :3], Xm[3:, 3:]
block = np.linalg.det(A) * np.linalg.det(D - C @ np.linalg.inv(A) @ B)
show("det R, det(R − 0)", [np.linalg.det(A), np.linalg.det(D - C @ np.linalg.inv(A) @ B)])
check("block formula = det(R)² = 1", block, 1.0, 1e-12)

# %% 3. Pinocchio's action matrix
section("3. Pinocchio SE3.toActionMatrix()")
pin_dets = [np.linalg.det(pin.SE3(R[k], p[k]).toActionMatrix()) for k in range(20)]
check("det of Pinocchio's X (linear-first layout, same determinant)", pin_dets, np.ones(20), 1e-12)

# %% 4. a proof, not a sample
section("4. symbolic: det X − 1 reduces to 0 exactly")
for parametrization in symbolic.PARAMETRIZATIONS:
    check_true(f"det X = 1 for a general rotation ({parametrization}) and symbolic p",
               symbolic.prove_plucker_determinant(parametrization))
print("\nExercise 1 done.")
