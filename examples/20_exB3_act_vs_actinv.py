# needs: featherdyn[verify] (Pinocchio): pip install "featherdyn[verify]"
"""Exercise 3 (second list) — Pinocchio's act / actInv on motions and forces; power invariance.

T = SE3(R_z(30°), (1, 0, 0)). Motions *and* forces move from A to B with
``T.act`` (type-aware: X for a Motion, X⁻ᵀ for a Force); ``actInv`` goes the
other way, B → A. The troubleshooting table's advice "motion uses act, force
uses actInv" breaks power invariance (§16's pitfall box has it right).

Run: python examples/20_exB3_act_vs_actinv.py
"""

# ruff: noqa: N816  (the chapter's frame subscripts, v_A, f_B, vJ, are kept on purpose)

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
from _check import P6, check, differs, section, show

import featherdyn as fd
from featherdyn import conventions

R = pin.utils.rpyToMatrix(0.0, 0.0, np.pi / 6)
p = np.array([1.0, 0.0, 0.0])
T = pin.SE3(R, p)
v_A = pin.Motion(np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0]))
f_A = pin.Force(np.array([0.0, 10.0, 0.0]), np.array([0.0, 0.0, 5.0]))

# %% 1. (b) act on both: power invariant
section("1. (b) v_B = T.act(v_A), f_B = T.act(f_A)")
v_B, f_B = T.act(v_A), T.act(f_A)
show("power A, power B", [v_A.dot(f_A), v_B.dot(f_B)])
check("v_A·f_A = v_B·f_B", v_B.dot(f_B), v_A.dot(f_A), 1e-13)

# %% 2. (c) actInv on the force
section("2. (c) the force moved with actInv")
wrong = v_B.dot(T.actInv(f_A))
err = abs(wrong - v_A.dot(f_A)) / abs(v_A.dot(f_A))
show("power with actInv(f)", wrong)
print(f"  relative error: {100 * err:.1f} %")
differs("power with actInv on the force", wrong, v_A.dot(f_A), 1.0)
check("actInv is the B → A transform: T.actInv(T.act(f)) = f", T.actInv(T.act(f_A)).vector, f_A.vector, 1e-14)

# %% 3. (d) the 6×6 matrices
section("3. (d) T.act(v) = X v, T.act(f) = X⁻ᵀ f")
X = np.block([[R, np.zeros((3, 3))], [pin.skew(p) @ R, R]])
Xinv_T = np.linalg.inv(X).T
v_fd, f_fd = conventions.from_pinocchio_motion(v_A), conventions.from_pinocchio_force(f_A)
check("T.act(v) = X v", conventions.from_pinocchio_motion(v_B).vector, X @ v_fd.vector, 1e-14)
check("T.act(f) = X⁻ᵀ f", conventions.from_pinocchio_force(f_B).vector, Xinv_T @ f_fd.vector, 1e-14)
Xf = fd.PluckerTransform(R, p)
check("featherdyn X.matrix() = X", Xf.matrix(), X, 1e-15)
check("featherdyn X.dual_matrix() = X⁻ᵀ", Xf.dual_matrix(), Xinv_T, 1e-14)
check("T.toActionMatrix() = P X P", T.toActionMatrix(), P6 @ X @ P6, 1e-15)
check("featherdyn apply_inverse = actInv (forces)", Xf.apply_inverse(f_fd).vector,
      conventions.from_pinocchio_force(T.actInv(f_A)).vector, 1e-14)
print("\nExercise 3 (second list) done.")
