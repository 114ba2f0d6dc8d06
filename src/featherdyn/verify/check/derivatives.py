"""The user's derivative matrices (``dtau_dq``, ``dg_dq``, ``dh_dq``, ``dv_dq`` … :data:`~.values.DERIVATIVE_SPECS`)
against featherdyn's.

featherdyn's are ``fd.rnea_derivatives(q, v, a)``, ``fd.aba_derivatives(q, v, tau)``,
``fd.generalized_gravity_derivatives(q)``, ``fd.center_of_mass_derivatives(q, v)``,
``fd.centroidal_dynamics_derivatives(q, v, a)`` (rows ``[k; p]``) and ``fd.kinematics_derivatives(q, v, a,
frame, reference)`` (rows ``[ω; v]``), with ∂/∂q along the tangent of ``fd.integrate`` (``v``'s layout, body
frame). On a mismatch, these readings of the user's matrix are tried, each alone, and every one under which
the comparison passes is reported (each where it applies):

* ``transposed``: the matrix is featherdyn's transposed (nv rows; a 6- or 3-row matrix given as
  `(nv, 6)` is refused by its shape, the error saying it is the transposed one);
* ``world_tangent``: the columns take the derivative along a world-frame
  (parent-frame) tangent, ``q' = exp(δ) q``: featherdyn's ``D · Ad(T)⁻¹``
  (``conventions.derivatives_to_parent_tangent``);
* ``linear_first_6d``: the free-flyer's columns (and rows, for nv rows) are ``[v; ω]``
  (Pinocchio's order) where featherdyn has ``[ω; v]``;
* ``linear_first_rows`` (6 motion rows): the rows are ``[v; ω]``; ``pk_rows`` (the centroidal momentum's):
  ``[p; k]``, Pinocchio's order; ``pinocchio_layout``: those rows and the free-flyer's columns both
  linear-first, as Pinocchio returns them;
* ``other_reference`` (a frame's): the derivative of the quantity in another reference frame;
* ``pinocchio_lwa`` (``dv_dq``, ``da_dq`` in LOCAL_WORLD_ALIGNED): Pinocchio's ``getFrame*Derivatives``
  convention, which holds the frame's origin fixed: the linear rows lack ``ω × J_v`` (``ω̇ × J_v``);
* ``spatial_classical`` (a frame's acceleration): ``da_*`` given where ``dac_*`` is asked for, or the reverse;
* ``negated`` (``dg_dq``): ``−∂g/∂q``, the derivative of the gravity force ``−g(q)``;
* ``quaternion_coordinates``: a `(rows, nq)` matrix, the derivative with
  respect to q's coordinates (the quaternion's four numbers), which the chain
  rule through ``q ⊕ δ`` turns into featherdyn's (``derivatives_from_coordinates``);
* ``missing_minv`` (``dddq_*``): the matrix is ``−∂τ/∂q`` (``−∂τ/∂q̇``) at
  ``q̈ = ABA(q, q̇, τ)`` — the factor ``M⁻¹`` is missing.
"""

from __future__ import annotations

import numpy as np

from ...conventions import derivatives_from_coordinates, derivatives_to_parent_tangent, derivatives_to_pinocchio
from ...errors import FeatherdynError
from ...frames import LOCAL_WORLD_ALIGNED, ReferenceFrame
from ..bridge import SWAP6
from ..report import CheckResult, compare
from .readings import Checker, Hypothesis
from .report import Finding
from .values import DERIVATIVE_SPECS

__all__ = ["DERIVATIVE_SUSPECTS", "derivative_checks"]

DERIVATIVE_SUSPECTS = ("transposed", "world_tangent", "linear_first_6d", "linear_first_rows", "pk_rows",
                       "pinocchio_layout", "other_reference", "pinocchio_lwa", "spatial_classical", "negated",
                       "quaternion_coordinates", "missing_minv")

