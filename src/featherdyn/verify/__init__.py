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

import numpy as np

from ..api import aba as fd_aba
from ..api import coriolis_matrix as fd_coriolis_matrix
from ..api import crba as fd_crba
from ..api import rnea as fd_rnea
from ..configuration import random_configuration as fd_random_configuration
from ..model import Model, massless_subtrees
from ..tolerances import VERIFY_ALGEBRA, VERIFY_DYNAMICS
from .algebra import algebra_checks
from .check import check_values
from .report import CheckResult, VerifyReport, compare, machine_meta
from .resolve import load_resolved, resolve_robot

__all__ = ["run", "run_or_report", "refused_by", "resolve_robot", "load_resolved", "ORACLES", "check_values", "CheckResult", "VerifyReport", "compare", "ALGEBRA_TOL",
           "DYNAMICS_TOL"]

ALGEBRA_TOL = VERIFY_ALGEBRA
"""Relative tolerance of the spatial-algebra comparisons (both libraries are exact to round-off)."""

DYNAMICS_TOL = VERIFY_DYNAMICS
"""Relative tolerance of the robot comparisons (the dynamics issue's standard)."""


ORACLES = ("pinocchio", "mujoco", "both", "drake", "all")
"""What ``oracle`` takes: one library, ``both`` (Pinocchio and MuJoCo) or ``all`` (with Drake too)."""


def _oracles(oracle: str, path: os.PathLike[str], fmt: str, floating_base: bool,
             contacts: Sequence[str]) -> tuple[set[str], dict[str, str]]:
    """The libraries ``oracle`` compares with on a ``fmt`` model, and (for ``all``) the ones left out with why.

    Raises:
        ModelError: a named oracle cannot take the model (Pinocchio an MJCF or SDF file, MuJoCo a floating-base
            URDF or an SDF file, constrained dynamics without Pinocchio).
    """
    from ..errors import ModelError

    if oracle not in ORACLES:
        raise ModelError(f"oracle: expected one of {', '.join(ORACLES)}, got {oracle!r}")
    wanted = {"pinocchio": {"pinocchio"}, "mujoco": {"mujoco"}, "both": {"pinocchio", "mujoco"},
              "drake": {"drake"}, "all": {"pinocchio", "mujoco", "drake"}}[oracle]
    refusals = {}
    if fmt == "mjcf":
        refusals["pinocchio"] = (f"{os.fspath(path)}: an MJCF model is compared with MuJoCo (--oracle mujoco) or "
                                 "Drake (--oracle drake); Pinocchio's MJCF reader disagrees with MuJoCo's compiler on "
                                 "most public models (docs/mjcf-models.md)")
    if fmt == "sdf":
        refusals["pinocchio"] = (f"{os.fspath(path)}: an SDFormat model is compared with Drake (--oracle drake): "
                                 "Pinocchio's wheel reads no SDF")
        refusals["mujoco"] = (f"{os.fspath(path)}: an SDFormat model is compared with Drake (--oracle drake): MuJoCo "
                              "reads no SDF")
    if fmt == "urdf" and floating_base:
        refusals["mujoco"] = ("--floating-base with --oracle mujoco: MuJoCo's URDF importer builds no free joint; "
                              "compare the floating base with Pinocchio or Drake, or an MJCF model with a <freejoint/> "
                              "with MuJoCo")
    if oracle != "all":
        for name in sorted(wanted & set(refusals)):
            raise ModelError(refusals[name])
    skipped = {name: refusals[name] for name in sorted(wanted & set(refusals))}
    wanted -= set(skipped)
    if contacts and "pinocchio" not in wanted:
        raise ModelError("--contacts compares constrained dynamics with Pinocchio: use --oracle pinocchio, both or all")
    return wanted, skipped


