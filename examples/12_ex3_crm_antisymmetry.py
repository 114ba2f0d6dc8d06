# needs: featherdyn[verify,symbolic] (Pinocchio, SymPy): pip install "featherdyn[verify,symbolic]"
"""Exercise 3 (first list) — the motion cross-product matrix of v = (0, 0, 1, 1, 0, 0).

The question asks to "verify that [v]× is antisymmetric ([v]× + [v]×ᵀ = 0)",
then "why does antisymmetry not hold?", and the hint says the matrix is *not*
6×6 antisymmetric. The hint is right, the question's claim is not:
[v]× + [v]×ᵀ = [[0, [v_O]×ᵀ], [[v_O]×, 0]] ≠ 0 whenever the linear part
v_O ≠ 0. What is antisymmetric is the *product*: v₁ × v₂ = −v₂ × v₁.

Run: python examples/12_ex3_crm_antisymmetry.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio", "sympy")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
from _check import P6, check, check_true, differs, section, show

import featherdyn as fd
from featherdyn import symbolic

v = np.array([0.0, 0.0, 1.0, 1.0, 0.0, 0.0])

# %% 1. [v]× by hand and by featherdyn and Pinocchio
section("1. [v]× = [[[ω]×, 0], [[v_O]×, [ω]×]]")
by_hand = np.array([
    [0, -1, 0, 0, 0, 0],
    [1, 0, 0, 0, 0, 0],
    [0, 0, 0, 0, 0, 0],
    [0, 0, 0, 0, -1, 0],
    [0, 0, -1, 1, 0, 0],
    [0, 1, 0, 0, 0, 0],
], dtype=float)
C = fd.crm(v)
show("crm(v)", C)
check("by hand", C, by_hand, 0.0)
check("Pinocchio Motion.action (swapped to angular first)", P6 @ pin.Motion(v[3:], v[:3]).action @ P6, C, 0.0)

# %% 2. is the matrix antisymmetric?
section("2. [v]× + [v]×ᵀ")
show("crm(v) + crm(v)ᵀ", C + C.T)
differs("the question's claim [v]× + [v]×ᵀ = 0", C + C.T, np.zeros((6, 6)), 0.5)
check("it is [[0, [v_O]×ᵀ], [[v_O]×, 0]]", C + C.T,
      np.block([[np.zeros((3, 3)), fd.skew(v[3:]).T], [fd.skew(v[3:]), np.zeros((3, 3))]]), 0.0)
pure = np.array([0.3, -0.2, 0.5, 0.0, 0.0, 0.0])
check("only a rotation through the origin (v_O = 0) has a skew crm", fd.crm(pure) + fd.crm(pure).T, np.zeros((6, 6)), 0.0)

# %% 3. the product is antisymmetric
section("3. v₁ × v₂ = −v₂ × v₁ (the hint)")
rng = np.random.default_rng(7)
for _ in range(5):
    a, b = rng.normal(size=6), rng.normal(size=6)
    check("crm(a) b = −crm(b) a", fd.crm(a) @ b, -fd.crm(b) @ a, 1e-14)
check_true("symbolic: v₁ × v₂ + v₂ × v₁ = 0 for general v₁, v₂", symbolic.prove_cross_antisymmetry())
print("\nExercise 3 done.")
