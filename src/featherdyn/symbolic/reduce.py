"""Exact reduction of trigonometric and unit-quaternion polynomials (SymPy), for :mod:`featherdyn.symbolic`.

``sin``/``cos`` of each symbol become symbols ``s``, ``c`` reduced with
``s² = 1 − c²``; ``w`` of a unit quaternion ``(x, y, z, w)`` is reduced with
``w² = 1 − x² − y² − z²``; floats become the rationals they print as. Both
rule sets are Gröbner bases with coprime leading terms, so the canonical form
is zero iff the expression vanishes on the constraint set::

    canonical(sin(a)² + cos(a)²) = 1

SymPy is imported on first use; without it :class:`MissingDependencyError`.

Sources: Cox, Little & O'Shea, *Ideals, Varieties, and Algorithms* ch. 2 (remainders by a Gröbner basis).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from types import ModuleType
from typing import Any, TypeAlias

import numpy as np

from ..errors import MissingDependencyError

# SymPy ships no type stubs: its expressions (and matrices of them) are typed by name only.
SymExpr: TypeAlias = Any
SymMatrix: TypeAlias = Any


def import_sympy() -> ModuleType:
    try:
        import sympy
    except ImportError:
        raise MissingDependencyError(
            "featherdyn.symbolic needs SymPy, which is not installed: pip install sympy"
        ) from None
    return sympy


def object_array(values: Iterable[SymExpr]) -> np.ndarray:
    """An object array (SymPy entries) from a nested sequence."""
    return np.array(list(values) if not isinstance(values, np.ndarray) else values, dtype=object)


def sympy_matrix(a: np.ndarray) -> SymMatrix:
    return import_sympy().Matrix(np.asarray(a, dtype=object).tolist())


class Reducer:
    """Canonical form of polynomial expressions in sin/cos of symbols and in a unit quaternion.

    ``sin(a)``, ``cos(a)`` of each symbol ``a`` become symbols ``s_a``, ``c_a``;
    after expansion ``s_a^k → s_a^(k mod 2) (1 − c_a²)^(k div 2)`` (and the same
    for ``w`` of a unit quaternion), then expansion again. Arguments that are
    sums or integer multiples of symbols are expanded first (``expand_trig``);
    other arguments (``sin(q/2)``) are treated as independent angles, so an
    identity relating them to ``sin(q)`` is reported as not proved (never the
    other way round). Rational functions are cancelled and their numerator
    and denominator reduced.
    """

    def __init__(self, quaternion: Sequence[SymExpr] | None = None) -> None:
        self.sp = import_sympy()
        self.quaternion = tuple(quaternion) if quaternion is not None else None
        self._sc: dict[SymExpr, tuple[SymExpr, SymExpr]] = {}

    def _pair(self, arg: SymExpr) -> tuple[SymExpr, SymExpr]:
        if arg not in self._sc:
            name = str(arg)
            self._sc[arg] = (self.sp.Symbol(f"_s[{name}]", real=True), self.sp.Symbol(f"_c[{name}]", real=True))
        return self._sc[arg]

    def poly(self, expr: SymExpr) -> SymExpr:
        """``expr`` with floats made rational and sin/cos of symbols replaced by ``s``/``c`` symbols."""
        sp = self.sp
        expr = sp.sympify(expr)
        floats = expr.atoms(sp.Float)
        if floats:
            expr = expr.xreplace({f: sp.Rational(repr(float(f))) for f in floats})
        trig = expr.atoms(sp.sin, sp.cos)
        if any(not t.args[0].is_Symbol for t in trig):
            expr = sp.expand_trig(expr)
            trig = expr.atoms(sp.sin, sp.cos)
        mapping = {}
        for t in trig:
            s, c = self._pair(t.args[0])
            mapping[t] = s if isinstance(t, sp.sin) else c
        return expr.xreplace(mapping) if mapping else expr

    def reduce(self, expr: SymExpr) -> SymExpr:
        """The canonical form of ``expr``: a reduced, expanded polynomial (or a quotient of two, cancelled)."""
        sp = self.sp
        e = self.poly(expr)
        if any(a.exp.is_negative and a.base.free_symbols for a in e.atoms(sp.Pow)):
            # a rational function (e.g. the CoM (m₁c₁ + m₂c₂)/(m₁ + m₂) of a composite body)
            num, den = sp.fraction(sp.cancel(sp.together(e)))
            num, den = self._reduce_poly(num), self._reduce_poly(den)
            return sp.cancel(num / den) if num != 0 else sp.Integer(0)
        return self._reduce_poly(e)

    def _reduce_poly(self, e: SymExpr) -> SymExpr:
        sp = self.sp
        e = sp.expand(e)
        rules: dict[SymExpr, SymExpr] = {s: 1 - c**2 for s, c in self._sc.values()}
        if self.quaternion is not None:
            x, y, z, w = self.quaternion
            rules[w] = 1 - x**2 - y**2 - z**2
        if not rules:
            return e

        def high_power(a: SymExpr) -> bool:
            return bool(a.is_Pow and a.base in rules and a.exp.is_Integer and a.exp >= 2)

        def lower(a: SymExpr) -> SymExpr:
            k = int(a.exp)
            return a.base ** (k % 2) * rules[a.base] ** (k // 2)

        return sp.expand(e.replace(high_power, lower))

    def back(self, expr: SymExpr) -> SymExpr:
        """Replace the ``s``/``c`` symbols by ``sin``/``cos`` again."""
        sp = self.sp
        mapping = {}
        for arg, (s, c) in self._sc.items():
            mapping[s] = sp.sin(arg)
            mapping[c] = sp.cos(arg)
        return expr.xreplace(mapping) if mapping else expr

    def is_zero(self, expr: SymExpr) -> bool:
        sp = self.sp
        if isinstance(expr, np.ndarray):
            return all(self.is_zero(e) for e in expr.ravel())
        if isinstance(expr, sp.MatrixBase):
            return all(self.is_zero(e) for e in expr)
        return bool(self.reduce(expr) == 0)


def canonical(expr: SymExpr, *, unit_quaternion: Sequence[SymExpr] | None = None) -> SymExpr:
    """The canonical expanded form of a trigonometric (and/or unit-quaternion) polynomial.

    ``sin``/``cos`` of symbols are reduced with ``sin² = 1 − cos²`` (compound
    arguments are expanded first), ``w²`` of ``unit_quaternion = (x, y, z, w)``
    with ``w² = 1 − x² − y² − z²``; floats are made rational. Two expressions
    are equal on the constraint set iff their canonical forms are equal.
    Matrices and object arrays are reduced entry by entry.
    """
    sp = import_sympy()
    red = Reducer(unit_quaternion)
    if isinstance(expr, np.ndarray):
        out = np.empty(expr.shape, dtype=object)
        for idx in np.ndindex(*expr.shape):
            out[idx] = red.back(red.reduce(expr[idx]))
        return out
    if isinstance(expr, sp.MatrixBase):
        return expr.applyfunc(lambda e: red.back(red.reduce(e)))
    return red.back(red.reduce(expr))


def is_zero(expr: SymExpr, *, unit_quaternion: Sequence[SymExpr] | None = None) -> bool:
    """Whether ``expr`` (scalar, matrix or object array) reduces to exactly zero (see :func:`canonical`)."""
    return Reducer(unit_quaternion).is_zero(expr)


def pretty_form(expr: SymExpr) -> SymExpr:
    """A readable form of a canonical expression: collect, then recombine cos(a ± b) where it shortens."""
    sp = import_sympy()
    if expr == 0:
        return expr
    out = sp.factor_terms(expr)
    if out.has(sp.sin, sp.cos) and sp.count_ops(out) < 120:
        short = sp.trigsimp(out)
        if sp.count_ops(short) <= sp.count_ops(out):
            out = short
    return out
