"""SymPy proofs of the chapter's identities, and closed-form dynamics of small robots.

Two kinds of functions live here.

**Proofs** (``prove_*``). Each builds the chapter's objects with featherdyn's
own code (:class:`~featherdyn.PluckerTransform`, :func:`~featherdyn.crm`,
:class:`~featherdyn.SpatialInertia`, ...) on SymPy object arrays, forms the
difference of the two sides of an identity and returns ``True`` when it
reduces to zero *exactly*. No random numeric point is ever used. The
reduction is polynomial and therefore canonical:

* a rotation is parametrised either by a unit quaternion ``(x, y, z, w)``
  (``w²`` is eliminated with ``x² + y² + z² + w² = 1``) or by roll-pitch-yaw
  angles (``sin θ``, ``cos θ`` become symbols ``s``, ``c`` and ``s²`` is
  eliminated with ``s² + c² = 1``);
* floats coming from constant model data (``1.0`` in a motion subspace) are
  replaced by the rationals they print as;
* the result is expanded. ``{s² + c² − 1}`` and ``{|q|² − 1}`` are Gröbner
  bases with coprime leading terms, so the remainder is zero iff the
  expression vanishes on the constraint set.

**Closed-form dynamics.** :func:`mass_matrix`, :func:`coriolis` and
:func:`gravity` run the reference algorithms (:func:`featherdyn.crba`,
:func:`featherdyn.coriolis_matrix`, :func:`featherdyn.generalized_gravity`) on
object arrays of symbols and reduce the result the same way;
:func:`symbolic_model` puts symbolic masses, lengths and gravity into a model.
:func:`lagrangian_two_link` derives ``M``, ``C``, ``g`` of the chapter's
appendix-D arm from its Lagrangian, independently of the spatial algebra, and
:func:`check_two_link` proves the two derivations equal.

SymPy is optional (a test dependency); it is imported on first use and its
absence raises :class:`~featherdyn.errors.MissingDependencyError`.

Sources: chapter §3 (``det X = 1``), §4 (Jacobi, ``crf = −crmᵀ``), §2.3
(power), §5.2 (parallel axis), §5.3 (10 parameters), appendices F and I;
Featherstone, *RBDA* (2008) ch. 2.

The package's modules: :mod:`.reduce` (the exact reduction), :mod:`.dynamics`
(the closed-form dynamics and the 2R arm), :mod:`.proofs` (the ``prove_*``
functions); every public name is here.
"""

from __future__ import annotations

from .dynamics import (
    APPENDIX_D,
    TwoLinkDynamics,
    check_two_link,
    coriolis,
    gravity,
    lagrangian_two_link,
    mass_matrix,
    symbolic_model,
    two_link_arm,
    two_link_symbols,
)
from .proofs import (
    PARAMETRIZATIONS,
    all_proofs,
    prove_crf_is_minus_crm_transpose,
    prove_cross_antisymmetry,
    prove_cross_equivariance,
    prove_dynamic_parameters_round_trip,
    prove_force_cross_duality,
    prove_gyroscopic_identity,
    prove_inertia_linear_in_dynamic_parameters,
    prove_jacobi_identity,
    prove_kinetic_energy_invariance,
    prove_parallel_axis,
    prove_plucker_determinant,
    prove_power_invariance,
    prove_pure_rotation_orthogonal,
    prove_transform_inverse,
)
from .reduce import canonical, is_zero

__all__ = [
    "PARAMETRIZATIONS",
    "APPENDIX_D",
    "TwoLinkDynamics",
    "all_proofs",
    "canonical",
    "check_two_link",
    "coriolis",
    "gravity",
    "is_zero",
    "lagrangian_two_link",
    "mass_matrix",
    "prove_cross_antisymmetry",
    "prove_cross_equivariance",
    "prove_crf_is_minus_crm_transpose",
    "prove_dynamic_parameters_round_trip",
    "prove_force_cross_duality",
    "prove_gyroscopic_identity",
    "prove_inertia_linear_in_dynamic_parameters",
    "prove_jacobi_identity",
    "prove_kinetic_energy_invariance",
    "prove_parallel_axis",
    "prove_plucker_determinant",
    "prove_power_invariance",
    "prove_pure_rotation_orthogonal",
    "prove_transform_inverse",
    "symbolic_model",
    "two_link_arm",
    "two_link_symbols",
]
