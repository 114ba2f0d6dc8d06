"""The usual suspects: the convention mistakes tried, alone and in pairs, when the values do not agree.

Each suspect is a change to the reading of the values (a field of
:class:`~featherdyn.verify.check.readings.Hypothesis`); the diagnosis keeps
the readings under which *every* comparison passes, single suspects first,
then pairs.
"""

from __future__ import annotations

import itertools

import numpy as np

from .readings import Change, Checker, Hypothesis
from .values import VECTOR_KEYS

__all__ = ["SUSPECTS", "atoms", "diagnose"]

#: The suspects tried on a mismatch, by the name a :class:`~featherdyn.verify.check.Finding` reports.
SUSPECTS = (
    "swapped_6d_halves",
    "world_frame_base_velocity",
    "quaternion_wxyz",
    "classical_base_acceleration",
    "gravity",
    "continuous_layout",
    "joint_order",
    "mass_matrix_triangle",
)

_GRAVITY_MAGNITUDES = (9.8, 9.80665, 10.0)


def atoms(ch: Checker) -> list[Change]:
    """Single-suspect changes applicable to this robot and these keys."""
    g = ch.given.arrays
    out: list[Change] = []
    vec = any(k in g for k in VECTOR_KEYS) or "M" in g
    if ch.ff is not None and vec:
        out.append({"swap6": True})
        out.append({"world": True})
    quats = {b.kind for b in ch.blocks if b.quat_at is not None}
    if quats:
        out.append({"quat_wxyz": "all"})
    if len(quats) > 1:  # a free-flyer and spherical joints: perhaps only the base's quaternion is (w, x, y, z)
        out.append({"quat_wxyz": "free_flyer"})
    if ch.ff is not None and "v" in g and (("a" in g and "tau" in g) or "ddq" in g):
        out.append({"classical": True})
    if "tau" in g or "ddq" in g:
        for gv in _gravity_candidates(np.asarray(ch.model.gravity, dtype=float)):
            out.append({"gravity": gv})
    for name in ch.orders:
        out.append({"order": name})
    if "M" in g:
        out += [{"triangle": "upper"}, {"triangle": "lower"}]
    return out


def diagnose(ch: Checker, forced_cos_sin: bool) -> list[Hypothesis]:
    """The readings that explain every comparison: single suspects first, then pairs."""
    base = Hypothesis(cos_sin=forced_cos_sin)
    single = atoms(ch)
    if forced_cos_sin:
        tiers = [[base], [base.merged(a) for a in single]]
    else:
        pairs = [base.merged(a).merged(b) for a, b in itertools.combinations(single, 2) if _compatible(a, b)]
        tiers = [[base.merged(a) for a in single], pairs]
    for tier in tiers:
        found = [h for h in tier if ch.explains(h)]
        if found:
            return found
    return []


def _compatible(a: Change, b: Change) -> bool:
    if set(a) & set(b):  # two gravities, two orders, two triangles, two quaternion readings
        return False
    # world-aligned base accelerations are already the classical p̈: the pair would count ω × v twice
    return set(a) | set(b) != {"world", "classical"}


def _gravity_candidates(g: np.ndarray) -> list[tuple[float, float, float]]:
    norm = float(np.linalg.norm(g))
    axis = g / norm if norm > 0 else np.array([0.0, 0.0, -1.0])
    cands = [-g, np.zeros(3)] + [s * mag * axis for mag in _GRAVITY_MAGNITUDES for s in (1.0, -1.0)]
    out: list[tuple[float, float, float]] = []
    for c in cands:
        x, y, z = (float(e) + 0.0 for e in c)  # + 0.0: no negative zeros in the report
        if not np.allclose(c, g, rtol=0, atol=1e-12) and (x, y, z) not in out:
            out.append((x, y, z))
    return out
