# needs: featherdyn[verify,symbolic] (Pinocchio, SymPy): pip install "featherdyn[verify,symbolic]"
"""Exercise 5 (first list) — the motion cross product satisfies Jacobi: it is the Lie bracket of se(3).

Checked numerically (featherdyn's crm and Pinocchio's Motion.cross), proved
symbolically for general vectors, and tied to se(3): with the 4×4 hat map
V^ = [[[ω]×, v], [0, 0]], the matrix commutator is the cross product,
[V₁^, V₂^] = (V₁ × V₂)^, and crm is a Lie-algebra homomorphism,
crm(V₁ × V₂) = crm(V₁) crm(V₂) − crm(V₂) crm(V₁).

Run: python examples/14_ex5_jacobi_identity.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("pinocchio", "sympy")  # first: a missing module is one line naming its install

import numpy as np
from _check import check, check_true, section

import featherdyn as fd
from featherdyn import conventions, symbolic

rng = np.random.default_rng(5)
V = rng.normal(size=(20, 3, 6))


def hat(v):
    out = np.zeros((4, 4))
    out[:3, :3] = fd.skew(v[:3])
    out[:3, 3] = v[3:]
    return out


# %% 1. numerically
section("1. v1 × (v2 × v3) + v2 × (v3 × v1) + v3 × (v1 × v2) = 0")
worst = 0.0
for v1, v2, v3 in V:
    jac = fd.crm(v1) @ (fd.crm(v2) @ v3) + fd.crm(v2) @ (fd.crm(v3) @ v1) + fd.crm(v3) @ (fd.crm(v1) @ v2)
    worst = max(worst, float(np.abs(jac).max()))
check("featherdyn, 20 random triples", worst, 0.0, 1e-13)
worst = 0.0
for v1, v2, v3 in V:
    a, b, c = (conventions.to_pinocchio_motion(fd.SpatialMotion.from_vector(x)) for x in (v1, v2, v3))
    jac = a.cross(b.cross(c)) + b.cross(c.cross(a)) + c.cross(a.cross(b))
    worst = max(worst, float(np.abs(jac.vector).max()))
check("Pinocchio Motion.cross, 20 random triples", worst, 0.0, 1e-13)

# %% 2. the Lie bracket of se(3)
section("2. [V1^, V2^] = (V1 × V2)^ and crm is a homomorphism")
for v1, v2, _ in V[:5]:
    check("4×4 commutator = hat of the cross product", hat(v1) @ hat(v2) - hat(v2) @ hat(v1), hat(fd.crm(v1) @ v2), 1e-13)
    check("crm(v1 × v2) = [crm(v1), crm(v2)]", fd.crm(fd.crm(v1) @ v2),
          fd.crm(v1) @ fd.crm(v2) - fd.crm(v2) @ fd.crm(v1), 1e-13)
    check("Modern Robotics ad_V = crm (conventions.ad_matrix)", conventions.ad_matrix(v1), fd.crm(v1), 0.0)

# %% 3. proof
section("3. symbolic proof for general v1, v2, v3")
check_true("Jacobi identity", symbolic.prove_jacobi_identity())
check_true("antisymmetry", symbolic.prove_cross_antisymmetry())
print("\nExercise 5 done.")
