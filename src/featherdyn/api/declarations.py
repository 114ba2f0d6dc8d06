"""The declared public algorithms (docs/architecture.md, "Adding an algorithm").

Each :class:`~featherdyn.api.declared.Declaration` here, with its kernel in
``core/cpp/declarations.hpp`` and its reference in ``featherdyn/algorithms``, is a whole
public function: ``fd.<name>`` (one state, any batch shape, ``out=``, Dask arrays,
``backend=``) and ``fd.compile(model).<name>``, made by :mod:`featherdyn.api.declared`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol, overload

import numpy as np
from numpy.typing import ArrayLike

from .. import configuration as _configuration
from ..algorithms import aba as _aba
from ..algorithms import centroidal as _centroidal
from ..algorithms import crba as _crba
from ..algorithms import derivatives as _ref
from ..algorithms import energy as _energy
from ..algorithms import jacobians as _jac
from ..algorithms import kinematics as _kin
from ..algorithms import kinematics_derivatives as _kd
from ..algorithms import rnea as _rnea
from ..algorithms import second_order as _second
from ..algorithms import vjp as _vjp
from ..model import Model
from ..results import (
    AbaSecondDerivatives,
    CenterOfMass,
    CenterOfMassDerivatives,
    CentroidalDynamicsDerivatives,
    Kinematics,
    KinematicsDerivatives,
    RneaSecondDerivatives,
)
from ..spatial import PluckerTransform, SpatialForce, SpatialMotion
from .declared import Declaration, Record, public_function

__all__ = ["rnea", "nonlinear_effects", "generalized_gravity", "crba", "aba", "frame_jacobian", "rnea_derivatives",
           "aba_derivatives", "rnea_second_derivatives", "aba_second_derivatives", "mass_matrix_inverse",
           "joint_torque_regressor", "frame_velocity_derivatives",
           "frame_acceleration_derivatives", "joint_jacobians", "frame_jacobian_time_variation", "kinetic_energy",
           "kinetic_energy_derivatives", "rnea_vjp", "aba_vjp", "crba_vjp",
           "potential_energy", "centroidal_momentum_matrix", "generalized_gravity_derivatives",
           "static_torque_derivatives", "forward_kinematics", "frame_placement", "center_of_mass",
           "centroidal_momentum", "kinematics_derivatives", "center_of_mass_derivatives",
           "centroidal_dynamics_derivatives", "frame_velocity", "frame_acceleration", "frame_classical_acceleration",
           "integrate", "difference", "integrate_derivatives", "difference_derivatives"]  # (and ``placements``: fd.compile(model).fk only)


class _CenterOfMassFunction(Protocol):
    """``fd.center_of_mass``'s type: the array without ``v``, a :class:`CenterOfMass` with it."""

    @overload
    def __call__(self, model: Model, q: ArrayLike, v: None = None, *, out: Any = None,
                 backend: str | None = None) -> np.ndarray: ...
    @overload
    def __call__(self, model: Model, q: ArrayLike, v: ArrayLike, *, out: Any = None,
                 backend: str | None = None) -> CenterOfMass: ...


#: a frame's motion as the :class:`SpatialMotion` the public functions return (no tags)
_MOTION = Record(SpatialMotion, (("vector", "motion"), ("frame", None), ("body", None), ("relative_to", None)))


def _center_of_mass(c: np.ndarray, cd: np.ndarray | None) -> np.ndarray | CenterOfMass:
    """``c`` alone, or with its velocity the :class:`CenterOfMass` ``(c, ċ)``."""
    return c if cd is None else CenterOfMass(c, cd)


_KINEMATICS_DERIVATIVES_DOC = """The derivatives of a frame's velocity, spatial and classical accelerations, or of a point's.

        Args:
            model: the tree.
            q: `(..., nq)`; v, a: `(..., nv)`.
            frame: the frame's name or index.
            reference: ``fd.LOCAL`` (the default), ``fd.WORLD`` or ``fd.LOCAL_WORLD_ALIGNED`` (or their names).
            point: optional `(..., 3)`, a point in the frame's coordinates: the derivatives are those of a frame
                at that point with the frame's orientation (in ``WORLD`` the same as the frame's).
            out: optional tuple of eight `(..., 6, nv)` float64 arrays to write into, in the record's order; the
                record returned holds them.
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        Returns:
            :class:`~featherdyn.KinematicsDerivatives` ``(dv_dq, dv_dv, da_dq, da_dv, da_da, dac_dq, dac_dv,
            dac_da)``, each `(..., 6, nv)`, rows ``[ω; v]``, ∂/∂q along the tangent of ``fd.integrate``, of::

                v_f = J q̇,    a_f = J q̈ + J̇ q̇  (spatial, no gravity),    a_f^c = [ω̇; a_lin + ω × v_lin]

            (``fd.frame_velocity``, ``fd.frame_acceleration``, ``fd.frame_classical_acceleration`` in
            ``reference``); ``dv_dv = da_da = dac_da = J``. The linear rows of ``dv_*`` and ``dac_*`` at a point
            are Pinocchio's ``getPointVelocityDerivatives`` and ``getPointClassicAccelerationDerivatives``. In
            ``LOCAL_WORLD_ALIGNED`` these are the derivatives of the functions themselves (the frame's axes and
            origin move with q; see ``docs/derivatives.md`` for Pinocchio's frame functions there).
        """

