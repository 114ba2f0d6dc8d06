"""SymPy as the oracle of issue 30's first-order derivatives and of ABA's second order.

The value references are dtype-generic: run on SymPy symbols they give a frame's motion, the centre of mass, the
centroidal momentum matrix and ABA's q̈ as expressions, which ``sympy`` differentiates exactly. Those derivatives,
evaluated at a point, are checked (to 1e-11 of their size) against

* the derivative references run on object arrays of SymPy numbers at the point (their dtype-generic path), and
* the public functions (the compiled core) at the point.

Only the vectors a derivative is taken along are symbols, the others the point's numbers, so the expressions stay
small enough (a full symbolic run of the centroidal rate took a minute). The models are spatial chains of random axes,
placements and inertias (``_models.random_tree``): revolute, prismatic, revolute for the first order; a revolute
then a prismatic joint for ABA's second order (its symbolic q̈ grows fast). Fixed bases, so q's
tangent is q itself. The evaluation is ``sympy.lambdify`` with common subexpressions (``subs`` takes seconds per
entry here).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from _models import random_tree

import featherdyn as fd
from featherdyn.algorithms import aba as aba_reference
from featherdyn.algorithms import kinematics_derivatives as kin_reference
from featherdyn.algorithms import second_order as second_reference
from featherdyn.algorithms.centroidal import centroidal_momentum_matrix_at
from featherdyn.algorithms.energy import center_of_mass
from featherdyn.algorithms.kinematics import forward_kinematics
from featherdyn.algorithms.kinematics_derivatives import _frame_motion

sympy = pytest.importorskip("sympy")

OBJECT = np.dtype(object)


class Symbolic:
    """A model, a point (q, q̇, x) to evaluate at (x: q̈ or τ), and states in which some of the three vectors are
    SymPy symbols and the others the point's numbers (as exact SymPy floats): the expressions stay small."""

    def __init__(self, model: fd.Model, seed: int) -> None:
        n = model.nv
        self.model = model
        self.syms = {c: sympy.symbols(f"{c}:{n}") for c in "qvx"}
        self.point = np.random.default_rng(seed).uniform(-1.0, 1.0, 3 * n)
        self.qn, self.vn, self.xn = np.split(self.point, 3)

    def state(self, symbolic: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(q, q̇, x) as object arrays: symbols for the vectors named in ``symbolic``, the point's numbers else."""
        return tuple(np.array(self.syms[c] if c in symbolic else [sympy.Float(float(y), 30) for y in x],  # type: ignore[return-value]
                              dtype=object) for c, x in zip("qvx", (self.qn, self.vn, self.xn), strict=True))

    def numbers(self, *exprs: Any) -> list[np.ndarray]:
        """Each array of expressions evaluated at the point (one lambdify for all)."""
        arrays = [np.asarray(e, dtype=object) for e in exprs]
        flat = [sympy.sympify(x) for a in arrays for x in a.reshape(-1)]
        f = sympy.lambdify(self.syms["q"] + self.syms["v"] + self.syms["x"], flat, "math", cse=True)
        values = np.array(f(*self.point), dtype=float)
        out, at = [], 0
        for a in arrays:
            out.append(values[at:at + a.size].reshape(a.shape))
            at += a.size
        return out

    def jacobian(self, e: np.ndarray, by: str) -> np.ndarray:
        """∂e/∂(the symbols of vector ``by``) (e.shape + (n,)) as expressions."""
        e = np.asarray(e, dtype=object)
        syms = self.syms[by]
        return np.array([[sympy.diff(x, s) for s in syms] for x in e.reshape(-1)], dtype=object).reshape(
            e.shape + (len(syms),))

    def reference_at_point(self, f: Any) -> list[np.ndarray]:
        """The reference function f(model, q, q̇, x) run on object arrays of SymPy numbers (its dtype-generic path),
        as floats."""
        return [np.array(r, dtype=float) for r in f(self.model, *self.state(""))]


def _close(got: np.ndarray, expected: np.ndarray, what: str) -> None:
    scale = max(1.0, float(np.abs(expected).max()))
    err = float(np.abs(got - expected).max()) / scale
    assert err < 1e-11, f"{what}: {err:.2e}"


CHAIN = Symbolic(random_tree(7, 3, root="revolute", kinds=("revolute", "prismatic"), branching=False), 1)


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a × b of two 3-vectors of expressions (written out: the oracle does not use the code it checks)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]], dtype=object)


