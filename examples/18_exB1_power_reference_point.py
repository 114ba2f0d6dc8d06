# needs: featherdyn (no extra: NumPy only)
"""Exercise 1 (second list) — a wrench and a twist at two reference points; power is the same.

f_O = (τ_O; f) = ((0, 0, 10); (5, 0, 0)), v_O = (ω; v_O) = ((0, 0, 2); (1, 0, 0)).
(a) P = τ_Oᵀω + fᵀv_O = 25. (b) with r_OP = (0.5, 0, 0): τ_P = τ_O − r_OP × f
= (0, 0, 10), v_P = v_O + ω × r_OP = (1, 1, 0). (c) P at P = 25.
(d) The exercise asks how much the wrong formula τ_P = τ_O + r_OP × f changes
the power: with its numbers, not at all — r_OP ∥ f, so r_OP × f = 0 and both
formulas give the same τ_P. The difference is 2 (r_OP × f)·ω; with
r_OP = (0, 0.5, 0) the wrong formula gives 15 instead of 25 (−40 %).

Run: python examples/18_exB1_power_reference_point.py
"""

# ruff: noqa: N816  (the chapter's frame subscripts, v_A, f_B, vJ, are kept on purpose)

# %% 0. setup
from __future__ import annotations

import numpy as np
from _check import check, section, show

import featherdyn as fd

tau_O, f = np.array([0.0, 0.0, 10.0]), np.array([5.0, 0.0, 0.0])
omega, v_O = np.array([0.0, 0.0, 2.0]), np.array([1.0, 0.0, 0.0])
wrench = fd.SpatialForce(tau_O, f)
twist = fd.SpatialMotion(omega, v_O)


def at(r_OP):
    """Both vectors re-expressed at P (same axes): the pose of O's frame in P's frame is (1, −r_OP)."""
    X_PO = fd.PluckerTransform(np.eye(3), -np.asarray(r_OP))
    return X_PO.apply(wrench), X_PO.apply(twist)


# %% 1. (a) power at O
section("1. (a) P at O")
P_O = twist.dot(wrench)
show("P_O", P_O)
check("P_O = 10·2 + 5·1 = 25", P_O, 25.0, 0.0)

# %% 2. (b, c) at P = O + (0.5, 0, 0)
section("2. (b, c) at P, r_OP = (0.5, 0, 0)")
r = np.array([0.5, 0.0, 0.0])
f_P, v_P = at(r)
show("f_P", f_P.vector)
show("v_P", v_P.vector)
check("τ_P = τ_O − r_OP × f = (0, 0, 10)", f_P.angular, tau_O - np.cross(r, f), 0.0)
check("v_P = v_O + ω × r_OP = (1, 1, 0)", v_P.linear, [1.0, 1.0, 0.0], 0.0)
check("P_P = 25", v_P.dot(f_P), 25.0, 1e-14)

# %% 3. (d) the wrong moment formula
section("3. (d) τ_P = τ_O + r_OP × f (wrong)")
wrong = (tau_O + np.cross(r, f)) @ omega + f @ v_P.linear
show("P with the wrong formula, r_OP = (0.5, 0, 0)", wrong)
check("no difference with the exercise's data (r_OP ∥ f)", wrong, 25.0, 1e-14)
r2 = np.array([0.0, 0.5, 0.0])
f_P2, v_P2 = at(r2)
wrong2 = (tau_O + np.cross(r2, f)) @ omega + f @ v_P2.linear
show("correct / wrong power with r_OP = (0, 0.5, 0)", [v_P2.dot(f_P2), wrong2])
check("correct: 25", v_P2.dot(f_P2), 25.0, 1e-14)
check("wrong: 15 (= 25 + 2 (r_OP × f)·ω)", wrong2, 25.0 + 2 * np.cross(r2, f) @ omega, 1e-14)
check("wrong: 15", wrong2, 15.0, 1e-14)
print("\nExercise 1 (second list) done.")
