# needs: featherdyn[verify] (Pinocchio): pip install "featherdyn[verify]"
"""Appendix C.2 — the spatial inertia transform I_B = X⁻ᵀ I_A X⁻¹, with the chapter's manual X⁻¹.

Measured: the chapter's manual ``X_inv = [[Rᵀ, 0], [−Rᵀ[p]×, Rᵀ]]`` *is* the
inverse of X, and ``X⁻ᵀ I_A X⁻¹`` *is* the transformed inertia — in
Featherstone's angular-first layout. But the script multiplies these
angular-first matrices with ``pin.Inertia.matrix()``, which is linear first,
and compares with another linear-first matrix: its "Max difference" is not
≈ 1e-14 but of the order of the inertia itself. Swapping the blocks (or using
featherdyn's angular-first ``SpatialInertia.matrix()``) makes it agree.

Run: python examples/07_inertia_transform.py
"""

# ruff: noqa: N816  (the chapter's frame subscripts, v_A, f_B, vJ, are kept on purpose)

# %% 0. setup: the chapter's numbers
from __future__ import annotations

from _check import needs

needs("pinocchio")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
from _check import P6, check, differs, section, show

import featherdyn as fd
from featherdyn import conventions

m = 5.0
c = np.array([0.1, -0.05, 0.02])
Ic = np.diag([0.01, 0.02, 0.03])
I_A = pin.Inertia(m, c, Ic)
R = pin.utils.rpyToMatrix(0.3, -0.1, 0.5)
p = np.array([0.5, 0.2, -0.1])
T_BA = pin.SE3(R, p)
I_B = T_BA.act(I_A)

# %% 1. the chapter's manual X and X⁻¹ (angular first)
section("1. manual X and X_inv as printed")
X = np.zeros((6, 6))
X[:3, :3] = R
X[3:, :3] = pin.skew(p) @ R
X[3:, 3:] = R
X_inv = np.zeros((6, 6))
X_inv[:3, :3] = R.T
X_inv[3:, :3] = -R.T @ pin.skew(p)
X_inv[3:, 3:] = R.T
check("X_inv @ X = 1 (the printed inverse is right)", X_inv @ X, np.eye(6), 1e-14)
X_fd = fd.PluckerTransform(R, p)
check("X = featherdyn X.matrix()", X, X_fd.matrix(), 1e-14)
check("X_inv = featherdyn X.inverse().matrix()", X_inv, X_fd.inverse().matrix(), 1e-14)

# %% 2. the chapter's comparison, as written: mixed layouts
section("2. chapter's comparison X⁻ᵀ · I_A.matrix() · X⁻¹ vs I_B.matrix()")
I_B_manual = X_inv.T @ I_A.matrix() @ X_inv
as_written = np.abs(I_B.matrix() - I_B_manual).max()
show("Max difference (chapter's script; it says '< 1e-14')", as_written)
differs("the chapter's C.2 comparison (pin .matrix() is linear first)", I_B.matrix(), I_B_manual, 0.1)

# %% 3. the same comparison with consistent layouts
section("3. consistent layouts")
I_A_fd = conventions.matrix6_from_pinocchio(I_A.matrix())  # P M P: angular first
check("featherdyn SpatialInertia.matrix() = P · pin.matrix() · P", fd.SpatialInertia(m, c, Ic).matrix(), I_A_fd, 1e-14)
I_B_fd = X_inv.T @ I_A_fd @ X_inv
check("X⁻ᵀ I_A X⁻¹ (angular first) = P · I_B.matrix() · P", I_B_fd, P6 @ I_B.matrix() @ P6, 1e-14)
check("featherdyn X.apply(inertia) = X* I X⁻¹", X_fd.apply(fd.SpatialInertia(m, c, Ic)).matrix(), I_B_fd, 1e-14)
check("from_pinocchio_inertia(T.act(I_A)) = X.apply(I_A)",
      conventions.from_pinocchio_inertia(I_B).matrix(), I_B_fd, 1e-14)

# %% 4. kinetic energy is invariant
section("4. ½ vᵀ I v is frame independent")
rng = np.random.default_rng(0)
v = pin.Motion(rng.normal(size=6))
T_A = 0.5 * v.dot(I_A * v)
v_B = T_BA.act(v)
T_B = 0.5 * v_B.dot(I_B * v_B)
show("T in A, T in B", [T_A, T_B])
check("kinetic energy (Pinocchio)", T_B, T_A, 1e-13)
v_fd = conventions.from_pinocchio_motion(v)
check("kinetic energy (featherdyn)", X_fd.apply(fd.SpatialInertia(m, c, Ic)).kinetic_energy(X_fd.apply(v_fd)), T_A, 1e-13)
print("\nAll appendix C.2 checks passed.")