DECLARATIONS: dict[str, Declaration] = {d.name: d for d in [
    Declaration(
        name="rnea",
        derivative="rnea_derivatives",
        inputs=("q", "v", "a", "f_ext"),
        optional=("f_ext",),
        options=("gravity",),
        outputs=("tau",),
        reference=_rnea.rnea,
        doc="""Joint forces ``τ`` `(..., nv)` that produce accelerations ``a`` in state ``(q, v)`` (RNEA).

        Args:
            model: the tree (gravity from ``model.gravity``).
            q: `(..., nq)`; v, a: `(..., nv)`.
            f_ext: optional `(..., nb, 6)` external spatial forces ``[n; f]`` on each
                body, in body coordinates (Pinocchio's ``fext`` in LOCAL frames).
            gravity: set ``False`` to leave gravity out.
            out: optional `(..., nv)` float64 array to write into.
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        ::

            τ = M(q) q̈ + C(q, q̇) q̇ + g(q) − Σ_i J_iᵀ f_i^ext
        """,
    ),
    Declaration(
        name="nonlinear_effects",
        method="nle",
        inputs=("q", "v"),
        outputs=("h",),
        reference=_rnea.nonlinear_effects,
        doc="""Coriolis, centrifugal and gravity forces `(..., nv)`.

        Args:
            q: `(..., nq)`; v: `(..., nv)`.
            out: optional `(..., nv)` float64 array to write into.

        ::

            h(q, q̇) = C(q, q̇) q̇ + g(q) = RNEA(q, q̇, 0)
        """,
    ),
    Declaration(
        name="generalized_gravity",
        derivative="generalized_gravity_derivatives",
        method="gravity",
        inputs=("q",),
        outputs=("g",),
        reference=_rnea.generalized_gravity,
        doc="""Gravity forces `(..., nv)`.

        Args:
            q: `(..., nq)`.
            out: optional `(..., nv)` float64 array to write into.

        ::

            g(q) = RNEA(q, 0, 0)
        """,
    ),
    Declaration(
        name="crba",
        inputs=("q",),
        outputs=("M",),
        reference=_crba.crba,
        doc="""The joint-space mass matrix ``M(q)`` `(..., nv, nv)`, full and symmetric (CRBA).

        Args:
            q: `(..., nq)`.
            out: optional `(..., nv, nv)` float64 array to write into.

        ::

            T = ½ q̇ᵀ M(q) q̇,    M_ij = S_iᵀ ⁱX_j^* I^C_j S_j   (j in the subtree of i)
        """,
    ),
    Declaration(
        name="aba",
        derivative="aba_derivatives",
        inputs=("q", "v", "tau", "f_ext"),
        optional=("f_ext",),
        options=("gravity",),
        outputs=("qdd",),
        reference=_aba.aba,
        doc="""Joint accelerations ``q̈`` `(..., nv)` produced by joint forces ``τ`` in state ``(q, v)`` (ABA).

        Args:
            model: the tree.
            q: `(..., nq)`; v, tau: `(..., nv)`.
            f_ext: optional `(..., nb, 6)` body-frame external forces ``[n; f]``.
            gravity: set ``False`` to leave gravity out.
            out: optional `(..., nv)` float64 array to write into.
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        ::

            q̈ = M(q)⁻¹ (τ − C(q, q̇) q̇ − g(q) + Σ_i J_iᵀ f_i^ext)

        Raises:
            SingularMassMatrixError: naming the joint, when ``M(q)`` is singular.
        """,
    ),
    Declaration(
        name="frame_jacobian",
        inputs=("q",),
        options=("frame", "reference"),
        outputs=("J",),
        reference=_jac.frame_jacobian_at,
        doc="""The geometric Jacobian of a frame, `(..., 6, nv)`, rows ``[ω; v]`` (``getFrameJacobian``).

        Args:
            q: `(..., nq)`.
            frame: the frame's name or index.
            reference: ``fd.LOCAL`` (the default), ``fd.WORLD`` or ``fd.LOCAL_WORLD_ALIGNED`` (or their names).
            out: optional `(..., 6, nv)` float64 array to write into.

        ::

            frame_velocity(model, q, v, frame, reference) = J v
        """,
    ),
    Declaration(
        name="joint_jacobians",
        inputs=("q",),
        outputs=("J",),
        reference=_jac.joint_jacobians_at,
        doc="""All joint columns in the world frame, `(..., 6, nv)` (Pinocchio's ``computeJointJacobians`` → ``data.J``).

        Args:
            q: `(..., nq)`.
            out: optional `(..., 6, nv)` float64 array to write into.

        ::

            J[:, k] = ⁰X_k S_k      (the Jacobian of body b keeps the columns of its support)
        """,
    ),
    Declaration(
        name="frame_jacobian_time_variation",
        inputs=("q", "v"),
        options=("frame", "reference"),
        outputs=("dJ",),
        reference=_jac.frame_jacobian_time_variation_at,
        doc="""``J̇ = dJ/dt`` of :func:`frame_jacobian` along ``q̇ = v``, `(..., 6, nv)` (``getFrameJacobianTimeVariation``).

        Args:
            q: `(..., nq)`; v: `(..., nv)`; frame: name or index; reference: ``fd.LOCAL`` (default) & co.
            out: optional `(..., 6, nv)` float64 array to write into.

        ::

            WORLD:   ⁰J̇[:, k] = ⁰v_k × ⁰J[:, k]
            LOCAL:   ᶠJ̇ = ᶠX_0 ⁰J̇ − ᶠv × ᶠJ
            LWA:     J̇ = blkdiag([ω]×, [ω]×) J_LWA + blkdiag(R, R) ᶠJ̇      (ω, R of the frame in the world)

        and the classical acceleration identity ``a_classical = J q̈ + J̇ q̇`` in LOCAL_WORLD_ALIGNED.
        """,
    ),
    Declaration(
        name="kinetic_energy",
        derivative="kinetic_energy_derivatives",
        inputs=("q", "v"),
        outputs=("T",),
        reference=_energy.kinetic_energy_at,
        doc="""Kinetic energy `(...)`.

        Args:
            q: `(..., nq)`; v: `(..., nv)`.
            out: optional `(...)` float64 array to write into.

        ::

            T = Σ_i ½ v_iᵀ I_i v_i + ½ Σ_k armature_k q̇_k² = ½ q̇ᵀ M(q) q̇
        """,
    ),
    Declaration(
        name="kinetic_energy_derivatives",
        inputs=("q", "v"),
        outputs=("dT_dq", "dT_dv"),
        reference=_energy.kinetic_energy_derivatives_at,
        doc="""``(∂T/∂q, ∂T/∂q̇)`` `(..., nv)` each: the kinetic energy's gradient, in O(nb).

        Args:
            q: `(..., nq)`; v: `(..., nv)`.
            out: optional tuple of two `(..., nv)` float64 arrays to write into.

        ∂/∂q along the tangent of ``fd.integrate``. With body ``i``'s velocity ``v_i``, its parent's ``v_λ(i)``
        and the momentum of its subtree ``h^C_i`` (all in body ``i``'s coordinates), for each column ``k`` of
        joint ``i``::

            ∂T/∂q_k = −S_kᵀ (v_λ(i) ×* h^C_i) = ½ q̇ᵀ (∂M/∂q_k) q̇,     ∂T/∂q̇ = M(q) q̇

        (moving ``q_k`` turns the subtree and its momentum rigidly: only the ancestors' joints stay behind).
        The gradient of ``⟨W, M(q)⟩`` for any ``W`` follows by polarisation, ``xᵀ M y = T(x + y) − T(x − y)``:
        ``featherdyn.torch``'s backward of ``crba`` and ``mass_matrix_inverse`` (docs/frameworks.md).
        """,
    ),
    Declaration(
        name="potential_energy",
        inputs=("q",),
        outputs=("U",),
        reference=_energy.potential_energy_at,
        doc="""Gravitational potential energy `(...)` (zero at the world origin).

        Args:
            q: `(..., nq)`.
            out: optional `(...)` float64 array to write into.

        ::

            U = −Σ_i m_i gᵀ ⁰c_i
        """,
    ),
    Declaration(
        name="centroidal_momentum_matrix",
        inputs=("q",),
        outputs=("A",),
        reference=_centroidal.centroidal_momentum_matrix_at,
        doc="""``A_G(q)`` `(..., 6, nv)` with ``h_G = A_G q̇`` (rows ``[k_G; p]``, world axes, about the CoM; ``ccrba``).

        Args:
            q: `(..., nq)`.
            out: optional `(..., 6, nv)` float64 array to write into.

        ::

            A_O[:, k] = ⁰I^C_k ⁰X_k S_k,    A_G = [[1, −c×], [0, 1]] A_O

        Raises:
            ModelError: the tree has no mass (the centre of mass is undefined).
        """,
    ),
    Declaration(
        name="rnea_derivatives",
        inputs=("q", "v", "a", "f_ext"),
        optional=("f_ext",),
        options=("gravity",),
        outputs=("dtau_dq", "dtau_dv", "M"),
        reference=_ref.rnea_derivatives,
        doc="""``(∂τ/∂q, ∂τ/∂q̇, ∂τ/∂q̈)``, each `(..., nv, nv)`, of ``τ = RNEA(q, q̇, q̈, f_ext)``.

        Args:
            q: `(..., nq)`; v, a: `(..., nv)`; f_ext: optional `(..., nb, 6)` body-frame forces ``[n; f]``.
            gravity: set ``False`` to leave gravity out.
            out: optional tuple of three `(..., nv, nv)` float64 arrays to write into.

        ∂/∂q along the tangent of ``fd.integrate`` (``q ⊕ δ``, δ in ``v``'s layout); the analytical algorithm
        (Carpentier & Mansard, RSS 2018)::

            ∂τ/∂q[:, j] = d/dε RNEA(q ⊕ ε e_j, q̇, q̈) |_{ε=0},    ∂τ/∂q̈ = M(q)
        """,
    ),
    Declaration(
        name="aba_derivatives",
        inputs=("q", "v", "tau", "f_ext"),
        optional=("f_ext",),
        options=("gravity",),
        outputs=("ddq_dq", "ddq_dv", "Minv"),
        reference=_ref.aba_derivatives,
        doc="""``(∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ)``, each `(..., nv, nv)`, of ``q̈ = ABA(q, q̇, τ, f_ext)``.

        Args:
            q: `(..., nq)`; v, tau: `(..., nv)`; f_ext: optional `(..., nb, 6)` body-frame forces.
            gravity: set ``False`` to leave gravity out.
            out: optional tuple of three `(..., nv, nv)` float64 arrays to write into.

        ::

            ∂q̈/∂q = −M⁻¹ ∂τ/∂q,   ∂q̈/∂q̇ = −M⁻¹ ∂τ/∂q̇   (RNEA's, at q̈ = ABA(q, q̇, τ)),   ∂q̈/∂τ = M⁻¹

        Raises:
            SingularMassMatrixError: naming the joint, when M(q) is singular.
        """,
    ),
    Declaration(
        name="rnea_vjp",
        inputs=("q", "v", "a", "w", "f_ext"),
        optional=("f_ext",),
        options=("gravity",),
        outputs=("grad_q", "grad_v", "grad_a"),
        reference=_vjp.rnea_vjp,
        doc="""``(wᵀ ∂τ/∂q, wᵀ ∂τ/∂q̇, wᵀ ∂τ/∂q̈)``, each `(..., nv)`: the gradient of ``wᵀ τ``, ``τ = RNEA(q, q̇, q̈,
        f_ext)``, in O(nb) — a reverse-mode step (a vector–Jacobian product) without forming the Jacobians.

        Args:
            q: `(..., nq)`; v, a: `(..., nv)`; w: `(..., nv)`, the cotangent of τ; f_ext: optional `(..., nb, 6)`
                body-frame forces ``[n; f]``.
            gravity: set ``False`` to leave gravity out.
            out: optional tuple of three `(..., nv)` float64 arrays to write into.

        ∂/∂q along the tangent of ``fd.integrate``, as ``fd.rnea_derivatives``; the same numbers as
        ``w @ fd.rnea_derivatives(...)`` at the cost of about two RNEAs (docs/derivatives.md, "Vector–Jacobian
        products")::

            grad_q = wᵀ ∂τ/∂q,   grad_v = wᵀ ∂τ/∂q̇,   grad_a = M(q) w
        """,
    ),
    Declaration(
        name="aba_vjp",
        inputs=("q", "v", "tau", "w", "f_ext"),
        optional=("f_ext",),
        options=("gravity",),
        outputs=("grad_q", "grad_v", "grad_tau"),
        reference=_vjp.aba_vjp,
        doc="""``(wᵀ ∂q̈/∂q, wᵀ ∂q̈/∂q̇, wᵀ ∂q̈/∂τ)``, each `(..., nv)`: the gradient of ``wᵀ q̈``, ``q̈ = ABA(q, q̇, τ,
        f_ext)``, in O(nb), without forming the Jacobians.

        Args:
            q: `(..., nq)`; v, tau: `(..., nv)`; w: `(..., nv)`, the cotangent of q̈; f_ext: optional
                `(..., nb, 6)` body-frame forces.
            gravity: set ``False`` to leave gravity out.
            out: optional tuple of three `(..., nv)` float64 arrays to write into.

        With ``λ = M⁻¹ w`` and RNEA's vector–Jacobian product (``fd.rnea_vjp``) at ``q̈ = ABA(q, q̇, τ)``::

            grad_q = −λᵀ ∂τ/∂q,   grad_v = −λᵀ ∂τ/∂q̇,   grad_tau = λ = M(q)⁻¹ w

        Raises:
            SingularMassMatrixError: naming the joint, when M(q) is singular.
        """,
    ),
    Declaration(
        name="crba_vjp",
        inputs=("q", "W"),
        outputs=("grad_q",),
        reference=_vjp.crba_vjp,
        doc="""``∂⟨W, M(q)⟩/∂q`` `(..., nv)`: the gradient of ``Σ_ij W_ij M_ij(q)`` — the mass matrix's vector–Jacobian
        product, without forming ``∂M/∂q`` (nv³ numbers a state), in the order of CRBA's own cost.

        Args:
            q: `(..., nq)`; W: `(..., nv, nv)`, the cotangent of M.
            out: optional `(..., nv)` float64 array to write into.

        ∂/∂q along the tangent of ``fd.integrate``; with ``W̃ = W + Wᵀ``, ``u_{i,b} = Σ_{j ≼ b} W̃_ij S_j`` and
        ``F_{i,c} = Σ_{b ∈ subtree(c)} I_b u_{i,b}``, for a column ``k`` of joint ``c`` (docs/derivatives.md)::

            ∂⟨W, M⟩/∂q_k = Σ_ij W_ij ∂M_ij/∂q_k = −S_kᵀ Σ_{i ≺ c} S_i ×* F_{i,c}
        """,
    ),
    Declaration(
        name="mass_matrix_inverse",
        inputs=("q",),
        outputs=("Minv",),
        reference=_ref.mass_matrix_inverse,
        doc="""``M(q)⁻¹`` `(..., nv, nv)`, never by inverting a dense M.

        Args:
            q: `(..., nq)`.
            out: optional `(..., nv, nv)` float64 array to write into.

        ::

            M⁻¹ e_j = ABA(q, 0, e_j) without gravity                   (the reference)
            M = Lᵀ L (tree-sparse),  M⁻¹ = Zᵀ Z,  Z = L⁻ᵀ               (the core: O(nv · depth) per row)

        Raises:
            SingularMassMatrixError: naming the joint, when M(q) is singular.
        """,
    ),
    Declaration(
        name="joint_torque_regressor",
        inputs=("q", "v", "a"),
        outputs=("Y",),
        reference=_ref.joint_torque_regressor,
        doc="""``Y`` `(..., nv, 10 nb)` with ``RNEA(q, q̇, q̈) = Y @ fd.dynamic_parameters(model)`` (gravity included).

        Args:
            q: `(..., nq)`; v, a: `(..., nv)`.
            out: optional `(..., nv, 10 nb)` float64 array to write into.

        ::

            Y[joint j, 10 i + k] = S_jᵀ ʲX_i* (I(e_k) a_i + v_i ×* I(e_k) v_i)    (j supporting body i)
        """,
    ),
    Declaration(
        name="frame_velocity_derivatives",
        inputs=("q", "v"),
        options=("frame", "reference"),
        outputs=("dv_dq", "dv_dv"),
        reference=_ref.frame_velocity_derivatives,
        doc="""``(∂v_f/∂q, ∂v_f/∂q̇)`` `(..., 6, nv)` of ``fd.frame_velocity(model, q, v, frame, reference)``.

        Args:
            q: `(..., nq)`; v: `(..., nv)`; frame: name or index; reference: ``fd.LOCAL`` (default) & co.
            out: optional tuple of two `(..., 6, nv)` float64 arrays to write into.

        ::

            v_f = J(q) q̇,   ∂v_f/∂q̇ = J

        In ``LOCAL_WORLD_ALIGNED`` this is the derivative of that function itself, whose reference
        point (the frame's origin) moves with q; Pinocchio's ``getFrameVelocityDerivatives`` keeps the
        point fixed: its linear rows lack ``ω × J_v[:, j]``. LOCAL and WORLD are the same in both.
        """,
    ),
    Declaration(
        name="frame_acceleration_derivatives",
        inputs=("q", "v", "a"),
        options=("frame", "reference"),
        outputs=("da_dq", "da_dv", "da_da"),
        reference=_ref.frame_acceleration_derivatives,
        doc="""``(∂a_f/∂q, ∂a_f/∂q̇, ∂a_f/∂q̈)`` `(..., 6, nv)` of ``fd.frame_acceleration`` (spatial, no gravity).

        Args:
            q: `(..., nq)`; v, a: `(..., nv)`; frame: name or index; reference: ``fd.LOCAL`` (default) & co.
            out: optional tuple of three `(..., 6, nv)` float64 arrays to write into.

        ::

            a_f = J q̈ + J̇ q̇,   ∂a_f/∂q̈ = J

        (``LOCAL_WORLD_ALIGNED``: as :func:`frame_velocity_derivatives`; Pinocchio's linear rows lack
        ``ω̇ × J_v[:, j]``.)
        """,
    ),
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
    Declaration(
        name="forward_kinematics",
        inputs=("q", "v", "a"),
        optional=("v", "a"),
        needs=(("a", "v"),),
        outputs=("H", "Hp", "vel", "acc"),
        reference=_kin.forward_kinematics_at,
        result=Record(Kinematics, (("model", "model"), ("_H", "H"), ("_Hp", "Hp"), ("_vel", "vel"), ("_acc", "acc"))),
        doc="""World placements, body velocities and spatial accelerations of every body.

        Args:
            model: the tree.
            q: `(..., nq)` configuration.
            v: `(..., nv)` joint velocity (optional).
            a: `(..., nv)` joint acceleration (optional; needs ``v``).
            out: optional tuple of float64 arrays to write into, one for each output formed: ``H``, ``Hp``
                `(..., nb, 4, 4)`, then ``vel`` with ``v``, ``acc`` with ``a`` `(..., nb, 6)`; the record returned
                holds read-only views of them.
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        Returns:
            :class:`~featherdyn.results.Kinematics`, gravity *not* included in the accelerations::

                ᵖM_i = ᵖM_J · M_J(q_i),   ⁰M_i = ⁰M_λ(i) · ᵖM_i
                v_i = X_up[i] v_λ(i) + S_i q̇_i,   a_i = X_up[i] a_λ(i) + S_i q̈_i + v_i × S_i q̇_i
        """,
    ),
    Declaration(
        name="placements",
        method="fk",
        inputs=("q",),
        outputs=("H",),
        reference=_kin.placements_at,
        doc="""World placements of the bodies as homogeneous matrices `(..., nb, 4, 4)` (``fd.compile(model).fk``).

        Args:
            q: `(..., nq)`.
            out: optional `(..., nb, 4, 4)` float64 array to write into.

        ::

            ⁰M_i = ⁰M_λ(i) · Xtree_i · M_J(q_i)
        """,
    ),
    Declaration(
        name="frame_velocity",
        inputs=("q", "v"),
        options=("frame", "reference"),
        outputs=("motion",),
        reference=_kin.frame_velocity_at,
        derivative="frame_velocity_derivatives",
        result=_MOTION,
        doc="""The spatial velocity of a frame `(..., 6)` in ``reference`` (Pinocchio's ``getFrameVelocity``).

        Args:
            q: `(..., nq)`; v: `(..., nv)`.
            frame: the frame's name or index.
            reference: ``fd.LOCAL`` (default), ``fd.WORLD`` or ``fd.LOCAL_WORLD_ALIGNED``.
            out: optional `(..., 6)` float64 array to write into; the motion returned holds a read-only view.
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        Returns:
            a :class:`~featherdyn.SpatialMotion` ``[ω; v]``::

                LOCAL:  ᶠv = ᶠX_b v_b      WORLD: ⁰X_f ᶠv      LOCAL_WORLD_ALIGNED: [R ω; R v]
        """,
    ),
    Declaration(
        name="frame_acceleration",
        inputs=("q", "v", "a"),
        options=("frame", "reference"),
        outputs=("motion",),
        reference=_kin.frame_acceleration_at,
        derivative="frame_acceleration_derivatives",
        result=_MOTION,
        doc="""The *spatial* acceleration of a frame `(..., 6)` in ``reference`` (``getFrameAcceleration``).

        Args:
            q: `(..., nq)`; v, a: `(..., nv)`.
            frame: the frame's name or index.
            reference: ``fd.LOCAL`` (default), ``fd.WORLD`` or ``fd.LOCAL_WORLD_ALIGNED``.
            out: optional `(..., 6)` float64 array to write into; the motion returned holds a read-only view.
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        Returns:
            a :class:`~featherdyn.SpatialMotion`: the time derivative of the spatial velocity, without gravity,
            re-expressed exactly like :func:`frame_velocity`. Its linear part is **not** the acceleration of the
            frame origin: see :func:`frame_classical_acceleration`::

                ᶠa = ᶠX_b a_b,    a_i = ⁱX_λ a_λ + S_i q̈_i + v_i × S_i q̇_i
        """,
    ),
    Declaration(
        name="frame_classical_acceleration",
        inputs=("q", "v", "a"),
        options=("frame", "reference"),
        outputs=("motion",),
        reference=_kin.frame_classical_acceleration_at,
        result=_MOTION,
        doc="""The classical acceleration of a frame `(..., 6)` (``getFrameClassicalAcceleration``).

        Args:
            q: `(..., nq)`; v, a: `(..., nv)`.
            frame: the frame's name or index.
            reference: ``fd.LOCAL`` (default), ``fd.WORLD`` or ``fd.LOCAL_WORLD_ALIGNED``.
            out: optional `(..., 6)` float64 array to write into; the motion returned holds a
                read-only view.
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        Returns:
            a :class:`~featherdyn.SpatialMotion`: angular part ``ω̇``, linear part the classical acceleration
            (chapter §7.2)::

                a_classical = a_spatial + [0; ω × v]      (ω, v of the frame, in the same reference)

            In ``LOCAL`` and ``LOCAL_WORLD_ALIGNED`` the linear part is the acceleration of the frame origin (in
            frame or world axes). In ``WORLD`` it is that of the body point passing through the world origin
            (Pinocchio's convention).
        """,
    ),
    Declaration(
        name="frame_placement",
        inputs=("q",),
        options=("frame",),
        outputs=("rotation", "translation"),
        reference=_kin.frame_placement_at,
        result=Record(PluckerTransform, (("rotation", "rotation"), ("translation", "translation"), ("source", None),
                                         ("target", None))),
        doc="""The world placement ``⁰M_f`` of a frame (name or index) as a :class:`PluckerTransform`, batch shape `(...)`.

        Args:
            q: `(..., nq)`.
            frame: the frame's name or index.
            out: optional tuple of float64 arrays ``(rotation (..., 3, 3), translation (..., 3))`` to write into;
                the transform returned holds read-only views of them.
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        ::

            ⁰M_f = ⁰M_body(f) · placement_f
        """,
    ),
    Declaration(
        name="center_of_mass",
        inputs=("q", "v"),
        optional=("v",),
        outputs=("position", "velocity"),
        reference=_energy.center_of_mass_at,
        result=_center_of_mass,
        doc="""The centre of mass of the whole tree in world coordinates.

        Args:
            q: `(..., nq)`; v: `(..., nv)` (optional).
            out: optional `(..., 3)` float64 array for ``c`` to write into, or with ``v`` a tuple of two
                (``c``, ``ċ``).
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        Returns:
            ``c`` `(..., 3)` without ``v``; with ``v`` a :class:`~featherdyn.CenterOfMass`
            ``(position, velocity)``::

                c = Σ m_i ⁰c_i / m,    ċ = Σ m_i ⁰R_i (v_i + ω_i × c_i) / m

        Raises:
            ModelError: the tree has no mass (the centre of mass is undefined).
        """,
    ),
    Declaration(
        name="centroidal_momentum",
        inputs=("q", "v"),
        outputs=("h",),
        reference=_centroidal.centroidal_momentum_at,
        result=Record(SpatialForce, (("vector", "h"), ("frame", None))),
        doc="""The centroidal momentum ``h_G = [k_G; p]`` `(..., 6)` as a :class:`SpatialForce`.

        Args:
            q: `(..., nq)`; v: `(..., nv)`.
            out: optional `(..., 6)` float64 array to write into; the force returned holds a read-only view.
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        ::

            h_G = A_G(q) q̇     (p = m ċ)
        """,
    ),
    Declaration(
        name="rnea_second_derivatives",
        inputs=("q", "v", "a", "f_ext"),
        optional=("f_ext",),
        options=("gravity",),
        outputs=("d2tau_dq2", "d2tau_dv2", "d2tau_dqdv", "dM_dq"),
        reference=_second.rnea_second_derivatives,
        result=RneaSecondDerivatives,
        doc="""The second derivatives of ``τ = RNEA(q, q̇, q̈, f_ext)``, each `(..., nv, nv, nv)`.

        Args:
            q: `(..., nq)`; v, a: `(..., nv)`; f_ext: optional `(..., nb, 6)` body-frame forces ``[n; f]``.
            gravity: set ``False`` to leave gravity out.
            out: optional tuple of four `(..., nv, nv, nv)` float64 arrays to write into (an earlier
                result is one); the record returned holds them.
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        Returns:
            :class:`~featherdyn.RneaSecondDerivatives` ``(d2tau_dq2, d2tau_dv2, d2tau_dqdv, dM_dq)``, ``[i, j, k]``
            the derivative of output i along input j, then along input k: the analytical first order
            (:func:`featherdyn.rnea_derivatives`) differentiated exactly (Singh, Russell & Wensing's analytical
            recursion), with ``q`` along ``fd.integrate``'s tangent ``q ⊕ ε e_k``::

                d2tau_dq2[i, j, k] = d/dε (∂τ_i/∂q_j)(q ⊕ ε e_k),   d2tau_dv2[i, j, k] = ∂²τ_i/∂q̇_j∂q̇_k,
                d2tau_dqdv[i, j, k] = ∂²τ_i/∂q_j∂q̇_k,              dM_dq[i, j, k] = ∂M_ij/∂q_k = ∂²τ_i/∂q_k∂q̈_j

            (∂²τ/∂q̈² = 0). ``d2tau_dq2[i]`` is symmetric in ``j, k`` for revolute and prismatic joints; on a
            free-flyer or spherical joint it is not: the difference is the first order along the tangent
            fields' Lie bracket (docs/derivatives.md).
        """,
    ),
    Declaration(
        name="aba_second_derivatives",
        inputs=("q", "v", "tau", "f_ext"),
        optional=("f_ext",),
        options=("gravity",),
        outputs=("d2ddq_dq2", "d2ddq_dv2", "d2ddq_dqdv", "d2ddq_dqdtau"),
        reference=_second.aba_second_derivatives,
        result=AbaSecondDerivatives,
        doc="""The second derivatives of ``q̈ = ABA(q, q̇, τ, f_ext)``, each `(..., nv, nv, nv)`.

        Args:
            q: `(..., nq)`; v, tau: `(..., nv)`; f_ext: optional `(..., nb, 6)` body-frame forces.
            gravity: set ``False`` to leave gravity out.
            out: optional tuple of four `(..., nv, nv, nv)` float64 arrays to write into (an earlier
                result is one); the record returned holds them.
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        Returns:
            :class:`~featherdyn.AbaSecondDerivatives` ``(d2ddq_dq2, d2ddq_dv2, d2ddq_dqdv, d2ddq_dqdtau)``,
            ``[i, j, k] = ∂²q̈_i/∂x_j∂y_k`` (q along ``fd.integrate``'s tangent, as
            :func:`featherdyn.rnea_second_derivatives`), from RNEA's at ``q̈`` (``RNEA(q, q̇, ABA(q, q̇, τ)) = τ``
            differentiated twice; never by differences)::

                d2ddq_dq2[:, j, k] = −M⁻¹ (∂²τ/∂q_j∂q_k + ∂M/∂q_j ∂q̈/∂q_k + ∂M/∂q_k ∂q̈/∂q_j)
                d2ddq_dv2 = −M⁻¹ ∂²τ/∂q̇²,   d2ddq_dqdv[:, j, k] = −M⁻¹ (∂²τ/∂q_j∂q̇_k + ∂M/∂q_j ∂q̈/∂q̇_k)
                d2ddq_dqdtau[:, j, k] = −(M⁻¹ ∂M/∂q_j M⁻¹)[:, k]

        Raises:
            SingularMassMatrixError: naming the joint, when M(q) is singular.
        """,
    ),
    # the configuration space (featherdyn/configuration.py: the reference and the docstrings; core/cpp/configuration.hpp)
    Declaration(
        name="integrate",
        derivative="integrate_derivatives",
        inputs=("q", "v"),
        outputs=("q_next",),
        reference=_configuration.integrate,
        doc=_configuration.integrate.__doc__ or "",
    ),
    Declaration(
        name="difference",
        derivative="difference_derivatives",
        inputs=("q0", "q1"),
        outputs=("v",),
        reference=_configuration.difference,
        doc=_configuration.difference.__doc__ or "",
    ),
    Declaration(
        name="integrate_derivatives",
        inputs=("q", "v"),
        outputs=("J_q", "J_v"),
        reference=_configuration.integrate_derivatives,
        doc=_configuration.integrate_derivatives.__doc__ or "",
    ),
    Declaration(
        name="difference_derivatives",
        inputs=("q0", "q1"),
        outputs=("J_0", "J_1"),
        reference=_configuration.difference_derivatives,
        doc=_configuration.difference_derivatives.__doc__ or "",
    ),
    Declaration(
        name="kinematics_derivatives",
        inputs=("q", "v", "a", "point"),
        optional=("point",),
        options=("frame", "reference"),
        outputs=KinematicsDerivatives._fields,
        reference=_kd.kinematics_derivatives,
        result=KinematicsDerivatives,
        doc=_KINEMATICS_DERIVATIVES_DOC,
    ),
    Declaration(
        name="center_of_mass_derivatives",
        inputs=("q", "v"),
        outputs=("dc_dq", "dcdot_dq"),
        reference=_kd.center_of_mass_derivatives,
        result=CenterOfMassDerivatives,
        doc="""``(∂c/∂q, ∂ċ/∂q)`` `(..., 3, nv)` of the centre of mass and its velocity, world coordinates.

        Args:
            q: `(..., nq)`; v: `(..., nv)`.
            out: optional tuple of two `(..., 3, nv)` float64 arrays to write into (an earlier result
                is one); the record returned holds them.
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        Returns:
            :class:`~featherdyn.CenterOfMassDerivatives` ``(dc_dq, dcdot_dq)`` (a pair), ∂/∂q along the tangent
            of ``fd.integrate``; ``dc_dq`` is the centre of mass's Jacobian (Pinocchio's ``jacobianCenterOfMass``)
            and ``∂ċ/∂q̇``::

                c = Σ m_i ⁰c_i / m,    ċ = J_c(q) q̇,    ∂c/∂q_j = lin(⁰I^C_k s_j) / m,
                ∂ċ/∂q_j = lin(s_j ×* h^C_k − ⁰I^C_k (s_j × v_λ(k))) / m      (s_j = ⁰S_j, joint k)

        Raises:
            ModelError: the tree has no mass (the centre of mass is undefined).
        """,
    ),
    Declaration(
        name="centroidal_dynamics_derivatives",
        inputs=("q", "v", "a"),
        outputs=("dh_dq", "dhdot_dq", "dhdot_dv", "dhdot_da"),
        reference=_kd.centroidal_dynamics_derivatives,
        result=CentroidalDynamicsDerivatives,
        doc="""The derivatives of the centroidal momentum and of its rate, each `(..., 6, nv)`.

        Args:
            q: `(..., nq)`; v, a: `(..., nv)`.
            out: optional tuple of four `(..., 6, nv)` float64 arrays to write into (an earlier
                result is one); the record returned holds them.
            backend: ``None`` (compiled for float64), ``"reference"`` or ``"compiled"``.

        Returns:
            :class:`~featherdyn.CentroidalDynamicsDerivatives` ``(dh_dq, dhdot_dq, dhdot_dv, dhdot_da)``, rows
            ``[k_G; p]`` about the centre of mass in world axes (``fd.centroidal_momentum``), ∂/∂q along the
            tangent of ``fd.integrate``::

                h_G = A_G(q) q̇,    ḣ_G = A_G q̈ + Ȧ_G q̇ = Σ_i ⁰X_i* (I_i a_i + v_i ×* I_i v_i) about c
                ∂ḣ_G/∂q̈ = ∂h_G/∂q̇ = A_G

            (Pinocchio's ``computeCentroidalDynamicsDerivatives``, its rows ``[p; k]``.)

        Raises:
            ModelError: the tree has no mass (the centre of mass is undefined).
        """,
    ),
]}

