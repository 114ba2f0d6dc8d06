# needs: featherdyn[verify,symbolic] (SymPy, example-robot-data): pip install "featherdyn[verify,symbolic]"
"""Exercise 7 (first list) — solving I a = f for an ill-conditioned spatial inertia (a thin rod).

Rod: m = 1 kg, length 1 m, radius 0.1 mm, reference frame at one end and
tilted (so the matrix is full). I_zz about its axis is m r²/2 = 5·10⁻⁹, so
cond(I) ≈ 10⁸. The solution of the *float* matrix is computed exactly with
rational arithmetic (SymPy), and four solvers are compared with it:
(a) the explicit inverse, (b) Cholesky, (c) LDLᵀ (both written out, with
triangular solves), (d) LAPACK's LU (np.linalg.solve) — plus the structured
solve through the CoM frame, I_O⁻¹ = X diag(I_c⁻¹, 1/m) Xᵀ.

Measured: the four general solvers all stay within the cond·ε bound of the
exact solution of the rounded matrix (≈ 10⁻¹⁰ – 10⁻⁹ here; the factorisation
matters far less than the conditioning). Measured against the exact
solution of the *exact* inertia, they all lose ≈ cond·ε to the rounding of I
itself; only the structured solve, which never forms the ill-conditioned
matrix, avoids that.

Also measured: chapter §14.1 says a small arm (1–5 kg links) has
cond(I) ≈ 10¹–10²; the Panda's link inertias (0.6–5 kg, about their joint
frames) have cond 1.5·10² – 2.6·10³.

Run: python examples/16_ex7_ill_conditioned_inertia.py
"""

# %% 0. setup
from __future__ import annotations

from _check import needs

needs("sympy", "example-robot-data")  # first: a missing module is one line naming its install

import numpy as np
import sympy as sp
from _check import check_true, section, show

import featherdyn as fd

m, length, radius = 1.0, 1.0, 1e-4
rod = fd.SpatialInertia.cylinder(m, radius, length)  # about its CoM, axis z
# a frame at one end, tilted (a generic rotation), so the thin direction mixes with every axis
R_tilt = fd.rotation.rpy_to_matrix([0.4, -0.7, 1.2])
X_end_com = fd.PluckerTransform(R_tilt, R_tilt @ np.array([0.0, 0.0, length / 2]))
I_end = X_end_com.apply(rod)
A = I_end.matrix()
f = np.array([0.3, -0.2, 0.5, 1.0, -2.0, 0.7])

# %% 1. conditioning
section("1. the matrix and its condition number")
show("I_end", A)
cond = np.linalg.cond(A)
show("cond(I)", f"{cond:.3e}")
check_true("ill-conditioned (cond > 1e7)", cond > 1e7)

# %% 2. exact solutions (rational arithmetic)
section("2. exact solutions: of the rounded float matrix, and of the exact inertia")
A_exact = sp.Matrix(6, 6, [sp.Rational(float(x)) for x in A.ravel()])
f_exact = sp.Matrix([sp.Rational(float(x)) for x in f])
a_rounded = np.array([float(x) for x in A_exact.LUsolve(f_exact)])
# the exact inertia: exact m, r, L and the float rotation entries taken as exact rationals
R_q = sp.Matrix(3, 3, [sp.Rational(float(x)) for x in R_tilt.ravel()])
m_q, r_q, L_q = sp.Integer(1), sp.Rational(1, 10000), sp.Integer(1)
Ic_q = sp.diag(m_q * (3 * r_q**2 + L_q**2) / 12, m_q * (3 * r_q**2 + L_q**2) / 12, m_q * r_q**2 / 2)
c_q = R_q * sp.Matrix([0, 0, L_q / 2])
I_true = fd.SpatialInertia(m_q, np.array(list(c_q), dtype=object), np.array((R_q * Ic_q * R_q.T).tolist(), dtype=object))
a_true = np.array([float(x) for x in sp.Matrix(I_true.matrix().tolist()).LUsolve(f_exact)])
show("a (exact, rounded to float)", a_rounded)
show("relative distance between the two exact solutions (the price of rounding I)",
     np.linalg.norm(a_rounded - a_true) / np.linalg.norm(a_true))


# %% 3. four solvers
def forward(L, b):
    y = np.zeros_like(b)
    for i in range(len(b)):
        y[i] = (b[i] - L[i, :i] @ y[:i]) / L[i, i]
    return y


def backward(U, y):
    x = np.zeros_like(y)
    for i in reversed(range(len(y))):
        x[i] = (y[i] - U[i, i + 1:] @ x[i + 1:]) / U[i, i]
    return x


def ldl(M):
    n = len(M)
    L, d = np.eye(n), np.zeros(n)
    for j in range(n):
        d[j] = M[j, j] - (L[j, :j] ** 2) @ d[:j]
        for i in range(j + 1, n):
            L[i, j] = (M[i, j] - (L[i, :j] * L[j, :j]) @ d[:j]) / d[j]
    return L, d


section("3. (a) inverse  (b) Cholesky  (c) LDLᵀ  (d) LU")
Lc = np.linalg.cholesky(A)
Ll, dl = ldl(A)
solutions = {
    "(a) inv(I) @ f": np.linalg.inv(A) @ f,
    "(b) Cholesky": backward(Lc.T, forward(Lc, f)),
    "(c) LDLᵀ": backward(Ll.T, forward(Ll, f) / dl),
    "(d) np.linalg.solve (LU)": np.linalg.solve(A, f),
}
# the structured solve: I_end = X* I_c X⁻¹  ⇒  I_end⁻¹ = X I_c⁻¹ Xᵀ   (I_c = diag(I_rot, m 1) is diagonal here)
X = X_end_com.matrix()
Ic_inv = np.diag(np.concatenate([1.0 / np.diag(rod.inertia_com), np.full(3, 1.0 / m)]))
solutions["structured X I_c⁻¹ Xᵀ f"] = X @ (Ic_inv @ (X.T @ f))
errors, errors_true = {}, {}
print(f"  {'':28s} {'vs exact(rounded I)':>20s} {'vs exact(true I)':>18s} {'residual':>10s}")
for name, a_num in solutions.items():
    errors[name] = np.linalg.norm(a_num - a_rounded) / np.linalg.norm(a_rounded)
    errors_true[name] = np.linalg.norm(a_num - a_true) / np.linalg.norm(a_true)
    res = np.linalg.norm(A @ a_num - f) / np.linalg.norm(f)
    print(f"  {name:28s} {errors[name]:20.2e} {errors_true[name]:18.2e} {res:10.2e}")
eps = np.finfo(float).eps
general = list(solutions)[:4]
for name in general:
    check_true(f"{name}: error ≤ 10·cond·ε = {10 * cond * eps:.1e}", errors[name] <= 10 * cond * eps)
check_true("the structured solve is closest to the true solution",
           errors_true["structured X I_c⁻¹ Xᵀ f"] < min(errors_true[name] for name in general))

# %% 4. the chapter's §14.1 condition-number claim, on the Panda
section("4. cond of the Panda's link inertias (chapter §14.1: 'small arms: 10¹–10²')")
panda = fd.load_robot("panda")
conds = []
for i in range(7):
    M = panda.inertias[i].matrix()
    conds.append(np.linalg.cond(M))
    print(f"  {panda.body_names[i]:12s} m = {panda.inertias.mass[i]:.3f} kg   cond = {conds[-1]:.3g}")
show("range", [min(conds), max(conds)])
check_true("every Panda arm link has cond > 100 (the chapter's range is too optimistic)", min(conds) > 100)
print("\nExercise 7 done.")
