"""``featherdyn verify ROBOT --contacts FRAME[,FRAME…]``: constrained dynamics against Pinocchio.

The frames are held as 3D point contacts (``fd.PointContact``, LOCAL_WORLD_ALIGNED;
Pinocchio's ``CONTACT_3D``) and, separately, the first one as a 6D contact
(``fd.FrameContact``, LOCAL; ``CONTACT_6D``, whose wrenches are ``[f; n]``).
Compared over the random states: q̈ and the contact forces of
``fd.constrained_dynamics`` with ``pin.constraintDynamics``, and the velocity
after an impact of ``fd.impulse_dynamics`` with ``pin.impulseDynamics``; their
derivatives (``fd.constrained_dynamics_derivatives``, ``fd.impulse_dynamics_derivatives``)
with ``computeConstraintDynamicsDerivatives`` and ``computeImpulseDynamicsDerivatives``
(whose ``ddq_dv`` of an impulse is ``∂(v⁺ − v⁻)/∂v⁻``).
"""

from __future__ import annotations

from typing import Any

import numpy as np

import featherdyn as fd

from ..configuration import random_configuration
from ..constraints import Constraint
from ..errors import ConstraintError, ModelError, SingularMassMatrixError
from .dynamics import RobotPair
from .pinocchio import require_pinocchio
from .report import CheckResult, compare

__all__ = ["contact_checks"]


def _pin_contacts(pin: Any, pm: Any, frames: list[str], kind: Any, ref: Any) -> tuple[Any, Any]:
    cms, cds = pin.StdVec_RigidConstraintModel(), pin.StdVec_RigidConstraintData()
    for f in frames:
        if not pm.existFrame(f):
            raise ModelError(f"--contacts: Pinocchio's model has no frame {f!r}")
        fr = pm.frames[pm.getFrameId(f)]
        cms.append(pin.RigidConstraintModel(kind, pm, fr.parentJoint, fr.placement, ref))
    for c in cms:
        cds.append(c.createData())
    return cms, cds


def contact_checks(pair: RobotPair, frames: list[str], samples: int = 10, seed: int = 0,
                   tol: float = 1e-9) -> list[CheckResult]:
    """The comparisons of the module docstring, relative errors ``|a − b| / max(|b|, 1)`` held to
    ``tol × cond(M)`` (accelerations and forces carry M⁻¹, as ABA's do)."""
    pin = require_pinocchio()
    model, pm, jm = pair.model, pair.pin_model, pair.jmap
    for f in frames:
        model.resolve_frame(f)  # an unknown frame: ModelError naming it
    pd = pm.createData()
    rng = np.random.default_rng(seed + 1)
    q = random_configuration(model, rng, size=samples)
    v = rng.normal(size=(samples, model.nv))
    tau = rng.normal(size=(samples, model.nv))
    settings = pin.ProximalSettings(1e-12, 0.0, 1)
    results: list[CheckResult] = []
    setups: list[tuple[str, list[Constraint], tuple[Any, Any], bool]] = [("3D point contacts (LOCAL_WORLD_ALIGNED)", [fd.PointContact(f, fd.LOCAL_WORLD_ALIGNED) for f in frames],
               _pin_contacts(pin, pm, frames, pin.ContactType.CONTACT_3D, pin.LOCAL_WORLD_ALIGNED), False),
              (f"a 6D contact at {frames[0]} (LOCAL)", [fd.FrameContact(frames[0], fd.LOCAL)],
               _pin_contacts(pin, pm, frames[:1], pin.ContactType.CONTACT_6D, pin.LOCAL), True)]
    for label, cons, (cms, cds), six in setups:
        try:
            res = fd.constrained_dynamics(model, q, v, tau, cons)
            vplus = fd.impulse_dynamics(model, q, v, cons).v_plus
            d = fd.constrained_dynamics_derivatives(model, q, v, tau, cons)
            di = fd.impulse_dynamics_derivatives(model, q, v, cons)
        except (ConstraintError, SingularMassMatrixError) as exc:
            results.append(CheckResult("contacts", f"constrained_dynamics, {label}", float("nan"), 0.0, 0, tol, True,
                                       f"skipped: {exc}"))
            continue
        pin.initConstraintDynamics(pm, pd, cms, cds)
        ddq_p, lam_p, vp_p = [], [], []
        derivs: dict[str, list[np.ndarray]] = {}
        rows = np.r_[3:6, 0:3] if six else np.arange(3 * len(cons))  # Pinocchio's 6D rows are [f; n]

        def keep(name: str, value: np.ndarray, derivs: dict[str, list[np.ndarray]] = derivs) -> None:
            derivs.setdefault(name, []).append(value)

        for s in range(samples):
            qp, vp = jm.q_to_pin(q[s]), jm.v_to_pin(v[s])
            ddq_p.append(jm.v_from_pin(pin.constraintDynamics(pm, pd, qp, vp, jm.v_to_pin(tau[s]), cms, cds,
                                                              settings).copy()))
            lam = pd.lambda_c.copy()
            lam_p.append(np.concatenate([lam[3:6], lam[:3]]) if six else lam)
            pin.computeConstraintDynamicsDerivatives(pm, pd, cms, cds, settings)
            for name, m in (("ddq_dq", pd.ddq_dq), ("ddq_dv", pd.ddq_dv), ("ddq_dtau", pd.ddq_dtau)):
                keep(name, jm.matrix_from_pin(m.copy()))
            for name, m in (("forces_dq", pd.dlambda_dq), ("forces_dv", pd.dlambda_dv),
                            ("forces_dtau", pd.dlambda_dtau)):
                keep(name, jm.columns_from_pin(m.copy())[rows])
            vp_p.append(jm.v_from_pin(pin.impulseDynamics(pm, pd, qp, vp, cms, cds, 0.0, settings).copy()))
            pin.computeImpulseDynamicsDerivatives(pm, pd, cms, cds, 0.0, settings)
            keep("dv_plus_dq", jm.matrix_from_pin(pd.ddq_dq.copy()))
            keep("dv_plus_dv", jm.matrix_from_pin(pd.ddq_dv.copy()) + np.eye(model.nv))
            keep("impulses_dq", jm.columns_from_pin(pd.dlambda_dq.copy())[rows])
            keep("impulses_dv", jm.columns_from_pin(pd.dlambda_dv.copy())[rows])
        t = tol * max(1.0, float(np.max(np.linalg.cond(fd.crba(model, q)))))  # q̈ carries M⁻¹, as for ABA
        results.append(compare("contacts", f"constrained_dynamics q̈ vs constraintDynamics, {label}", res.ddq,
                               np.stack(ddq_p), t, ""))
        results.append(compare("contacts", f"constrained_dynamics forces vs data.lambda_c, {label}", res.lagrange,
                               np.stack(lam_p), t, ""))
        results.append(compare("contacts", f"impulse_dynamics v⁺ vs impulseDynamics, {label}", vplus,
                               np.stack(vp_p), t, ""))
        for name, theirs in derivs.items():
            ours = getattr(d, name) if hasattr(d, name) else getattr(di, name)
            source = "computeImpulseDynamicsDerivatives" if hasattr(di, name) else "computeConstraintDynamicsDerivatives"
            results.append(compare("contacts", f"{name} vs {source}, {label}", ours, np.stack(theirs), t, ""))
    return results