def run(robot: str | os.PathLike[str] | None = None, *, floating_base: bool = False, samples: int = 10,
        seed: int = 0, tol: float | None = None, algebra: bool = True, strict: bool = False,
        progress: Callable[[str], None] | None = None, contacts: Sequence[str] = (),
        oracle: str | None = None) -> VerifyReport:
    """Verify one robot (and the spatial algebra) against Pinocchio, MuJoCo, Drake or all three.

    Args:
        robot: a robot-library name, a URDF, MJCF or SDFormat path, or ``None`` for the default robot.
        floating_base: put the root link of a URDF on a free-flyer joint (in every library).
        samples: random states per check; seed: the random seed (same seed, same report).
        tol: relative tolerance for the robot comparisons (default :data:`DYNAMICS_TOL`).
        algebra: also compare the spatial algebra with Pinocchio's operations (with Pinocchio as oracle).
        strict: physicality warnings of the loader become errors.
        progress: called with a short message as each stage starts.
        contacts: frames to hold fixed (3D point contacts in LOCAL_WORLD_ALIGNED, and one 6D contact in
            LOCAL on the first): constrained and impulse dynamics compared with Pinocchio's
            ``constraintDynamics`` / ``impulseDynamics``.
        oracle: ``"pinocchio"`` (the default for a URDF), ``"mujoco"`` (the default for an MJCF:
            :mod:`featherdyn.verify.mujoco`), ``"both"`` (those two), ``"drake"`` (the default for an SDFormat
            file: :mod:`featherdyn.verify.drake`) or ``"all"`` (the three; those that cannot take the model are
            left out and named in ``meta["oracles_skipped"]``).

    Raises:
        ModelError, URDFError, MJCFError: the robot cannot be found or loaded, or the oracle cannot take it
            (Pinocchio for an MJCF model, MuJoCo for a floating-base URDF, Drake's parser refusing the file,
            featherdyn unable to load an SDFormat file).
        MissingDependencyError: the oracle is not installed.
    """
    from ..readers.mjcf import model_format
    from .dynamics import RobotPair, dynamics_checks, identity_checks, model_diagnostics

    if samples < 1:
        raise ValueError(f"samples: expected a positive number of samples, got {samples}")
    tol = DYNAMICS_TOL if tol is None else tol
    name, path = resolve_robot(robot)
    fmt = "sdf" if path.suffix.lower() == ".sdf" else model_format(path)
    oracle = oracle or {"mjcf": "mujoco", "sdf": "drake"}.get(fmt, "pinocchio")
    used, skipped = _oracles(oracle, path, fmt, floating_base, contacts)
    use_pin, use_mj, use_dk = "pinocchio" in used, "mujoco" in used, "drake" in used
    if use_pin:
        from .pinocchio import pinocchio_version, require_pinocchio

        require_pinocchio()
    if use_mj:
        from .mujoco import mujoco_version, require_mujoco

        require_mujoco()
    if use_dk:
        from .drake import drake_version, require_drake

        require_drake()
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        if fmt == "sdf":
            from .drake import load_sdf_model

            model = load_sdf_model(path, strict)
        else:
            model = load_resolved(path, floating_base, strict)
    for frame in contacts:  # an unknown contact frame is refused before any work
        model.resolve_frame(frame)
    base = "floating" if model.floating_base else "fixed"  # the model's (an MJCF free joint makes it floating)
    oracles = " and ".join(o for o, used in (("Pinocchio", use_pin), ("MuJoCo", use_mj), ("Drake", use_dk)) if used)
    report = VerifyReport(
        title=f"featherdyn verify {name} ({base} base, nq={model.nq}, nv={model.nv}, {model.nbodies} bodies; "
              f"{samples} states, seed {seed}" + ("" if oracle == "pinocchio" else f"; against {oracles}") + ")",
        meta={**machine_meta(), "robot": name, "format": fmt, "oracle": oracle,
              "floating_base": model.floating_base, "samples": samples, "seed": seed, "tol": tol,
              "nq": model.nq, "nv": model.nv, "nbodies": model.nbodies,
              "load_warnings": sorted({str(w.message) for w in caught})},
    )
    report.meta[fmt] = str(path)  # type: ignore[literal-required]  # "urdf", "mjcf" or "sdf"
    if skipped:
        report.meta["oracles_skipped"] = skipped
    if use_pin:
        report.meta["pinocchio"] = pinocchio_version()
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
    if use_mj:
        from .mujoco import compile_mujoco, mujoco_checks

        report.meta["mujoco"] = mujoco_version()
        if progress:
            progress("compiling the model with MuJoCo")
        report.results += mujoco_checks(model, compile_mujoco(path, fmt), fmt, samples=samples, seed=seed, tol=tol)
    if use_dk:
        from . import drake as _drake

        report.meta["drake"] = drake_version()
        if progress:
            progress("parsing the model with Drake")
        try:
            plant = _drake.build_drake(path, model, weld_root=fmt == "urdf" and not model.floating_base)
        except _drake.DrakeRefusedError as exc:  # as a format an oracle cannot read: named, not a failed comparison
            if oracle != "all":
                raise
            report.meta["oracles_skipped"] = {**skipped, "drake": str(exc)}
        else:
            report.meta["drake_warnings"] = plant.warnings
            report.meta["oracle_notes"] = [*(f"Drake's parser ignores: {w}"
                                             for w in _drake.dynamics_warnings(plant.warnings)), *plant.notes]
            report.results += _drake.drake_checks(model, plant, samples=samples, seed=seed, tol=tol)
    if not use_pin:  # the laws that need no oracle (with Pinocchio they come with its checks)
        rng = np.random.default_rng(seed)
        q = fd_random_configuration(model, rng, samples)
        v, a = rng.normal(size=(2, samples, model.nv))
        M = fd_crba(model, q)
        tau = fd_rnea(model, q, v, a)
        report.results += identity_checks(model, q, v, a, tau, M, fd_coriolis_matrix(model, q, v), tol,
                                          singular=bool(massless_subtrees(model)) or _singular(model, q, v, tau))
    report.diagnostics = model_diagnostics(model).to_dict()
    report.meta["seconds"] = round(time.perf_counter() - t0, 3)
    return report


