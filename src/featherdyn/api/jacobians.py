"""The Jacobians of the declared functions, as compositions of declared functions (docs/frameworks.md).

The frameworks' operations (``featherdyn.jax``, ``featherdyn.torch``) take every derivative from here, in their
own arrays: a rule calls declared functions through a :class:`Framework` (the framework's own operations, so
that a Jacobian made of operations that have Jacobians is differentiated again: ``jax.hessian`` of ``fj.rnea``
runs ``rnea_derivatives``' rule, which reads ``fd.rnea_second_derivatives``).

:func:`jacobians` ``(fw, name, model, x, options)`` → ``{output: {input: J}}``, ``J`` `(..., *output, n)` with
``J[..., o, k] = ∂output_o/∂x_k``; ``n`` is ``nv`` for ``q`` (along ``fd.integrate``'s tangent, as the NumPy
derivative functions), the input's length otherwise, ``nv²`` for a matrix (``W``, flattened row-major:
:func:`matrix_inputs`). An input missing from an output's table does not enter
it (its Jacobian is zero, as ``∂τ/∂q̈`` of ``nonlinear_effects``); ``f_ext`` (of ``rnea`` and ``aba`` only) enters
through the generalized force :func:`generalized_force`, a linear map the frameworks apply and transpose without
its Jacobian. A function with neither a rule nor a declared ``derivative`` raises
:class:`~featherdyn.errors.FeatherdynError` naming it: never a silent zero.

* A declaration with ``derivative`` needs nothing here (its derivative's outputs, in order, are the Jacobians);
* :data:`RULES` holds the others, each a few lines of the identities they rest on (each checked by
  ``jax.test_util.check_grads`` and ``torch.autograd.gradcheck`` against finite differences).

The configuration's tangent map ``δ = T(q) q̇`` (and ``q̇ = E(q) δ``, their transposes) is here too, once, for
both frameworks: :func:`tangent_of_coordinates` & co.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, Protocol

import numpy as np

from .._state_checks import MATRICES
from ..errors import FeatherdynError
from ..frames import LOCAL, LOCAL_WORLD_ALIGNED
from ..model import Model
from .declarations import DECLARATIONS

__all__ = ["Framework", "RULES", "VJPS", "F_EXT", "jacobians", "mass_matrix_vjp", "matrix_inputs", "generalized_force",
           "generalized_force_transpose", "f_ext_tangent", "f_ext_cotangent", "has_jacobians", "tangent_of_coordinates", "coordinates_of_tangent",
           "tangent_transpose", "coordinates_transpose", "normalize"]


class Framework(Protocol):
    """What a rule uses of a framework: its declared operations and a few array functions."""

    def call(self, name: str, model: Model, inputs: dict[str, Any], options: dict[str, Any]) -> tuple[Any, ...]:
        """The outputs of ``fd.<name>`` on the framework's arrays (inputs by name, absent ones ``None``; options
        by name as the public functions take them)."""
        ...

    def einsum(self, spec: str, *xs: Any) -> Any: ...
    def const(self, a: np.ndarray) -> Any: ...
    def concat(self, xs: Sequence[Any], axis: int) -> Any: ...
    def stack(self, xs: Sequence[Any], axis: int) -> Any: ...
    def zeros(self, shape: tuple[int, ...]) -> Any: ...
    def cos(self, x: Any) -> Any: ...
    def sin(self, x: Any) -> Any: ...
    def sqrt(self, x: Any) -> Any: ...
    def isfinite(self, x: Any, /) -> Any: ...
    def where(self, condition: Any, x: Any, y: Any, /) -> Any: ...


Table = dict[str, dict[str, Any]]
Rule = Callable[[Framework, Model, dict[str, Any], dict[str, Any]], Table]

#: ε_ijk: (a × b)_i = ε_ijk a_j b_k
_EPS = np.zeros((3, 3, 3))
for _i, _j, _k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
    _EPS[_i, _j, _k], _EPS[_i, _k, _j] = 1.0, -1.0
#: hat(m) = Σ_s _HAT[:, :, s] m_s: the 4×4 matrix of a twist m = [ω; v] (``[[ω]×, v], [0, 0]``)
_HAT = np.zeros((4, 4, 6))
_HAT[:3, :3, :3] = -_EPS  # [ω]×_ij = -ε_ijk ω_k
for _i in range(3):
    _HAT[_i, 3, 3 + _i] = 1.0


def _swap(fw: Framework, J: Any) -> Any:
    """``J[..., i, j, k]`` → ``J[..., i, k, j]``."""
    return fw.einsum("...ijk->...ikj", J)


def _own(name: str, fw: Framework, model: Model, x: dict[str, Any], options: dict[str, Any]) -> tuple[Any, ...]:
    decl = DECLARATIONS[name]
    return fw.call(name, model, {n: x.get(n) for n in decl.inputs}, {k: v for k, v in options.items()
                                                                       if k in decl.options})


# --- first order: compositions of the first-order derivative functions -------------------------------------------

def _nonlinear_effects(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``h(q, q̇) = RNEA(q, q̇, 0)``."""
    d = fw.call("rnea_derivatives", model, {"q": x["q"], "v": x["v"], "a": fw.zeros((model.nv,))}, {})
    return {"h": {"q": d[0], "v": d[1]}}


