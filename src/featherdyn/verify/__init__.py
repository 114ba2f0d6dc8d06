"""The verification tool behind ``featherdyn verify``.

``run()`` compares featherdyn with Pinocchio over seeded random values and
checks the identities that need no oracle; it returns a
:class:`VerifyReport` (``.passed``, ``.to_table()``, ``.to_json()``).

Today it covers the spatial algebra (transforms, cross products, inertias,
rotations). Robot models and dynamics add their own check groups to the same
report.
"""

from __future__ import annotations

from .report import CheckResult, VerifyReport, compare, machine_meta

__all__ = ["run", "CheckResult", "VerifyReport", "compare", "DEFAULT_TOL"]

DEFAULT_TOL = 1e-12
"""Relative tolerance of the algebra comparisons (float64; both libraries are exact to round-off)."""


def run(*, samples: int = 50, seed: int = 0, tol: float | None = None) -> VerifyReport:
    """Run every check and return the report.

    Args:
        samples: random values per check.
        seed: seed of ``numpy.random.default_rng``; the same seed gives the same report.
        tol: relative tolerance (default :data:`DEFAULT_TOL`).

    Raises:
        MissingDependencyError: Pinocchio is not installed.
    """
    from ._pinocchio import pinocchio_version
    from .algebra import algebra_checks

    if samples < 1:
        raise ValueError(f"samples: expected a positive number of samples, got {samples}")
    tol = DEFAULT_TOL if tol is None else tol
    report = VerifyReport(
        title=f"featherdyn verify: spatial algebra vs Pinocchio ({samples} samples, seed {seed})",
        meta={**machine_meta(), "pinocchio": pinocchio_version(), "samples": samples, "seed": seed, "tol": tol},
    )
    report.results += algebra_checks(samples=samples, seed=seed, tol=tol)
    return report