# the public functions, typed by their results (the arguments are checked at the call: api/declared.py)
rnea: Callable[..., np.ndarray] = public_function(DECLARATIONS["rnea"])
nonlinear_effects: Callable[..., np.ndarray] = public_function(DECLARATIONS["nonlinear_effects"])
generalized_gravity: Callable[..., np.ndarray] = public_function(DECLARATIONS["generalized_gravity"])
crba: Callable[..., np.ndarray] = public_function(DECLARATIONS["crba"])
aba: Callable[..., np.ndarray] = public_function(DECLARATIONS["aba"])
frame_jacobian: Callable[..., np.ndarray] = public_function(DECLARATIONS["frame_jacobian"])
rnea_derivatives: Callable[..., tuple[np.ndarray, np.ndarray, np.ndarray]] = public_function(DECLARATIONS["rnea_derivatives"])
aba_derivatives: Callable[..., tuple[np.ndarray, np.ndarray, np.ndarray]] = public_function(DECLARATIONS["aba_derivatives"])
rnea_vjp: Callable[..., tuple[np.ndarray, np.ndarray, np.ndarray]] = public_function(DECLARATIONS["rnea_vjp"])
aba_vjp: Callable[..., tuple[np.ndarray, np.ndarray, np.ndarray]] = public_function(DECLARATIONS["aba_vjp"])
crba_vjp: Callable[..., np.ndarray] = public_function(DECLARATIONS["crba_vjp"])
rnea_second_derivatives: Callable[..., RneaSecondDerivatives] = public_function(DECLARATIONS["rnea_second_derivatives"])
aba_second_derivatives: Callable[..., AbaSecondDerivatives] = public_function(DECLARATIONS["aba_second_derivatives"])
mass_matrix_inverse: Callable[..., np.ndarray] = public_function(DECLARATIONS["mass_matrix_inverse"])
joint_torque_regressor: Callable[..., np.ndarray] = public_function(DECLARATIONS["joint_torque_regressor"])
frame_velocity_derivatives: Callable[..., tuple[np.ndarray, np.ndarray]] = public_function(DECLARATIONS["frame_velocity_derivatives"])
frame_acceleration_derivatives: Callable[..., tuple[np.ndarray, np.ndarray, np.ndarray]] = public_function(DECLARATIONS["frame_acceleration_derivatives"])
joint_jacobians: Callable[..., np.ndarray] = public_function(DECLARATIONS["joint_jacobians"])
frame_jacobian_time_variation: Callable[..., np.ndarray] = public_function(DECLARATIONS["frame_jacobian_time_variation"])
kinetic_energy: Callable[..., np.ndarray] = public_function(DECLARATIONS["kinetic_energy"])
kinetic_energy_derivatives: Callable[..., tuple[np.ndarray, np.ndarray]] = public_function(
    DECLARATIONS["kinetic_energy_derivatives"])
