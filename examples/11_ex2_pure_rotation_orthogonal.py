# needs: featherdyn[symbolic] (SymPy): pip install "featherdyn[symbolic]"
"""Exercise 2 (first list) — a pure rotation X_rot is orthogonal; a general X is not.

X_rot = diag(R, R) satisfies X_rot⁻¹ = X_rotᵀ. With p ≠ 0, X⁻¹ =
[[Rᵀ, 0], [−Rᵀ[p]×, Rᵀ]] while Xᵀ = [[Rᵀ, −Rᵀ[p]×], [0, Rᵀ]] — not equal.
What Xᵀ *is*: the inverse of the force transform, (X*)⁻¹ = Xᵀ. (Appendix F.1
prints "(X*)⁻¹ = (X⁻¹)* = X⁻ᵀ", but X⁻ᵀ is X* itself; the right-hand side
should be Xᵀ.)

Run: python examples/11_ex2_pure_rotation_orthogonal.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("sympy")  # first: a missing module is one line naming its install

import numpy as np
from _check import check, check_true, differs, section, show

import featherdyn as fd
from featherdyn import symbolic
from featherdyn.rotation import rpy_to_matrix

R = rpy_to_matrix([0.3, -0.2, 1.1])
p = np.array([0.5, -0.4, 0.2])

# %% 1. pure rotation
section("1. X_rot = diag(R, R)")
X_rot = fd.PluckerTransform(R, np.zeros(3)).matrix()
check("X_rot⁻¹ = X_rotᵀ", np.linalg.inv(X_rot), X_rot.T, 1e-14)
check("X_rot X_rotᵀ = 1", X_rot @ X_rot.T, np.eye(6), 1e-14)
check_true("symbolic proof (general quaternion rotation)", symbolic.prove_pure_rotation_orthogonal("quaternion"))

# %% 2. a general transform is not orthogonal
section("2. X with p ≠ 0")
X = fd.PluckerTransform(R, p)
Xm = X.matrix()
show("X Xᵀ", Xm @ Xm.T)
differs("X⁻¹ vs Xᵀ (general X is not orthogonal)", np.linalg.inv(Xm), Xm.T, 0.1, note="differs, as expected")
check("X⁻¹ = [[Rᵀ, 0], [−Rᵀ[p]×, Rᵀ]] = X.inverse().matrix()", np.linalg.inv(Xm), X.inverse().matrix(), 1e-14)
check("X Xᵀ lower-right block = [p]×[p]×ᵀ + 1", (Xm @ Xm.T)[3:, 3:], fd.skew(p) @ fd.skew(p).T + np.eye(3), 1e-14)

# %% 3. what Xᵀ is: the inverse of the force transform (appendix F.1 corrected)
section("3. (X*)⁻¹ = (X⁻¹)* = Xᵀ")
check("(X*)⁻¹ = Xᵀ", np.linalg.inv(X.dual_matrix()), Xm.T, 1e-14)
check("(X⁻¹)* = Xᵀ", X.inverse().dual_matrix(), Xm.T, 1e-14)
differs("F.1 as printed: (X*)⁻¹ = X⁻ᵀ", np.linalg.inv(X.dual_matrix()), np.linalg.inv(Xm).T, 0.1)
check("X*ᵀ = X⁻¹ (F.1, right)", X.dual_matrix().T, np.linalg.inv(Xm), 1e-14)
check_true("symbolic proof of the inverse/dual identities", symbolic.prove_transform_inverse("quaternion"))
print("\nExercise 2 done.")
