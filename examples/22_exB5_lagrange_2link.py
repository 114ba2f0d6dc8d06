# needs: featherdyn[verify,symbolic] (Pinocchio, SymPy): pip install "featherdyn[verify,symbolic]"
"""Exercise 5 (second list) — from spatial inertia to the 2-link mass matrix, and the Lagrangian.

2-DOF planar arm, links ℓ₁, ℓ₂, masses m₁, m₂, CoMs at the link midpoints
(slender rods: I_zz = m ℓ²/12 about the CoM). Everything symbolic:
(a) body-frame spatial inertias, (b) Plücker transforms ¹X₀(q₁), ²X₁(q₂),
(c) link velocities by the recursion, (d) T = ½ Σ v_iᵀ I_i v_i and
M(q) = ∂²T/∂q̇², (e) the same M from CRBA run on symbols and from the
Lagrangian of the centre-of-mass coordinates.

Run: python examples/22_exB5_lagrange_2link.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio", "sympy")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
import sympy as sp
from _check import check, check_true, section

import featherdyn as fd
from featherdyn import symbolic
from featherdyn.verify.bridge import pinocchio_model_from

l1, l2, m1, m2 = sp.symbols("l1 l2 m1 m2", positive=True)
q1, q2, v1, v2 = sp.symbols("q1 q2 v1 v2", real=True)
zero, one = sp.Integer(0), sp.Integer(1)


def obj(x):
    return np.array(x, dtype=object)


def rz(t):
    return obj([[sp.cos(t), -sp.sin(t), 0], [sp.sin(t), sp.cos(t), 0], [0, 0, 1]])


def rod_inertia(m, length):
    I = m * length**2 / 12
    return fd.SpatialInertia(m, obj([length / 2, 0, 0]), obj([[I, 0, 0], [0, I, 0], [0, 0, I]]))


# %% 1. (a) spatial inertias in the body frames (frame i on joint i)
section("1. (a) I₁, I₂")
I1, I2 = rod_inertia(m1, l1), rod_inertia(m2, l2)
print("  I₁ =", sp.Matrix(I1.matrix().tolist()))

# %% 2. (b) transforms
section("2. (b) ¹X₀(q₁), ²X₁(q₂)")
X_10 = fd.PluckerTransform(rz(q1), obj([0, 0, 0]), validate=False).inverse()
X_21 = fd.PluckerTransform(rz(q2), obj([l1, 0, 0]), validate=False).inverse()
print("  ²X₁ (rows ω_z, v_x, v_y) =", sp.Matrix(X_21.matrix().tolist())[[2, 3, 4], [2, 3, 4]])

# %% 3. (c) velocities
section("3. (c) v₁ = S q̇₁,  v₂ = ²X₁ v₁ + S q̇₂")
S = fd.SpatialMotion(obj([0, 0, 1]), obj([0, 0, 0]))
vel1 = S * v1
vel2 = X_21.apply(vel1) + S * v2
print("  v₂ =", list(symbolic.canonical(obj(vel2.vector))))
_ = X_10  # the base does not move: ¹X₀ v₀ = 0

# %% 4. (d) kinetic energy and M(q)
section("4. (d) T = ½ Σ v_iᵀ I_i v_i,  M = ∂²T/∂q̇²")
T = symbolic.canonical(I1.kinetic_energy(vel1) + I2.kinetic_energy(vel2))
M = sp.Matrix(2, 2, lambda i, j: symbolic.canonical(sp.diff(T, (v1, v2)[i], (v1, v2)[j])))
print("  M(q) =", M.applyfunc(sp.factor_terms))
expected = sp.Matrix([
    [(m1 * l1**2) / 3 + m2 * (l1**2 + l2**2 / 3 + l1 * l2 * sp.cos(q2)), m2 * (l2**2 / 3 + l1 * l2 * sp.cos(q2) / 2)],
    [m2 * (l2**2 / 3 + l1 * l2 * sp.cos(q2) / 2), m2 * l2**2 / 3],
])
check_true("M = the textbook uniform-rod 2R matrix", symbolic.is_zero(M - expected))

# %% 5. (e) CRBA on symbols and the Lagrangian agree
section("5. (e) CRBA (featherdyn.crba on symbols) and Lagrange")
params = {"l1": l1, "l2": l2, "m1": m1, "m2": m2, "c1": l1 / 2, "c2": l2 / 2,
          "I1": m1 * l1**2 / 12, "I2": m2 * l2**2 / 12}
arm = symbolic.two_link_arm(params)
M_crba = symbolic.mass_matrix(arm, (q1, q2))
check_true("CRBA M == spatial-algebra M", symbolic.is_zero(M_crba - M))
lag = symbolic.lagrangian_two_link(params)
check_true("Lagrangian M == spatial-algebra M", symbolic.is_zero(lag.M.subs({lag.q[1]: q2}) - M))
# and numerically against Pinocchio, at l = (1, 0.8), m = (3, 2)
num = {l1: 1.0, l2: 0.8, m1: 3.0, m2: 2.0}
arm_num = symbolic.two_link_arm({"l1": 1.0, "l2": 0.8, "m1": 3.0, "m2": 2.0, "c1": 0.5, "c2": 0.4,
                                 "I1": 3.0 * 1.0**2 / 12, "I2": 2.0 * 0.8**2 / 12, "g": 9.81})
qs = np.array([0.3, -1.1])
pm = pinocchio_model_from(arm_num)
M_pin = pin.crba(pm, pm.createData(), qs)
check("M(q) at q = (0.3, −1.1) vs Pinocchio crba", np.array(M.subs(num | {q2: qs[1]}).evalf(), dtype=float), M_pin, 1e-12)
check("fd.crba", fd.crba(arm_num, qs), M_pin, 1e-12)
print("\nExercise 5 (second list) done.")