_EXPLAIN = {
    "transposed": "{key} is featherdyn's matrix transposed (rows and columns exchanged)",
    "world_tangent": "{key} differentiates along a world-frame (parent-frame) tangent q' = exp(δ)·q; featherdyn's "
                     "tangent is the body frame's (fd.integrate): convert with "
                     "fd.conventions.derivatives_to_parent_tangent",
    "linear_first_6d": "{key} has the free-flyer's {what} as [v; ω] (Pinocchio's order); featherdyn's "
                       "are [ω; v]: convert with fd.conventions.derivatives_from_pinocchio",
    "linear_first_rows": "{key} has its rows as [v; ω] (Pinocchio's order); featherdyn's motion rows are [ω; v]: "
                         "swap the halves of the rows (fd.conventions.derivatives_from_pinocchio(model, D, "
                         "rows='spatial') also converts a free-flyer's columns)",
    "pk_rows": "{key} has its rows as [p; k] (Pinocchio's computeCentroidalDynamicsDerivatives order); featherdyn's "
               "centroidal rows are [k; p]: swap the halves of the rows",
    "pinocchio_layout": "{key} is in Pinocchio's layout: rows {rows} and the free-flyer's columns [v; ω]; "
                        "featherdyn's are [ω; v] (and [k; p]): fd.conventions.derivatives_from_pinocchio(model, D, "
                        "rows='spatial')",
    "other_reference": "{key} is the derivative in the {other} frame; it was compared in {reference}",
    "pinocchio_lwa": "{key} holds the frame's origin fixed, as Pinocchio's getFrame*Derivatives do in "
                     "LOCAL_WORLD_ALIGNED; featherdyn differentiates the function itself, whose linear part refers "
                     "to the moving origin: its linear rows add {term}",
    "spatial_classical": "{key} is featherdyn's {other}: the {what} acceleration's derivative, where {key} is the "
                         "{asked} acceleration's",
    "negated": "{key} is −∂g/∂q, the derivative of the gravity force −g(q); featherdyn's g(q) is the torque in "
               "τ = M q̈ + C q̇ + g(q) (Pinocchio's computeGeneralizedGravity)",
    "quaternion_coordinates": "{key} is a derivative with respect to q's coordinates (the quaternion's four numbers), "
                              "not along the tangent: fd.conventions.derivatives_from_coordinates turns it into "
                              "featherdyn's",
    "missing_minv": "{key} is −∂τ/∂q (−∂τ/∂q̇) at q̈ = ABA(q, q̇, τ): the factor M⁻¹ is missing "
                    "(∂q̈/∂q = −M⁻¹ ∂τ/∂q)",
}

#: a reading: (the words of its explanation's placeholders, the user's matrix read so, featherdyn's matrix)
Reading = tuple[dict[str, str], np.ndarray, np.ndarray]


def _lwa_origin_fixed(ch: Checker, key: str, x: dict[str, np.ndarray], expected: np.ndarray) -> np.ndarray:
    """featherdyn's ``dv_dq`` (``da_dq``) in LOCAL_WORLD_ALIGNED with the origin held fixed (Pinocchio's):
    the linear rows less ``ω × J_v`` (``ω̇ × J_v``), J_v the Jacobian's linear rows in LOCAL_WORLD_ALIGNED."""
    import featherdyn as fd

    model, frame = ch.model, ch.frame
    assert frame is not None
    if key == "dv_dq":
        w = fd.frame_velocity(model, x["q"], x["v"], frame, LOCAL_WORLD_ALIGNED).vector[..., :3]
    else:
        w = fd.frame_acceleration(model, x["q"], x["v"], x["a"], frame, LOCAL_WORLD_ALIGNED).vector[..., :3]
    jv = fd.frame_jacobian(model, x["q"], frame, LOCAL_WORLD_ALIGNED)[..., 3:, :]
    out = expected.copy()
    out[..., 3:, :] -= np.cross(w[..., None, :], np.swapaxes(jv, -1, -2)).swapaxes(-1, -2)
    return out