def _singular(model: Model, q: np.ndarray, v: np.ndarray, tau: np.ndarray) -> bool:
    """Whether ABA finds M singular at the states ``q`` (a massless floating base whose bodies cannot resist one
    rotation, as two_link_arm's): the identities that solve with M are then left out, as with Pinocchio."""
    from ..errors import SingularMassMatrixError

    try:
        fd_aba(model, q, v, tau)
    except SingularMassMatrixError:
        return True
    return False


def refused_by(report: VerifyReport) -> dict[str, str]:
    """The oracle the report was asked for, with its reason, when it could not take the model (``{"drake":
    Drake's reason}``: nothing was compared with it); empty when it was compared (``meta["oracles_skipped"]``)."""
    return {k: why for k, why in report.meta.get("oracles_skipped", {}).items() if k == report.meta.get("oracle")}


def run_or_report(robot: str, **options: object) -> VerifyReport:
    """:func:`run` on one robot of ``featherdyn verify --all``; a robot that does not load gives a
    report with one failed ``load`` row (the error's words) instead of an exception, and a robot Drake cannot
    take as featherdyn's model (:class:`~featherdyn.verify.drake.DrakeRefusedError`) a report without rows whose
    ``meta["oracles_skipped"]`` holds Drake's reason (:func:`refused_by`: listed, not failed).

    A top-level function, so that a Dask worker can run it (``--all --scheduler``).
    """
    from ..errors import FeatherdynError
    from .drake import DrakeRefusedError  # (pydrake itself is imported only where Drake is used)

    try:
        return run(robot, **options)  # type: ignore[arg-type]
    except DrakeRefusedError as exc:  # as run() names an oracle that cannot take the model under --oracle all
        return VerifyReport(title=f"featherdyn verify {robot}: refused by Drake",
                            meta={**machine_meta(), "robot": robot, "oracle": "drake",
                                  "floating_base": bool(options.get("floating_base")),
                                  "oracles_skipped": {"drake": str(exc)}})
    except FeatherdynError as exc:
        rep = VerifyReport(title=f"featherdyn verify {robot}: not loadable", meta={"robot": robot, "error": str(exc)})
        rep.results.append(CheckResult("load", "load_model", float("nan"), float("nan"), 0, 0.0, False, str(exc)))
        return rep
