"""``featherdyn check``: the user's own numbers checked against featherdyn, with a diagnosis of any mismatch.

The values (from the user's code, another library or a log) are arrays named

=======  =====================  ==================================================
key      shape                  compared with
=======  =====================  ==================================================
``q``    `(nq,)` or `(N, nq)`   (input; always required)
``v``    `(nv,)` or `(N, nv)`   (input; required with ``tau`` or ``ddq``)
``a``    `(nv,)` or `(N, nv)`   (input; required with ``tau`` unless ``ddq`` is given)
``tau``  `(nv,)` or `(N, nv)`   ``fd.rnea(q, v, a)`` (when ``a`` is given)
``M``    `(nv, nv)` or ...      ``fd.crba(q)``
``ddq``  `(nv,)` or `(N, nv)`   forward dynamics: ``tau`` vs ``fd.rnea(q, v, ddq)``
``dtau_dq``, ``dtau_dv``  `(nv, nv)`  ``fd.rnea_derivatives(q, v, a)``
``dddq_dq``, ``dddq_dv``  `(nv, nv)`  ``fd.aba_derivatives(q, v, tau)``
``dg_dq``                 `(nv, nv)`  ``fd.generalized_gravity_derivatives(q)``
``dc_dq``, ``dcdot_dq``   `(3, nv)`   ``fd.center_of_mass_derivatives(q, v)``
``dh_dq``, ``dhdot_dq``, ``dhdot_dv``, ``dhdot_da``  `(6, nv)`, rows ``[k; p]``
                                      ``fd.centroidal_dynamics_derivatives(q, v, a)``
``dv_dq``, ``dv_dv``, ``da_dq``, ``da_dv``, ``da_da``, ``dac_dq``, ``dac_dv``, ``dac_da``  `(6, nv)`, rows
                                      ``[ω; v]``: ``fd.kinematics_derivatives(q, v, a, frame, reference)``
                                      (``frame=`` is required with them; ``reference=`` LOCAL by default)
=======  =====================  ==================================================

Every ``*_dq`` matrix may also be given with respect to q's coordinates (nq columns). The table is
:data:`.values.DERIVATIVE_SPECS`. Derivative matrices that disagree are read as described in
:mod:`.derivatives` (transposed, a world-frame tangent, ``[v; ω]`` or ``[p; k]`` rows, a free-flyer's ``[v; ω]``
columns, another reference frame, Pinocchio's LOCAL_WORLD_ALIGNED convention, spatial for classical
acceleration, a negated gravity derivative, quaternion coordinates, a missing ``M⁻¹``).

in the featherdyn convention (``docs/conventions.md``) or in Pinocchio's (``q`` with
continuous joints as ``(cos θ, sin θ)``, joints in Pinocchio's order, the
free-flyer velocity ``[v; ω]`` LOCAL), one state or a batch along a leading axis.
Each quantity is compared with the relative error ``|a − b| / max(|b|, 1)``
per state (``b`` = featherdyn's value, :func:`~featherdyn.verify.compare`).
Forward dynamics (``ddq`` for ``tau``) is judged by its backward error, the
joint forces ``fd.rnea(q, v, ddq)`` against ``tau``: comparing ``fd.aba(q, v,
tau)`` with ``ddq`` directly would amplify the round-off of a float32 ``tau``
by the condition number of ``M`` (1e4 and more on arms with light fingers).

On a mismatch the usual suspects are tried, alone and in pairs, and every
reading of the values under which *all* comparisons pass is reported:

* ``swapped_6d_halves``: the free-flyer block of ``v``, ``a``, ``tau``, ``ddq``
  (and of ``M``) has its 6D halves swapped (linear first vs angular first);
* ``world_frame_base_velocity``: the free-flyer velocity is world-aligned
  (Pinocchio's LOCAL_WORLD_ALIGNED) instead of in the base frame::

      v_b = [Rᵀω_w; Rᵀṗ],   a_b = [Rᵀω̇_w; Rᵀp̈ − ω_b × v_b],   τ_b = [Rᵀn_w; Rᵀf_w],   M_b = T M_w Tᵀ

* ``quaternion_wxyz``: quaternions (free-flyer, spherical) in ``(w, x, y, z)``
  order instead of ``(x, y, z, w)``;
* ``classical_base_acceleration``: the free-flyer acceleration is the classical
  one (``Rᵀp̈``) instead of the spatial one::

      a_spatial = a_classical − [0; ω × v]     (base coordinates)

* ``gravity``: computed with another gravity along the model's gravity axis
  (``−g``, ``0``, ``±9.8``, ``±9.80665``, ``±10``);
* ``continuous_layout``: continuous joints as ``(cos θ, sin θ)`` where the
  convention has the angle, or the reverse (told by the length of ``q``);
* ``joint_order``: joints in Pinocchio's (or featherdyn's), alphabetical or
  reversed order (a free-flyer stays first), inputs and outputs permuted;
* ``mass_matrix_triangle``: ``M`` holds only its upper (or lower) triangle.

Readings that change the *layout* of the user's arrays (joint order, 6D halves,
quaternion order, continuous joints, triangle) are applied in the user's own
layout, before the declared convention is converted to featherdyn's; the others
(frames, accelerations, gravity) in featherdyn's.

The package: :mod:`.values` reads and validates the arrays, :mod:`.readings`
reads them under a hypothesis and compares, :mod:`.suspects` lists the
mistakes tried, :mod:`.diagnosis` puts a finding into words, :mod:`.report`
holds the result. The command line (``featherdyn check``) lives in
:mod:`featherdyn.tools.cli`, which imports this package, never the reverse
(``docs/architecture.md``).
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Mapping

import numpy as np
from numpy.typing import ArrayLike

from ...errors import FeatherdynError, ModelError
from ...frames import LOCAL, ReferenceFrame, as_reference_frame
from ...joints import RevoluteJoint
from ...model import Model
from ...tolerances import CHECK_VALUES
from ..bridge import JointMap, pinocchio_model_from
from ..pinocchio import PinModel, require_pinocchio
from ..report import ROUNDOFF, CheckResult
from ..resolve import resolve_robot
from .derivatives import DERIVATIVE_SUSPECTS, derivative_checks
from .diagnosis import explain, largest_discrepancy
from .readings import Checker, Hypothesis, Layout
from .report import CheckReport, Finding, agree, one_line
from .suspects import SUSPECTS, diagnose
from .values import DERIVATIVE_KEYS, DERIVATIVE_SPECS, KEYS, ValuesError, load_npz, validate

__all__ = [
    "check_values",
    "CheckReport",
    "Finding",
    "ValuesError",
    "SUSPECTS",
    "DEFAULT_TOL",
    "CONVENTIONS",
]

#: Default relative tolerance: loose enough for values saved as float32 or rounded in a log.
DEFAULT_TOL = CHECK_VALUES  # (featherdyn.tolerances)

CONVENTIONS = ("featherdyn", "pinocchio")

#: what ``robot`` may be: a robot-library name, a URDF path, or a model.
Robot = str | os.PathLike[str] | Model


def _load_robot(robot: Robot, floating_base: bool, need_pin: bool
                ) -> tuple[str, str | None, Model, PinModel | None, JointMap | None, list[str]]:
    """``(name, urdf, model, pin_model, joint map, loader warnings)``; Pinocchio only where it can be had."""
    from ...mjcf import model_format
    from ..resolve import load_resolved

    caught_msgs: list[str] = []
    if isinstance(robot, Model):
        if floating_base and not robot.floating_base:
            raise ModelError("floating_base=True needs a model with a free-flyer root (load it with floating_base=True)")
        model, name, path = robot, robot.name, None
    else:
        name, urdf = resolve_robot(robot)
        # an MJCF model: Pinocchio's mirror is built from featherdyn's model (its MJCF reader disagrees with MuJoCo)
        path = str(urdf) if model_format(urdf) == "urdf" else None
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            model = load_resolved(urdf, floating_base)
        caught_msgs = sorted({str(w.message) for w in caught})
    try:
        pin = require_pinocchio()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if path is None:
                pm = pinocchio_model_from(model)
            elif floating_base:
                pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
            else:
                pm = pin.buildModelFromUrdf(path)
        jm = JointMap(model, pm)
    except (FeatherdynError, ValueError, RuntimeError):
        if need_pin:
            raise
        pm, jm = None, None
    return name, path, model, pm, jm, caught_msgs


def check_values(values: Mapping[str, ArrayLike] | str | os.PathLike[str], robot: Robot, floating_base: bool = False,
                 convention: str = "featherdyn", tol: float = DEFAULT_TOL, frame: str | int | None = None,
                 reference: ReferenceFrame | str = LOCAL) -> CheckReport:
    """Check the user's numbers against featherdyn and, on a mismatch, say which usual suspect explains them.

    Args:
        values: a mapping of arrays (``q``, ``v``, ``a`` and any of ``tau``,
            ``M``, ``ddq`` with ``tau``; see the module docstring for shapes) or
            the path of an ``.npz`` file holding them. One state, or a batch
            along a leading axis (the same for every array).
        robot: a robot-library name, a URDF path, or a featherdyn :class:`~featherdyn.Model`.
        floating_base: put the root link on a free-flyer joint.
        convention: ``"featherdyn"`` or ``"pinocchio"`` (the layout of the values).
        tol: relative tolerance, ``|a − b| / max(|b|, 1)`` per state.
        frame: the frame (name or index) of the frame derivatives ``dv_dq`` & co. (required with them);
            reference: their reference frame (``LOCAL``, ``WORLD``, ``LOCAL_WORLD_ALIGNED`` or its name).

    Returns:
        a :class:`CheckReport`: ``.passed``, ``.results``, ``.diagnosis``,
        ``.to_text()``, ``.to_json()``.

    Raises:
        ValuesError: no such file, not an ``.npz`` archive, a key missing, or a frame's derivative without a frame.
        ShapeError, NonFiniteError, DTypeError: an array has the wrong shape, NaN or
            infinity, or is not numeric (the message names the key and the expected shape).
        ModelError, URDFError: the robot cannot be found or loaded.
        MissingDependencyError: ``convention="pinocchio"`` without Pinocchio installed.
    """
    if convention not in CONVENTIONS:
        raise ValueError(f"convention: expected one of {', '.join(CONVENTIONS)}, got {convention!r}")
    if not (isinstance(tol, (int, float)) and 0 < tol < math.inf):
        raise ValueError(f"tol: expected a positive finite number, got {tol!r}")
    source = None
    if isinstance(values, (str, os.PathLike)):
        source = os.fspath(values)
        values = load_npz(values)
    elif not isinstance(values, Mapping):
        raise ValuesError(f"values: expected a mapping of arrays or the path of an .npz file, got "
                          f"{type(values).__name__}")
    ref = as_reference_frame(reference)  # (a bad name: ShapeError naming the three)
    frame_keys = [k for k in DERIVATIVE_KEYS if DERIVATIVE_SPECS[k].frame and k in values]
    if frame_keys and frame is None:
        raise ValuesError(f"{', '.join(frame_keys)}: a frame's derivatives: name the frame (check_values(frame=...), "
                          "featherdyn check --frame NAME) and its reference (default LOCAL)")
    name, path, model, pm, jm, load_warnings = _load_robot(robot, floating_base, convention == "pinocchio")
    frame_index = model.resolve_frame(frame) if frame is not None else None  # (an unknown frame: ModelError)

    continuous = {e.fd_body for e in jm.entries if e.continuous} if jm is not None else \
        {i for i, j in enumerate(model.joints) if isinstance(j, RevoluteJoint)
         and not np.isfinite(model.lower[model.idx_q[i]]) and not np.isfinite(model.upper[model.idx_q[i]])}
    # the allowed lengths of q: the declared layout, and the one with continuous joints flipped
    layout = Layout(model, pm, jm, convention, continuous)
    nq_decl, nq_flip = layout.declared_nq, layout.declared_nq + layout.flip_nq
    flipped = "cos θ, sin θ" if convention == "featherdyn" else "angle"
    nq_allowed = {nq_decl: ""}
    if nq_flip != nq_decl:
        nq_allowed[nq_flip] = f"continuous joints as {flipped}"
    if floating_base or model.floating_base:
        other = (nq_decl - 7, model.nv - 6, "without --floating-base")
    else:
        other = (nq_decl + 7, model.nv + 6, "with --floating-base")
    given = validate(values, nq_allowed, model.nv, other)

    ch = Checker(model, pm, jm, convention, continuous, given, tol, frame_index, ref)
    forced = given.arrays["q"].shape[1] != nq_decl
    base = "floating" if model.floating_base else "fixed"
    states = f"{given.n} state{'s' if given.n != 1 else ''}" if given.batched else "one state"
    title = (f"featherdyn check {source or 'values'} against {name} ({base} base, nq={model.nq}, nv={model.nv}), "
             f"{convention} convention, {states}, tol {tol:g}")
    report = CheckReport(title=title, meta={
        "robot": name, "urdf": path, "source": source, "floating_base": model.floating_base,
        "convention": convention, "tol": tol, "states": given.n, "batched": given.batched,
        "keys": [k for k in KEYS if k in given.arrays], "ignored_keys": list(given.ignored),
        "dtypes": given.dtypes, "compared": ch.quantities() + ch.derivative_keys(), "load_warnings": load_warnings,
        **({"frame": model.frames[frame_index].name, "reference": ref.name} if frame_index is not None else {}),
    })
    if forced:
        q_len = given.arrays["q"].shape[1]
        report.results = [CheckResult("check", "q layout", math.inf, math.inf, 0, tol, False,
                                      f"q has length {q_len}, the {convention} convention's nq is {nq_decl}")]
    else:
        report.results = [ch.result(Hypothesis(), q) for q in ch.quantities()]
        derivative_results, derivative_findings = derivative_checks(ch, tol)
        report.results += derivative_results
        if all(r.passed for r in report.results[: len(report.results) - len(derivative_results)]) \
                and not all(r.passed for r in derivative_results):
            report.diagnosis = derivative_findings
            report.summary = ("explained by " + " or ".join(f.suspect for f in derivative_findings)
                              if derivative_findings else
                              "no usual suspect explains the derivative matrices (tried: "
                              + ", ".join(DERIVATIVE_SUSPECTS) + ")")
            return report
        if report.passed:
            report.summary = f"{agree(len(report.results))} within {tol:g}"
            return report
        worst = max(r.max_rel for r in report.results)
        if worst <= ROUNDOFF:  # no suspect can explain what is only round-off
            report.summary = (f"the values agree to round-off (largest relative error {worst:.1e}); the tolerance "
                              f"{tol:g} is below what double precision can resolve (about {ROUNDOFF:g})")
            return report

    for h in diagnose(ch, forced):
        explanation, details = explain(ch, h)
        # every quantity given, re-compared under the reading: the derivative matrices at the corrected state
        results = tuple([ch.result(h, q, group="corrected") for q in ch.quantities()]
                        + [ch.derivative_result(h, k, group="corrected") for k in ch.derivative_keys()])
        report.diagnosis.append(Finding(h.suspects, explanation, results, details))
    if report.diagnosis:
        report.summary = "explained by " + " or ".join(f.suspect for f in report.diagnosis)
        return report
    h0 = Hypothesis(cos_sin=forced)
    rows = [ch.result(h0, q) for q in ch.quantities()]
    lead = "" if not forced else f"continuous joints read as {flipped} (the length of q says so); "
    try:
        where, info = largest_discrepancy(ch, h0, rows) if not all(r.passed for r in rows) else \
            ("the values agree once q's continuous joints are read that way", {})
    except (FeatherdynError, ValueError) as exc:  # the values cannot even be read
        where, info = one_line(exc), {}
    report.summary = f"no usual suspect explains it; {lead}{where}"
    low = sorted({d for d in given.dtypes.values() if d in ("float32", "float16")})
    if low:  # float32 round-off of q alone moves tau by ~1e-6 relative on long arms (UR5: up to 4e-6)
        report.summary += (f" — the values are {'/'.join(low)}, whose round-off alone can exceed the tolerance "
                           f"{tol:g}: retry with --tol 1e-5 (float32) to tell round-off from a real discrepancy")
    report.largest_discrepancy = info or None
    return report