def _readings(suspect: str, key: str, raw: np.ndarray, given: np.ndarray, expected: np.ndarray,
              at_aba: dict[str, np.ndarray], ch: Checker, x: dict[str, np.ndarray]) -> list[Reading]:
    """The readings of the user's matrix under ``suspect`` (none where it does not apply)."""
    model, spec, q = ch.model, DERIVATIVE_SPECS[key], x["q"]
    joint_rows = spec.rows == "joint"
    square = raw.shape[-1] == model.nv
    six = spec.rows in ("motion", "momentum")
    ff = ch.ff is not None
    if suspect == "transposed" and square and joint_rows:
        return [({}, np.swapaxes(given, -1, -2), expected)]
    if suspect == "world_tangent" and square and key.endswith("_dq"):
        return [({}, given, derivatives_to_parent_tangent(model, q, expected))]
    if suspect == "linear_first_6d" and square and ff:
        return [({"what": "rows and columns" if joint_rows else "columns"},
                 derivatives_to_pinocchio(model, given, "generalized" if joint_rows else "other"), expected)]
    if suspect == "linear_first_rows" and square and spec.rows == "motion":
        return [({}, given[..., SWAP6, :], expected)]
    if suspect == "pk_rows" and square and spec.rows == "momentum":
        return [({}, given[..., SWAP6, :], expected)]
    if suspect == "pinocchio_layout" and square and six and ff:
        return [({"rows": "[v; ω]" if spec.rows == "motion" else "[p; k]"},
                 derivatives_to_pinocchio(model, given, "spatial"), expected)]
    if suspect == "other_reference" and spec.frame:
        return [({"other": ref.name, "reference": ch.reference.name}, given,
                 ch.derivatives_at(Hypothesis(), ref)[key]) for ref in ReferenceFrame if ref is not ch.reference]
    if suspect == "pinocchio_lwa" and key in ("dv_dq", "da_dq") and ch.reference is LOCAL_WORLD_ALIGNED:
        term = "ω × J_v" if key == "dv_dq" else "ω̇ × J_v"
        return [({"term": term}, given, _lwa_origin_fixed(ch, key, x, expected))]
    if suspect == "spatial_classical" and spec.frame and key[:3] in ("da_", "dac") and not key.endswith("_da"):
        other = "dac_" + key[3:] if key.startswith("da_") else "da_" + key[4:]
        ours = ch.derivatives_at(Hypothesis())
        asked, what = ("spatial", "classical") if key.startswith("da_") else ("classical", "spatial")
        return [({"other": other, "asked": asked, "what": what}, given, ours[other])] if other in ours else []
    if suspect == "negated" and key == "dg_dq":
        return [({}, given, -expected)]
    if (suspect == "quaternion_coordinates" and key.endswith("_dq") and raw.shape[-1] == model.nq != model.nv
            and ch.convention == "featherdyn"):
        return [({}, derivatives_from_coordinates(model, q, raw), expected)]
    if suspect == "missing_minv" and square and key in at_aba:
        return [({}, given, -at_aba[key])]
    return []


def derivative_checks(ch: Checker, tol: float) -> tuple[list[CheckResult], list[Finding]]:
    """``(comparisons, findings)`` for the derivative keys present; findings only for failed comparisons."""
    import featherdyn as fd

    g = ch.given.arrays
    keys = ch.derivative_keys()
    if not keys:
        return [], []
    model = ch.model
    results = [ch.derivative_result(Hypothesis(), key) for key in keys]
    if all(r.passed for r in results):
        return results, []
    try:
        x = ch.read(Hypothesis())
        ours = ch.derivatives_at(Hypothesis())  # (every field of each function: da_* and dac_* both)
    except (FeatherdynError, ValueError):  # (the failed rows say why)
        return results, []
    at_aba: dict[str, np.ndarray] = {}
    if "dddq_dq" in g or "dddq_dv" in g:
        qdd = fd.aba(model, x["q"], x["v"], x["tau"])
        at_aba["dddq_dq"], at_aba["dddq_dv"], _ = fd.rnea_derivatives(model, x["q"], x["v"], qdd)

    findings: list[Finding] = []
    for key, r in zip(keys, results, strict=True):
        if r.passed:
            continue
        given, expected = x.get(key, g[key]), ours[key]
        explained: list[tuple[np.ndarray, np.ndarray]] = []
        for suspect in DERIVATIVE_SUSPECTS:
            try:
                readings = _readings(suspect, key, g[key], given, expected, at_aba, ch, x)
            except (FeatherdynError, ValueError):
                continue
            for words, mine, theirs in readings:
                # a reading that changes nothing more than one already found is the same reading (a free-flyer's
                # columns that are zero read alike in either order): the first, simpler one is reported
                if any(np.array_equal(mine, m) and np.array_equal(theirs, t) for m, t in explained):
                    continue
                cand = compare("corrected", ch.label(key), mine, theirs, tol, "")
                if cand.passed:
                    explained.append((mine, theirs))
                    findings.append(Finding((suspect,), _EXPLAIN[suspect].format(key=key, **words), (cand,),
                                            {"key": key}))
    return results, findings
