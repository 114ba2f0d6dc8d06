"""The user's derivative matrices (``dtau_dq``, ``dtau_dv``, ``dddq_dq``, ``dddq_dv``) against featherdyn's.

featherdyn's are ``fd.rnea_derivatives(q, v, a)`` and ``fd.aba_derivatives(q, v,
tau)``, with ∂/∂q along the tangent of ``fd.integrate`` (``v``'s layout, body
frame). On a mismatch, these readings of the user's matrix are tried, each
alone, and every one under which the comparison passes is reported:

* ``transposed``: the matrix is featherdyn's transposed;
* ``world_tangent``: the columns take the derivative along a world-frame
  (parent-frame) tangent, ``q' = exp(δ) q``: featherdyn's ``D · Ad(T)⁻¹``
  (``conventions.derivatives_to_parent_tangent``);
* ``linear_first_6d``: the free-flyer's rows and columns are ``[v; ω]``
  (Pinocchio's order) where featherdyn has ``[ω; v]``;
* ``quaternion_coordinates``: an ``(nv, nq)`` matrix, the derivative with
  respect to q's coordinates (the quaternion's four numbers), which the chain
  rule through ``q ⊕ δ`` turns into featherdyn's (``derivatives_from_coordinates``);
* ``missing_minv`` (``dddq_*``): the matrix is ``−∂τ/∂q`` (``−∂τ/∂q̇``) at
  ``q̈ = ABA(q, q̇, τ)`` — the factor ``M⁻¹`` is missing.
"""

from __future__ import annotations

import numpy as np

from ...conventions import derivatives_from_coordinates, derivatives_to_parent_tangent, derivatives_to_pinocchio
from ...errors import FeatherdynError
from ..report import CheckResult, compare
from .readings import Checker, Hypothesis
from .report import Finding, one_line
from .values import DERIVATIVE_KEYS

__all__ = ["DERIVATIVE_SUSPECTS", "derivative_checks"]

DERIVATIVE_SUSPECTS = ("transposed", "world_tangent", "linear_first_6d", "quaternion_coordinates", "missing_minv")

_NAMES = {"dtau_dq": "dtau_dq vs fd.rnea_derivatives", "dtau_dv": "dtau_dv vs fd.rnea_derivatives",
          "dddq_dq": "dddq_dq vs fd.aba_derivatives", "dddq_dv": "dddq_dv vs fd.aba_derivatives"}

_EXPLAIN = {
    "transposed": "{key} is featherdyn's matrix transposed (rows and columns exchanged)",
    "world_tangent": "{key} differentiates along a world-frame (parent-frame) tangent q' = exp(δ)·q; featherdyn's "
                     "tangent is the body frame's (fd.integrate): convert with "
                     "fd.conventions.derivatives_to_parent_tangent",
    "linear_first_6d": "{key} has the free-flyer's rows and columns as [v; ω] (Pinocchio's order); featherdyn's "
                       "are [ω; v]: convert with fd.conventions.derivatives_from_pinocchio",
    "quaternion_coordinates": "{key} is a derivative with respect to q's coordinates (the quaternion's four numbers), "
                              "not along the tangent: fd.conventions.derivatives_from_coordinates turns it into "
                              "featherdyn's",
    "missing_minv": "{key} is −∂τ/∂q (−∂τ/∂q̇) at q̈ = ABA(q, q̇, τ): the factor M⁻¹ is missing "
                    "(∂q̈/∂q = −M⁻¹ ∂τ/∂q)",
}


def _reading(suspect: str, key: str, raw: np.ndarray, given: np.ndarray, expected: np.ndarray,
             at_aba: dict[str, np.ndarray], ch: Checker, q: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """``(the user's matrix read so, featherdyn's matrix)`` under ``suspect``, or ``None`` where it does not apply."""
    model = ch.model
    square = raw.shape[-1] == model.nv
    if suspect == "transposed" and square:
        return np.swapaxes(given, -1, -2), expected
    if suspect == "world_tangent" and square and key.endswith("_dq"):
        return given, derivatives_to_parent_tangent(model, q, expected)
    if suspect == "linear_first_6d" and square:
        return derivatives_to_pinocchio(model, given), expected
    if (suspect == "quaternion_coordinates" and key.endswith("_dq") and raw.shape[-1] == model.nq != model.nv
            and ch.convention == "featherdyn"):
        return derivatives_from_coordinates(model, q, raw), expected
    if suspect == "missing_minv" and square and key in at_aba:
        return given, -at_aba[key]
    return None


def derivative_checks(ch: Checker, tol: float) -> tuple[list[CheckResult], list[Finding]]:
    """``(comparisons, findings)`` for the derivative keys present; findings only for failed comparisons."""
    import featherdyn as fd

    g = ch.given.arrays
    keys = [k for k in DERIVATIVE_KEYS if k in g]
    if not keys:
        return [], []
    model = ch.model
    try:
        x = ch.read(Hypothesis())
    except (FeatherdynError, ValueError) as exc:
        return [CheckResult("check", _NAMES[k], np.inf, np.inf, 0, tol, False, one_line(exc)) for k in keys], []
    q = x["q"]
    jm = ch.pinocchio_map() if ch.convention == "pinocchio" else None
    ours: dict[str, np.ndarray] = {}
    at_aba: dict[str, np.ndarray] = {}
    if "dtau_dq" in g or "dtau_dv" in g:
        ours["dtau_dq"], ours["dtau_dv"], _ = fd.rnea_derivatives(model, q, x["v"], x["a"])
    if "dddq_dq" in g or "dddq_dv" in g:
        ours["dddq_dq"], ours["dddq_dv"], _ = fd.aba_derivatives(model, q, x["v"], x["tau"])
        qdd = fd.aba(model, q, x["v"], x["tau"])
        at_aba["dddq_dq"], at_aba["dddq_dv"], _ = fd.rnea_derivatives(model, q, x["v"], qdd)

    results: list[CheckResult] = []
    findings: list[Finding] = []
    for key in keys:
        given = g[key]
        expected = ours[key]
        if given.shape[-1] != model.nv:  # with respect to q's coordinates: the reading below
            r = CheckResult("check", _NAMES[key], np.inf, np.inf, 0, tol, False,
                            f"{key} has {given.shape[-1]} columns (nq): a derivative with respect to q's coordinates")
        else:
            if jm is not None:
                given = jm.matrix_from_pin(given)
            r = compare("check", _NAMES[key], given, expected, tol, "")
        results.append(r)
        if r.passed:
            continue
        for suspect in DERIVATIVE_SUSPECTS:
            try:
                pair = _reading(suspect, key, g[key], given, expected, at_aba, ch, q)
            except (FeatherdynError, ValueError):
                continue
            if pair is None:
                continue
            cand = compare("corrected", _NAMES[key], pair[0], pair[1], tol, "")
            if cand.passed:
                findings.append(Finding((suspect,), _EXPLAIN[suspect].format(key=key), (cand,), {"key": key}))
    return results, findings
