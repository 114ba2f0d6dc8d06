"""The declared public algorithms (docs/architecture.md, "Adding an algorithm").

Each :class:`~featherdyn.api.declared.Declaration` here, with its kernel in
``core/cpp/declarations.hpp`` and its reference in ``featherdyn/algorithms``, is a whole
public function: ``fd.<name>`` (one state, any batch shape, ``out=``, Dask arrays,
``backend=``) and ``fd.compile(model).<name>``, made by :mod:`featherdyn.api.declared`.
"""

from __future__ import annotations

from ..algorithms import derivatives as _ref
from .declared import Declaration, public_function

__all__ = ["generalized_gravity_derivatives", "static_torque_derivatives"]

DECLARATIONS: dict[str, Declaration] = {d.name: d for d in [
    Declaration(
        name="generalized_gravity_derivatives",
        inputs=("q",),
        outputs=("dg_dq",),
        reference=_ref.generalized_gravity_derivatives,
        doc="""``∂g/∂q`` `(..., nv, nv)` of the generalized gravity ``g(q) = RNEA(q, 0, 0)``.

        Args:
            q: `(..., nq)`.
            out: optional `(..., nv, nv)` float64 array to write into.

        ∂/∂q along the tangent of ``fd.integrate`` (``q ⊕ δ``, δ in ``v``'s layout); Pinocchio's
        ``computeGeneralizedGravityDerivatives`` (its free-flyer columns in ``[v; ω]`` order)::

            ∂g/∂q[:, j] = d/dε RNEA(q ⊕ ε e_j, 0, 0) |_{ε=0}
        """,
    ),
    Declaration(
        name="static_torque_derivatives",
        inputs=("q", "f_ext"),
        outputs=("dtau_dq",),
        reference=_ref.static_torque_derivatives,
        doc="""``∂τ_s/∂q`` `(..., nv, nv)` of the static torque ``τ_s(q) = g(q) − Σ_i J_iᵀ f_i``.

        Args:
            q: `(..., nq)`.
            f_ext: `(..., nb, 6)` body-frame spatial forces ``[n; f]``, held fixed in their bodies.
            out: optional `(..., nv, nv)` float64 array to write into.

        ``τ_s = RNEA(q, 0, 0, f_ext)``; ∂/∂q along the tangent of ``fd.integrate``; Pinocchio's
        ``computeStaticTorqueDerivatives`` (forces in the joint frames, linear part first)::

            ∂τ_s/∂q[:, j] = d/dε RNEA(q ⊕ ε e_j, 0, 0, f_ext) |_{ε=0}
        """,
    ),
]}

generalized_gravity_derivatives = public_function(DECLARATIONS["generalized_gravity_derivatives"])
static_torque_derivatives = public_function(DECLARATIONS["static_torque_derivatives"])
