"""Spatial vector algebra: the chapter's ``spatial_algebra.py``.

Motion vectors ``m = [ω; v_O]`` (M⁶) and force vectors ``f = [n_O; f]`` (F⁶)
in Featherstone's order (angular first), Plücker transforms, the spatial
cross products and the spatial rigid-body inertia. Everything broadcasts over
leading batch axes and keeps the dtype it is given (float64, float32, or
object arrays of SymPy expressions).

The classes exist for type safety: a motion and a force never add, a force is
never moved with the motion transform, and the only mixed product is power::

    motion.dot(force) = ωᵀ n_O + vᵀ f         (invariant under any X)

Sources: Featherstone, *Rigid Body Dynamics Algorithms* (2008) ch. 2;
chapter §2–§5, §13 and appendices A, F, H.
The pieces live in private modules, one concept each, and every name is
re-exported here: :mod:`._spatial_ops` (raw-array kernels: 3D cross products,
``skew``), :mod:`._spatial_vectors` (``SpatialMotion``, ``SpatialForce``,
``crm``, ``crf``, the cross products, screws), :mod:`._spatial_inertia`
(``SpatialInertia``) and :mod:`._spatial_transform` (``PluckerTransform``,
``rotx`` … ``plux``); each imports only the ones before it.
"""

from __future__ import annotations

# Every name keeps its address featherdyn.spatial_algebra.NAME, the private helpers included
# (the reference algorithms import _cross3, _crm_apply and _skew from here).
from ._spatial_inertia import SpatialInertia, _bcast_inertia, _init_i, _sym_from  # noqa: F401
from ._spatial_ops import (  # noqa: F401
    _CRF_A,
    _CRF_B,
    _CRM_A,
    _CRM_B,
    _NEXT,
    _PREV,
    _adopt_dtype,
    _batch_index,
    _bcast,
    _bcast_rp,
    _crf_apply,
    _crm_apply,
    _cross3,
    _fmt,
    _is_weak,
    _kind,
    _matvec,
    _mT,
    _raw_hint,
    _skew,
    _sum_last,
    _tags,
    _unskew,
    skew,
    unskew,
)
from ._spatial_transform import (  # noqa: F401
    PluckerTransform,
    _apply_type_error,
    _init_x,
    _rot_axis,
    plux,
    rotx,
    roty,
    rotz,
    xlt,
)
from ._spatial_vectors import (  # noqa: F401
    Screw,
    SpatialForce,
    SpatialMotion,
    _init,
    _mix_error,
    _raw_force,
    _raw_motion,
    _scalar_factor,
    _SpatialValue,
    crf,
    crm,
    cross_force,
    cross_motion,
    screw_parameters,
)

__all__ = [
    "SpatialMotion",
    "SpatialForce",
    "PluckerTransform",
    "SpatialInertia",
    "Screw",
    "cross_motion",
    "cross_force",
    "crm",
    "crf",
    "skew",
    "unskew",
    "screw_parameters",
    "rotx",
    "roty",
    "rotz",
    "xlt",
    "plux",
]
