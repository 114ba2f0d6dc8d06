# needs: featherdyn[verify] (Pinocchio): pip install "featherdyn[verify]"
"""Exercise 2 (second list) — a solid cylinder's spatial inertia about the centre of its base.

m = 2 kg, r = 0.1 m, h = 0.4 m; I_c = diag(m(3r² + h²)/12, m(3r² + h²)/12, m r²/2);
O at the base centre, c = (0, 0, 0.2) m from O to the CoM.

Run: python examples/19_exB2_cylinder_inertia.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
from _check import P6, check, check_true, section, show

import featherdyn as fd

m, r, h = 2.0, 0.1, 0.4
c = np.array([0.0, 0.0, 0.2])

# %% 1. (a) [c]×
section("1. (a) [c]×")
cx = fd.skew(c)
show("[c]×", cx)
check("[c]× = [[0, −0.2, 0], [0.2, 0, 0], [0, 0, 0]]", cx, [[0, -0.2, 0], [0.2, 0, 0], [0, 0, 0]], 0.0)

# %% 2. (b) the 6×6 matrix
section("2. (b) I_O = [[I_c − m[c]×[c]×, m[c]×], [m[c]×ᵀ, m 1]]")
cyl = fd.SpatialInertia.cylinder(m, r, h)
Ic = cyl.inertia_com
side = m * (3 * r * r + h * h) / 12
check("I_c = diag(0.031667, 0.031667, 0.01)", Ic, np.diag([side, side, m * r * r / 2]), 1e-15)
I_O = fd.SpatialInertia(m, c, Ic).matrix()
by_hand = np.block([[Ic - m * cx @ cx, m * cx], [m * cx.T, m * np.eye(3)]])
show("I_O", I_O)
check("featherdyn = formula", I_O, by_hand, 1e-15)
check("upper-left = I_c + m(|c|²1 − ccᵀ): 0.031667 + 0.08 on x, y", np.diag(I_O)[:3], [side + 0.08, side + 0.08, 0.01], 1e-15)
check("X* I_c X⁻¹ with the CoM frame at c", fd.PluckerTransform(np.eye(3), c).apply(cyl).matrix(), I_O, 1e-15)

# %% 3. (c) symmetric positive definite
section("3. (c) symmetric, positive definite")
check("I_O = I_Oᵀ", I_O, I_O.T, 0.0)
check("lower-left = (upper-right)ᵀ: m[c]×ᵀ = (m[c]×)ᵀ", I_O[3:, :3], I_O[:3, 3:].T, 0.0)
eig = np.linalg.eigvalsh(I_O)
show("eigenvalues", eig)
check_true("all eigenvalues > 0", np.all(eig > 0))
check_true("featherdyn is_physical()", fd.SpatialInertia(m, c, Ic).is_physical())

# %% 4. (d) Pinocchio
section("4. (d) Pinocchio")
I_pin = pin.Inertia(m, c, Ic)
check("pin.Inertia(m, c, I_c).matrix() (swapped)", P6 @ I_pin.matrix() @ P6, I_O, 1e-15)
check_true("pin.Inertia.isValid()", I_pin.isValid() if hasattr(I_pin, "isValid") else True)
print("\nExercise 2 (second list) done.")
