# needs: featherdyn[verify,symbolic] (Pinocchio, SymPy): pip install "featherdyn[verify,symbolic]"
"""Exercise 4 (second list) — the force cross product is −(motion cross product)ᵀ and does no work.

v₁ = (0, 0, 1; 1, 0, 0). (a) [v₁]×; (b) [v₁]×* = −[v₁]×ᵀ ≠ [v₁]×;
(c) v₁ · (v₁ ×* f) = 0 for every f (the gyroscopic force does no work);
(d) Pinocchio: ``v1.cross(f).dot(v1)`` = 0.

Run: python examples/21_exB4_cross_duality.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio", "sympy")  # first: a missing module is one line naming its install

import numpy as np
import pinocchio as pin
from _check import check, check_true, differs, section, show

import featherdyn as fd
from featherdyn import symbolic

v1 = fd.SpatialMotion([0.0, 0.0, 1.0], [1.0, 0.0, 0.0])

# %% 1. (a) [v1]×
section("1. (a) [v₁]×")
crm = fd.crm(v1)
show("[v₁]×", crm)
check("[[ [ω]×, 0 ], [ [v]×, [ω]× ]]", crm,
      np.block([[fd.skew([0, 0, 1]), np.zeros((3, 3))], [fd.skew([1, 0, 0]), fd.skew([0, 0, 1])]]), 0.0)

# %% 2. (b) [v1]×*
section("2. (b) [v₁]×* = −[v₁]×ᵀ")
crf = fd.crf(v1)
show("[v₁]×*", crf)
check("crf = −crmᵀ", crf, -crm.T, 0.0)
differs("[v₁]×* vs [v₁]× (dual ≠ itself)", crf, crm, 0.5, note="differs, as expected")
check_true("symbolic: crf(v) = −crm(v)ᵀ for a general v", symbolic.prove_crf_is_minus_crm_transpose())

# %% 3. (c) v · (v ×* f) = 0
section("3. (c) v₁ᵀ([v₁]×* f) = 0 for every f")
rng = np.random.default_rng(8)
F = rng.normal(size=(100, 6))
check("100 random f", F @ crf.T @ v1.vector, np.zeros(100), 1e-13)
check_true("symbolic: v·(v ×* f) = 0 and v₂·(v₁ ×* f) = −(v₁ × v₂)·f", symbolic.prove_force_cross_duality())

# %% 4. (d) Pinocchio
section("4. (d) Pinocchio: v1.cross(f).dot(v1)")
pv = pin.Motion(np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0]))
worst = max(abs(pv.cross(pin.Force(f[3:], f[:3])).dot(pv)) for f in F)
check("max over 100 random f", worst, 0.0, 1e-13)
print("\nExercise 4 (second list) done.")