@pytest.mark.slow
@pytest.mark.parametrize("reference", [fd.LOCAL, fd.WORLD, fd.LOCAL_WORLD_ALIGNED])
def test_kinematics_derivatives_are_sympys(reference: fd.ReferenceFrame) -> None:
    s, model = CHAIN, CHAIN.model
    fid = model.frame_id("b2_tool")

    def motion(symbolic: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """v_f, a_f and a_f^c = [ω̇; a_lin + ω × v_lin] with the vectors named symbolic."""
        vf, af = _frame_motion(model, *s.state(symbolic), fid, reference, None, (), OBJECT)
        return vf, af, np.concatenate([af[:3], af[3:] + _cross(vf[:3], vf[3:])])

    by = {c: motion(c) for c in "qvx"}
    oracle = [s.jacobian(by["q"][0], "q"), s.jacobian(by["v"][0], "v"), s.jacobian(by["q"][1], "q"),
              s.jacobian(by["v"][1], "v"), s.jacobian(by["x"][1], "x"), s.jacobian(by["q"][2], "q"),
              s.jacobian(by["v"][2], "v"), s.jacobian(by["x"][2], "x")]
    exact = s.numbers(*oracle)
    ours = s.reference_at_point(lambda m, q, v, a: kin_reference.kinematics_derivatives(m, q, v, a, fid, reference))
    core = fd.kinematics_derivatives(model, s.qn, s.vn, s.xn, "b2_tool", reference)
    for name, e, x, c in zip(fd.KinematicsDerivatives._fields, exact, ours, core, strict=True):
        _close(x, e, f"reference on SymPy numbers: {name}")
        _close(c, e, f"core: {name}")
    assert np.abs(exact[2]).max() > 0.1 and np.abs(exact[5] - exact[2]).max() > 0.01  # not trivially zero


def test_center_of_mass_derivatives_are_sympys() -> None:
    s, model = CHAIN, CHAIN.model
    q, v, _ = s.state("q")
    dc = s.jacobian(center_of_mass(model, forward_kinematics(model, q)), "q")
    cdot = dc @ v  # ċ = ∂c/∂q q̇ (q's tangent is q)
    exact = s.numbers(dc, s.jacobian(cdot, "q"))
    ours = s.reference_at_point(lambda m, q, v, _: kin_reference.center_of_mass_derivatives(m, q, v))
    core = fd.center_of_mass_derivatives(model, s.qn, s.vn)
    for name, e, x, k in zip(fd.CenterOfMassDerivatives._fields, exact, ours, core, strict=True):
        _close(x, e, f"reference on SymPy numbers: {name}")
        _close(k, e, f"core: {name}")
    assert np.abs(exact[1]).max() > 0.1


@pytest.mark.slow
def test_centroidal_dynamics_derivatives_are_sympys() -> None:
    """h_G = A_G(q) q̇, so ḣ_G = Σ_j ∂A_G/∂q_j q̇ q̇_j + A_G q̈ and every derivative is assembled from A_G and its
    first and second derivatives in q, which SymPy takes (q symbols only: the expressions stay small)."""
    s, model = CHAIN, CHAIN.model
    n = model.nv
    q = s.state("q")[0]
    A = centroidal_momentum_matrix_at(model, q)
    dA = list(np.moveaxis(s.jacobian(A, "q"), -1, 0))
    d2A = [list(np.moveaxis(s.jacobian(dA[j], "q"), -1, 0)) for j in range(n)]
    values = s.numbers(A, *dA, *(x for row in d2A for x in row))
    An, dAn, d2An = values[0], values[1:n + 1], [values[1 + n + j * n:1 + n + (j + 1) * n] for j in range(n)]
    v, a = s.vn, s.xn
    dh_dq = np.stack([dAn[j] @ v for j in range(n)], axis=-1)
    dhdot_dq = np.stack([sum(d2An[j][k] @ v * v[j] for j in range(n)) + dAn[k] @ a for k in range(n)], axis=-1)
    dhdot_dv = np.stack([sum(dAn[j][:, k] * v[j] for j in range(n)) + dAn[k] @ v for k in range(n)], axis=-1)
    exact = [dh_dq, dhdot_dq, dhdot_dv, An]
    ours = s.reference_at_point(kin_reference.centroidal_dynamics_derivatives)
    core = fd.centroidal_dynamics_derivatives(model, s.qn, s.vn, s.xn)
    for name, e, x, k in zip(fd.CentroidalDynamicsDerivatives._fields, exact, ours, core, strict=True):
        _close(x, e, f"reference on SymPy numbers: {name}")
        _close(k, e, f"core: {name}")
    assert np.abs(exact[1]).max() > 0.1


def test_aba_second_derivatives_are_sympys() -> None:
    s = Symbolic(random_tree(8, 2, root="revolute", kinds=("prismatic",), branching=False), 2)
    model = s.model

    def qdd(symbolic: str) -> np.ndarray:
        return aba_reference.aba(model, *s.state(symbolic))  # x = τ

    d_q, d_v = s.jacobian(qdd("q"), "q"), s.jacobian(qdd("v"), "v")
    d_qv, d_qx = s.jacobian(qdd("qv"), "q"), s.jacobian(qdd("qx"), "q")
    exact = s.numbers(s.jacobian(d_q, "q"), s.jacobian(d_v, "v"), s.jacobian(d_qv, "v"), s.jacobian(d_qx, "x"))
    ours = s.reference_at_point(second_reference.aba_second_derivatives)
    core = fd.aba_second_derivatives(model, s.qn, s.vn, s.xn)
    for name, e, x, k in zip(fd.AbaSecondDerivatives._fields, exact, ours, core, strict=True):
        _close(x, e, f"reference on SymPy numbers: {name}")
        _close(k, e, f"core: {name}")
    assert min(np.abs(v).max() for v in exact) > 0.01