def _dM_dq(fw: Framework, model: Model, q: Any) -> Any:
    """``∂M/∂q`` `(..., nv, nv, nv)`, ``[i, j, k] = ∂M_ij/∂q_k``: column ``j`` of ``M`` is ``RNEA(q, 0, e_j)`` without
    gravity, so ``∂(M e_j)/∂q`` is ``fd.rnea_derivatives(q, 0, e_j).dtau_dq`` — all columns in one batched call
    (half the time of ``fd.rnea_second_derivatives(q, 0, 0).dM_dq``, which forms three more tensors; and
    differentiable again through ``rnea_derivatives``' Jacobians)."""
    q1, E = _unit_columns(fw, model, q)
    d = fw.call("rnea_derivatives", model, {"q": q1, "v": fw.zeros((model.nv,)), "a": E}, {"gravity": False})
    return fw.einsum("...jik->...ijk", d[0])


def _crba(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    return {"M": {"q": _dM_dq(fw, model, x["q"])}}


def _mass_matrix_inverse(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``∂M⁻¹/∂q_k = −M⁻¹ (∂M/∂q_k) M⁻¹``."""
    Minv = fw.call("mass_matrix_inverse", model, {"q": x["q"]}, {})[0]
    return {"Minv": {"q": -fw.einsum("...ia,...abk,...bj->...ijk", Minv, _dM_dq(fw, model, x["q"]), Minv)}}


def _kinetic_energy_derivatives(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``T = ½ q̇ᵀ M q̇``'s gradient ``(½ q̇ᵀ ∂(M q̇)/∂q, M q̇)`` differentiated: ``M q̇ = RNEA(q, 0, q̇)`` without
    gravity, so with ``τ`` that RNEA and its derivatives ``∂τ/∂q``, ``∂²τ/∂q²``::

        ∂(∂T/∂q_k)/∂q_l = ½ Σ_i q̇_i ∂²τ_i/∂q_k∂q_l,   ∂(∂T/∂q_k)/∂q̇_j = (∂τ/∂q)_jk,
        ∂(M q̇)/∂q = ∂τ/∂q,                           ∂(M q̇)/∂q̇ = M
    """
    v = x["v"]
    at_rest = {"q": x["q"], "v": fw.zeros((model.nv,)), "a": v}
    d = fw.call("rnea_derivatives", model, at_rest, {"gravity": False})
    d2 = fw.call("rnea_second_derivatives", model, at_rest, {"gravity": False})
    return {"dT_dq": {"q": 0.5 * fw.einsum("...i,...ikl->...kl", v, d2[0]), "v": _transpose(fw, d[0])},
            "dT_dv": {"q": d[0], "v": d[2]}}


def _transpose(fw: Framework, A: Any) -> Any:
    return fw.einsum("...ij->...ji", A)


def _potential_energy(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``∂U/∂q = g(q)``, the generalized gravity (Lagrange: ``τ = M q̈ + C q̇ + ∂U/∂q``)."""
    return {"U": {"q": fw.call("generalized_gravity", model, {"q": x["q"]}, {})[0]}}


def _centroidal_momentum(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``h = A(q) q̇``: ``∂h/∂q`` and ``A = ∂ḣ/∂q̈`` of ``fd.centroidal_dynamics_derivatives``."""
    d = fw.call("centroidal_dynamics_derivatives", model, {"q": x["q"], "v": x["v"], "a": fw.zeros((model.nv,))}, {})
    return {"h": {"q": d[0], "v": d[3]}}


def _center_of_mass(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``c(q)``, ``ċ = J_c(q) q̇``: ``∂c/∂q = J_c``, ``∂ċ/∂q̇ = J_c`` (``fd.center_of_mass_derivatives``)."""
    v = x.get("v")
    d = fw.call("center_of_mass_derivatives", model, {"q": x["q"], "v": fw.zeros((model.nv,)) if v is None else v},
                {})
    table: Table = {"position": {"q": d[0]}}
    if v is not None:
        table["velocity"] = {"q": d[1], "v": d[0]}
    return table


def _frame_classical_acceleration(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``fd.kinematics_derivatives``' classical rows; ``∂a'/∂q̈ = J`` (``ω × v`` does not depend on ``q̈``)."""
    d = _own("kinematics_derivatives", fw, model, x, o)
    return {"motion": {"q": d[5], "v": d[6], "a": d[7]}}


def _unit_columns(fw: Framework, model: Model, q: Any) -> tuple[Any, Any]:
    """``q`` `(..., 1, nq)` and the unit velocities ``e_j`` `(nv, nv)`: one batched call gives a matrix function's
    derivative column by column, ``∂(A e_j)/∂q``."""
    return q[..., None, :], fw.const(np.eye(model.nv))


def _frame_jacobian(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``∂J_ij/∂q_k = ∂(J e_j)_i/∂q_k``: ``fd.frame_velocity_derivatives(q, e_j).dv_dq`` (``J q̇`` is the frame's
    velocity), all columns in one batched call."""
    q, E = _unit_columns(fw, model, x["q"])
    d = _own("frame_velocity_derivatives", fw, model, {"q": q, "v": E}, o)
    return {"J": {"q": fw.einsum("...jik->...ijk", d[0])}}


def _centroidal_momentum_matrix(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``∂A_ij/∂q_k = ∂(A e_j)_i/∂q_k``: ``fd.centroidal_dynamics_derivatives(q, e_j, 0).dh_dq``."""
    q, E = _unit_columns(fw, model, x["q"])
    d = fw.call("centroidal_dynamics_derivatives", model, {"q": q, "v": E, "a": fw.zeros((model.nv,))}, {})
    return {"A": {"q": fw.einsum("...jik->...ijk", d[0])}}


def _supports(model: Model) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(dof_dof, body_dof, own)``: ``dof_dof[j, k]`` = 1 when dof ``k``'s joint is dof ``j``'s joint or one of
    its ancestors; ``body_dof[b, k]`` likewise for body ``b``; ``own[b, k]`` when ``k`` is body ``b``'s joint's."""
    nb, nv = model.nbodies, model.nv
    body_dof, own = np.zeros((nb, nv)), np.zeros((nb, nv))
    for b in range(nb):
        iv, n = model.idx_v[b], type(model.joints[b]).nv
        own[b, iv:iv + n] = 1.0
        c = b
        while c >= 0:
            body_dof[b, model.idx_v[c]:model.idx_v[c] + type(model.joints[c]).nv] = 1.0
            c = model.parents[c]
    dof_dof = np.zeros((nv, nv))
    for b in range(nb):
        dof_dof[own[b] > 0] = body_dof[b]
    return dof_dof, body_dof, own


def _joint_jacobians(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """The world columns ``S_j`` move with the joints that carry them: ``∂S_j/∂q_k = S_k ×ₘ S_j`` when ``k``'s
    joint is ``j``'s or an ancestor (each joint's tangent is a motion on the right of its placement), else 0::

        S_k ×ₘ S_j = [ω_k × ω_j;  ω_k × v_j + v_k × ω_j]
    """
    J = fw.call("joint_jacobians", model, {"q": x["q"]}, {})[0]
    eps, mask = fw.const(_EPS), fw.const(_supports(model)[0])
    W, V = J[..., :3, :], J[..., 3:, :]
    top = fw.einsum("iab,...ak,...bj,jk->...ijk", eps, W, W, mask)
    bottom = (fw.einsum("iab,...ak,...bj,jk->...ijk", eps, W, V, mask)
              + fw.einsum("iab,...ak,...bj,jk->...ijk", eps, V, W, mask))
    return {"J": {"q": fw.concat([top, bottom], -3)}}


def _placements_dq(fw: Framework, model: Model, q: Any, H: Any) -> Any:
    """``∂H_b/∂q_k = hat(S_k) H_b`` for ``k`` supporting body ``b`` (``S_k``: ``fd.joint_jacobians``' world
    column), `(..., nb, 4, 4, nv)`."""
    J = fw.call("joint_jacobians", model, {"q": q}, {})[0]
    return fw.einsum("rcs,...sk,...bct,bk->...brtk", fw.const(_HAT), J, H, fw.const(_supports(model)[1]))


def _placements(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    H = fw.call("placements", model, {"q": x["q"]}, {})[0]
    return {"H": {"q": _placements_dq(fw, model, x["q"], H)}}


def _body_frames(model: Model) -> list[int]:
    """Each body's own frame (kind ``body``, identity placement), for the derivative functions of frames."""
    frames = []
    for b in range(model.nbodies):
        found = [i for i, f in enumerate(model.frames) if f.kind == "body" and f.body == b
                 and np.array_equal(f.placement.rotation, np.eye(3)) and not np.any(f.placement.translation)]
        if not found:
            raise FeatherdynError(f"featherdyn: the derivative of forward_kinematics needs a frame of body "
                                  f"{model.body_names[b]!r} at its origin (the model has none)")
        frames.append(found[0])
    return frames


def _body_columns(fw: Framework, model: Model, q: Any, H: Any) -> Any:
    """``ᵇS_k = [Rᵀω_k; Rᵀ(v_k + ω_k × p)]`` `(..., nb, 6, nv)`: each joint column in each body's coordinates
    (``H = [R p]`` the body's placement, ``[ω_k; v_k]`` ``fd.joint_jacobians``' world column), all pairs."""
    J = fw.call("joint_jacobians", model, {"q": q}, {})[0]
    R, p = H[..., :3, :3], H[..., :3, 3]
    w_b = fw.einsum("...bji,...jk->...bik", R, J[..., :3, :])
    v_w = J[..., None, 3:, :] + fw.einsum("iac,...ak,...bc->...bik", fw.const(_EPS), J[..., :3, :], p)  # v + ω × p
    return fw.concat([w_b, fw.einsum("...bji,...bjk->...bik", R, v_w)], -2)


def generalized_force(fw: Framework, model: Model, q: Any, f: Any) -> Any:
    """``u = Σ_b J_bᵀ f_b`` `(..., nv)` of body-frame forces ``f`` `(..., nb, 6)` (``J_b`` body ``b``'s Jacobian in
    its own coordinates): ``−RNEA(q, 0, 0, f)`` without gravity. ``f_ext`` enters ``rnea`` and ``aba`` through it
    (:func:`f_ext_tangent`); linear in ``f``, its transpose is :func:`generalized_force_transpose`."""
    zero = fw.zeros((model.nv,))
    return -fw.call("rnea", model, {"q": q, "v": zero, "a": zero, "f_ext": f}, {"gravity": False})[0]


def generalized_force_transpose(fw: Framework, model: Model, q: Any, w: Any) -> Any:
    """``f̄_b = J_b w`` `(..., nb, 6)`: the bodies' velocities at ``q̇ = w`` in their own coordinates
    (``fd.forward_kinematics(q, w).vel``) — the gradient of ``wᵀ u`` with respect to the forces."""
    return fw.call("forward_kinematics", model, {"q": q, "v": w}, {})[2]


def f_ext_tangent(fw: Framework, name: str, table: Table, u_dot: Any) -> Any:
    """The output's tangent from ``u̇`` (:func:`generalized_force` of ``ḟ``): ``τ = RNEA(q, q̇, q̈) − u`` gives
    ``−u̇``; ``q̈ = ABA(q, q̇, τ + u)`` gives ``(∂q̈/∂τ) u̇`` (:data:`F_EXT`)."""
    into = F_EXT[name]
    return -u_dot if into is None else fw.einsum("...ij,...j->...i", table["qdd"][into], u_dot)


def f_ext_cotangent(name: str, ybar: Any, xbar: dict[str, Any]) -> Any:
    """``ū`` from the output's cotangent ``ȳ`` and the inputs' (``x̄``): the transpose of :func:`f_ext_tangent`,
    ``−ȳ`` for ``rnea``, ``τ̄`` for ``aba``; ``f_ext``'s gradient is then :func:`generalized_force_transpose` of
    it."""
    into = F_EXT[name]
    return -ybar if into is None else xbar[into]


#: the functions differentiated with respect to ``f_ext``, and how its generalized force ``u`` enters: added to an
#: input (``aba``: ``q̈ = ABA(q, q̇, τ + u)``), or ``None``, subtracted from the output (``rnea``: ``τ − u``)
F_EXT: dict[str, str | None] = {"rnea": None, "aba": "tau"}


def _forward_kinematics(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``H``: :func:`_placements_dq`; ``Hp = ᵖM_b(q_b)``: ``∂Hp_b/∂q_k = Hp_b hat(ᵇS_k)`` for ``k`` of ``b``'s joint,
    ``ᵇS = [Rᵀω; Rᵀ(v + ω × p)]`` the column in the body's coordinates; ``vel``, ``acc``: each body frame's
    ``fd.frame_velocity_derivatives`` / ``fd.frame_acceleration_derivatives`` in ``LOCAL``."""
    q, v, a = x["q"], x.get("v"), x.get("a")
    H, Hp = fw.call("forward_kinematics", model, {"q": q, "v": v, "a": a}, {})[:2]
    S_b = _body_columns(fw, model, q, H)
    own = fw.const(_supports(model)[2])
    table: Table = {"H": {"q": _placements_dq(fw, model, q, H)},
                    "Hp": {"q": fw.einsum("...brc,cts,...bsk,bk->...brtk", Hp, fw.const(_HAT), S_b, own)}}
    if v is not None:
        frames = _body_frames(model)
        vel = [_own("frame_velocity_derivatives", fw, model, {"q": q, "v": v}, {"frame": f, "reference": LOCAL})
               for f in frames]
        table["vel"] = {"q": fw.stack([d[0] for d in vel], -3), "v": fw.stack([d[1] for d in vel], -3)}
        if a is not None:
            acc = [_own("frame_acceleration_derivatives", fw, model, {"q": q, "v": v, "a": a},
                        {"frame": f, "reference": LOCAL}) for f in frames]
            table["acc"] = {n: fw.stack([d[k] for d in acc], -3) for k, n in enumerate(("q", "v", "a"))}
    return table


def _frame_placement(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``∂R/∂q_k = [ω_k]× R``, ``∂p/∂q_k = v_k`` with ``[ω_k; v_k]`` the frame's Jacobian in
    ``LOCAL_WORLD_ALIGNED``."""
    R = _own("frame_placement", fw, model, x, o)[0]
    J = fw.call("frame_jacobian", model, {"q": x["q"]}, {"frame": o["frame"], "reference": LOCAL_WORLD_ALIGNED})[0]
    return {"rotation": {"q": fw.einsum("iab,...ak,...bj->...ijk", fw.const(_EPS), J[..., :3, :], R)},
            "translation": {"q": J[..., 3:, :]}}


# --- second order: the first-order derivative functions' Jacobians ------------------------------------------------

def _rnea_derivatives(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``∂(∂τ/∂q)/∂q̈ = ∂M/∂q`` with its last two indices swapped (``∂²τ_i/∂q_j∂q̈_k = ∂M_ik/∂q_j``) & co."""
    S = _own("rnea_second_derivatives", fw, model, x, o)
    return {"dtau_dq": {"q": S[0], "v": S[2], "a": _swap(fw, S[3])},
            "dtau_dv": {"q": _swap(fw, S[2]), "v": S[1]},
            "M": {"q": S[3]}}


def _aba_derivatives(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``∂M⁻¹_ik/∂q_j = ∂²q̈_i/∂q_j∂τ_k`` & co. (``fd.aba_second_derivatives``)."""
    S = _own("aba_second_derivatives", fw, model, x, o)
    return {"ddq_dq": {"q": S[0], "v": S[2], "tau": S[3]},
            "ddq_dv": {"q": _swap(fw, S[2]), "v": S[1]},
            "Minv": {"q": _swap(fw, S[3])}}


def _generalized_gravity_derivatives(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    zero = fw.zeros((model.nv,))
    return {"dg_dq": {"q": fw.call("rnea_second_derivatives", model, {"q": x["q"], "v": zero, "a": zero},
                                   {"gravity": True})[0]}}


def _static_torque_derivatives(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``τ(q) = RNEA(q, 0, 0, f_ext)``: its second derivative ``∂²τ/∂q²``."""
    zero = fw.zeros((model.nv,))
    return {"dtau_dq": {"q": fw.call("rnea_second_derivatives", model,
                                     {"q": x["q"], "v": zero, "a": zero, "f_ext": x["f_ext"]}, {"gravity": True})[0]}}


def _rnea_vjp(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``(wᵀ ∂τ/∂q, wᵀ ∂τ/∂q̇, M w)`` differentiated: ``w`` contracted with RNEA's second derivatives
    (``fd.rnea_second_derivatives``: ``∂²τ_i/∂q_j∂q̈_k = ∂M_ik/∂q_j``) and, in ``w``, the Jacobians themselves."""
    w = x["w"]
    S = _own("rnea_second_derivatives", fw, model, x, o)
    D = _own("rnea_derivatives", fw, model, x, o)
    row = "...i,...ijk->...jk"
    return {"grad_q": {"q": fw.einsum(row, w, S[0]), "v": fw.einsum(row, w, S[2]),
                       "a": fw.einsum("...i,...ikj->...jk", w, S[3]), "w": _transpose(fw, D[0])},
            "grad_v": {"q": fw.einsum("...i,...ikj->...jk", w, S[2]), "v": fw.einsum(row, w, S[1]),
                       "w": _transpose(fw, D[1])},
            "grad_a": {"q": fw.einsum("...i,...jik->...jk", w, S[3]), "w": D[2]}}


def _crba_vjp(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``Σ_ij W_ij ∂M_ij/∂q`` differentiated: in ``q``, ``Σ_ij W_ij ∂²M_ij/∂q_k∂q_l`` (``M e_j = RNEA(q, 0, e_j)``
    without gravity: ``fd.rnea_second_derivatives`` at the unit columns, all in one batched call); in ``W``
    (flattened row-major, :func:`matrix_inputs`), ``∂M_ij/∂q_k`` itself."""
    nv = model.nv
    q1, E = _unit_columns(fw, model, x["q"])
    S = fw.call("rnea_second_derivatives", model, {"q": q1, "v": fw.zeros((nv,)), "a": E}, {"gravity": False})
    dM = fw.einsum("...ijk->...kij", S[3][..., 0, :, :, :])  # (∂M/∂q, the same at every unit column)
    return {"grad_q": {"q": fw.einsum("...ij,...jikl->...kl", x["W"], S[0]),
                       "W": dM.reshape(tuple(dM.shape[:-2]) + (nv * nv,))}}


def input_tail(input_name: str) -> int:
    """How many trailing dimensions an input has of its own (the rest are its batch): 2 for ``f_ext`` `(nb, 6)`
    and a matrix (``W`` `(nv, nv)`), 1 for every other input (a vector)."""
    return 2 if input_name == "f_ext" or input_name in MATRICES else 1


def matrix_inputs(name: str) -> set[str]:
    """The inputs of ``fd.<name>`` that are matrices (``W`` `(..., nv, nv)`): their Jacobians are taken with the
    matrix flattened row-major (``J[..., o, i nv + j] = ∂output_o/∂W_ij``), so the frameworks flatten its
    direction before the product and shape its gradient back after it."""
    return {n for n in DECLARATIONS[name].inputs if n in MATRICES}


def _aba_vjp(fw: Framework, model: Model, x: dict[str, Any], o: dict[str, Any]) -> Table:
    """``(wᵀ ∂q̈/∂q, wᵀ ∂q̈/∂q̇, M⁻¹ w)`` differentiated: ``w`` contracted with ``fd.aba_second_derivatives``
    (``∂²q̈_i/∂q_j∂τ_k = ∂M⁻¹_ik/∂q_j``; ``q̈`` is linear in ``τ``, so ``∂²q̈/∂q̇∂τ = 0``) and, in ``w``, the
    Jacobians."""
    w = x["w"]
    S = _own("aba_second_derivatives", fw, model, x, o)
    D = _own("aba_derivatives", fw, model, x, o)
    row = "...i,...ijk->...jk"
    return {"grad_q": {"q": fw.einsum(row, w, S[0]), "v": fw.einsum(row, w, S[2]), "tau": fw.einsum(row, w, S[3]),
                       "w": _transpose(fw, D[0])},
            "grad_v": {"q": fw.einsum("...i,...ikj->...jk", w, S[2]), "v": fw.einsum(row, w, S[1]),
                       "w": _transpose(fw, D[1])},
            "grad_tau": {"q": fw.einsum("...i,...ikj->...jk", w, S[3]), "w": D[2]}}


#: the rules of the functions whose declaration has no ``derivative`` (module docstring)
RULES: dict[str, Rule] = {
    "nonlinear_effects": _nonlinear_effects, "crba": _crba, "mass_matrix_inverse": _mass_matrix_inverse,
    "kinetic_energy_derivatives": _kinetic_energy_derivatives, "potential_energy": _potential_energy,
    "centroidal_momentum": _centroidal_momentum, "center_of_mass": _center_of_mass,
    "frame_classical_acceleration": _frame_classical_acceleration, "frame_jacobian": _frame_jacobian,
    "centroidal_momentum_matrix": _centroidal_momentum_matrix, "joint_jacobians": _joint_jacobians,
    "placements": _placements, "forward_kinematics": _forward_kinematics, "frame_placement": _frame_placement,
    "rnea_derivatives": _rnea_derivatives, "aba_derivatives": _aba_derivatives,
    "generalized_gravity_derivatives": _generalized_gravity_derivatives,
    "static_torque_derivatives": _static_torque_derivatives, "rnea_vjp": _rnea_vjp, "aba_vjp": _aba_vjp,
    "crba_vjp": _crba_vjp,
}


# --- vector-Jacobian products that contract as they go -----------------------------------------------------------

def mass_matrix_vjp(fw: Framework, model: Model, q: Any, W: Any) -> Any:
    """``∂⟨W, M(q)⟩/∂q`` `(..., nv)` along ``fd.integrate``'s tangent, for ``W`` `(..., nv, nv)`, without forming
    ``∂M/∂q`` (nv³ a state): ``fd.crba_vjp`` (one pass per column over its subtree, docs/derivatives.md). A
    non-finite cotangent gives a non-finite gradient, as the Jacobian's product would (the kernel refuses a
    non-finite ``W``): the finite part is contracted, and ``Σ W · 0`` carries NaN and ±inf into the result."""
    spill = 0.0 * fw.einsum("...ij->...", W)[..., None]
    W = fw.where(fw.isfinite(W), W, 0.0)
    return fw.call("crba_vjp", model, {"q": q, "W": W}, {})[0] + spill


def _crba_product(fw: Framework, model: Model, x: dict[str, Any], ybars: dict[str, Any], o: dict[str, Any]
              ) -> dict[str, Any]:
    return {"q": mass_matrix_vjp(fw, model, x["q"], ybars["M"])}


def _mass_matrix_inverse_vjp(fw: Framework, model: Model, x: dict[str, Any], ybars: dict[str, Any],
                             o: dict[str, Any]) -> dict[str, Any]:
    """``∂⟨W, M⁻¹⟩/∂q = ∂⟨−M⁻¹ W M⁻¹, M⟩/∂q`` (``∂M⁻¹ = −M⁻¹ ∂M M⁻¹``, ``M⁻¹`` symmetric)."""
    Minv = fw.call("mass_matrix_inverse", model, {"q": x["q"]}, {})[0]
    return {"q": mass_matrix_vjp(fw, model, x["q"], -fw.einsum("...ia,...ab,...bj->...ij", Minv, ybars["Minv"], Minv))}


def _dynamics_vjp(vjp: str, inputs: tuple[str, str, str]) -> Vjp:
    """``rnea``'s and ``aba``'s: ``x̄ = ȳᵀ ∂y/∂x`` by ``fd.rnea_vjp`` / ``fd.aba_vjp`` (O(nb), no Jacobian)."""

    def product(fw: Framework, model: Model, x: dict[str, Any], ybars: dict[str, Any], o: dict[str, Any]
                ) -> dict[str, Any]:
        (ybar,) = ybars.values()
        g = fw.call(vjp, model, {**x, "w": ybar}, {"gravity": o.get("gravity", True)})
        return dict(zip(inputs, g, strict=True))

    return product


Vjp = Callable[[Framework, Model, dict[str, Any], dict[str, Any], dict[str, Any]], dict[str, Any]]
#: ``{name: vjp(fw, model, x, {output: ȳ}, options) → {input: x̄}}`` (``q``'s along the tangent; ``f_ext``'s through
#: :func:`f_ext_cotangent`): the first-order reverse products that contract as they go — ``crba``'s and ``M⁻¹``'s
#: without ``∂M/∂q`` (nv³ a state), ``rnea``'s and ``aba``'s in O(nb) without their Jacobians (nv² a state, O(nv·nb)
#: to form). featherdyn.torch's backward takes them when no graph is made of the backward (``create_graph=False``);
#: featherdyn.jax's reverse mode through its linear primitive's transpose. A second order goes through
#: :data:`RULES` (the vector–Jacobian products have Jacobians of their own).
VJPS: dict[str, Vjp] = {"crba": _crba_product, "mass_matrix_inverse": _mass_matrix_inverse_vjp,
                        "rnea": _dynamics_vjp("rnea_vjp", ("q", "v", "a")),
                        "aba": _dynamics_vjp("aba_vjp", ("q", "v", "tau"))}


def has_jacobians(name: str) -> bool:
    """Whether :func:`jacobians` knows ``fd.<name>``'s derivatives."""
    return name in RULES or DECLARATIONS[name].derivative is not None


def jacobians(fw: Framework, name: str, model: Model, x: dict[str, Any], options: dict[str, Any]) -> Table:
    """``{output: {input: J}}`` of ``fd.<name>`` at the inputs ``x`` (by name; ``None`` when absent), ``options``
    by name as the public function takes them (module docstring). ``f_ext`` is not in it: it enters ``rnea`` and
    ``aba`` (:data:`F_EXT`) through :func:`generalized_force`, which the frameworks apply and transpose as it is."""
    rule = RULES.get(name)
    decl = DECLARATIONS[name]
    if rule is not None:
        table = rule(fw, model, x, options)
    elif decl.derivative is None:
        raise FeatherdynError(f"{name}: its derivatives are not available (a function's derivatives come from its "
                              "declaration's derivative or api/jacobians.py; docs/frameworks.md lists them)")
    else:
        outs = _own(decl.derivative, fw, model, x, options)
        table = {decl.outputs[0]: dict(zip((n for n in decl.inputs if n != "f_ext"), outs, strict=False))}
    return table


# --- the configuration's tangent --------------------------------------------------------------------------------

def _quat_parts(q: Any) -> tuple[Any, Any]:
    return q[..., :3], q[..., 3:]


def _cross(fw: Framework, a: Any, b: Any) -> Any:
    return fw.einsum("iab,...a,...b->...i", fw.const(_EPS), a, b)


def _rot_T(fw: Framework, quat: Any, x: Any, transpose: bool) -> Any:
    """``R(quat/|quat|) x`` (``Rᵀ x``): ``x + 2w (u × x) + 2 u × (u × x)`` with ``(u, w)`` the unit quaternion."""
    n2 = fw.einsum("...i,...i->...", quat, quat)[..., None]
    u, w = _quat_parts(quat)
    u = -u if transpose else u
    t = _cross(fw, u, x)
    return x + (2 * w * t + 2 * _cross(fw, u, t)) / n2


def _blocks(model: Model) -> list[tuple[str, int, int, int, int]]:
    """``(kind, iq, nq, iv, nv)`` of each joint."""
    return [(j.kind, iq, type(j).nq, iv, type(j).nv)
            for j, iq, iv in zip(model.joints, model.idx_q, model.idx_v, strict=True)]


def _rz(fw: Framework, th: Any, xy: Any, transpose: bool) -> Any:
    c, s = fw.cos(th), fw.sin(th)
    s = -s if transpose else s
    return fw.stack([c * xy[..., 0] - s * xy[..., 1], s * xy[..., 0] + c * xy[..., 1]], -1)


def tangent_of_coordinates(fw: Framework, model: Model, q: Any, dq: Any) -> Any:
    """``δ = T(q) q̇`` `(..., nv)`: the tangent (``fd.integrate``'s) of a coordinate direction ``q̇`` `(..., nq)` at
    ``q``, for the functions as featherdyn computes them (quaternions normalised first)::

        quaternion (u, w):   ω = 2 vec(q̄ ⊗ q̇) / |q|²  = 2 (w u̇ − ẇ u − u × u̇) / |q|²
        free-flyer [p, quat]: v = R(quat)ᵀ ṗ;          planar [x, y, θ]: [ω, v_x, v_y] = [θ̇, Rz(θ)ᵀ (ẋ, ẏ)]
    """
    parts = []
    for kind, iq, nq, _iv, _nv in _blocks(model):
        if kind in ("spherical", "free_flyer"):
            at = iq + (3 if kind == "free_flyer" else 0)
            quat, dquat = q[..., at:at + 4], dq[..., at:at + 4]
            n2 = fw.einsum("...i,...i->...", quat, quat)[..., None]
            u, w = _quat_parts(quat)
            du, dw = _quat_parts(dquat)
            parts.append(2 * (w * du - dw * u - _cross(fw, u, du)) / n2)
            if kind == "free_flyer":
                parts.append(_rot_T(fw, quat, dq[..., iq:iq + 3], transpose=True))
        elif kind == "planar":
            parts += [dq[..., iq + 2:iq + 3], _rz(fw, q[..., iq + 2], dq[..., iq:iq + 2], transpose=True)]
        elif nq:
            parts.append(dq[..., iq:iq + nq])
    return _joined(fw, parts, q, dq)


def tangent_transpose(fw: Framework, model: Model, q: Any, g: Any) -> Any:
    """``Tᵀ g`` `(..., nq)`: a gradient ``g`` `(..., nv)` along the tangent as a gradient in ``q``'s coordinates
    (the transpose of :func:`tangent_of_coordinates`)."""
    parts = []
    for kind, iq, nq, iv, _nv in _blocks(model):
        if kind in ("spherical", "free_flyer"):
            at = iq + (3 if kind == "free_flyer" else 0)
            quat = q[..., at:at + 4]
            gw = g[..., iv:iv + 3]
            if kind == "free_flyer":
                parts.append(_rot_T(fw, quat, g[..., iv + 3:iv + 6], transpose=False))
            n2 = fw.einsum("...i,...i->...", quat, quat)[..., None]
            u, w = _quat_parts(quat)
            parts += [2 * (w * gw + _cross(fw, u, gw)) / n2, -2 * fw.einsum("...i,...i->...", u, gw)[..., None] / n2]
        elif kind == "planar":
            parts += [_rz(fw, q[..., iq + 2], g[..., iv + 1:iv + 3], transpose=False), g[..., iv:iv + 1]]
        elif nq:
            parts.append(g[..., iv:iv + nq])
    return _joined(fw, parts, q, g)


def coordinates_of_tangent(fw: Framework, model: Model, q: Any, delta: Any) -> Any:
    """``q̇ = E(q) δ`` `(..., nq)`: the coordinate direction of ``fd.integrate(q, ε δ)`` at ε = 0 (``T E = 1`` at a
    unit quaternion)::

        quaternion: q̇ = ½ q ⊗ [ω; 0];  free-flyer: ṗ = R(quat) v;  planar: (ẋ, ẏ) = Rz(θ) (v_x, v_y), θ̇ = ω
    """
    parts = []
    for kind, iq, nq, iv, _nv in _blocks(model):
        if kind in ("spherical", "free_flyer"):
            at = iq + (3 if kind == "free_flyer" else 0)
            quat, om = q[..., at:at + 4], delta[..., iv:iv + 3]
            if kind == "free_flyer":
                parts.append(_rot_T(fw, quat, delta[..., iv + 3:iv + 6], transpose=False))
            u, w = _quat_parts(quat)
            parts += [0.5 * (w * om + _cross(fw, u, om)), -0.5 * fw.einsum("...i,...i->...", u, om)[..., None]]
        elif kind == "planar":
            parts += [_rz(fw, q[..., iq + 2], delta[..., iv + 1:iv + 3], transpose=False), delta[..., iv:iv + 1]]
        elif nq:
            parts.append(delta[..., iv:iv + nq])
    return _joined(fw, parts, q, delta)


def coordinates_transpose(fw: Framework, model: Model, q: Any, gq: Any) -> Any:
    """``Eᵀ g`` `(..., nv)`: a gradient in ``q``'s coordinates as the gradient along the tangent,
    ``d/dδ L(fd.integrate(q, δ))`` (the transpose of :func:`coordinates_of_tangent`)."""
    parts = []
    for kind, iq, nq, _iv, nv in _blocks(model):
        if kind in ("spherical", "free_flyer"):
            at = iq + (3 if kind == "free_flyer" else 0)
            quat, g4 = q[..., at:at + 4], gq[..., at:at + 4]
            u, w = _quat_parts(quat)
            parts.append(0.5 * (w * g4[..., :3] - _cross(fw, u, g4[..., :3]) - u * g4[..., 3:]))
            if kind == "free_flyer":
                parts.append(_rot_T(fw, quat, gq[..., iq:iq + 3], transpose=True))
        elif kind == "planar":
            parts += [gq[..., iq + 2:iq + 3], _rz(fw, q[..., iq + 2], gq[..., iq:iq + 2], transpose=True)]
        elif nv:
            parts.append(gq[..., iq:iq + nq])
    return _joined(fw, parts, q, gq)


def normalize(fw: Framework, model: Model, q: Any) -> Any:
    """``q`` `(..., nq)` with each quaternion divided by its norm (``fd.normalize`` in the framework,
    differentiable): what a function differentiated in coordinates off the unit quaternions calls first."""
    parts, done = [], 0
    for kind, iq, _nq, _iv, _nv in _blocks(model):
        if kind in ("spherical", "free_flyer"):
            at = iq + (3 if kind == "free_flyer" else 0)
            quat = q[..., at:at + 4]
            parts += [q[..., done:at], quat / fw.einsum("...i,...i->...", quat, quat)[..., None] ** 0.5]
            done = at + 4
    return fw.concat([*parts, q[..., done:]], -1) if parts else q


def _joined(fw: Framework, parts: list[Any], q: Any, x: Any) -> Any:
    """The parts concatenated on a common batch (each broadcast against ``q`` and ``x``'s batch)."""
    batch = np.broadcast_shapes(tuple(q.shape[:-1]), tuple(x.shape[:-1]))
    if not parts:
        return fw.zeros(batch + (0,))
    return fw.concat([p + fw.zeros(batch + (1,)) for p in parts], -1)
