# needs: featherdyn[symbolic] (SymPy): pip install "featherdyn[symbolic]"
"""Appendix I — symbolic verification with SymPy: the chapter's snippets, then general proofs.

The chapter checks det X = 1 for a rotation about z and the Jacobi identity
for three particular vectors, and starts a Lagrangian 2R derivation it does
not finish ("see the Lagrange topic"). Here: its snippets as written, then
``featherdyn.symbolic``'s proofs for a *general* rotation (unit quaternion and
roll-pitch-yaw) and general vectors, and the 2R derivation finished — with
the CoM at the link end as in its snippet, and in general — and proved equal
to CRBA/RNEA run on symbols.

Run: python examples/09_sympy_verification.py
"""

# ruff: noqa: N816  (the chapter's frame subscripts, v_A, f_B, vJ, are kept on purpose)

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("sympy")  # first: a missing module is one line naming its install

import sympy as sp
from _check import check_true, section
from sympy import Matrix, cos, simplify, sin, symbols, zeros

from featherdyn import symbolic

# %% 1. the chapter's det X with a rotation about z
section("1. chapter: det X = 1 for R = R_z(θ)")
theta = symbols("theta")
px, py, pz = symbols("p_x p_y p_z")
R = Matrix([[cos(theta), -sin(theta), 0], [sin(theta), cos(theta), 0], [0, 0, 1]])
p = Matrix([px, py, pz])
skew_p = Matrix([[0, -pz, py], [pz, 0, -px], [-py, px, 0]])
X = zeros(6, 6)
X[:3, :3] = R
X[3:, :3] = skew_p * R
X[3:, 3:] = R
det_X = simplify(X.det())
print(f"  det(X) = {det_X}")
check_true("chapter's det X = 1", det_X == 1)
check_true("featherdyn.symbolic: det X = 1 for a general unit-quaternion rotation",
           symbolic.prove_plucker_determinant("quaternion"))
check_true("featherdyn.symbolic: det X = 1 for general roll-pitch-yaw", symbolic.prove_plucker_determinant("rpy"))

# %% 2. the chapter's Jacobi check with three particular vectors
section("2. chapter: Jacobi identity for v1, v2, v3 given")


def crossm_matrix(v):
    w, vl = v[:3], v[3:]
    skew_w = Matrix([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    skew_v = Matrix([[0, -vl[2], vl[1]], [vl[2], 0, -vl[0]], [-vl[1], vl[0], 0]])
    M = zeros(6, 6)
    M[:3, :3] = skew_w
    M[3:, :3] = skew_v
    M[3:, 3:] = skew_w
    return M


v1, v2, v3 = Matrix([1, 0, 0, 0, 1, 0]), Matrix([0, 1, 0, 1, 0, 0]), Matrix([0, 0, 1, 0, 0, 1])
jacobi = (crossm_matrix(v1) * (crossm_matrix(v2) * v3) + crossm_matrix(v2) * (crossm_matrix(v3) * v1)
          + crossm_matrix(v3) * (crossm_matrix(v1) * v2))
print(f"  Jacobi identity check: {list(jacobi)}")
check_true("chapter's particular vectors give 0", jacobi == zeros(6, 1))
check_true("featherdyn.symbolic: Jacobi for general v1, v2, v3 (18 symbols)", symbolic.prove_jacobi_identity())

# %% 3. the chapter's 2R Lagrangian snippet (CoM at the link ends), finished
section("3. 2R mass matrix with point masses at the link ends (the snippet's assumption)")
l1, l2, m1, m2, g = symbols("l1 l2 m1 m2 g", positive=True)
ends = {"c1": l1, "c2": l2, "I1": 0, "I2": 0, "l1": l1, "m1": m1, "m2": m2, "g": g}
lag = symbolic.lagrangian_two_link(ends)
print(f"  M(q) = {lag.M}")
q1, q2 = lag.q
expected = Matrix([[m1 * l1**2 + m2 * (l1**2 + l2**2 + 2 * l1 * l2 * cos(q2)), m2 * (l2**2 + l1 * l2 * cos(q2))],
                   [m2 * (l2**2 + l1 * l2 * cos(q2)), m2 * l2**2]])
check_true("M = textbook point-mass 2R matrix", symbolic.is_zero(lag.M - expected))
arm = symbolic.two_link_arm(ends)
check_true("CRBA on symbols (featherdyn.crba) gives the same M", symbolic.is_zero(symbolic.mass_matrix(arm, lag.q) - lag.M))

# %% 4. the general 2R arm: Lagrangian = spatial algebra, exactly
section("4. general 2R arm: Lagrangian M, C, g == CRBA / Coriolis / RNEA on symbols")
general = symbolic.lagrangian_two_link()
print(f"  M = {general.M}")
print(f"  C = {general.C}")
print(f"  g = {general.g.T}")
check_true("check_two_link(): M, C, g identical", symbolic.check_two_link())
M_dot = sum((general.M.diff(qi) * vi for qi, vi in zip(general.q, general.v, strict=True)), sp.zeros(2, 2))
N = M_dot - 2 * general.C
check_true("Ṁ − 2C is skew-symmetric", symbolic.is_zero(N + N.T))

# %% 5. every proof of featherdyn.symbolic
section("5. all identities of the chapter, proved for general arguments")
results = symbolic.all_proofs(("quaternion", "rpy"))
for name, ok in results.items():
    print(f"  {'True ' if ok else 'FALSE'} {name}")
check_true("every proof returns True", all(results.values()))
print("\nAll appendix I checks passed.")
