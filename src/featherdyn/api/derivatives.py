"""The public derivatives: of inverse and forward dynamics, of frame motion, and the torque regressor.

Tangent convention: a derivative with respect to ``q`` is taken along the
tangent of ``fd.integrate`` — ``q ⊕ δ`` with δ in ``v``'s layout (the
free-flyer's ``[ω; v]`` in its own frame, a spherical joint's ω in the child
frame) — the tangent Pinocchio uses, up to its ``[v; ω]`` order. Float64
input runs the compiled core (``core/cpp/derivatives.hpp``,
``frame_derivatives.hpp``, ``regressor.hpp``); other dtypes (and
``backend="reference"``) run the reference in ``algorithms/derivatives.py``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .. import _dask
from .. import core as _compiled
from ..algorithms import derivatives as _ref
from ..frames import LOCAL, ReferenceFrame, as_reference_frame
from ..model import Model
from ._backend import CORE, core_path, select_backend
from ._checks import as_dtype, batch_with_f_ext, check_f_ext, check_state, finite_result, quiet
from .dynamics import crba

_EMPTY = np.empty
_NDARRAY = np.ndarray

__all__ = ["rnea_derivatives", "aba_derivatives", "mass_matrix_inverse", "frame_velocity_derivatives",
           "frame_acceleration_derivatives", "joint_torque_regressor", "dynamic_parameters"]


def rnea_derivatives(model: Model, q: ArrayLike, v: ArrayLike, a: ArrayLike, f_ext: ArrayLike | None = None, *,
                     backend: str | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(∂τ/∂q, ∂τ/∂q̇, ∂τ/∂q̈)``, each `(..., nv, nv)`, of ``τ = RNEA(q, q̇, q̈, f_ext)``.

    Args:
        q: `(..., nq)`; v, a: `(..., nv)`; f_ext: optional `(..., nb, 6)` body-frame forces ``[n; f]``.

    ::

        ∂τ/∂q[:, j] = d/dε RNEA(q ⊕ ε e_j, q̇, q̈) |_{ε=0},    ∂τ/∂q̈ = M(q)
    """
    core = core_path(model, backend)
    if core is not None:
        # one float64 state: the binding as is (it refuses anything else, and checks the state itself)
        dq, dv, M = _EMPTY(core.shape_M), _EMPTY(core.shape_M), _EMPTY(core.shape_M)
        try:
            if CORE.rnea_derivatives(core.cm, q, v, a, f_ext, dq, dv, M) == 0:
                return dq, dv, M
        except TypeError:  # arguments the binding does not take as they are: the general path converts
            pass
    if _dask.lazy(q, v, a, f_ext):
        return _dask.call(rnea_derivatives, model, {"q": q, "v": v, "a": a, "f_ext": f_ext}, backend=backend)
    fx = check_f_ext(model, f_ext)
    st = check_state(model, q, v=v, a=a)
    dtype = batch_with_f_ext(st, fx)[1]
    qd, qdd = st.arrays["v"], st.arrays["a"]
    if select_backend(backend, dtype) == "compiled":
        dq, dv, M = _compiled.rnea_derivatives(model, st.q, qd, qdd, fx)
        return as_dtype(dq, dtype), as_dtype(dv, dtype), as_dtype(M, dtype)
    dq, dv = quiet(_ref.rnea_derivatives, model, st.q, qd, qdd, fx)
    return (finite_result(dq, "rnea_derivatives"), finite_result(dv, "rnea_derivatives"),
            crba(model, st.q, backend="reference"))


