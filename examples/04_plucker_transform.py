# needs: featherdyn[verify] (Pinocchio): pip install "featherdyn[verify]"
"""§10.2 — the 6×6 Plücker transform, and forces moved with X⁻ᵀ; featherdyn against Pinocchio.

T = SE3(R_z(45°), (1, 0, 0)). The chapter's code is right here: ``T.act`` is
``X`` on a Motion and ``X⁻ᵀ`` on a Force (so both use ``act``), and power is
invariant. Its manual check builds X in angular-first order and compares
component by component with ``.angular``/``.linear``, which is why the
layout mistake of §10.1 does not bite.

Run: python examples/04_plucker_transform.py
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

R = pin.utils.rpyToMatrix(0.0, 0.0, np.pi / 4)
p = np.array([1.0, 0.0, 0.0])
T = pin.SE3(R, p)
X = fd.PluckerTransform(R, p)
w, v = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
n, f = np.array([0.0, 0.0, 5.0]), np.array([0.0, 10.0, 0.0])

# %% 1. motion: T.act(v) = X v
section("1. motions: X = [[R, 0], [[p]×R, R]]")
X_manual = np.block([[R, np.zeros((3, 3))], [pin.skew(p) @ R, R]])
v_A = pin.Motion(v, w)
v_B = T.act(v_A)
v_B_manual = X_manual @ np.concatenate([v_A.angular, v_A.linear])
show("Pinocchio v_B (angular, linear)", np.concatenate([v_B.angular, v_B.linear]))
show("manual X v_A", v_B_manual)
check("T.act(motion) = X v", np.concatenate([v_B.angular, v_B.linear]), v_B_manual, 1e-14)
v_B_fd = X.apply(fd.SpatialMotion(w, v))
check("featherdyn X.apply(motion)", v_B_fd.vector, v_B_manual, 1e-14)
s2 = np.sqrt(2) / 2
check("by hand: (0, 0, 1; √2/2, √2/2 − 1, 0)", v_B_fd.vector, [0, 0, 1, s2, s2 - 1, 0], 1e-14)

# %% 2. force: T.act(f) = X⁻ᵀ f, and power is invariant
section("2. forces: X* = X⁻ᵀ = [[R, [p]×R], [0, R]]")
f_A = pin.Force(f, n)
f_B = T.act(f_A)
X_star = np.linalg.inv(X_manual).T
f_B_manual = X_star @ np.concatenate([n, f])
check("T.act(force) = X⁻ᵀ f", np.concatenate([f_B.angular, f_B.linear]), f_B_manual, 1e-14)
f_B_fd = X.apply(fd.SpatialForce(n, f))
check("featherdyn X.apply(force)", f_B_fd.vector, f_B_manual, 1e-14)
check("featherdyn X.dual_matrix() = X⁻ᵀ", X.dual_matrix(), X_star, 1e-14)
show("power in A, in B", [v_A.dot(f_A), v_B.dot(f_B)])
check("power invariant (Pinocchio)", v_B.dot(f_B), v_A.dot(f_A), 1e-12)
check("power invariant (featherdyn)", v_B_fd.dot(f_B_fd), 5.0, 1e-12)

# %% 3. the 6×6 matrices of both libraries
section("3. matrices: featherdyn (angular first) vs Pinocchio (linear first)")
check("X.matrix() = P·T.toActionMatrix()·P", X.matrix(), P6 @ T.toActionMatrix() @ P6, 1e-14)
check("X.dual_matrix() = P·T.toDualActionMatrix()·P", X.dual_matrix(), P6 @ T.toDualActionMatrix() @ P6, 1e-14)
check("X = X_trans · X_rot (§3.2)", X.matrix(), fd.PluckerTransform(np.eye(3), p).matrix() @ fd.PluckerTransform(R, np.zeros(3)).matrix(), 1e-14)

# %% 4. the pitfall: moving the force with actInv
section("4. T.actInv(force) breaks power invariance (troubleshooting-table erratum)")
wrong = v_B.dot(T.actInv(f_A))
show("v_B · actInv(f_A)", wrong)
differs("power with actInv on the force", wrong, v_A.dot(f_A), 1.0)
print("\nAll §10.2 checks passed.")
