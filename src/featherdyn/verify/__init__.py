"""The verification tool behind ``featherdyn verify``.

:func:`run` builds a robot in featherdyn and in Pinocchio from the same URDF,
maps joints by name, compares every kinematic and dynamic quantity over
seeded random states, checks the identities that need no oracle, and reports
per-link inertia validity, mass-matrix conditioning and singular subtrees. It
also compares the spatial algebra with Pinocchio's own operations. The result
is a :class:`VerifyReport` (``.passed``, ``.to_table()``, ``.to_json()``,
``.to_html()``).
"""

from __future__ import annotations

import os
import time
import warnings
from collections.abc import Callable, Sequence

from ..tolerances import VERIFY_ALGEBRA, VERIFY_DYNAMICS
from .check import check_values
from .report import CheckResult, VerifyReport, compare, machine_meta
from .resolve import resolve_robot

__all__ = ["run", "run_or_report", "resolve_robot", "check_values", "CheckResult", "VerifyReport", "compare", "ALGEBRA_TOL",
           "DYNAMICS_TOL"]

ALGEBRA_TOL = VERIFY_ALGEBRA
"""Relative tolerance of the spatial-algebra comparisons (both libraries are exact to round-off)."""

DYNAMICS_TOL = VERIFY_DYNAMICS
"""Relative tolerance of the robot comparisons (the dynamics issue's standard)."""


def run(robot: str | os.PathLike[str] | None = None, *, floating_base: bool = False, samples: int = 10,
        seed: int = 0, tol: float | None = None, algebra: bool = True, strict: bool = False,
        progress: Callable[[str], None] | None = None, contacts: Sequence[str] = ()) -> VerifyReport:
    """Verify one robot (and the spatial algebra) against Pinocchio.

    Args:
        robot: a robot-library name, a URDF path, or ``None`` for the default robot.
        floating_base: put the root link on a free-flyer joint (in both libraries).
        samples: random states per check; seed: the random seed (same seed, same report).
        tol: relative tolerance for the robot comparisons (default :data:`DYNAMICS_TOL`).
        algebra: also compare the spatial algebra with Pinocchio's operations.
        strict: physicality warnings of the URDF loader become errors.
        progress: called with a short message as each stage starts.
        contacts: frames to hold fixed (3D point contacts in LOCAL_WORLD_ALIGNED, and one 6D contact in
            LOCAL on the first): constrained and impulse dynamics compared with Pinocchio's
            ``constraintDynamics`` / ``impulseDynamics``.

    Raises:
        ModelError, URDFError: the robot cannot be found or loaded.
        MissingDependencyError: Pinocchio is not installed.
    """
    from ..urdf import load_urdf
    from ._pinocchio import pinocchio_version
    from .algebra import algebra_checks
    from .dynamics import RobotPair, dynamics_checks, model_diagnostics

    if samples < 1:
        raise ValueError(f"samples: expected a positive number of samples, got {samples}")
    tol = DYNAMICS_TOL if tol is None else tol
    name, path = resolve_robot(robot)
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = load_urdf(path, floating_base=floating_base, strict=strict)
    for frame in contacts:  # an unknown contact frame is refused before any work
        model.resolve_frame(frame)
    base = "floating" if floating_base else "fixed"
    report = VerifyReport(
        title=f"featherdyn verify {name} ({base} base, nq={model.nq}, nv={model.nv}, {model.nbodies} bodies; "
              f"{samples} states, seed {seed})",
        meta={**machine_meta(), "pinocchio": pinocchio_version(), "robot": name, "urdf": str(path),
              "floating_base": floating_base, "samples": samples, "seed": seed, "tol": tol,
              "nq": model.nq, "nv": model.nv, "nbodies": model.nbodies,
              "load_warnings": sorted({str(w.message) for w in caught})},
    )
    if algebra:
        if progress:
            progress("spatial algebra")
        report.results += algebra_checks(samples=samples, seed=seed, tol=min(tol, ALGEBRA_TOL))
    if progress:
        progress("building the Pinocchio model")
    pair = RobotPair.from_urdf(model, str(path), floating_base)
    report.results += dynamics_checks(pair, samples=samples, seed=seed, tol=tol, progress=progress)
    if contacts:
        from .contacts import contact_checks

        if progress:
            progress("constrained dynamics")
        report.results += contact_checks(pair, list(contacts), samples=samples, seed=seed, tol=tol)
        report.meta["contacts"] = list(contacts)
    report.diagnostics = model_diagnostics(model).to_dict()
    report.meta["seconds"] = round(time.perf_counter() - t0, 3)
    return report


def run_or_report(robot: str, **options: object) -> VerifyReport:
    """:func:`run` on one robot of ``featherdyn verify --all``; a robot that does not load gives a
    report with one failed ``load`` row (the error's words) instead of an exception.

    A top-level function, so that a Dask worker can run it (``--all --scheduler``).
    """
    from ..errors import FeatherdynError

    try:
        return run(robot, **options)  # type: ignore[arg-type]
    except FeatherdynError as exc:
        rep = VerifyReport(title=f"featherdyn verify {robot}: not loadable", meta={"robot": robot, "error": str(exc)})
        rep.results.append(CheckResult("load", "load_urdf", float("nan"), float("nan"), 0, 0.0, False, str(exc)))
        return rep