def aba_derivatives(model: Model, q: ArrayLike, v: ArrayLike, tau: ArrayLike, f_ext: ArrayLike | None = None, *,
                    backend: str | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(∂q̈/∂q, ∂q̈/∂q̇, ∂q̈/∂τ)``, each `(..., nv, nv)`, of ``q̈ = ABA(q, q̇, τ, f_ext)``::

        ∂q̈/∂q = −M⁻¹ ∂τ/∂q,   ∂q̈/∂q̇ = −M⁻¹ ∂τ/∂q̇   (RNEA's, at q̈ = ABA(q, q̇, τ)),   ∂q̈/∂τ = M⁻¹

    Raises:
        SingularMassMatrixError: naming the joint, when M(q) is singular.
    """
    core = core_path(model, backend)
    if core is not None:
        dq, dv, Minv, qdd = _EMPTY(core.shape_M), _EMPTY(core.shape_M), _EMPTY(core.shape_M), _EMPTY(core.nv)
        try:
            if CORE.aba_derivatives(core.cm, q, v, tau, f_ext, qdd, dq, dv, Minv) == 0:
                return dq, dv, Minv
        except TypeError:  # arguments the binding does not take as they are: the general path converts
            pass
    if _dask.lazy(q, v, tau, f_ext):
        return _dask.call(aba_derivatives, model, {"q": q, "v": v, "tau": tau, "f_ext": f_ext}, backend=backend)
    fx = check_f_ext(model, f_ext)
    st = check_state(model, q, v=v, tau=tau)
    dtype = batch_with_f_ext(st, fx)[1]
    qd, t = st.arrays["v"], st.arrays["tau"]
    if select_backend(backend, dtype) == "compiled":
        return tuple(as_dtype(x, dtype) for x in _compiled.aba_derivatives(model, st.q, qd, t, fx))  # type: ignore[return-value]
    out = quiet(_ref.aba_derivatives, model, st.q, qd, t, fx)
    return tuple(finite_result(x, "aba_derivatives") for x in out)  # type: ignore[return-value]


def mass_matrix_inverse(model: Model, q: ArrayLike, *, backend: str | None = None) -> np.ndarray:
    """``M(q)⁻¹`` `(..., nv, nv)`, never by inverting a dense M::

        M⁻¹ e_j = ABA(q, 0, e_j) without gravity                   (the reference)
        M = Lᵀ L (tree-sparse),  M⁻¹ = Zᵀ Z,  Z = L⁻ᵀ               (the core: O(nv · depth) per row)

    Raises:
        SingularMassMatrixError: naming the joint, when M(q) is singular.
    """
    core = core_path(model, backend)
    if core is not None:
        Minv = _EMPTY(core.shape_M)
        try:
            if CORE.mass_matrix_inverse(core.cm, q, Minv) == 0:
                return Minv
        except TypeError:  # arguments the binding does not take as they are: the general path converts
            pass
    if _dask.lazy(q):
        return _dask.call(mass_matrix_inverse, model, {"q": q}, backend=backend)
    st = check_state(model, q)
    if select_backend(backend, st.dtype) == "compiled":
        return as_dtype(_compiled.mass_matrix_inverse(model, st.q), st.dtype)
    return finite_result(quiet(_ref.mass_matrix_inverse, model, st.q), "mass_matrix_inverse")


def frame_velocity_derivatives(model: Model, q: ArrayLike, v: ArrayLike, frame: str | int,
                               reference: ReferenceFrame | str = LOCAL, *,
                               backend: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``(∂v_f/∂q, ∂v_f/∂q̇)`` `(..., 6, nv)` of ``fd.frame_velocity(model, q, v, frame, reference)``::

        v_f = J(q) q̇,   ∂v_f/∂q̇ = J

    In ``LOCAL_WORLD_ALIGNED`` this is the derivative of that function itself, whose reference
    point (the frame's origin) moves with q; Pinocchio's ``getFrameVelocityDerivatives`` keeps the
    point fixed: its linear rows lack ``ω × J_v[:, j]``. LOCAL and WORLD are the same in both.
    """
    if _dask.lazy(q, v):
        return _dask.call(frame_velocity_derivatives, model, {"q": q, "v": v}, frame=frame, reference=reference, backend=backend)
    fid, ref = model.resolve_frame(frame), as_reference_frame(reference)
    st = check_state(model, q, v=v)
    if select_backend(backend, st.dtype) == "compiled":
        return tuple(as_dtype(x, st.dtype)  # type: ignore[return-value]
                     for x in _compiled.frame_velocity_derivatives(model, st.q, st.arrays["v"], fid, ref.code))
    out = quiet(_ref.frame_motion_derivatives, model, st.q, st.arrays["v"], None, fid, ref)
    return tuple(finite_result(x, "frame_velocity_derivatives") for x in out)  # type: ignore[return-value]


def frame_acceleration_derivatives(model: Model, q: ArrayLike, v: ArrayLike, a: ArrayLike, frame: str | int,
                                   reference: ReferenceFrame | str = LOCAL, *,
                                   backend: str | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(∂a_f/∂q, ∂a_f/∂q̇, ∂a_f/∂q̈)`` `(..., 6, nv)` of ``fd.frame_acceleration`` (spatial, no gravity)::

        a_f = J q̈ + J̇ q̇,   ∂a_f/∂q̈ = J

    (``LOCAL_WORLD_ALIGNED``: as :func:`frame_velocity_derivatives`; Pinocchio's linear rows lack
    ``ω̇ × J_v[:, j]``.)
    """
    if _dask.lazy(q, v, a):
        return _dask.call(frame_acceleration_derivatives, model, {"q": q, "v": v, "a": a}, frame=frame, reference=reference, backend=backend)
    fid, ref = model.resolve_frame(frame), as_reference_frame(reference)
    st = check_state(model, q, v=v, a=a)
    if select_backend(backend, st.dtype) == "compiled":
        out = _compiled.frame_acceleration_derivatives(model, st.q, st.arrays["v"], st.arrays["a"], fid, ref.code)
        return tuple(as_dtype(x, st.dtype) for x in out)  # type: ignore[return-value]
    ref_out = quiet(_ref.frame_motion_derivatives, model, st.q, st.arrays["v"], st.arrays["a"], fid, ref)[2:]
    return tuple(finite_result(x, "frame_acceleration_derivatives") for x in ref_out)  # type: ignore[return-value]


def joint_torque_regressor(model: Model, q: ArrayLike, v: ArrayLike, a: ArrayLike, *,
                           backend: str | None = None) -> np.ndarray:
    """``Y`` `(..., nv, 10 nb)` with ``RNEA(q, q̇, q̈) = Y @ fd.dynamic_parameters(model)`` (gravity included)::

        Y[joint j, 10 i + k] = S_jᵀ ʲX_i* (I(e_k) a_i + v_i ×* I(e_k) v_i)    (j supporting body i)
    """
    if _dask.lazy(q, v, a):
        return _dask.call(joint_torque_regressor, model, {"q": q, "v": v, "a": a}, backend=backend)
    st = check_state(model, q, v=v, a=a)
    if select_backend(backend, st.dtype) == "compiled":
        return as_dtype(_compiled.joint_torque_regressor(model, st.q, st.arrays["v"], st.arrays["a"]), st.dtype)
    return finite_result(quiet(_ref.joint_torque_regressor, model, st.q, st.arrays["v"], st.arrays["a"]),
                         "joint_torque_regressor")


def dynamic_parameters(model: Model) -> np.ndarray:
    """The bodies' ten dynamic parameters stacked, `(10 nb,)`, in ``SpatialInertia.to_dynamic_parameters`` order::

        π_i = [m, m c_x, m c_y, m c_z, I_xx, I_xy, I_yy, I_xz, I_yz, I_zz]   (I about body i's origin)
    """
    return _ref.dynamic_parameters(model)
