"""Mass and rotational inertia of MuJoCo geoms (used by :mod:`featherdyn.readers.mjcf`), as MuJoCo's compiler computes them.

Each primitive's volume ``V`` (or area, with ``shellinertia``) and its inertia
per unit mass ``J`` (diagonal, in the geom frame, about its centre); the mass
is ``ρ V``, or the given ``mass`` (then ``ρ = mass / V``); the inertia
``m J``. Sizes are MuJoCo's: sphere ``r``; capsule and cylinder ``r`` and
the half length ``h``; ellipsoid the three radii; box the three half sizes.
Solids::

    sphere     V = 4/3 π r³          J = 2/5 r² (1, 1, 1)
    ellipsoid  V = 4/3 π a b c       J = 1/5 (b² + c², a² + c², a² + b²)
    cylinder   V = π r² 2h           J = ((3r² + 4h²)/12, same, r²/2)
    box        V = 8 a b c           J = 1/3 (b² + c², a² + c², a² + b²)
    capsule    cylinder + two hemispheres: with m_c, m_s their masses (H = 2h)
               I_xx = m_c (3r² + H²)/12 + m_s (2r²/5 + H²/4 + 3Hr/8),   I_zz = m_c r²/2 + m_s 2r²/5

Shells (``shellinertia="true"``): sphere ``A = 4π r²``, ``J = 2/3 r²``; box
six plates; cylinder a tube and two discs; capsule a tube and two
hemispherical shells (centre of mass ``r/2`` from the flat face). Ellipsoid
shells are not supported (MuJoCo uses an approximation).

Source: MuJoCo documentation (geom ``mass``, ``density``, ``shellinertia``;
compiler ``inertiafromgeom``); the formulas are the standard ones, checked
against MuJoCo's compiled ``body_mass`` / ``body_inertia``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

__all__ = ["SOLID_TYPES", "geom_mass_inertia"]

SOLID_TYPES = ("sphere", "capsule", "ellipsoid", "cylinder", "box")


def _solid(kind: str, s: Sequence[float]) -> tuple[float, tuple[float, float, float]]:
    """``(V, I/ρ)``: the volume and the inertia per unit density (diagonal, geom frame)."""
    pi = math.pi
    if kind == "capsule":  # cylinder + two hemispheres; the commonest first
        r, H = s[0], 2 * s[1]
        Vc, Vs = pi * r * r * H, 4 / 3 * pi * r**3
        axial = Vc * r * r / 2 + Vs * 2 * r * r / 5
        lateral = Vc * (3 * r * r + H * H) / 12 + Vs * (2 * r * r / 5 + H * H / 4 + 3 * H * r / 8)
        return Vc + Vs, (lateral, lateral, axial)
    if kind == "sphere":
        r = s[0]
        V = 4 / 3 * pi * r**3
        j = V * 2 / 5 * r * r
        return V, (j, j, j)
    if kind == "ellipsoid":
        a, b, c = s[:3]
        V = 4 / 3 * pi * a * b * c
        return V, (V / 5 * (b * b + c * c), V / 5 * (a * a + c * c), V / 5 * (a * a + b * b))
    if kind == "cylinder":
        r, h = s[0], s[1]
        V = pi * r * r * 2 * h
        lateral = V * ((3 * r * r + 4 * h * h) / 12)
        return V, (lateral, lateral, V * (r * r / 2))
    # box
    a, b, c = s[:3]
    V = 8 * a * b * c
    return V, (V / 3 * (b * b + c * c), V / 3 * (a * a + c * c), V / 3 * (a * a + b * b))


def _shell(kind: str, s: Sequence[float]) -> tuple[float, tuple[float, float, float]] | None:
    """``(A, I/ρ)`` of the surface (area density ``ρ``), or ``None`` where unsupported (ellipsoid)."""
    pi = math.pi
    if kind == "sphere":
        r = s[0]
        A = 4 * pi * r * r
        j = A * 2 / 3 * r * r
        return A, (j, j, j)
    if kind == "box":
        half = s[:3]
        area = 0.0
        J = [0.0, 0.0, 0.0]
        for n in range(3):  # the two plates normal to axis n, at ±half[n]
            u, w = [k for k in range(3) if k != n]
            a_u, a_w = half[u], half[w]
            m = 4 * a_u * a_w  # each plate's area
            area += 2 * m
            J[n] += 2 * (m * (a_u * a_u + a_w * a_w) / 3)
            J[u] += 2 * (m * (a_w * a_w / 3 + half[n] ** 2))
            J[w] += 2 * (m * (a_u * a_u / 3 + half[n] ** 2))
        return area, (J[0], J[1], J[2])
    if kind == "cylinder":
        r, H = s[0], 2 * s[1]
        tube, disc = 2 * pi * r * H, pi * r * r
        lateral = tube * (r * r / 2 + H * H / 12) + 2 * disc * (r * r / 4 + H * H / 4)
        return tube + 2 * disc, (lateral, lateral, tube * r * r + 2 * disc * r * r / 2)
    if kind == "capsule":
        r, H = s[0], 2 * s[1]
        tube, sphere = 2 * pi * r * H, 4 * pi * r * r
        hemisphere = sphere / 2  # a hemispherical shell: centre of mass r/2 from its flat face
        hemi = hemisphere * (2 / 3 * r * r - r * r / 4 + (H / 2 + r / 2) ** 2)
        lateral = tube * (r * r / 2 + H * H / 12) + 2 * hemi
        return tube + sphere, (lateral, lateral, tube * r * r + sphere * 2 / 3 * r * r)
    return None


def geom_mass_inertia(kind: str, size: Sequence[float], density: float, mass: float | None,
                      shell: bool) -> tuple[float, tuple[float, float, float]] | None:
    """``(m, I)`` of a primitive geom: its mass and diagonal inertia (three floats) about its centre, geom axes.

    ``mass`` (when given) wins over ``density``. ``None`` for an unsupported
    shell. Callers check sizes are positive first.

    Raises:
        ValueError: a ``mass`` given for a volume (or area) that underflows to 0: MuJoCo's error too.
    """
    got = _shell(kind, size) if shell else _solid(kind, size)
    if got is None:
        return None
    V, J = got
    if mass is not None and V == 0.0:  # positive sizes whose product underflows (size="1e-110")
        what = "area" if shell else "volume"
        raise ValueError(f"the {kind}'s {what} underflows to 0, so its mass has no density to spread (mass / "
                         f"{what} = {mass:g} / 0); MuJoCo refuses the body (its inertia would not exceed mjMINVAL)")
    k = mass / V if mass is not None else density
    return (mass if mass is not None else density * V), (J[0] * k, J[1] * k, J[2] * k)