potential_energy: Callable[..., np.ndarray] = public_function(DECLARATIONS["potential_energy"])
centroidal_momentum_matrix: Callable[..., np.ndarray] = public_function(DECLARATIONS["centroidal_momentum_matrix"])
generalized_gravity_derivatives: Callable[..., np.ndarray] = public_function(DECLARATIONS["generalized_gravity_derivatives"])
static_torque_derivatives: Callable[..., np.ndarray] = public_function(DECLARATIONS["static_torque_derivatives"])
forward_kinematics: Callable[..., Kinematics] = public_function(DECLARATIONS["forward_kinematics"])
placements: Callable[..., np.ndarray] = public_function(DECLARATIONS["placements"])
frame_placement: Callable[..., PluckerTransform] = public_function(DECLARATIONS["frame_placement"])
center_of_mass: _CenterOfMassFunction = public_function(DECLARATIONS["center_of_mass"])
centroidal_momentum: Callable[..., SpatialForce] = public_function(DECLARATIONS["centroidal_momentum"])
frame_velocity: Callable[..., SpatialMotion] = public_function(DECLARATIONS["frame_velocity"])
frame_acceleration: Callable[..., SpatialMotion] = public_function(DECLARATIONS["frame_acceleration"])
frame_classical_acceleration: Callable[..., SpatialMotion] = public_function(DECLARATIONS["frame_classical_acceleration"])
center_of_mass_derivatives: Callable[..., CenterOfMassDerivatives] = public_function(
    DECLARATIONS["center_of_mass_derivatives"])
centroidal_dynamics_derivatives: Callable[..., CentroidalDynamicsDerivatives] = public_function(
    DECLARATIONS["centroidal_dynamics_derivatives"])
integrate: Callable[..., np.ndarray] = public_function(DECLARATIONS["integrate"])
difference: Callable[..., np.ndarray] = public_function(DECLARATIONS["difference"])
integrate_derivatives: Callable[..., tuple[np.ndarray, np.ndarray]] = public_function(
    DECLARATIONS["integrate_derivatives"])
difference_derivatives: Callable[..., tuple[np.ndarray, np.ndarray]] = public_function(
    DECLARATIONS["difference_derivatives"])
kinematics_derivatives: Callable[..., KinematicsDerivatives] = public_function(DECLARATIONS["kinematics_derivatives"])

