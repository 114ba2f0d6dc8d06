"""Result values of the algorithms: plain frozen records of arrays and spatial values.

Both implementations (the reference in :mod:`featherdyn.algorithms` and the
compiled engine) return these, and the public functions hand them to the
caller unchanged, so they live below both, next to the model they describe.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .model import Model
from .spatial import PluckerTransform, SpatialMotion

__all__ = ["Kinematics", "CenterOfMass", "RneaSecondDerivatives", "AbaSecondDerivatives", "KinematicsDerivatives",
           "CenterOfMassDerivatives", "CentroidalDynamicsDerivatives"]


class Kinematics:
    """The result of :func:`featherdyn.forward_kinematics` (body axis last among the batch axes).

    Attributes:
        placements: world placements ``⁰M_i`` of the bodies, batch shape `(..., nb)`.
        velocities: body velocities ``v_i`` in body coordinates `(..., nb, 6)` (``None`` if no ``v``).
        accelerations: spatial accelerations ``a_i`` in body coordinates `(..., nb, 6)`,
            without gravity (``None`` if no ``a``).
        parent_placements: ``ᵖM_i``, the pose of each body in its parent, `(..., nb)`.

    A frozen record. The compiled core fills it with arrays — the homogeneous placements `(..., nb, 4, 4)` and
    the motions `(..., nb, 6)`, read-only — and the spatial values above are made from them on first access
    (so a call that reads one body's placement does not pay for every body's).
    """

    __slots__ = ("_H", "_Hp", "_acc", "_values", "_vel", "model")
    #: the record's fields, in order (what Dask and pickling rebuild it from)
    FIELDS = ("model", "placements", "velocities", "accelerations", "parent_placements")

    model: Model
    _H: np.ndarray
    _Hp: np.ndarray
    _vel: np.ndarray | None
    _acc: np.ndarray | None
    _values: tuple[PluckerTransform, SpatialMotion | None, SpatialMotion | None, PluckerTransform]

    def __init__(self, model: Model, placements: PluckerTransform, velocities: SpatialMotion | None,
                 accelerations: SpatialMotion | None, parent_placements: PluckerTransform) -> None:
        object.__setattr__(self, "model", model)
        object.__setattr__(self, "_values", (placements, velocities, accelerations, parent_placements))

    def _spatial(self) -> tuple[PluckerTransform, SpatialMotion | None, SpatialMotion | None, PluckerTransform]:
        try:
            return self._values
        except AttributeError:  # filled by the core: made now, once
            def pose(H: np.ndarray) -> PluckerTransform:
                return PluckerTransform._wrap(H[..., :3, :3], H[..., :3, 3], None, None)

            def motion(m: np.ndarray | None) -> SpatialMotion | None:
                return None if m is None else SpatialMotion._wrap(m, None)

            values = (pose(self._H), motion(self._vel), motion(self._acc), pose(self._Hp))
            object.__setattr__(self, "_values", values)
            return values

    @property
    def placements(self) -> PluckerTransform:
        return self._spatial()[0]

    @property
    def velocities(self) -> SpatialMotion | None:
        return self._spatial()[1]

    @property
    def accelerations(self) -> SpatialMotion | None:
        return self._spatial()[2]

    @property
    def parent_placements(self) -> PluckerTransform:
        return self._spatial()[3]

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError(f"Kinematics is a frozen record: cannot set {name!r}")

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"Kinematics is a frozen record: cannot delete {name!r}")

    def __reduce__(self) -> tuple[type, tuple[object, ...]]:
        return Kinematics, tuple(getattr(self, f) for f in self.FIELDS)

    def __repr__(self) -> str:
        return (f"Kinematics(model={self.model.name!r}, placements batch shape {self.placements.shape}, "
                f"velocities={'yes' if self.velocities is not None else 'None'}, "
                f"accelerations={'yes' if self.accelerations is not None else 'None'})")


class CenterOfMass(NamedTuple):
    """Position `(..., 3)` and velocity `(..., 3)` of the centre of mass, in world coordinates."""

    position: np.ndarray
    velocity: np.ndarray


class RneaSecondDerivatives(NamedTuple):
    """The second derivatives of ``τ = RNEA(q, q̇, q̈)``, each `(..., nv, nv, nv)`, ``[i, j, k]`` =
    ``∂²τ_i/∂x_j∂y_k`` (``q`` along ``fd.integrate``'s tangent; :func:`featherdyn.rnea_second_derivatives`)."""

    d2tau_dq2: np.ndarray  #: ∂(∂τ_i/∂q_j)/∂q_k
    d2tau_dv2: np.ndarray  #: ∂²τ_i/∂q̇_j∂q̇_k
    d2tau_dqdv: np.ndarray  #: ∂²τ_i/∂q_j∂q̇_k
    dM_dq: np.ndarray  # noqa: N815 (the public name)  ∂M_ij/∂q_k


class AbaSecondDerivatives(NamedTuple):
    """The second derivatives of ``q̈ = ABA(q, q̇, τ)``, each `(..., nv, nv, nv)`, ``[i, j, k]`` =
    ``∂²q̈_i/∂x_j∂y_k`` (:func:`featherdyn.aba_second_derivatives`)."""

    d2ddq_dq2: np.ndarray  #: ∂(∂q̈_i/∂q_j)/∂q_k
    d2ddq_dv2: np.ndarray  #: ∂²q̈_i/∂q̇_j∂q̇_k
    d2ddq_dqdv: np.ndarray  #: ∂²q̈_i/∂q_j∂q̇_k
    d2ddq_dqdtau: np.ndarray  #: ∂²q̈_i/∂q_j∂τ_k


class KinematicsDerivatives(NamedTuple):
    """The derivatives of a frame's motion (:func:`featherdyn.kinematics_derivatives`), each `(..., 6, nv)`, rows
    ``[ω; v]`` in the reference asked for: of its spatial velocity ``v_f`` (``dv_*``), its spatial acceleration
    ``a_f`` (``da_*``) and its classical acceleration ``a_f^c = [ω̇; a_lin + ω × v_lin]`` (``dac_*``, whose linear
    rows are the acceleration of the frame's origin, or of the point given), against ``q`` (along the tangent of
    ``fd.integrate``), ``q̇`` and ``q̈``. ``dv_dv = da_da = dac_da = J``, the frame's Jacobian."""

    dv_dq: np.ndarray
    dv_dv: np.ndarray
    da_dq: np.ndarray
    da_dv: np.ndarray
    da_da: np.ndarray
    dac_dq: np.ndarray
    dac_dv: np.ndarray
    dac_da: np.ndarray


class CenterOfMassDerivatives(NamedTuple):
    """``(∂c/∂q, ∂ċ/∂q)`` `(..., 3, nv)` of the centre of mass and its velocity in world coordinates
    (:func:`featherdyn.center_of_mass_derivatives`); ``∂c/∂q = ∂ċ/∂q̇`` is the centre of mass's Jacobian."""

    dc_dq: np.ndarray
    dcdot_dq: np.ndarray


class CentroidalDynamicsDerivatives(NamedTuple):
    """``(∂h_G/∂q, ∂ḣ_G/∂q, ∂ḣ_G/∂q̇, ∂ḣ_G/∂q̈)`` `(..., 6, nv)` of the centroidal momentum ``h_G = [k_G; p]``
    (about the centre of mass, world axes: :func:`featherdyn.centroidal_momentum`) and of its rate ``ḣ_G``
    (:func:`featherdyn.centroidal_dynamics_derivatives`); ``∂ḣ_G/∂q̈ = ∂h_G/∂q̇ = A_G``."""

    dh_dq: np.ndarray
    dhdot_dq: np.ndarray
    dhdot_dv: np.ndarray
    dhdot_da: np.ndarray
